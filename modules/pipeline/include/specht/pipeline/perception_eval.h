// specht/pipeline/perception_eval.h: perception scored on a simulated drive (what
// `specht sim` writes: sim.rawlog with its stereo frames, stereo/agents.csv with every
// agent in view), against the simulator's truth:
//   detection  each shipped model (its files; input size — unless the model fixes
//              it —, thresholds and class map from the parameters' detect section)
//              on every left image, against the agents in view
//              (eval/detection.h, IoU ≥ iou): an agent counts when at least
//              min_visible of it shows and its box is at least min_height_px tall;
//              less visible or smaller agents are don't-care; scored by class and,
//              as any_class, whatever class the detector gave
//   distance   for each agent found, the fused box distance (our SGM + fusion, the
//              depth Z of the box) against the depth of the agent's true centre
//              along the optical axis, absolute and relative
//   tracks     (with a replay of the drive: `specht replay DIR/sim.rawlog`) the
//              perceived tracks (tracks.csv, SLAM's map frame, moved into the truth's
//              frame by the alignment of SLAM's trajectory to the true one) against
//              the agents at each camera frame: CLEAR MOT (eval/mot.h) where an agent
//              counts as for detection and within max_range_m, every other agent
//              present don't-care; each track's class (its detector vote) against the
//              class of the agent it followed most (macro F1); SLAM's ATE
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

struct PerceptionEvalOptions {
  double min_visible = 0.5;
  double min_height_px = 40;
  double iou = 0.5;
  double max_range_m = 25;
  double match_threshold_m = 1.0;
  std::vector<std::string> models = {"yolo-fastest", "fastestdet"};  // detect.h ShippedModel names
};

// Throws InputError naming the file and line when the drive's outputs are missing or
// malformed. `progress(fraction)` is called after every frame when given.
nlohmann::json EvaluatePerception(const std::string& sim_dir, const params::Params& params, const std::string& data_dir,
                                  const PerceptionEvalOptions& options,
                                  const std::function<void(double)>& progress = nullptr);

// The tracks part alone.
nlohmann::json EvaluatePerceivedTracks(const std::string& sim_dir, const std::string& replay_dir,
                                       const PerceptionEvalOptions& options);

}  // namespace specht::pipeline
