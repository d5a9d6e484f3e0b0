// specht/classify/dataset_io.h: prepared datasets on disk, readable with numpy:
//   windows.npy      float32, windows × features × length (NumPy .npy v1.0)
//   handcrafted.npy  float32, windows × HandcraftedFeatureCount() (the baseline's)
//   windows.csv      index,object_id,label,t0_s,t1_s (the window's first and last point's
//                    time; datasets of older versions lack the last two: then NaN)
//   dataset.json     feature names, length, classes, counts per preprocessing step
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"

namespace specht::classify {

struct PreparedDataset {
  Dataset windows;  // y indexes `classes`
  std::vector<float> handcrafted;
  std::vector<std::string> labels;  // per window
  // Per window: the time of its first and last point (s; NaN where the dataset was
  // prepared before windows.csv had them). A window's span says which windows of
  // another dataset, cut from the same tracks, lie inside it (crossval's train_on).
  std::vector<double> t0_s, t1_s;
  std::vector<std::string> classes;
  nlohmann::json info;  // dataset.json

  // Appends `w`'s identity, label (y indexes `classes`, −1 for none) and span; its
  // features and handcrafted row are the caller's.
  void AddWindow(const Window& w, int y);
};

// Removes the windows without a class (y = −1: AIS vessels of unknown type) from
// `d` and returns them, each part in its original order.
PreparedDataset SplitOffUnlabelled(PreparedDataset& d);

// Self-training's pseudo-labels (PseudoLabelOptions): the windows of `unlabelled`
// that a teacher gives at least `votes` of its class probabilities (size × classes;
// the forest's are its trees' vote fractions), with the most probable class as y and
// the teacher's probabilities as their Dataset::teacher (for distillation);
// `per_class` gets how many of each class.
Dataset PseudoLabelled(const std::vector<float>& probabilities, const PreparedDataset& unlabelled, double votes,
                       int classes, std::vector<long>& per_class);

// The handcrafted (baseline) feature rows of the windows in `rows`.
std::vector<float> HandcraftedRows(const PreparedDataset& d, const std::vector<size_t>& rows);

void WriteNpy(const std::string& path, const std::vector<float>& data, const std::vector<size_t>& shape);
// Throws InputError naming the file on a bad header, dtype or truncated data.
std::vector<float> ReadNpy(const std::string& path, std::vector<size_t>& shape);

// Whether every window of `d` has its span (t0_s, t1_s).
bool HasSpans(const PreparedDataset& d);

void WritePrepared(const PreparedDataset& d, const std::string& dir);
PreparedDataset ReadPrepared(const std::string& dir);

}  // namespace specht::classify
