// `specht run <scenario.yaml> [--mission M.yaml] [--seeds A-B] [--stack full|truth] [--map DIR] [--nodes
// [--perception-node] [--domain N]] -o DIR`: the closed loop (pipeline/mission_runs.h).
#include "commands.h"
#include "specht/pipeline/mission_runs.h"

namespace specht::app {
namespace {

struct RunArgs {
  CommonArgs common;
  pipeline::MissionRunInputs in;
  std::string seeds;
  std::string stack = "full";
  std::optional<int> domain;
};

}  // namespace

void AddRunCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "drive a scenario's mission in closed loop (plan, track, decide)");
  cmd->add_option("scenario", args->in.scenario, "scenario file (datasets/scenarios/*.yaml)")->required();
  cmd->add_option("--mission", args->in.mission,
                  "mission file (goals: waypoints, park: BAY); default: park in the first bay");
  cmd->add_option("--seeds", args->seeds, "seed N or range A-B (default: the scenario's seed)");
  cmd->add_option("--stack", args->stack,
                  "full: SLAM localisation and tracks from noisy detections (closed_loop.localization slam, "
                  "perception detections); truth: the simulator's pose and agents, the oracle to compare with "
                  "(--set overrides either)")
      ->check(CLI::IsMember({"full", "truth"}))
      ->capture_default_str();
  cmd->add_option("--map", args->in.map_dir,
                  "localise on the map a mapping drive of this scenario left (its map-<seed>/ folder) and plan on "
                  "its grid, instead of mapping from scratch (closed_loop.localization map; full stack only)");
  cmd->add_flag("--nodes", args->in.nodes,
                "run the stack as `specht node stack` in a process of its own, over DDS in lockstep with the "
                "simulated car (its console and report in stack-<seed>/); full stack only, no video");
  cmd->add_flag("--perception-node", args->in.perception_node,
                "with --nodes: the tracker runs as `specht node perception`, a third process the run restarts when "
                "it dies (its console and report in perception-<seed>/)");
  cmd->add_option("--domain", args->domain, "with --nodes: the DDS domain id (same as --set dds.domain=N)");
  AddCommonOptions(*cmd, args->common, "specht-out/run");
  cmd->callback([args, &exit_code] {
    if (!args->seeds.empty()) args->in.seeds = ParseSeedRange(args->seeds, 0);
    args->in.data_dir = DataDir(args->common);
    const bool full = args->stack == "full";
    if (!full && !args->in.map_dir.empty()) throw CLI::ValidationError("--map", "the truth stack reads no map");
    const std::string localization = !full ? "truth" : args->in.map_dir.empty() ? "slam" : "map";
    auto& o = args->common.overrides;
    if (args->domain) o.push_back("dds.domain=" + std::to_string(*args->domain));
    o.insert(o.begin(), {"closed_loop.localization=" + localization,
                         std::string("closed_loop.perception=") + (full ? "detections" : "truth")});
    exit_code = pipeline::RunMissions(LoadParams(args->common), args->in, args->common.out_dir, args->common.quiet);
  });
}

}  // namespace specht::app
