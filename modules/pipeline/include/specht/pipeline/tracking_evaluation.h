// specht/pipeline/tracking_evaluation.h: multi-object tracking on simulated scenes,
// scored with CLEAR MOT — what `specht track` runs. Each scenario runs once per seed;
// its agents are detected with noise, misses, false alarms and class errors (section
// "synthetic_detections", sim/detections.h) and tracked (section "track"). Writes
//   truth.csv     the visible agents per detection frame (io/object_tracks.h)
//   tracks.csv    the tracker's confirmed and coasting tracks per frame, with the
//                 class of the agent each track followed most (truth_class): the
//                 input of `specht classify prepare`
//   tracks.png    the first run: static world, agent paths (grey), tracks by class
//   report.json   CLEAR MOT per run and over all runs, tracker time per frame
// With a model (a `specht classify train` output) the trajectory classifier runs
// online: after every tracker update, on each confirmed track's latest window, with
// the scene's map features (the network combined with the model's forest unless
// network_only); its probabilities go into the track's class_probabilities (the
// p_<class> columns of tracks.csv), and report.json scores its class per track-frame
// against the class of the agent the track followed, next to the tracker's vote.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "specht/classify/trajectory_classifier.h"
#include "specht/core/params.h"
#include "specht/sim/detections.h"
#include "specht/sim/scenario.h"
#include "specht/track/tracker.h"

namespace specht::pipeline {

struct TrackingEvaluationInputs {
  std::vector<std::string> scenarios;                // scenario files
  std::vector<std::pair<uint64_t, uint64_t>> seeds;  // per scenario, first and last; none = the scenario's own
  std::string model_dir;                             // "" = no online classifier
  bool network_only = false;
  double match_threshold_m = 1.0;  // CLEAR MOT match distance
};

class TrackingEvaluation {
 public:
  // Loads the scenarios and the model: InputError (file, reason) before anything is written.
  TrackingEvaluation(const params::Params& params, TrackingEvaluationInputs inputs);
  // Runs every scenario and seed and writes the outputs into `out_dir` (which exists).
  // An interrupt (core/interrupt.h) stops after the run in progress, writing the runs
  // done; returns 0, or 128 + the signal.
  int Run(const std::string& out_dir, bool quiet);

 private:
  TrackingEvaluationInputs in_;
  track::TrackerOptions tracker_;
  sim::SyntheticDetectionOptions detection_;
  std::vector<sim::Scenario> scenarios_;
  std::vector<std::pair<uint64_t, uint64_t>> seeds_;
  std::shared_ptr<const classify::TrajectoryClassifier> classifier_;
};

}  // namespace specht::pipeline
