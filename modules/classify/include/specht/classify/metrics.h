// specht/classify/metrics.h: classification scores and the confusion matrix.
//   precision_c = TP_c / (TP_c + FP_c),  recall_c = TP_c / (TP_c + FN_c)
//   F1_c = 2 P R / (P + R)  (0 when undefined)
//   macro F1 = mean over classes present in the truth; weighted F1 = Σ support_c F1_c / N
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace specht::classify {

struct Scores {
  std::vector<std::vector<long>> confusion;  // [truth][predicted]
  std::vector<double> f1, precision, recall;
  std::vector<long> support;
  double macro_f1 = 0, weighted_f1 = 0, accuracy = 0;

  nlohmann::json ToJson(const std::vector<std::string>& classes) const;
};

// The most probable class of each row of `probabilities` (rows of `classes`; ties: the
// lower index).
std::vector<int> MostProbable(const std::vector<float>& probabilities, int classes);

// Labels outside [0, classes) are ignored.
Scores Score(const std::vector<int>& truth, const std::vector<int>& predicted, int classes);

// The confusion matrix as a picture (rows: truth, columns: predicted; each row
// normalised to its support, counts written in the cells), like the paper's Fig. 6.
void WriteConfusionPng(const Scores& s, const std::vector<std::string>& classes, const std::string& title,
                       const std::string& path);

// Counts per class after each preprocessing step as grouped bars on a log scale
// (the vessel paper's Figure 3): `counts` is step → class → count, drawn in the
// order of `steps`.
void WriteStepCountsPng(const std::map<std::string, std::map<std::string, long>>& counts,
                        const std::vector<std::string>& steps, const std::vector<std::string>& classes,
                        const std::string& title, const std::string& path);

// One point of a learning curve: a score (mean ± std over folds) at a share of the
// training objects.
struct CurvePoint {
  double share = 0, mean = 0, std = 0;
};

// Learning curves, one line per model (model → points in share order) with ± std
// bars, shares on a log₂ axis (¼, ½, 1 evenly spaced).
void WriteLearningCurvePng(const std::map<std::string, std::vector<CurvePoint>>& curves, const std::string& title,
                           const std::string& y_label, const std::string& path);

}  // namespace specht::classify
