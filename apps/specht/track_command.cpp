// `specht track <scenario.yaml>... [--seeds A-B] -o DIR`: multi-object tracking on
// simulated scenes. Each scenario runs once per seed; its agents are detected with
// noise, misses, false alarms and class errors (section "synthetic_detections") and
// tracked (section "track"); the result is scored with CLEAR MOT against the agents
// that were visible. Writes
//   truth.csv     the visible agents per detection frame (io/object_tracks.h)
//   tracks.csv    the tracker's confirmed and coasting tracks per frame, with the
//                 class of the agent each track followed most (truth_class): the
//                 input of `specht classify prepare`
//   tracks.png    the first run: static world, agent paths (grey), tracks by class
//   report.json   CLEAR MOT per run and over all runs, tracker time per frame
// With --model DIR (a `specht classify train` output) the trajectory classifier runs
// online: after every tracker update, on each confirmed track's latest window, with
// the scene's map features (the network combined with the model's forest unless
// --network-only); its probabilities go into the track's
// class_probabilities, and report.json scores its class per track-frame against the
// class of the agent the track followed, next to the tracker's own detection vote.
#include <cstdio>
#include <map>
#include <optional>

#include "commands.h"
#include "run_setup.h"
#include "specht/pipeline/map_features.h"
#include "specht/classify/metrics.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/progress.h"
#include "specht/eval/mot.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/sim/world.h"
#include "specht/pipeline/online_classifier.h"
#include "specht/pipeline/synthetic_tracking.h"

