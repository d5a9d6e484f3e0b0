// specht/plan/tracker.h: following a planned path — a steering law and a speed
// profile, stretch by stretch between cusps.
//
// Steering, `steering: rear_wheel_feedback` (default; Samson 1992, in the form of
// Paden et al. 2016, "A Survey of Motion Planning and Control Techniques for
// Self-driving Urban Vehicles", §V-B): the path's own curvature fed forward plus
// feedback on the rear axle's lateral error e (left of the path positive) and
// heading error θe = θ − θ_ref at its projection on the path:
//   tan δ = L · ( κ cos θe / (1 − κ e) − k_heading · sgn(v) · θe − k_lateral · e · sin θe / θe )
// κ = dθ/dσ with σ the signed travel (negative in reverse), so the same law serves
// both directions. Near the path it gives e'' + k_heading e' + k_lateral e = 0 over
// distance travelled: errors decay within metres whatever the speed, and a short
// manoeuvre (a parking correction of a few decimetres) is driven on its planned arcs
// rather than cut short.
// `steering: pure_pursuit` (Coulter 1992): the goal point lies `lookahead` ahead on the current
// stretch (d = min_lookahead + k · |v|; never past the stretch's: near the end it lies on the line of the end pose's
// heading beyond it, so the car arrives aligned); with α its bearing from the car's heading, δ = atan(2 L sin α / d).
// In reverse the same law runs for a virtual car facing backwards (heading θ + π) and the angle is negated (θ̇ = v tan δ
// / L with v < 0). Speed: v ≤ max speed of the direction, v ≤ √(a_lat / κ) for the path's curvature ahead, v ≤ ½ δ̇_max
// / (L |dκ/ds|) so the steering can keep up through S-bends, v ≤ √(2 a_brake s) with s the distance left to the
// stretch's end, where the car stops before the next stretch starts (a gear change) or the goal, and v ≤ approach_speed
// within approach_distance of the path's end (precision where goals sit: bays between parked cars).
#pragma once

#include <cstddef>
#include <string>

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
  double steer_ready_deg = 2.0;
  std::string steering = "rear_wheel_feedback";
  double k_heading = 2.0;
  double k_lateral = 2.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("steering", steering, {"rear_wheel_feedback", "pure_pursuit"},
             "steering law: curvature fed forward with error feedback, or pure pursuit");
    v.Param("k_heading", k_heading, "rear_wheel_feedback: gain on the heading error, per metre travelled",
            Range::Of(0.0, 20.0));
    v.Param("k_lateral", k_lateral, "rear_wheel_feedback: gain on the lateral error, per square metre",
            Range::Of(0.0, 50.0));
    v.Param("min_lookahead_m", min_lookahead_m,
            "pure-pursuit lookahead at standstill (also the reach of the "
            "speed profile's curvature look-ahead)",
            Range::Of(0.2, 10.0));
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
    v.Param("steer_ready_deg", steer_ready_deg, "a stopped car first turns its wheels to within this of the command",
            Range::Of(0.1, 90.0));
  }
};

struct Command {
  double speed_mps = 0;  // signed: negative reverses
  double steer_rad = 0;
};

class PathTracker {
 public:
  PathTracker(const TrackerOptions& options, const CarOptions& car, Path path);
  // The command for the car at `pose` moving at `speed_mps` (signed) with its
  // wheels at `steer_rad` (as the car reports them). A stopped car whose wheels are more than
  // steer_ready_deg from the command turns them before it moves: a parking
  // manoeuvre's short arcs are driven on their curvature, not on the way to it.
  Command Update(const Pose& pose, double speed_mps, double steer_rad);
  bool finished() const { return finished_; }
  // Distance left along the path from the car's projection.
  double remaining_m() const { return remaining_; }
  const Path& path() const { return path_; }
  // Path points from the car's projection onward (for collision look-ahead).
  size_t progress_index() const { return index_; }

 private:
  double PurePursuit(const Pose& pose, double lookahead, size_t end, double left, int direction) const;
  double RearWheelFeedback(const Pose& pose, size_t end, int direction) const;
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
