// specht/plan/local_planner.h: the local planner over a receding horizon — the OMPL
// kinodynamic planner (kinodynamic.h) from the moving car to a pose on the global
// route (hybrid A*'s smoothed path) a horizon ahead, time-aware against the road
// users' predicted motion, the route's remainder spliced on behind.
//
// One call:
//   1. the car's projection on the route (never behind `from_index`);
//   2. the local goal: the route pose horizon_m ahead along it, or the stretch's end
//      when a cusp or the route's end comes first; a goal inside a road user's
//      footprint moves on along the route past it and a car length more, to come back
//      onto the route (up to twice the horizon). Where the
//      stretch left is shorter than min_horizon_m (the final manoeuvre into a bay,
//      a cusp), or it reverses and `reverse` is off, the call plans nothing: the
//      route is followed;
//   3. SST (or RRT, KPIECE1) from the car's pose, speed and steering angle to the
//      goal, in the stretch's direction only (a reversing stretch is planned in
//      reverse), guided by the route's stretch to it, against the moving obstacles
//      at the time the car would be there;
//   4. the path: the planned one, then the route from the first point past its end.
// Budget: max_iterations per call (reproducible); time_budget_ms is a hard limit that
// should not bind on a machine meeting the stack's real-time target. OMPL's seed is
// restarted at `seed` before every call, so a call's answer depends only on its input.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/plan/kinodynamic.h"

namespace specht::plan {

// Section "local_planner".
struct LocalPlannerOptions {
  bool enabled = true;
  bool reverse = false;
  double rate_hz = 2.0;
  double horizon_m = 12.0;
  double min_horizon_m = 4.0;
  std::string planner = "sst";
  int max_iterations = 6000;
  double time_budget_ms = 500;
  bool stop_at_first_solution = true;
  double goal_tolerance_m = 0.3;
  double goal_heading_tolerance_deg = 8.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("enabled", enabled,
            "drive on the OMPL local planner's paths over a receding horizon (off: on the global route alone)");
    v.Param("reverse", reverse,
            "plan reversing stretches too (off: they follow the route, hybrid A*'s smoothed path, which keeps "
            "its clearance better in reverse)");
    v.Param("rate_hz", rate_hz, "replanning rate while driving", Range::Of(0.1, 50.0));
    v.Param("horizon_m", horizon_m, "the local goal lies this far ahead along the route", Range::Of(1.0, 100.0));
    v.Param("min_horizon_m", min_horizon_m,
            "closer than this to a cusp or the route's end the route is followed (the final manoeuvre)",
            Range::Of(0.0, 100.0));
    v.Choice("planner", planner, {"sst", "rrt", "kpiece"}, "OMPL control planner of the local plans");
    v.Param("max_iterations", max_iterations, "planner iterations per call (the reproducible budget)",
            Range::Of(1, 10000000).Fixed());
    v.Param("time_budget_ms", time_budget_ms, "hard limit per call", Range::Of(1.0, 60000.0).Fixed());
    v.Param("stop_at_first_solution", stop_at_first_solution,
            "SST: take the first path to the local goal (a new one follows within 1/rate_hz)");
    v.Param("goal_tolerance_m", goal_tolerance_m, "the local path ends within this of the local goal",
            Range::Of(0.01, 5.0));
    v.Param("goal_heading_tolerance_deg", goal_heading_tolerance_deg, "…and within this heading", Range::Of(0.5, 90.0));
  }
  std::vector<std::string> Relations() const;
};

// One call's answer. `path` is followed when `found`; `skipped` says the route is
// followed by design (no local plan wanted there), `failure` why none was found.
struct LocalPlan {
  bool found = false;
  bool skipped = false;
  std::string failure;
  Path path;                // the local path, then the route's remainder
  size_t route_index = 0;   // the car's projection on the route (the next call's from_index)
  size_t local_points = 0;  // path.points[0, local_points) came from the local planner
  size_t route_resume = 0;  // the route's index where the spliced remainder starts
  double milliseconds = 0;
  long iterations = 0;
};

class LocalPlanner {
 public:
  // `kinodynamic`: the planner's model settings (steering share, control steps,
  // costs); the budget, the planner and the goal tolerance come from `options`.
  LocalPlanner(const LocalPlannerOptions& options, const KinodynamicOptions& kinodynamic, const CarOptions& car,
               std::shared_ptr<const DistanceMap> map);
  ~LocalPlanner();

  // A plan from `pose` (moving at `motion`) along `route`, whose points before
  // `from_index` are behind the car. `seed` restarts OMPL's sequence for this call.
  LocalPlan Plan(const Pose& pose, const StartMotion& motion, const Path& route, size_t from_index,
                 const std::vector<MovingObstacle>& obstacles, unsigned seed) const;

  const LocalPlannerOptions& options() const { return o_; }

 private:
  LocalPlannerOptions o_;
  CarOptions car_;
  std::shared_ptr<const DistanceMap> map_;
  std::unique_ptr<KinodynamicPlanner> forward_, reverse_;  // each drives its stretch's direction only
};

// The discs covering a road user's box (centre, heading, half length and width)
// grown by `margin_m`, moving with it: the obstacles a kinodynamic plan avoids.
std::vector<MovingObstacle> BoxDiscs(double x, double y, double yaw, double half_length, double half_width, double vx,
                                     double vy, double margin_m);

}  // namespace specht::plan
