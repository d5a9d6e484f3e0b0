// specht/plan/tracker.h: following a planned path — pure pursuit for the steering
// and a speed profile, stretch by stretch between cusps.
//
// Steering (Coulter 1992): the goal point lies `lookahead` ahead on the current
// stretch (d = min_lookahead + k · |v|; never past the stretch's: near the end it lies on the line of the end pose's heading beyond it, so the
// car arrives aligned); with α its bearing from the car's heading,
// δ = atan(2 L sin α / d). In
// reverse the same law runs for a virtual car facing backwards (heading θ + π) and
// the angle is negated (θ̇ = v tan δ / L with v < 0).
// Speed: v ≤ max speed of the direction, v ≤ √(a_lat / κ) for the path's curvature
// ahead, v ≤ ½ δ̇_max / (L |dκ/ds|) so the steering can keep up through S-bends,
// v ≤ √(2 a_brake s) with s the distance left to the stretch's end, where
// the car stops before the next stretch starts (a gear change) or the goal, and
// v ≤ approach_speed within approach_distance of the path's end (precision where
// goals sit: bays between parked cars).
#pragma once

#include <cstddef>

#include "specht/plan/path.h"

namespace specht::plan {

// Section "tracker".
struct TrackerOptions {
  double min_lookahead_m = 1.0;
  double lookahead_per_mps = 0.5;
  double max_lateral_accel_mps2 = 1.5;
  double goal_tolerance_m = 0.05;
  double approach_distance_m = 8.0;
  double approach_speed_mps = 1.0;
  double stop_speed_mps = 0.05;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("min_lookahead_m", min_lookahead_m, "pure-pursuit lookahead at standstill", Range::Of(0.2, 10.0));
    v.Param("lookahead_per_mps", lookahead_per_mps, "lookahead added per m/s", Range::Of(0.0, 5.0));
    v.Param("max_lateral_accel_mps2", max_lateral_accel_mps2, "speed limit in curves: v²κ ≤ this",
            Range::Of(0.1, 10.0));
    v.Param("approach_distance_m", approach_distance_m, "the last metres of a path are driven slowly",
            Range::Of(0.0, 100.0));
    v.Param("approach_speed_mps", approach_speed_mps, "speed limit on the approach (goals sit in tight spots)",
            Range::Of(0.1, 20.0));
    v.Param("goal_tolerance_m", goal_tolerance_m, "a stretch's end is reached within this distance",
            Range::Of(0.005, 1.0));
    v.Param("stop_speed_mps", stop_speed_mps, "below this the car counts as stopped", Range::Of(0.001, 1.0));
  }
};

struct Command {
  double speed_mps = 0;  // signed: negative reverses
  double steer_rad = 0;
};

class PathTracker {
 public:
  PathTracker(const TrackerOptions& options, const CarOptions& car, Path path);
  // The command for the car at `pose` moving at `speed_mps` (signed).
  Command Update(const Pose& pose, double speed_mps);
  bool finished() const { return finished_; }
  // Distance left along the path from the car's projection.
  double remaining_m() const { return remaining_; }
  const Path& path() const { return path_; }
  // Path points from the car's projection onward (for collision look-ahead).
  size_t progress_index() const { return index_; }

 private:
  TrackerOptions o_;
  CarOptions car_;
  Path path_;
  std::vector<size_t> stretch_end_;  // per point: index of its stretch's last point
  std::vector<double> along_;        // arc length from the start
  size_t index_ = 0;                 // nearest point, never behind
  double remaining_ = 0;
  bool finished_ = false;
};

}  // namespace specht::plan
