// specht/classify/trajectory_classifier.h: a trained model together with the
// preprocessing it was trained with, for classifying new trajectories — every
// window of a recorded track (`specht classify predict`) or the latest window of a
// live one (the tracker's confirmed tracks, online).
//
// The preprocessing (section "classify" as it was at `classify prepare`, plus the
// global position bounds) travels in the model's JSON, so a model never meets
// windows cut or normalised differently from its training set.
//
// A model trained on shorter windows (`train --train-on`, as `eval --train-on`
// scores it) carries two: "preprocessing" cuts the windows it classifies (e.g. 360
// points) and "input_preprocessing" the shorter ones its models take (e.g. 60). A
// window is then cut again into input windows — its points chunked at the shorter
// length, stationary pieces dropped, which with a window length that is a multiple
// of the input length are exactly the shorter windows of the same track that lie
// within it (crossval.h's WindowsWithin) — and a model of input windows gives it the
// mean of its probabilities over them, 1/classes each where none is left. The
// forest always takes the input windows; the network too, unless it was fine-tuned
// on windows of the full length (its own length says which).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "specht/classify/baseline.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"

namespace specht::classify {

// What `classify prepare` stores with a dataset and `classify train` copies into
// the model: the options and the fitted position bounds.
nlohmann::json PreprocessingJson(const PreprocessOptions& o, const PositionBounds& bounds);

// Why models of `shorter`'s windows cannot classify `windows`' windows as described
// above (train --train-on): other classes, a window length that is not a multiple of
// the shorter one, or a preprocessing that differs in more than the length (named by
// its first differing key); empty when they can. Both from dataset.json's
// "preprocessing".
std::string ShorterWindowsProblem(const PreparedDataset& windows, const PreparedDataset& shorter);

class TrajectoryClassifier {
 public:
  // How windows are cut and normalised: the options and the fitted position bounds.
  struct Preprocessing {
    PreprocessOptions options;
    PositionBounds bounds;
  };

  // <path>.json/.pt as Classifier::Save writes them. Throws InputError naming the
  // file when the model carries no preprocessing or it does not fit the network.
  // With `forest_path` (the forest.yml trained beside the network on the same
  // windows), Classify returns the two combined (CombinedProbabilities).
  static TrajectoryClassifier Load(const std::string& path, const std::string& forest_path = "");
  // The model `classify train` (or `ais train`) wrote into `dir`: dir/model, combined
  // with dir/forest.yml when it exists, unless `network_only`.
  static TrajectoryClassifier LoadDirectory(const std::string& dir, bool network_only = false);

  // The latest window of a trajectory: the last `length` points of its last piece
  // after splitting at gaps and jumps; none when that piece is shorter than
  // min_fill · length or the window is stationary (the model never saw either).
  std::optional<Window> LatestWindow(const Trajectory& t) const;
  // All windows of the trajectories, as for training (steps 1–3).
  std::vector<Window> Windows(const std::vector<Trajectory>& trajectories) const;
  // Class probabilities per window (windows × classes, row-major), batched.
  std::vector<float> Classify(const std::vector<Window>& windows, const MapFeatures& map = {}) const;

  const std::vector<std::string>& classes() const { return model_.classes(); }
  void set_threads(int threads) { model_.set_threads(threads); }  // libtorch threads (Classifier::set_threads)
  const PreprocessOptions& preprocessing() const { return windows_.options; }
  // The input windows' length when the models take shorter windows (see above), else 0.
  int input_length() const { return inputs_ ? inputs_->options.length : 0; }
  // What Classify answers with, as the reports name it: "network+forest" or "network".
  std::string combination() const { return forest_ ? "network+forest" : "network"; }

 private:
  TrajectoryClassifier(Classifier model, Preprocessing windows, std::optional<Preprocessing> inputs)
      : model_(std::move(model)), windows_(std::move(windows)), inputs_(std::move(inputs)) {}
  Classifier model_;
  Preprocessing windows_;                // cuts the windows Classify is given
  std::optional<Preprocessing> inputs_;  // the shorter windows the models take, if any
  std::optional<ForestBaseline> forest_;
};

}  // namespace specht::classify
