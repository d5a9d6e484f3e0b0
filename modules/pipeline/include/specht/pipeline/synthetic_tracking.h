// specht/pipeline/synthetic_tracking.h: a simulated scene run through synthetic detections
// (sim/detections.h) and the tracker, with the truth recorded alongside —
// what `specht track`, the tracking tests and the classifier's robot dataset use.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "specht/io/object_tracks.h"
#include "specht/sim/detections.h"
#include "specht/sim/scenario.h"
#include "specht/track/tracker.h"

namespace specht::pipeline {

struct SyntheticRun {
  // One row per detection frame: the agents visible then (id "<prefix><agent
  // id>#<episode>", class = the agent's; the others as don't-care rows), and the tracker's confirmed and coasting
  // tracks (id
  // "<prefix>t<track id>", class = the track's).
  std::vector<io::ObjectSample> truth, tracks;
  long frames = 0, detections = 0;
  double simulated_s = 0;
  double tracker_seconds = 0;  // wall time inside Tracker::Update
};

// Simulates `scenario` with `seed` for its duration. `progress(fraction)` is called
// every simulated second when given; `on_tracks(tracks, now)` after every tracker
// update with the tracks the frame records and the simulated time, as in the
// samples (e.g. to classify them online).
SyntheticRun RunSyntheticTracking(
    const sim::Scenario& scenario, uint64_t seed, const track::TrackerOptions& tracker,
    const sim::SyntheticDetectionOptions& detection, const std::string& id_prefix,
    const std::function<void(double)>& progress = nullptr,
    const std::function<void(std::vector<types::Track>&, double t_s)>& on_tracks = nullptr);

// Sets each track sample's truth_class to the class of the truth object its track
// was matched to most often (`truth_of_hypothesis`, from eval::EvaluateMot), "none"
// for tracks never matched.
void LabelTracksFromTruth(std::vector<io::ObjectSample>& tracks, const std::vector<io::ObjectSample>& truth,
                          const std::map<std::string, std::string>& truth_of_hypothesis);

}  // namespace specht::pipeline
