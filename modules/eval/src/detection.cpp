#include "specht/eval/detection.h"

#include <algorithm>
#include <numeric>

namespace specht::eval {

double IoU(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  const double uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

DetectionScorer::DetectionScorer(double iou_threshold, std::vector<double> band_edges_m)
    : iou_threshold_(iou_threshold), band_edges_m_(std::move(band_edges_m)) {}

std::string DetectionScorer::Band(double range_m) const {
  double lower = 0;
  for (double edge : band_edges_m_) {
    if (range_m < edge)
      return std::to_string(static_cast<int>(lower)) + "-" + std::to_string(static_cast<int>(edge)) + " m";
    lower = edge;
  }
  return std::to_string(static_cast<int>(lower)) + "+ m";
}

std::vector<int> DetectionScorer::AddFrame(const std::vector<TruthBox>& truth,
                                           const std::vector<DetectedBox>& detections) {
  ++frames_;
  for (const auto& t : truth) {
    if (!t.care) continue;
    ++per_class_[t.cls].truth, ++all_.truth, ++per_band_[Band(t.range_m)].truth;
  }
  std::vector<size_t> order(detections.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return detections[a].score > detections[b].score; });
  std::vector<bool> taken(truth.size(), false);
  std::vector<int> found(detections.size(), -1);
  for (size_t i : order) {
    const DetectedBox& d = detections[i];
    int best = -1;
    double best_iou = iou_threshold_;
    for (size_t k = 0; k < truth.size(); ++k) {
      const double iou = IoU(d.box, truth[k].box);
      if (!taken[k] && truth[k].cls == d.cls && iou >= best_iou) best = static_cast<int>(k), best_iou = iou;
    }
    if (best >= 0) {
      taken[best] = true;
      if (!truth[best].care) continue;
      found[i] = best;
      ++per_class_[d.cls].found, ++all_.found, ++per_band_[Band(truth[best].range_m)].found;
      continue;
    }
    const bool on_dont_care = std::any_of(
        truth.begin(), truth.end(), [&](const TruthBox& t) { return !t.care && IoU(d.box, t.box) >= iou_threshold_; });
    if (!on_dont_care) ++per_class_[d.cls].false_positives, ++all_.false_positives;
  }
  return found;
}

nlohmann::json DetectionScorer::ToJson() const {
  const auto counts = [](const DetectionCounts& c) {
    return nlohmann::json{{"truth", c.truth},
                          {"found", c.found},
                          {"false_positives", c.false_positives},
                          {"recall", c.Recall()},
                          {"precision", c.Precision()}};
  };
  nlohmann::json j = {{"frames", frames_},
                      {"iou_threshold", iou_threshold_},
                      {"all", counts(all_)},
                      {"false_positives_per_frame", FalsePositivesPerFrame()}};
  for (const auto& [cls, c] : per_class_) j["per_class"][cls] = counts(c);
  for (const auto& [band, c] : per_band_) j["recall_by_range"][band] = {{"truth", c.truth}, {"recall", c.Recall()}};
  return j;
}

}  // namespace specht::eval
