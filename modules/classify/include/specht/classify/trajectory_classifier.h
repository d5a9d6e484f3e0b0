// specht/classify/trajectory_classifier.h: a trained model together with the
// preprocessing it was trained with, for classifying new trajectories — every
// window of a recorded track (`specht classify predict`) or the latest window of a
// live one (the tracker's confirmed tracks, online).
//
// The preprocessing (section "classify" as it was at `classify prepare`, plus the
// global position bounds) travels in the model's JSON, so a model never meets
// windows cut or normalised differently from its training set.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "specht/classify/baseline.h"
#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"

namespace specht::classify {

// What `classify prepare` stores with a dataset and `classify train` copies into
// the model: the options and the fitted position bounds.
nlohmann::json PreprocessingJson(const PreprocessOptions& o, const PositionBounds& bounds);

class TrajectoryClassifier {
 public:
  // <path>.json/.pt as Classifier::Save writes them. Throws InputError naming the
  // file when the model carries no preprocessing or it does not fit the network.
  // With `forest_path` (the forest.yml trained beside the network on the same
  // windows), Classify returns the two combined (CombinedProbabilities).
  static TrajectoryClassifier Load(const std::string& path, const std::string& forest_path = "");

  // The latest window of a trajectory: the last `length` points of its last piece
  // after splitting at gaps and jumps; none when that piece is shorter than
  // min_fill · length or the window is stationary (the model never saw either).
  std::optional<Window> LatestWindow(const Trajectory& t) const;
  // All windows of the trajectories, as for training (steps 1–3).
  std::vector<Window> Windows(const std::vector<Trajectory>& trajectories) const;
  // Class probabilities per window (windows × classes, row-major), batched.
  std::vector<float> Classify(const std::vector<Window>& windows, const MapFeatures& map = {}) const;

  const std::vector<std::string>& classes() const { return model_.classes(); }
  const PreprocessOptions& preprocessing() const { return options_; }
  // What Classify answers with, as the reports name it: "network+forest" or "network".
  std::string combination() const { return forest_ ? "network+forest" : "network"; }

 private:
  TrajectoryClassifier(Classifier model, PreprocessOptions options, PositionBounds bounds)
      : model_(std::move(model)), options_(std::move(options)), bounds_(bounds) {}
  Classifier model_;
  PreprocessOptions options_;
  PositionBounds bounds_;
  std::optional<ForestBaseline> forest_;
};

}  // namespace specht::classify
