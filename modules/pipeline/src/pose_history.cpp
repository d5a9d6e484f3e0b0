#include "specht/pipeline/pose_history.h"

#include <algorithm>
#include <cmath>

#include "specht/core/error.h"

namespace specht::pipeline {
namespace {

double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

}  // namespace

mrpt::poses::CPose3D Interpolate(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b, double s) {
  const auto lerp = [s](double u, double v) { return u + s * (v - u); };
  const auto angle = [s](double u, double v) { return Wrap(u + s * Wrap(v - u)); };
  return {lerp(a.x(), b.x()),      lerp(a.y(), b.y()),          lerp(a.z(), b.z()),
          angle(a.yaw(), b.yaw()), angle(a.pitch(), b.pitch()), angle(a.roll(), b.roll())};
}

void PoseHistory::Add(Stamp t, const mrpt::poses::CPose3D& pose) {
  if (!poses_.empty() && t < poses_.back().stamp)
    throw RuntimeError("pose history: a pose at " + std::to_string(t.Seconds()) + " s after one at " +
                       std::to_string(poses_.back().stamp.Seconds()) + " s");
  if (!poses_.empty() && t == poses_.back().stamp)
    poses_.back().pose = pose;
  else
    poses_.push_back({t, pose});
  while (poses_.size() > 2 && SecondsBetween(poses_.front().stamp, t) > keep_s_) poses_.pop_front();
}

std::optional<mrpt::poses::CPose3D> PoseHistory::At(Stamp t) const {
  if (poses_.empty()) return std::nullopt;
  if (t <= poses_.front().stamp) return poses_.front().pose;
  if (t >= poses_.back().stamp) return poses_.back().pose;
  const auto after =
      std::lower_bound(poses_.begin(), poses_.end(), t, [](const StampedPose& p, Stamp s) { return p.stamp < s; });
  const auto before = std::prev(after);
  const double span = SecondsBetween(before->stamp, after->stamp);
  const double s = span > 0 ? SecondsBetween(before->stamp, t) / span : 1.0;
  return Interpolate(before->pose, after->pose, s);
}

std::optional<StampedPose> PoseHistory::Latest() const {
  if (poses_.empty()) return std::nullopt;
  return poses_.back();
}

}  // namespace specht::pipeline
