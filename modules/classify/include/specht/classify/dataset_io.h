// specht/classify/dataset_io.h: prepared datasets on disk, readable with numpy:
//   windows.npy      float32, windows × features × length (NumPy .npy v1.0)
//   handcrafted.npy  float32, windows × HandcraftedFeatureCount() (the baseline's)
//   windows.csv      index,object_id,label
//   dataset.json     feature names, length, classes, counts per preprocessing step
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"

namespace specht::classify {

struct PreparedDataset {
  Dataset windows;  // y indexes `classes`
  std::vector<float> handcrafted;
  std::vector<std::string> labels;  // per window
  std::vector<std::string> classes;
  nlohmann::json info;  // dataset.json
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

void WritePrepared(const PreparedDataset& d, const std::string& dir);
PreparedDataset ReadPrepared(const std::string& dir);

}  // namespace specht::classify
