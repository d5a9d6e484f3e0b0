#include "specht/pipeline/synthetic_tracking.h"

#include <chrono>
#include <cmath>
#include <map>

#include "specht/sim/simulator.h"

namespace specht::pipeline {

SyntheticRun RunSyntheticTracking(const sim::Scenario& scenario, uint64_t seed,
                                  const track::TrackerOptions& tracker_options,
                                  const sim::SyntheticDetectionOptions& detection, const std::string& prefix,
                                  const std::function<void(double)>& progress,
                                  const std::function<void(std::vector<types::Track>&, double t_s)>& on_tracks) {
  sim::Simulator sim(scenario, seed);
  sim::SyntheticDetector detector(detection, seed);
  track::Tracker tracker(tracker_options);
  SyntheticRun run;
  const long steps = std::lround(scenario.duration_s / sim::Simulator::kStepS);
  std::map<int, std::pair<double, int>> episode;  // agent → (last seen, episode)
  const auto ignore = [](Stamp, const mrpt::obs::CObservation::Ptr&) {};
  for (long k = 0; k < steps; ++k) {
    sim.Step(ignore);
    if (progress && (k + 1) % 100 == 0) progress(static_cast<double>(k + 1) / steps);
    if (!detector.Due(sim)) continue;
    const auto detections = detector.Detect(sim);
    const auto t0 = std::chrono::steady_clock::now();
    tracker.Update(detections, sim.stamp());
    run.tracker_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++run.frames;
    run.detections += static_cast<long>(detections.size());
    const double t = sim.time_s();
    for (const auto& a : detector.visible()) {
      auto [it, fresh] = episode.try_emplace(a.id, t, 1);
      if (!fresh && t - it->second.first > detection.truth_episode_gap_s) ++it->second.second;
      it->second.first = t;
      const std::string id = prefix + std::to_string(a.id) + "#" + std::to_string(it->second.second);
      run.truth.push_back({id, t, a.pose.x, a.pose.y, sim::Name(a.cls), "", false, {}});
    }
    for (const auto& a : detector.hidden())
      run.truth.push_back(
          {prefix + std::to_string(a.id) + "#hidden", t, a.pose.x, a.pose.y, sim::Name(a.cls), "", true, {}});
    std::vector<types::Track> tracks = tracker.Tracks();
    if (on_tracks) on_tracks(tracks, t);
    for (const auto& tr : tracks)
      run.tracks.push_back(
          {prefix + "t" + std::to_string(tr.id), t, tr.x_m, tr.y_m, tr.cls, "", false, tr.class_probabilities});
  }
  run.simulated_s = sim.time_s();
  return run;
}

void LabelTracksFromTruth(std::vector<io::ObjectSample>& tracks, const std::vector<io::ObjectSample>& truth,
                          const std::map<std::string, std::string>& truth_of_hypothesis) {
  std::map<std::string, std::string> class_of_truth;
  for (const auto& s : truth) class_of_truth[s.id] = s.cls;
  for (auto& s : tracks) {
    const auto it = truth_of_hypothesis.find(s.id);
    s.truth_cls = it == truth_of_hypothesis.end() ? "none" : class_of_truth[it->second];
  }
}

}  // namespace specht::pipeline
