// `specht plan <map> [--start x,y,deg] --goal x,y,deg|bay:NAME [--planner P] -o DIR`
// (pipeline/planning_run.h).
#include "commands.h"
#include "specht/pipeline/planning_run.h"

namespace specht::app {
namespace {

struct PlanArgs {
  CommonArgs common;
  pipeline::PlanningInputs in;
};

}  // namespace

void AddPlanCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* cmd =
      app.add_subcommand("plan", "plan a path for the car on a map (hybrid A* + smoothing, or OMPL SST/RRT/KPIECE1)");
  cmd->add_option("map", args->in.map, "ROS map YAML, MRPT .gridmap, or a scenario YAML")->required();
  cmd->add_option("--start", args->in.start, "x,y,heading_deg of the rear axle (default: a scenario's ego start)");
  cmd->add_option("--goal", args->in.goal, "x,y,heading_deg, or bay:NAME in a scenario")->required();
  cmd->add_option("--planner", args->in.planner, "hybrid_astar (then smoothing), or OMPL's sst, rrt, kpiece")
      ->check(CLI::IsMember({"hybrid_astar", "sst", "rrt", "kpiece"}))
      ->capture_default_str();
  cmd->add_flag("--guided", args->in.guided, "kinodynamic planners: sample around hybrid A*'s path (guide_bias)");
  AddCommonOptions(*cmd, args->common, "specht-out/plan");
  cmd->callback([args, &exit_code] {
    exit_code = pipeline::PlanOnMap(LoadParams(args->common), args->in, args->common.out_dir);
  });
}

}  // namespace specht::app
