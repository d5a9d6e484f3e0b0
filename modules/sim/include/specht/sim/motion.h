// specht/sim/motion.h: how things move. Every mover follows a route of waypoints;
// its class decides how:
//
//   class       cruise m/s (sampled)       turning                     stops
//   pedestrian  N(1.4, 0.3) in [0.5, 2.8]  up to 120°/s, heading noise pauses 0.5–3 s at
//              (jogs ×1.9 with p = 0.15)                              waypoints (p = 0.6)
//   cyclist     N(4.5, 1.2) in [1.8, 8]    up to 35°/s, slows in turns no
//   car         N(7, 2) in [3, 12]         bicycle model (L 2.7 m,     1–3 s at 'stop'
//                                          steer ≤ 35°), slows in turns waypoints
//   ego         scenario's cruise speed    bicycle model of the ego     at 'stop' waypoints
//
// Bicycle movers (cars, the ego) follow the route as a polyline by pure pursuit:
// the goal is the point of the route a lookahead distance d = max(2, 0.8 v + 1.5) m
// ahead of the mover's projection on it, the steering δ = atan(2 L sin α / d) with α
// the bearing of that point and |δ| ≤ δ_max, and the kinematics
//   ẋ = v cos θ,  ẏ = v sin θ,  θ̇ = v tan δ / L.
// In curves the speed is capped by a lateral acceleration of 2 m/s² at the pursuit
// curvature κ = 2 sin α / d (v ≤ √(2/|κ|)); before a stop waypoint by v ≤ √(2 a_dec s).
// Pedestrians and cyclists head for their next waypoint with a bounded turn rate. Speeds overlap between classes on
// purpose: no single speed threshold separates them; turning and stopping behaviour does.
#pragma once

#include <random>

#include "specht/sim/scenario.h"

namespace specht::sim {

struct MotionParams {
  double cruise_mps = 1.4;
  double accel_mps2 = 1.0, decel_mps2 = 1.5;
  double max_turn_rate = 2.0;  // rad/s, for non-bicycle movers
  bool bicycle = false;
  double wheelbase_m = 2.7, max_steer_rad = 0.6;
  double pivot_ahead_m = 0.0;  // bicycle movers: the pose point's distance ahead of the rear axle
  double heading_noise = 0.0;  // rad/s std. dev. of a random turn-rate disturbance
  double pause_probability = 0.0, pause_min_s = 0.5, pause_max_s = 3.0;
  double stop_s = 0.0;   // wait at 'stop' waypoints
  double reach_m = 0.5;  // a waypoint is reached within this distance
  double length_m = 0.5, width_m = 0.5;
};

// A class's parameters, with its cruise speed drawn from `rng`.
MotionParams SampleMotion(AgentClass cls, std::mt19937_64& rng);
MotionParams EgoMotion(const Ego& ego);

struct MoverState {
  Pose2 pose;
  double speed_mps = 0;
  double yaw_rate = 0;
  double accel_mps2 = 0;
  double steer_rad = 0;  // bicycle movers under StepCommanded
  size_t target = 0;     // index of the waypoint heading for
  double wait_s = 0;     // remaining pause
  bool finished = false;
};

class RouteFollower {
 public:
  // A route with loop = false ends at its last waypoint, or with back_and_forth
  // returns along itself and starts again.
  RouteFollower(std::vector<Waypoint> route, bool loop, MotionParams params, Pose2 start, bool back_and_forth = false);
  void Step(double dt, std::mt19937_64& rng);
  // Closed loop: one step driven by a controller instead of the route — the speed
  // approaches `speed_mps` (negative: reverse) within the accel/decel limits, the
  // steering angle follows `steer_rad` (clamped to ±max_steer) at up to
  // `steer_rate_rad_s`, and the bicycle kinematics integrate.
  void StepCommanded(double dt, double speed_mps, double steer_rad, double steer_rate_rad_s);
  const MoverState& state() const { return state_; }
  const MotionParams& params() const { return params_; }

 private:
  // Pure pursuit along the polyline; returns the target speed.
  double PursuePath();
  // Heads for the next waypoint; returns the target speed.
  double HeadForWaypoint(std::mt19937_64& rng);
  size_t Next(size_t i) const { return i + 1 < route_.size() ? i + 1 : 0; }

  std::vector<Waypoint> route_;
  bool loop_;
  MotionParams params_;
  MoverState state_;
};

}  // namespace specht::sim
