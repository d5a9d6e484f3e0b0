// specht/pipeline/perception_eval.h: perception scored on a simulated drive (what
// `specht sim` writes: sim.rawlog with its stereo frames, stereo/agents.csv with every
// agent in view), against the simulator's truth:
//   detection  each shipped model (its files; input size — unless the model fixes
//              it —, thresholds and class map from the parameters' detect section)
//              on every left image, against the agents in view
//              (eval/detection.h, IoU ≥ iou): an agent counts when at least
//              min_visible of it shows and its box is at least min_height_px tall;
//              less visible or smaller agents are don't-care
//   distance   for each agent found, the fused box distance (our SGM + fusion, the
//              depth Z of the box) against the depth of the agent's true centre
//              along the optical axis, absolute and relative
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "specht/core/params.h"

namespace specht::pipeline {

struct PerceptionEvalOptions {
  double min_visible = 0.5;
  double min_height_px = 40;
  double iou = 0.5;
  std::vector<std::string> models = {"yolo-fastest", "fastestdet"};  // detect.h ShippedModel names
};

// Throws InputError naming the file and line when the drive's outputs are missing or
// malformed. `progress(fraction)` is called after every frame when given.
nlohmann::json EvaluatePerception(const std::string& sim_dir, const params::Params& params,
                                  const std::string& data_dir, const PerceptionEvalOptions& options,
                                  const std::function<void(double)>& progress = nullptr);

}  // namespace specht::pipeline
