// specht/plan/kinodynamic.h: the kinodynamic planner — OMPL's control-based
// planners (ompl::control: SST, RRT, KPIECE1) over the car's bicycle model, with
// a hard time budget per call.
//
// State (x, y, θ, δ, v, t): rear-axle pose, steering angle, speed, time since the
// start. Control (v_target, δ̇). Propagation integrates, in sub-steps of
// integration_step_s,
//   δ ← clamp(δ + δ̇ dt, ±δmax·steer_fraction)       (steering rate |δ̇| ≤ δ̇max)
//   v ← v + clamp(v_target − v, ±a_max dt)            (acceleration limit)
//   x ← x + v cos θ dt,  y ← y + v sin θ dt,  θ ← θ + v tan δ / L dt,  t ← t + dt
// so every path is continuous in curvature and speed and respects the car's limits
// (v_target ∈ [−v_rev, v_max]). Validity: the footprint (disc cover, then the
// rectangle; DistanceMap::Free) against the map's obstacles and, at the state's
// time t, against each moving obstacle's predicted position (constant velocity):
// a disc of the obstacle's radius that every footprint disc must clear by the
// margin.
//
// Cost of a motion from s₁ to s₂ (what SST minimises; RRT and KPIECE1 stop at
// the first solution):
//   c = (objective == time ? Δt : Δs) · (v₂ < 0 ? reverse_penalty : 1)
//     + clearance_weight · Δs · max(0, 1 − d(s₂) / clearance_target_m)
//     + gear_change_penalty · [sign v₁ ≠ sign v₂]
// with Δs the distance between the rear-axle positions and d(s₂) the footprint's
// disc-cover clearance. The goal is a pose: within goal_tolerance_m of the goal
// position and goal_heading_tolerance_deg of its heading (speed and steering free).
//
// Guide: a path from the global search (hybrid A*) makes a share guide_bias of the
// random samples fall near it (σ = guide_sigma_m), so trees grow along the passage
// the search found instead of filling open space — tight goals get reached.
//
// Time: every call ends by time_budget_ms (OMPL's timed termination condition) or
// max_iterations (0: no limit), whichever comes first; SST keeps improving until
// then unless stop_at_first_solution. Randomness: OMPL's global seed (set once per
// process from `seed`); with the budget set by max_iterations alone, a process's
// sequence of calls is reproducible, and Reseed() makes the calls after it so
// whatever ran before (a closed loop reseeds each call from its run's seed).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/plan/distance_map.h"
#include "specht/plan/hybrid_astar.h"