namespace specht::app {
namespace {

struct TrackArgs {
  CommonArgs common;
  std::vector<std::string> scenarios;
  std::string seeds;
  std::string model_dir;
  bool network_only = false;
  double match_threshold_m = 1.0;
};

// The online classifier's class per (track sample id, time) of one run: the most
// probable class of the track's latest window.
using OnlineClasses = std::map<std::pair<std::string, double>, std::string>;

void RecordOnlineClasses(const std::vector<types::Track>& tracks, const std::string& prefix, double t_s,
                         OnlineClasses& out) {
  for (const auto& t : tracks) {
    if (t.state != "confirmed" || t.class_probabilities.empty()) continue;
    const auto best = std::max_element(t.class_probabilities.begin(), t.class_probabilities.end(),
                                       [](auto& a, auto& b) { return a.second < b.second; });
    out[{prefix + "t" + std::to_string(t.id), t_s}] = best->first;
  }
}

std::array<unsigned char, 3> ClassColour(const std::string& cls) {
  if (cls == "pedestrian") return {220, 40, 40};
  if (cls == "cyclist") return {230, 150, 0};
  if (cls == "car") return {30, 90, 220};
  return {120, 0, 160};
}

void WriteTracksPng(const sim::Scenario& scenario, const pipeline::SyntheticRun& run, const std::string& path) {
  std::map<std::string, Trajectory> truth, tracks;
  std::map<std::string, std::string> track_class;
  auto add = [](Trajectory& t, const io::ObjectSample& s) {
    t.push_back({Stamp::FromSeconds(s.t_s), mrpt::poses::CPose3D(s.x_m, s.y_m, 0, 0, 0, 0)});
  };
  for (const auto& s : run.truth) add(truth[s.id], s);
  for (const auto& s : run.tracks) add(tracks[s.id], s), track_class[s.id] = s.cls;
  std::vector<io::PathOverlay> overlays;
  bool first = true;
  for (const auto& [id, t] : truth) {
    overlays.push_back({&t, {170, 170, 170}, first ? "agents (truth, visible part)" : ""});
    first = false;
  }
  std::map<std::string, bool> labelled;
  for (const auto& [id, t] : tracks) {
    const std::string& cls = track_class[id];
    overlays.push_back({&t, ClassColour(cls), labelled[cls] ? "" : "tracks: " + cls});
    labelled[cls] = true;
  }
  const sim::World world(scenario);
  io::WriteMapPng(world.TrueGrid(0.1), overlays, path);
}

int RunTrack(const TrackArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& tracker = params.Get<track::TrackerOptions>("track");
  const auto& detection = params.Get<sim::SyntheticDetectionOptions>("synthetic_detections");
  std::vector<sim::Scenario> scenarios;
  for (const auto& path : a.scenarios) scenarios.push_back(sim::LoadScenario(path));
  std::vector<std::pair<uint64_t, uint64_t>> seeds;
  for (const auto& s : scenarios) seeds.push_back(ParseSeedRange(a.seeds, s.seed));
  std::shared_ptr<const classify::TrajectoryClassifier> classifier;
  if (!a.model_dir.empty())
    classifier = std::make_shared<classify::TrajectoryClassifier>(
        classify::TrajectoryClassifier::LoadDirectory(a.model_dir, a.network_only));
  const auto latest = pipeline::OnlineClassifier::Averaging::kLatest;
  PrepareOutputDir(a.common, params);
  const std::string& out = a.common.out_dir;
  // Per labelled track-frame the classifier saw: truth, classifier, tracker vote.
  std::vector<int> online_truth, online_predicted, online_vote;
  double online_s = 0;
  long online_classified = 0;

  double total_s = 0;
  for (size_t i = 0; i < scenarios.size(); ++i)
    total_s += scenarios[i].duration_s * static_cast<double>(seeds[i].second - seeds[i].first + 1);
  io::RunReport report("track");
  ProgressLine progress("track", "s simulated", !a.common.quiet);
  std::vector<io::ObjectSample> all_truth, all_tracks;
  eval::MotResult total;
  double done_s = 0, tracker_s = 0;
  long frames = 0;
  nlohmann::json runs = nlohmann::json::array();
  for (size_t i = 0; i < scenarios.size(); ++i) {
    for (uint64_t seed = seeds[i].first; seed <= seeds[i].second; ++seed) {
      const std::string prefix = "s" + std::to_string(seed) + "/" + scenarios[i].name + "/";
      const classify::MapFeatures map = classifier ? pipeline::ScenarioMapFeatures(scenarios[i]) : classify::MapFeatures{};
      std::optional<pipeline::OnlineClassifier> online_classifier;
      if (classifier) online_classifier.emplace(classifier, latest);
      OnlineClasses online;
      pipeline::SyntheticRun run = pipeline::RunSyntheticTracking(
          scenarios[i], seed, tracker, detection, prefix,
          [&](double f) {
            progress.Update(done_s + f * scenarios[i].duration_s, (done_s + f * scenarios[i].duration_s) / total_s);
          },
          [&](std::vector<types::Track>& tracks, double t_s) {
            if (!online_classifier) return;
            online_classifier->Update(tracks, map);
            RecordOnlineClasses(tracks, prefix, t_s, online);
          });
      done_s += scenarios[i].duration_s;
      const eval::MotResult mot = eval::EvaluateMot(run.truth, run.tracks, a.match_threshold_m);
      pipeline::LabelTracksFromTruth(run.tracks, run.truth, mot.truth_of_hypothesis);
      if (classifier) {
        const auto& classes = classifier->classes();
        const auto index = [&](const std::string& c) {
          return static_cast<int>(std::find(classes.begin(), classes.end(), c) - classes.begin());
        };
        for (const auto& sample : run.tracks) {
          const auto it = online.find({sample.id, sample.t_s});
          if (it == online.end() || index(sample.truth_cls) == static_cast<int>(classes.size())) continue;
          online_truth.push_back(index(sample.truth_cls));
          online_predicted.push_back(index(it->second));
          online_vote.push_back(index(sample.cls));
        }
        online_s += online_classifier->seconds();
        online_classified += online_classifier->windows();
      }
      if (all_truth.empty()) WriteTracksPng(scenarios[i], run, out + "/tracks.png");
      nlohmann::json j = mot.ToJson();
      j["scenario"] = scenarios[i].name;
      j["seed"] = seed;
      runs.push_back(j);
      total.Add(mot);
      tracker_s += run.tracker_seconds;
      frames += run.frames;
      all_truth.insert(all_truth.end(), run.truth.begin(), run.truth.end());
      all_tracks.insert(all_tracks.end(), run.tracks.begin(), run.tracks.end());
    }
  }
  io::WriteObjectTracks(all_truth, out + "/truth.csv");
  io::WriteObjectTracks(all_tracks, out + "/tracks.csv");
  auto& j = report.json();
  j["metrics"] = total.ToJson();
  j["metrics"]["match_threshold_m"] = a.match_threshold_m;
  j["runs"] = runs;
  j["timing"] = {{"frames", frames}, {"tracker_ms_per_frame", frames ? 1000.0 * tracker_s / frames : 0.0}};
  if (classifier) {
    const int k = static_cast<int>(classifier->classes().size());
    const auto by_classifier = classify::Score(online_truth, online_predicted, k);
    const auto by_vote = classify::Score(online_truth, online_vote, k);
    j["online_classification"] = {
        {"model", a.model_dir},
        {"combination", classifier->combination()},
        {"track_frames", online_truth.size()},
        {"classifier", by_classifier.ToJson(classifier->classes())},
        {"tracker_vote", by_vote.ToJson(classifier->classes())},
        {"classifier_ms_per_window", online_classified ? 1000.0 * online_s / online_classified : 0.0},
        {"classifier_ms_per_frame", frames ? 1000.0 * online_s / frames : 0.0}};
    std::printf("track: online classifier on %zu labelled track-frames: macro F1 %.3f (tracker's detection vote "
                "%.3f), %.2f ms per frame\n",
                online_truth.size(), by_classifier.macro_f1, by_vote.macro_f1, frames ? 1000.0 * online_s / frames : 0.0);
  }
  for (const char* f : {"truth.csv", "tracks.csv", "tracks.png"}) report.AddOutput(f);
  report.Write(out);
  progress.Finish();
  std::printf("track: %zu runs, %.0f track-seconds: MOTA %.3f, MOTP %.3f m, ID switches %ld (%.2f per 100 s), "
              "FP %ld, FN %ld; tracker %.3f ms per frame\n",
              runs.size(), total.track_seconds, total.mota, total.motp_m, total.id_switches,
              total.id_switches_per_100s, total.false_positives, total.false_negatives,
              frames ? 1000.0 * tracker_s / frames : 0.0);
  return 0;
}

}  // namespace

void AddTrackCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<TrackArgs>();
  CLI::App* cmd = app.add_subcommand("track", "multi-object tracking on simulated scenes, scored with CLEAR MOT");
  cmd->add_option("scenarios", args->scenarios, "scenario files (datasets/scenarios/*.yaml)")->required();
  cmd->add_option("--seeds", args->seeds, "seed N or range A-B (default: each scenario's own seed)");
  cmd->add_option("--model", args->model_dir, "classify confirmed tracks online with this classify-train output");
  cmd->add_flag("--network-only", args->network_only,
                "with --model: the network alone (default: combined with the model's forest.yml)");
  cmd->add_option("--match-threshold", args->match_threshold_m, "CLEAR MOT match distance (m)")->capture_default_str();
  AddCommonOptions(*cmd, args->common, "specht-out/track");
  cmd->callback([args, &exit_code] { exit_code = RunTrack(*args); });
}

}  // namespace specht::app
