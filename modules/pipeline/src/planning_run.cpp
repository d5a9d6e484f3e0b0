// A planner alone (planning_run.h) on a map — hybrid A* then the Ceres smoother (default), or the
// kinodynamic planner (OMPL SST, RRT or KPIECE1; section "kinodynamic", its path
// as planned). The map is a ROS map_server
// YAML, an MRPT .gridmap, or a simulator scenario (its true static grid at 0.1 m;
// the start defaults to its ego's, the car is its ego's, and `bay:NAME` parks in a
// marked bay: the car's footprint centred on the bay, nose along the bay's
// heading). Writes
//   path.csv      x_m,y_m,theta_rad,direction (rear-axle centre, +1 forward)
//   plan.png      the map, the path by direction, footprints along it
//   report.json   found, length, gear changes, clearance, curvature, timings
#include "specht/pipeline/planning_run.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "specht/core/error.h"
#include "specht/decide/mission.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/pipeline/run_directory.h"
#include "specht/plan/draw.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/kinodynamic.h"
#include "specht/plan/smoother.h"
#include "specht/sim/world.h"

namespace specht::pipeline {
namespace {

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string Fixed(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

plan::Pose ParsePose(const std::string& text, const char* what) {
  double x = 0, y = 0, deg = 0;
  char c1 = 0, c2 = 0, rest = 0;
  if (std::sscanf(text.c_str(), "%lf%c%lf%c%lf%c", &x, &c1, &y, &c2, &deg, &rest) != 5 || c1 != ',' || c2 != ',')
    throw InputError(std::string("--") + what + ": \"" + text + "\" is not x,y,heading_deg");
  return {x, y, deg * M_PI / 180.0};
}

}  // namespace

int PlanOnMap(const params::Params& params, const PlanningInputs& a, const std::string& out) {
  plan::CarOptions car = params.Get<plan::CarOptions>("car");
  const auto& search_options = params.Get<plan::HybridAStarOptions>("hybrid_astar");
  const auto& smoother = params.Get<plan::SmootherOptions>("smoother");

  std::shared_ptr<plan::DistanceMap> map;
  std::optional<sim::Scenario> scenario;
  if (EndsWith(a.map, ".gridmap")) {
    map = std::make_shared<plan::DistanceMap>(plan::DistanceMap::FromGrid(io::ReadMrptGridmap(a.map)));
  } else {
    const std::string text = [&] {
      std::ifstream f(a.map);
      if (!f) throw InputError(a.map + ": cannot open");
      return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    if (text.find("image:") != std::string::npos) {
      map = std::make_shared<plan::DistanceMap>(plan::DistanceMap::FromGrid(io::ReadRosMap(a.map)));
    } else {
      scenario = sim::LoadScenario(a.map);
      map = std::make_shared<plan::DistanceMap>(plan::DistanceMap::FromGrid(sim::World(*scenario).TrueGrid(0.1)));
    }
  }
  if (scenario) car = pipeline::ScenarioCar(*scenario, car);  // plan for the scenario's own car
  plan::Pose start;
  if (!a.start.empty())
    start = ParsePose(a.start, "start");
  else if (scenario)
    start = pipeline::EgoRearAxle(*scenario, scenario->ego.start);
  else
    throw InputError("--start is needed with a map (only a scenario has a default start)");
  plan::Pose goal;
  if (a.goal.rfind("bay:", 0) == 0) {
    if (!scenario) throw InputError("--goal bay:NAME needs a scenario as the map");
    const std::string name = a.goal.substr(4);
    const std::vector<decide::Bay> bays = pipeline::MissionSiteOf(*scenario).bays;
    const auto bay = std::find_if(bays.begin(), bays.end(), [&](auto& b) { return b.name == name; });
    if (bay == bays.end()) throw InputError("--goal: the scenario has no bay \"" + name + "\"");
    goal = decide::BayPose(*bay, car);
  } else {
    goal = ParsePose(a.goal, "goal");
  }

  PrepareRunDirectory(out, params);
  io::RunReport report("plan");
  auto& j = report.json();
  j["inputs"] = {{"map", a.map},
                 {"planner", a.planner},
                 {"start", {start.x, start.y, start.theta * 180 / M_PI}},
                 {"goal", {goal.x, goal.y, goal.theta * 180 / M_PI}}};
  plan::PlanResult found;
  plan::Path path;
  std::string detail;  // the planner's own figures for the summary line
  if (a.planner == "hybrid_astar") {
    plan::SearchWithFallback search(search_options, params.Get<plan::HybridAStarOptions>("hybrid_astar_fine"), car,
                                    map);
    found = search.Plan(start, goal);
    j["timing"] = {{"heuristic_ms", found.heuristic_milliseconds}, {"search_ms", found.milliseconds}};
    j["metrics"] = {{"expansions", found.expansions}, {"fine_search", search.last_used_fine()}};
    path = found.path;
    if (found.found) {
      const plan::SmoothResult smooth = plan::SmoothPath(found.path, *map, car, smoother);
      path = smooth.path;
      j["metrics"]["smoothed"] = smooth.accepted;
      j["metrics"]["smoothing_note"] = smooth.note;
      j["timing"]["smoothing_ms"] = smooth.milliseconds;
      j["timing"]["total_ms"] = found.milliseconds + smooth.milliseconds;
      detail = std::to_string(found.expansions) + " expansions" + (search.last_used_fine() ? " (fine search)" : "") +
               "; search " + Fixed(found.milliseconds) + " ms (+ heuristic " + Fixed(found.heuristic_milliseconds) +
               "), smoothing " + Fixed(smooth.milliseconds) + " ms" +
               (smooth.accepted ? "" : " (not smoothed: " + smooth.note + ")");
    }
  } else {
    plan::KinodynamicOptions options = params.Get<plan::KinodynamicOptions>("kinodynamic");
    options.planner = a.planner;
    plan::KinodynamicPlanner planner(options, car, map);
    plan::PlanResult guide;
    if (a.guided) guide = plan::HybridAStar(search_options, car, map).Plan(start, goal);
    const plan::KinodynamicResult k = planner.Plan(start, goal, {}, guide.found ? &guide.path : nullptr);
    found = k;
    path = k.path;
    j["timing"] = {{"total_ms", k.milliseconds}, {"budget_ms", options.time_budget_ms}};
    if (a.guided) j["timing"]["guide_ms"] = guide.milliseconds + guide.heuristic_milliseconds;
    j["metrics"] = {{"iterations", k.expansions},
                    {"approximate", k.approximate},
                    {"goal_distance_m", k.goal_distance_m},
                    {"cost", k.cost},
                    {"duration_s", k.duration_s}};
    detail = std::to_string(k.expansions) + " iterations of " + options.planner + " in " + Fixed(k.milliseconds) +
             " ms (budget " + Fixed(options.time_budget_ms) + "), driving time " + Fixed(k.duration_s) + " s" +
             (!a.guided     ? ""
              : guide.found ? ", guided by hybrid A* (" + Fixed(guide.milliseconds) + " ms)"
                            : ", unguided (hybrid A*: " + guide.failure + ")");
  }
  j["metrics"]["found"] = found.found;
  if (found.found) {
    double clearance = INFINITY;
    for (const auto& p : path.points) clearance = std::min(clearance, map->Clearance(car, p.pose));
    j["metrics"]["length_m"] = path.Length();
    j["metrics"]["gear_changes"] = path.GearChanges();
    j["metrics"]["min_clearance_m"] = clearance;
    j["metrics"]["max_curvature_per_m"] = path.MaxCurvature();
    j["metrics"]["curvature_limit_per_m"] = 1.0 / car.MinTurningRadius();
    io::WriteTextAtomically(out + "/path.csv", path.ToCsv());
    report.AddOutput("path.csv");
  } else {
    j["metrics"]["failure"] = found.failure;
  }
  io::WritePng(plan::DrawPlan(*map, car, path, start, goal), out + "/plan.png");
  report.AddOutput("plan.png");
  report.Write(out);
  if (!found.found) {
    std::printf("plan: no path (%s) after %ld %s, %.1f ms\n", found.failure.c_str(), found.expansions,
                a.planner == "hybrid_astar" ? "expansions" : "iterations", found.milliseconds);
    return 1;
  }
  std::printf("plan: %.1f m, %d gear changes, clearance %.2f m; %s\n", path.Length(), path.GearChanges(),
              j["metrics"]["min_clearance_m"].get<double>(), detail.c_str());
  return 0;
}

}  // namespace specht::pipeline