namespace specht::plan {

// Section "kinodynamic".
struct KinodynamicOptions {
  std::string planner = "sst";
  std::string objective = "length";
  double time_budget_ms = 250;
  int max_iterations = 0;
  bool stop_at_first_solution = false;
  std::string directions = "both";
  double steer_fraction = 0.85;
  double goal_tolerance_m = 0.3;
  double goal_heading_tolerance_deg = 10;
  double goal_bias = 0.05;
  double integration_step_s = 0.02;
  double control_step_s = 0.05;
  int min_control_steps = 4;
  int max_control_steps = 30;
  double reverse_penalty = 2.0;
  double gear_change_penalty = 5.0;
  double clearance_weight = 0.5;
  double clearance_target_m = 0.5;
  double guide_bias = 0.5;
  double guide_sigma_m = 1.0;
  double sst_selection_radius = 0.5;
  double sst_pruning_radius = 0.1;
  int seed = 1;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("planner", planner, {"sst", "rrt", "kpiece"},
             "OMPL control planner: SST (asymptotically near-optimal), RRT, KPIECE1");
    v.Choice("objective", objective, {"length", "time"}, "what a motion costs before penalties");
    v.Param("time_budget_ms", time_budget_ms, "hard limit per call", Range::Of(1.0, 600000.0).Fixed());
    v.Param("max_iterations", max_iterations,
            "also stop after this many planner iterations (0: no limit; "
            "reproducible calls)",
            Range::Of(0, 100000000).Fixed());
    v.Param("stop_at_first_solution", stop_at_first_solution,
            "SST: return the first solution instead of "
            "improving it until the budget ends");
    v.Choice("directions", directions, {"both", "forward", "reverse"},
             "the directions a path may drive in (a local plan keeps its route stretch's)");
    v.Param("steer_fraction", steer_fraction,
            "plan with this share of the steering limit (the rest is the "
            "tracker's)",
            Range::Of(0.3, 1.0));
    v.Param("goal_tolerance_m", goal_tolerance_m, "goal reached within this distance", Range::Of(0.01, 5.0));
    v.Param("goal_heading_tolerance_deg", goal_heading_tolerance_deg, "and within this heading difference",
            Range::Of(0.5, 180.0));
    v.Param("goal_bias", goal_bias, "share of samples drawn at the goal", Range::Of(0.0, 1.0));
    v.Param("integration_step_s", integration_step_s, "Euler sub-step of the propagation",
            Range::Of(0.001, 0.2).Log().Fixed());
    v.Param("control_step_s", control_step_s, "propagation step: states are checked this often (v_max · this apart)",
            Range::Of(0.01, 1.0).Log());
    v.Param("min_control_steps", min_control_steps, "shortest control duration, in steps", Range::Of(1, 100));
    v.Param("max_control_steps", max_control_steps, "longest control duration, in steps", Range::Of(1, 1000));
    v.Param("reverse_penalty", reverse_penalty, "cost factor on reversing", Range::Of(1.0, 100.0));
    v.Param("gear_change_penalty", gear_change_penalty, "cost of a change of direction (m or s)",
            Range::Of(0.0, 1000.0));
    v.Param("clearance_weight", clearance_weight, "cost per metre driven with no clearance", Range::Of(0.0, 100.0));
    v.Param("clearance_target_m", clearance_target_m, "clearance beyond which a motion costs nothing extra",
            Range::Of(0.01, 10.0));
    v.Param("guide_bias", guide_bias, "share of samples drawn near the guide path (when one is given)",
            Range::Of(0.0, 1.0));
    v.Param("guide_sigma_m", guide_sigma_m, "spread of the samples around the guide path", Range::Of(0.01, 20.0).Log());
    v.Param("sst_selection_radius", sst_selection_radius, "SST: radius for picking the best nearby node",
            Range::Of(0.01, 10.0).Log());
    v.Param("sst_pruning_radius", sst_pruning_radius, "SST: witness radius for pruning dominated nodes",
            Range::Of(0.001, 5.0).Log());
    v.Param("seed", seed, "OMPL's random seed (set once per process)", Range::Of(1, 1000000000).Fixed());
  }
  std::vector<std::string> Relations() const;
};

// A moving obstacle as a disc with a constant velocity (a track's prediction).
struct MovingObstacle {
  double x = 0, y = 0;    // at plan time, m
  double vx = 0, vy = 0;  // m/s
  double radius_m = 0.3;
};

// Whether the car's discs at `pose` clear every obstacle where it is `t_s` after plan
// time (the planner's check of a state; 0: where they stand now).
bool ClearOfMovingObstacles(const DiscCover& discs, const Pose& pose, const std::vector<MovingObstacle>& obstacles,
                            double t_s = 0);

// How the car moves at the start: a replan from a moving car starts at its speed and
// steering angle (clamped to the planner's limits), not from rest.
struct StartMotion {
  double speed_mps = 0;  // signed
  double steer_rad = 0;
};

struct KinodynamicResult : PlanResult {
  bool approximate = false;     // the path ends short of the goal (found is then false)
  double goal_distance_m = 0;   // from the path's end to the goal
  double cost = 0;              // under the objective above
  double duration_s = 0;        // driving time of the path
  std::vector<double> times_s;  // per path point: when the car is there
  std::string planner;
};

class KinodynamicPlanner {
 public:
  KinodynamicPlanner(const KinodynamicOptions& options, const CarOptions& car, std::shared_ptr<const DistanceMap> map);
  ~KinodynamicPlanner();
  // Throws InputError when start or goal is outside the map or in collision.
  // `obstacles` are checked at the time the car would be there; `guide` (optional,
  // e.g. hybrid A*'s path) biases the sampling.
  KinodynamicResult Plan(const Pose& start, const Pose& goal, const std::vector<MovingObstacle>& obstacles = {},
                         const Path* guide = nullptr, const StartMotion& motion = {});
  // Restarts OMPL's seed sequence (process-wide) at `seed`: the calls that follow
  // draw the numbers they would after any other Reseed(seed).
  static void Reseed(unsigned seed);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace specht::plan
