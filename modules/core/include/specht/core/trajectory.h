// specht/core/trajectory.h: a time-stamped sequence of poses (the car's base_link
// in some fixed frame), the common currency of SLAM, evaluation and writers.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <vector>

#include "specht/core/time.h"

namespace specht {

struct StampedPose {
  Stamp stamp;
  mrpt::poses::CPose3D pose;
};

using Trajectory = std::vector<StampedPose>;

// Path length along the positions, in metres.
double PathLength(const Trajectory& t);

}  // namespace specht
