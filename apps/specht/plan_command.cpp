// `specht plan <map> [--start x,y,deg] --goal x,y,deg|bay:NAME -o DIR`: the global
// planner alone (hybrid A*, then the Ceres smoother) on a map: a ROS map_server
// YAML, an MRPT .gridmap, or a simulator scenario (its true static grid at 0.1 m;
// the start defaults to its ego's, the car is its ego's, and `bay:NAME` parks in a
// marked bay: the car's footprint centred on the bay, nose along the bay's
// heading). Writes
//   path.csv      x_m,y_m,theta_rad,direction (rear-axle centre, +1 forward)
//   plan.png      the map, the path by direction, footprints along it
//   report.json   found, length, gear changes, clearance, curvature, timings
#include <cmath>
#include <cstdio>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "run_setup.h"
#include "specht/core/error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/plan/draw.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/smoother.h"
#include "specht/sim/world.h"

namespace specht::app {
namespace {

struct PlanArgs {
  CommonArgs common;
  std::string map, start, goal;
};

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

plan::Pose ParsePose(const std::string& text, const char* what) {
  double x = 0, y = 0, deg = 0;
  char c1 = 0, c2 = 0, rest = 0;
  if (std::sscanf(text.c_str(), "%lf%c%lf%c%lf%c", &x, &c1, &y, &c2, &deg, &rest) != 5 || c1 != ',' || c2 != ',')
    throw InputError(std::string("--") + what + ": \"" + text + "\" is not x,y,heading_deg");
  return {x, y, deg * M_PI / 180.0};
}

int RunPlan(const PlanArgs& a) {
  const params::Params params = LoadParams(a.common);
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
  if (scenario) {  // plan for the scenario's own car
    const sim::VehicleModel& v = scenario->ego.model;
    car.wheelbase_m = v.wheelbase_m, car.max_steer_deg = v.max_steer_rad * 180 / M_PI;
    car.length_m = v.length_m, car.width_m = v.width_m;
    car.max_speed_mps = v.max_speed_mps, car.max_accel_mps2 = v.max_accel_mps2;
  }
  plan::Pose start;
  if (!a.start.empty()) start = ParsePose(a.start, "start");
  else if (scenario) start = {scenario->ego.start.x, scenario->ego.start.y, scenario->ego.start.yaw_rad};
  else throw InputError("--start is needed with a map (only a scenario has a default start)");
  plan::Pose goal;
  if (a.goal.rfind("bay:", 0) == 0) {
    if (!scenario) throw InputError("--goal bay:NAME needs a scenario as the map");
    const std::string name = a.goal.substr(4);
    const auto bay = std::find_if(scenario->bays.begin(), scenario->bays.end(), [&](auto& b) { return b.name == name; });
    if (bay == scenario->bays.end()) throw InputError("--goal: the scenario has no bay \"" + name + "\"");
    const double back = car.length_m / 2 - car.rear_overhang_m;  // footprint centre ahead of the rear axle
    goal = {bay->pose.x - back * std::cos(bay->pose.yaw_rad), bay->pose.y - back * std::sin(bay->pose.yaw_rad),
            bay->pose.yaw_rad};
  } else {
    goal = ParsePose(a.goal, "goal");
  }

  PrepareOutputDir(a.common, params);
  const std::string& out = a.common.out_dir;
  plan::HybridAStar search(search_options, car, map);
  const plan::PlanResult found = search.Plan(start, goal);
  io::RunReport report("plan");
  auto& j = report.json();
  j["inputs"] = {{"map", a.map},
                 {"start", {start.x, start.y, start.theta * 180 / M_PI}},
                 {"goal", {goal.x, goal.y, goal.theta * 180 / M_PI}}};
  j["timing"] = {{"heuristic_ms", found.heuristic_milliseconds}, {"search_ms", found.milliseconds}};
  plan::Path path = found.path;
  if (found.found) {
    const plan::SmoothResult smooth = plan::SmoothPath(found.path, *map, car, smoother);
    path = smooth.path;
    double clearance = INFINITY;
    for (const auto& p : path.points) clearance = std::min(clearance, map->Clearance(car, p.pose));
    j["metrics"] = {{"found", true},
                    {"length_m", path.Length()},
                    {"gear_changes", path.GearChanges()},
                    {"min_clearance_m", clearance},
                    {"max_curvature_per_m", path.MaxCurvature()},
                    {"curvature_limit_per_m", 1.0 / car.MinTurningRadius()},
                    {"expansions", found.expansions},
                    {"smoothed", smooth.accepted},
                    {"smoothing_note", smooth.note}};
    j["timing"]["smoothing_ms"] = smooth.milliseconds;
    j["timing"]["total_ms"] = found.milliseconds + smooth.milliseconds;
    io::WriteTextAtomically(out + "/path.csv", path.ToCsv());
    report.AddOutput("path.csv");
  } else {
    j["metrics"] = {{"found", false}, {"failure", found.failure}, {"expansions", found.expansions}};
  }
  io::WritePng(plan::DrawPlan(*map, car, path, start, goal), out + "/plan.png");
  report.AddOutput("plan.png");
  report.Write(out);
  if (!found.found) {
    std::printf("plan: no path (%s) after %ld expansions, %.1f ms\n", found.failure.c_str(), found.expansions,
                found.milliseconds);
    return 1;
  }
  std::printf("plan: %.1f m, %d gear changes, clearance %.2f m, %ld expansions; search %.1f ms (+ heuristic %.1f), "
              "smoothing %.1f ms%s\n",
              path.Length(), path.GearChanges(), j["metrics"]["min_clearance_m"].get<double>(), found.expansions,
              found.milliseconds, found.heuristic_milliseconds, j["timing"]["smoothing_ms"].get<double>(),
              j["metrics"]["smoothed"].get<bool>() ? "" : (" (not smoothed: " + j["metrics"]["smoothing_note"].get<std::string>() + ")").c_str());
  return 0;
}

}  // namespace

void AddPlanCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* cmd = app.add_subcommand("plan", "plan a path for the car on a map (hybrid A* + smoothing)");
  cmd->add_option("map", args->map, "ROS map YAML, MRPT .gridmap, or a scenario YAML")->required();
  cmd->add_option("--start", args->start, "x,y,heading_deg of the rear axle (default: a scenario's ego start)");
  cmd->add_option("--goal", args->goal, "x,y,heading_deg, or bay:NAME in a scenario")->required();
  AddCommonOptions(*cmd, args->common, "specht-out/plan");
  cmd->callback([args, &exit_code] { exit_code = RunPlan(*args); });
}

}  // namespace specht::app
