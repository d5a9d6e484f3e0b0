// `specht track <scenario.yaml>... [--seeds A-B] [--model DIR] -o DIR`: multi-object
// tracking on simulated scenes, scored with CLEAR MOT (pipeline/tracking_evaluation.h).
#include "commands.h"
#include "specht/pipeline/tracking_evaluation.h"

namespace specht::app {
namespace {

struct TrackArgs {
  CommonArgs common;
  std::vector<std::string> scenarios;
  std::string seeds;
  pipeline::TrackingEvaluationInputs inputs;
};

int RunTrack(TrackArgs& a) {
  const params::Params params = LoadParams(a.common);
  a.inputs.scenarios = a.scenarios;
  if (!a.seeds.empty()) a.inputs.seeds.assign(a.scenarios.size(), ParseSeedRange(a.seeds, 0));
  pipeline::TrackingEvaluation evaluation(params, a.inputs);
  PrepareOutputDir(a.common, params);
  return evaluation.Run(a.common.out_dir, a.common.quiet);
}

}  // namespace

void AddTrackCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<TrackArgs>();
  CLI::App* cmd = app.add_subcommand("track", "multi-object tracking on simulated scenes, scored with CLEAR MOT");
  cmd->add_option("scenarios", args->scenarios, "scenario files (datasets/scenarios/*.yaml)")->required();
  cmd->add_option("--seeds", args->seeds, "seed N or range A-B (default: each scenario's own seed)");
  cmd->add_option("--model", args->inputs.model_dir,
                  "classify confirmed tracks online with this classify-train output");
  cmd->add_flag("--network-only", args->inputs.network_only,
                "with --model: the network alone (default: combined with the model's forest.yml)");
  cmd->add_option("--match-threshold", args->inputs.match_threshold_m, "CLEAR MOT match distance (m)")
      ->capture_default_str();
  AddCommonOptions(*cmd, args->common, "specht-out/track");
  cmd->callback([args, &exit_code] { exit_code = RunTrack(*args); });
}

}  // namespace specht::app
