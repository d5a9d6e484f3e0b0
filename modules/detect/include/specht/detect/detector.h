// specht/detect/detector.h: a CNN object detector on OpenCV's dnn module.
//
// Models: darknet (cfg + weights; YOLO heads decoded by OpenCV's region layer into
// rows (cx, cy, w, h, objectness, class scores…), normalised to the input) and ONNX
// FastestDet (one 1×(5+C)×H×W map: objectness (sigmoid), box regression, class
// probabilities (softmax); a cell (gx, gy) predicts
//   cx = (gx + tanh(t_x)) / W,  cy = (gy + tanh(t_y)) / H,  w = σ(t_w),  h = σ(t_h),
//   score = objectness^0.6 · class^0.4   (as FastestDet's reference decoder)).
// The image is resized to the input size (stretched, as both models were trained) or
// letterboxed; boxes are mapped back to image pixels, thresholded per driving
// class, and suppressed per class (non-maximum suppression on IoU).
#pragma once

#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::detect {

// The driving classes every model's labels map to.
inline const std::vector<std::string>& DrivingClasses() {
  static const std::vector<std::string> classes = {"pedestrian", "cyclist",      "car",  "truck",
                                                   "bus",        "traffic_sign", "other"};
  return classes;
}

// Section "detect".
struct DetectorOptions {
  std::string format = "darknet";                         // darknet | fastestdet_onnx
  std::string model = "models/yolo-fastest-1.1.weights";  // relative paths: to the data directory
  std::string config = "models/yolo-fastest-1.1.cfg";
  std::string labels = "models/coco.names";
  int input_width = 960, input_height = 288;
  bool letterbox = false;
  double score_threshold = 0.3;
  std::vector<std::string> class_thresholds;  // "car=0.25": per driving class
  double nms_iou = 0.45;
  double rider_overlap = 0.5;
  int threads = 2;
  std::string backend = "opencv";  // opencv | default
  // "model label=driving class"; labels not listed are dropped.
  std::vector<std::string> class_map = {
      "person=pedestrian", "bicycle=cyclist",        "motorbike=cyclist",         "car=car", "truck=truck", "bus=bus",
      "train=other",       "stop sign=traffic_sign", "traffic light=traffic_sign"};

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("format", format, {"darknet", "fastestdet_onnx"}, "model format and head decoder");
    v.Param("model", model, "weights (.weights) or .onnx; relative to the data directory unless absolute");
    v.Param("config", config, "darknet .cfg (darknet only)");
    v.Param("labels", labels, "class names, one per line, in the model's order");
    v.Param("input_width", input_width, "network input width (px, multiple of 32)", Range::Of(32, 1280));
    v.Param("input_height", input_height, "network input height (px, multiple of 32)", Range::Of(32, 1280));
    v.Param("letterbox", letterbox, "keep the aspect ratio (pad) instead of stretching to the input size");
    v.Param("score_threshold", score_threshold, "keep detections scoring at least this", Range::Of(0.01, 0.99));
    v.Param("class_thresholds", class_thresholds,
            "per driving class score thresholds overriding score_threshold, as \"class=threshold\"");
    v.Param("nms_iou", nms_iou, "suppress a box overlapping a better one of its class by more than this IoU",
            Range::Of(0.1, 0.9));
    v.Param("rider_overlap", rider_overlap,
            "a pedestrian box covering at least this share of a cyclist (bicycle, motorbike) box is its rider: "
            "the two become one cyclist; 0 = never",
            Range::Of(0.0, 1.0));
    v.Param("threads", threads,
            "OpenCV threads for inference; OpenCV's count is process-wide, set when the detector loads",
            Range::Of(1, 64).Fixed());
    v.Choice("backend", backend, {"opencv", "default"}, "cv::dnn backend");
    v.Param("class_map", class_map,
            "\"model label=driving class\" (pedestrian, cyclist, car, truck, bus, "
            "traffic_sign, other); unlisted labels are dropped");
  }
  std::vector<std::string> Relations() const;
  // The parsed lists (Relations() reports malformed entries).
  std::map<std::string, std::string> ClassMap() const;
  std::map<std::string, double> ClassThresholds() const;
};

// The options for a model shipped in the data directory's models/: "yolo-fastest"
// (the defaults) or "fastestdet". InputError for another name.
DetectorOptions ShippedModel(const std::string& name);

struct Detection {
  cv::Rect2d box;     // image pixels
  std::string cls;    // driving class
  std::string label;  // the model's own label
  double score = 0;
};

class Detector {
 public:
  // Loads the model (paths relative to data_dir). InputError names a missing or
  // unreadable file or a model whose output does not fit the decoder.
  Detector(const DetectorOptions& options, const std::string& data_dir);
  ~Detector();
  // `image`: 8-bit BGR or grayscale.
  std::vector<Detection> Detect(const cv::Mat& image);
  const DetectorOptions& options() const { return options_; }

 private:
  struct Net;
  DetectorOptions options_;
  std::map<std::string, std::string> class_map_;  // options_'s lists, parsed once
  std::map<std::string, double> class_thresholds_;
  std::vector<std::string> labels_;
  std::unique_ptr<Net> net_;
};

double IoU(const cv::Rect2d& a, const cv::Rect2d& b);

// COCO models see a rider and the bicycle apart: each cyclist box (the vehicle) takes
// the pedestrian box covering the largest share of it, if at least `overlap`, and
// becomes one cyclist with the union of both boxes and the higher score.
std::vector<Detection> MergeRiders(std::vector<Detection> detections, double overlap);

}  // namespace specht::detect
