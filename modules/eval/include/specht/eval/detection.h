// specht/eval/detection.h: 2D detections scored against ground-truth boxes, frame by
// frame, as KITTI and PASCAL VOC score them.
//
// In each frame, detections in order of falling score take the unmatched truth box of
// their own class with the highest IoU = |A ∩ B| / |A ∪ B| ≥ iou_threshold. One that
// takes a box marked "care" finds it; one that takes a don't-care box (too small,
// too hidden) counts for nothing. An unmatched detection is a false positive, unless
// it overlaps a don't-care box of any class by the threshold (it saw something real
// that the protocol does not score). Recall = found / care boxes; precision = found /
// (found + false positives); both per class, over all classes, and per distance band
// of the truth (a false positive has no distance: bands report recall only).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace specht::eval {

struct TruthBox {
  std::string cls;
  cv::Rect2d box;
  bool care = true;
  double range_m = 0;
};

struct DetectedBox {
  std::string cls;
  cv::Rect2d box;
  double score = 0;
};

struct DetectionCounts {
  long truth = 0, found = 0, false_positives = 0;
  double Recall() const { return truth > 0 ? static_cast<double>(found) / truth : 0.0; }
  double Precision() const {
    return found + false_positives > 0 ? static_cast<double>(found) / (found + false_positives) : 0.0;
  }
};

double IoU(const cv::Rect2d& a, const cv::Rect2d& b);

class DetectionScorer {
 public:
  // Distance bands by their upper edges in metres (the last band is open).
  explicit DetectionScorer(double iou_threshold = 0.5, std::vector<double> band_edges_m = {10, 20, 30});
  // One frame; returns, for each detection, the index of the truth box it found (-1: none).
  std::vector<int> AddFrame(const std::vector<TruthBox>& truth, const std::vector<DetectedBox>& detections);

  const std::map<std::string, DetectionCounts>& per_class() const { return per_class_; }
  const DetectionCounts& all() const { return all_; }
  long frames() const { return frames_; }
  double FalsePositivesPerFrame() const {
    return frames_ > 0 ? static_cast<double>(all_.false_positives) / frames_ : 0.0;
  }
  nlohmann::json ToJson() const;

 private:
  std::string Band(double range_m) const;
  double iou_threshold_;
  std::vector<double> band_edges_m_;
  std::map<std::string, DetectionCounts> per_class_, per_band_;
  DetectionCounts all_;
  long frames_ = 0;
};

}  // namespace specht::eval
