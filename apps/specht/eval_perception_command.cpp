// `specht eval perception SIM_DIR`: the detectors, our SGM and the box fusion on a
// simulated drive (a `specht sim` output with a camera), against the simulator's
// truth (pipeline/perception_eval.h): recall and precision per class and by range,
// false positives per frame, distance errors. Writes report.json/.md.
#include "commands.h"
#include "run_setup.h"
#include "specht/core/progress.h"
#include "specht/core/text.h"
#include "specht/io/report.h"
#include "specht/pipeline/perception_eval.h"

namespace specht::app {
namespace {

struct EvalPerceptionArgs {
  CommonArgs common;
  std::string sim_dir, replay_dir;
  pipeline::PerceptionEvalOptions options;
};

int RunEvalPerception(const EvalPerceptionArgs& a) {
  const params::Params params = LoadParams(a.common);
  const std::string data_dir = DataDir(a.common);
  PrepareOutputDir(a.common, params);
  ProgressLine progress("eval perception", "%", !a.common.quiet);
  const nlohmann::json result = pipeline::EvaluatePerception(a.sim_dir, params, data_dir, a.options,
                                                             [&](double f) { progress.Update(100 * f, f); });
  progress.Finish();
  io::RunReport report("eval perception");
  report.json()["inputs"] = {{"sim_dir", a.sim_dir}, {"replay_dir", a.replay_dir}, {"models", a.options.models}};
  report.json()["metrics"] = result;
  if (!a.replay_dir.empty()) {
    const nlohmann::json tracks = pipeline::EvaluatePerceivedTracks(a.sim_dir, a.replay_dir, a.options);
    report.json()["metrics"]["tracks"] = tracks;
    std::printf(
        "perceived tracks: MOTA %.3f, %.2f ID switches per 100 track-seconds, class macro F1 (detector vote) "
        "%.3f over %d tracks; SLAM ATE %.3f m\n",
        tracks["mot"]["mota"].get<double>(), tracks["mot"]["id_switches_per_100s"].get<double>(),
        tracks["class_detector_vote"]["macro_f1"].get<double>(), tracks["class_detector_vote"]["tracks"].get<int>(),
        tracks["slam_ate_rmse_m"].get<double>());
  }
  report.Write(a.common.out_dir);
  for (const auto& [model, m] : result["detection"].items())
    std::printf(
        "%s: recall %.3f, precision %.3f, %.3f false positives/frame over %ld frames; distance error p50 %.2f m\n",
        model.c_str(), m["all"]["recall"].get<double>(), m["all"]["precision"].get<double>(),
        m["false_positives_per_frame"].get<double>(), m["frames"].get<long>(),
        m["distance_abs_error_m"].value("p50", 0.0));
  return 0;
}

}  // namespace

void AddEvalPerceptionCommand(CLI::App& eval, int& exit_code) {
  auto args = std::make_shared<EvalPerceptionArgs>();
  CLI::App* cmd =
      eval.add_subcommand("perception", "detection recall and precision, fused distances on a simulated drive");
  cmd->add_option("sim_dir", args->sim_dir, "a `specht sim` output of a scenario with a camera")->required();
  AddCommonOptions(*cmd, args->common, "specht-out/eval-perception");
  cmd->add_option("--models", args->options.models, "shipped detectors to score (yolo-fastest, fastestdet)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--replay", args->replay_dir,
                  "a `specht replay` output of this drive: score its perceived tracks (CLEAR MOT, class F1)");
  cmd->add_option("--max-range", args->options.max_range_m, "tracks: agents farther than this are don't-care (m)")
      ->capture_default_str();
  cmd->add_option("--min-visible", args->options.min_visible, "an agent counts when this share of it shows")
      ->capture_default_str();
  cmd->add_option("--min-height", args->options.min_height_px, "…and its box is at least this tall (px)")
      ->capture_default_str();
  cmd->callback([args, &exit_code] { exit_code = RunEvalPerception(*args); });
}

}  // namespace specht::app
