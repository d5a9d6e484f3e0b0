// specht/pipeline/pose_history.h: the car's recent poses (base_link in the map frame,
// one per scan as SLAM or the localizer placed it) and its pose at any stamp between
// two of them — where a camera frame taken between two scans was taken from.
//
// Between p0 at t0 and p1 at t1, at t with s = (t − t0) / (t1 − t0):
//   position           (1 − s) · p0 + s · p1
//   yaw, pitch, roll   a0 + s · wrap(a1 − a0)   (the shorter way round)
// Before the first pose the first is taken, after the last the last (held, never
// extrapolated): Covers() says whether a later pose already brackets the stamp.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <deque>
#include <optional>

#include "specht/core/time.h"
#include "specht/core/trajectory.h"

namespace specht::pipeline {

class PoseHistory {
 public:
  // Poses older than `keep_s` before the newest are dropped.
  explicit PoseHistory(double keep_s = 30.0) : keep_s_(keep_s) {}

  // Stamps must not decrease (a pose at the newest stamp replaces it).
  void Add(Stamp t, const mrpt::poses::CPose3D& map_from_base);
  // A pose at or after `t` is known.
  bool Covers(Stamp t) const { return !poses_.empty() && poses_.back().stamp >= t; }
  // The pose at `t` as above; nullopt before any pose.
  std::optional<mrpt::poses::CPose3D> At(Stamp t) const;
  std::optional<StampedPose> Latest() const;

 private:
  double keep_s_;
  std::deque<StampedPose> poses_;
};

// The pose a fraction s ∈ [0, 1] of the way from a to b (the interpolation above).
mrpt::poses::CPose3D Interpolate(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b, double s);

}  // namespace specht::pipeline
