#include "specht/core/trajectory.h"

namespace specht {

double PathLength(const Trajectory& t) {
  double length = 0;
  for (size_t i = 1; i < t.size(); ++i) length += t[i].pose.distanceTo(t[i - 1].pose);
  return length;
}

}  // namespace specht
