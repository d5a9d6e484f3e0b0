// specht/pipeline/planning_run.h: a planner alone on a map — what `specht plan` runs.
// Hybrid A* then the Ceres smoother (default), or the kinodynamic planner (OMPL SST,
// RRT or KPIECE1; section "kinodynamic", its path as planned, optionally guided by
// hybrid A*'s). The map is a ROS map_server YAML, an MRPT .gridmap, or a simulator
// scenario (its true static grid at 0.1 m; the start defaults to its ego's, the car
// is its ego's, and "bay:NAME" parks in a marked bay). Writes path.csv
// (x_m,y_m,theta_rad,direction of the rear-axle centre), plan.png and a report
// (found, length, gear changes, clearance, curvature, timings).
#pragma once

#include <string>

#include "specht/core/params.h"

namespace specht::pipeline {

struct PlanningInputs {
  std::string map;                       // map YAML, .gridmap or scenario YAML
  std::string start;                     // "x,y,heading_deg" of the rear axle, or "" (a scenario's ego start)
  std::string goal;                      // "x,y,heading_deg", or "bay:NAME" in a scenario
  std::string planner = "hybrid_astar";  // or sst, rrt, kpiece
  bool guided = false;                   // kinodynamic planners: sample around hybrid A*'s path
};

// Exit code 0 when a path was found, 1 when not (the report says why).
int PlanOnMap(const params::Params& params, const PlanningInputs& in, const std::string& out_dir);

}  // namespace specht::pipeline
