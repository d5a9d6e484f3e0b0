#include "specht/pipeline/tracking_evaluation.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>

#include "internal/perception_video.h"
#include "specht/classify/metrics.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/eval/mot.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/pipeline/map_features.h"
#include "specht/pipeline/online_classifier.h"
#include "specht/pipeline/synthetic_tracking.h"
#include "specht/sim/world.h"

namespace specht::pipeline {
namespace {

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

void WriteTracksPng(const sim::Scenario& scenario, const SyntheticRun& run, const std::string& path) {
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
    overlays.push_back({&t, internal::ClassColour(cls), labelled[cls] ? "" : "tracks: " + cls});
    labelled[cls] = true;
  }
  const sim::World world(scenario);
  io::WriteMapPng(world.TrueGrid(0.1), overlays, path);
}

}  // namespace

TrackingEvaluation::TrackingEvaluation(const params::Params& params, TrackingEvaluationInputs inputs)
    : in_(std::move(inputs)),
      tracker_(params.Get<track::TrackerOptions>("track")),
      detection_(params.Get<sim::SyntheticDetectionOptions>("synthetic_detections")) {
  for (size_t i = 0; i < in_.scenarios.size(); ++i) {
    scenarios_.push_back(sim::LoadScenario(in_.scenarios[i]));
    seeds_.push_back(i < in_.seeds.size() ? in_.seeds[i] : std::pair{scenarios_.back().seed, scenarios_.back().seed});
  }
  if (!in_.model_dir.empty())
    classifier_ = std::make_shared<classify::TrajectoryClassifier>(
        classify::TrajectoryClassifier::LoadDirectory(in_.model_dir, in_.network_only));
}

int TrackingEvaluation::Run(const std::string& out, bool quiet) {
  // Per labelled track-frame the classifier_ saw: truth, classifier_, tracker vote.
  std::vector<int> online_truth, online_predicted, online_vote;
  double online_s = 0;
  long online_classified = 0;

  double total_s = 0;
  for (size_t i = 0; i < scenarios_.size(); ++i)
    total_s += scenarios_[i].duration_s * static_cast<double>(seeds_[i].second - seeds_[i].first + 1);
  io::RunReport report("track");
  ProgressLine progress("track", "s simulated", !quiet);
  std::vector<io::ObjectSample> all_truth, all_tracks;
  eval::MotResult total;
  double done_s = 0, tracker_s = 0;
  long frames = 0;
  nlohmann::json runs = nlohmann::json::array();
  for (size_t i = 0; i < scenarios_.size() && !InterruptRequested(); ++i) {
    const classify::MapFeatures map = classifier_ ? ScenarioMapFeatures(scenarios_[i]) : classify::MapFeatures{};
    for (uint64_t seed = seeds_[i].first; seed <= seeds_[i].second && !InterruptRequested(); ++seed) {
      const std::string prefix = "s" + std::to_string(seed) + "/" + scenarios_[i].name + "/";
      std::optional<OnlineClassifier> online_classifier;
      if (classifier_) online_classifier.emplace(classifier_, OnlineClassifier::Averaging::kLatest);
      OnlineClasses online;
      SyntheticRun run = RunSyntheticTracking(
          scenarios_[i], seed, tracker_, detection_, prefix,
          [&](double f) {
            progress.Update(done_s + f * scenarios_[i].duration_s, (done_s + f * scenarios_[i].duration_s) / total_s);
          },
          [&](std::vector<types::Track>& tracks, double t_s) {
            if (!online_classifier) return;
            online_classifier->Update(tracks, map);
            RecordOnlineClasses(tracks, prefix, t_s, online);
          });
      done_s += scenarios_[i].duration_s;
      const eval::MotResult mot = eval::EvaluateMot(run.truth, run.tracks, in_.match_threshold_m);
      LabelTracksFromTruth(run.tracks, run.truth, mot.truth_of_hypothesis);
      if (classifier_) {
        const auto& classes = classifier_->classes();
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
      if (all_truth.empty()) WriteTracksPng(scenarios_[i], run, out + "/tracks.png");
      nlohmann::json j = mot.ToJson();
      j["scenario"] = scenarios_[i].name;
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
  j["metrics"]["match_threshold_m"] = in_.match_threshold_m;
  j["runs"] = runs;
  j["timing"] = {{"frames", frames}, {"tracker_ms_per_frame", frames ? 1000.0 * tracker_s / frames : 0.0}};
  if (classifier_) {
    const int k = static_cast<int>(classifier_->classes().size());
    const auto by_classifier = classify::Score(online_truth, online_predicted, k);
    const auto by_vote = classify::Score(online_truth, online_vote, k);
    j["online_classification"] = {
        {"model", in_.model_dir},
        {"combination", classifier_->combination()},
        {"track_frames", online_truth.size()},
        {"classifier", by_classifier.ToJson(classifier_->classes())},
        {"tracker_vote", by_vote.ToJson(classifier_->classes())},
        {"classifier_ms_per_window", online_classified ? 1000.0 * online_s / online_classified : 0.0},
        {"classifier_ms_per_frame", frames ? 1000.0 * online_s / frames : 0.0}};
    std::printf(
        "track: online classifier on %zu labelled track-frames: macro F1 %.3f (tracker's detection vote "
        "%.3f), %.2f ms per frame\n",
        online_truth.size(), by_classifier.macro_f1, by_vote.macro_f1, frames ? 1000.0 * online_s / frames : 0.0);
  }
  for (const char* f : {"truth.csv", "tracks.csv", "tracks.png"}) report.AddOutput(f);
  if (InterruptRequested()) report.SetInterrupted(std::to_string(runs.size()) + " runs");
  report.Write(out);
  progress.Finish();
  std::printf(
      "track: %zu runs, %.0f track-seconds: MOTA %.3f, MOTP %.3f m, ID switches %ld (%.2f per 100 s), "
      "FP %ld, FN %ld; tracker %.3f ms per frame\n",
      runs.size(), total.track_seconds, total.mota, total.motp_m, total.id_switches, total.id_switches_per_100s,
      total.false_positives, total.false_negatives, frames ? 1000.0 * tracker_s / frames : 0.0);
  return InterruptExitCode();
}

}  // namespace specht::pipeline
