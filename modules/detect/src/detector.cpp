#include "specht/detect/detector.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "specht/core/error.h"

namespace specht::detect {
namespace {

bool IsDrivingClass(const std::string& c) {
  const auto& all = DrivingClasses();
  return std::find(all.begin(), all.end(), c) != all.end();
}

std::string Resolve(const std::string& path, const std::string& data_dir) {
  if (path.empty() || path.front() == '/' || data_dir.empty()) return path;
  return data_dir + "/" + path;
}

void RequireFile(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": " + what + " not found");
}

double Sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// A candidate in network-normalised coordinates (0..1 of the input).
struct Candidate {
  double cx, cy, w, h, score;
  int label;
};

std::vector<std::pair<std::string, double>> ParseThresholds(const std::vector<std::string>& entries,
                                                            std::vector<std::string>* problems) {
  return params::ParseNumberAssignments(
      entries, "class_thresholds", [](double t) { return t > 0 && t < 1; }, "in (0, 1)", problems);
}

}  // namespace

std::vector<std::string> DetectorOptions::Relations() const {
  std::vector<std::string> problems;
  for (const auto& [label, cls] : params::SplitAssignments(class_map, "class_map", &problems))
    if (!IsDrivingClass(cls))
      problems.push_back("class_map: '" + cls + "' (for '" + label + "') is not a driving class");
  for (const auto& [cls, value] : params::SplitAssignments(class_thresholds, "class_thresholds", nullptr))
    if (!IsDrivingClass(cls)) problems.push_back("class_thresholds: '" + cls + "' is not a driving class");
  ParseThresholds(class_thresholds, &problems);
  if (input_width % 32 != 0 || input_height % 32 != 0)
    problems.push_back("input_width and input_height: multiples of 32");
  if (format == "darknet" && config.empty()) problems.push_back("config: a darknet model needs its .cfg");
  return problems;
}

std::map<std::string, std::string> DetectorOptions::ClassMap() const {
  std::map<std::string, std::string> map;
  for (const auto& [label, cls] : params::SplitAssignments(class_map, "class_map", nullptr)) map[label] = cls;
  return map;
}

std::map<std::string, double> DetectorOptions::ClassThresholds() const {
  std::map<std::string, double> map;
  for (const auto& [cls, t] : ParseThresholds(class_thresholds, nullptr)) map[cls] = t;
  return map;
}

DetectorOptions ShippedModel(const std::string& name) {
  DetectorOptions o;
  if (name == "yolo-fastest") return o;
  if (name != "fastestdet") throw InputError("no shipped model '" + name + "' (yolo-fastest, fastestdet)");
  o.format = "fastestdet_onnx";
  o.model = "models/FastestDet.onnx";
  o.config = "";
  o.input_width = o.input_height = 352;
  return o;
}

struct Detector::Net {
  cv::dnn::Net net;
  std::vector<std::string> outputs;
  std::string model_path;
};

Detector::Detector(const DetectorOptions& options, const std::string& data_dir)
    : options_(options), net_(std::make_unique<Net>()) {
  const auto problems = options.Relations();
  if (!problems.empty()) throw InputError("detect: " + problems.front());
  class_map_ = options.ClassMap();
  class_thresholds_ = options.ClassThresholds();
  // OpenCV's thread count is process-wide, and changing it while another thread runs
  // OpenCV work can crash TBB's arena: set once here, never around each inference.
  if (cv::getNumThreads() != options.threads) cv::setNumThreads(options.threads);
  const std::string model = Resolve(options.model, data_dir), labels = Resolve(options.labels, data_dir);
  RequireFile(model, "model");
  RequireFile(labels, "labels file");
  std::ifstream in(labels);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) labels_.push_back(line);
  if (labels_.empty()) throw InputError(labels + ": no class names");
  net_->model_path = model;
  try {
    if (options.format == "darknet") {
      const std::string config = Resolve(options.config, data_dir);
      RequireFile(config, "darknet config");
      net_->net = cv::dnn::readNetFromDarknet(config, model);
    } else {
      net_->net = cv::dnn::readNetFromONNX(model);
    }
  } catch (const cv::Exception& e) {
    throw InputError(model + ": cannot load as " + options.format + " model: " + e.err);
  }
  if (net_->net.empty()) throw InputError(model + ": cannot load as " + options.format + " model");
  net_->net.setPreferableBackend(options.backend == "opencv" ? cv::dnn::DNN_BACKEND_OPENCV
                                                             : cv::dnn::DNN_BACKEND_DEFAULT);
  net_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  net_->outputs = net_->net.getUnconnectedOutLayersNames();
}

Detector::~Detector() = default;

std::vector<Detection> Detector::Detect(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw InputError("detect: image must be 8-bit grayscale or BGR, got " +
                     (image.empty() ? std::string("an empty image") : cv::typeToString(image.type())));
  cv::Mat bgr = image;
  if (image.channels() == 1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  const cv::Size input(options_.input_width, options_.input_height);
  // Resize (stretch) or letterbox: image pixel = (network pixel − pad) / scale.
  double scale_x = static_cast<double>(input.width) / bgr.cols, scale_y = static_cast<double>(input.height) / bgr.rows;
  double pad_x = 0, pad_y = 0;
  cv::Mat resized;
  if (options_.letterbox) {
    scale_x = scale_y = std::min(scale_x, scale_y);
    const cv::Size inner(static_cast<int>(std::lround(bgr.cols * scale_x)),
                         static_cast<int>(std::lround(bgr.rows * scale_y)));
    pad_x = (input.width - inner.width) / 2.0;
    pad_y = (input.height - inner.height) / 2.0;
    cv::Mat inner_image;
    cv::resize(bgr, inner_image, inner, 0, 0, cv::INTER_LINEAR);
    cv::copyMakeBorder(inner_image, resized, static_cast<int>(pad_y),
                       input.height - inner.height - static_cast<int>(pad_y), static_cast<int>(pad_x),
                       input.width - inner.width - static_cast<int>(pad_x), cv::BORDER_CONSTANT, cv::Scalar::all(114));
  } else {
    cv::resize(bgr, resized, input, 0, 0, cv::INTER_LINEAR);
  }
  // Darknet models were trained on RGB, FastestDet on BGR.
  const cv::Mat blob =
      cv::dnn::blobFromImage(resized, 1 / 255.0, input, cv::Scalar(), options_.format == "darknet", false);
  net_->net.setInput(blob);
  std::vector<cv::Mat> outputs;
  try {
    net_->net.forward(outputs, net_->outputs);
  } catch (const cv::Exception& e) {
    throw InputError(net_->model_path + ": cannot run at " + std::to_string(input.width) + "×" +
                     std::to_string(input.height) + " (detect.input_width/input_height): " + e.err);
  }

  const int classes = static_cast<int>(labels_.size());
  std::vector<Candidate> candidates;
  auto mismatch = [&](const std::string& got) {
    return InputError(net_->model_path + ": output " + got + " does not fit the " + options_.format + " decoder with " +
                      std::to_string(classes) + " labels");
  };
  if (options_.format == "darknet") {
    for (const cv::Mat& out : outputs) {
      if (out.dims != 2 || out.cols != 5 + classes)
        throw mismatch(std::to_string(out.dims) + "-d, " + std::to_string(out.cols) + " columns");
      for (int r = 0; r < out.rows; ++r) {
        const float* row = out.ptr<float>(r);
        const float* best = std::max_element(row + 5, row + 5 + classes);
        candidates.push_back({row[0], row[1], row[2], row[3], *best, static_cast<int>(best - (row + 5))});
      }
    }
  } else {
    const cv::Mat& out = outputs.front();
    if (out.dims != 4 || out.size[1] != 5 + classes) throw mismatch(std::to_string(out.dims) + "-d");
    const int h = out.size[2], w = out.size[3];
    auto at = [&](int c, int y, int x) { return out.ptr<float>(0, c)[y * w + x]; };
    for (int gy = 0; gy < h; ++gy)
      for (int gx = 0; gx < w; ++gx) {
        int best = 0;
        for (int c = 1; c < classes; ++c)
          if (at(5 + c, gy, gx) > at(5 + best, gy, gx)) best = c;
        const double score = std::pow(at(0, gy, gx), 0.6) * std::pow(at(5 + best, gy, gx), 0.4);
        candidates.push_back({(gx + std::tanh(at(1, gy, gx))) / w, (gy + std::tanh(at(2, gy, gx))) / h,
                              Sigmoid(at(3, gy, gx)), Sigmoid(at(4, gy, gx)), score, best});
      }
  }

  std::map<std::string, std::vector<Detection>> by_class;
  for (const Candidate& c : candidates) {
    const auto mapped = class_map_.find(labels_[static_cast<size_t>(c.label)]);
    if (mapped == class_map_.end()) continue;
    const auto t = class_thresholds_.find(mapped->second);
    if (c.score < (t != class_thresholds_.end() ? t->second : options_.score_threshold)) continue;
    const double x0 = ((c.cx - c.w / 2) * input.width - pad_x) / scale_x,
                 y0 = ((c.cy - c.h / 2) * input.height - pad_y) / scale_y;
    const double x1 = ((c.cx + c.w / 2) * input.width - pad_x) / scale_x,
                 y1 = ((c.cy + c.h / 2) * input.height - pad_y) / scale_y;
    cv::Rect2d box(cv::Point2d(std::max(0.0, x0), std::max(0.0, y0)),
                   cv::Point2d(std::min<double>(bgr.cols, x1), std::min<double>(bgr.rows, y1)));
    if (box.area() <= 0) continue;
    by_class[mapped->second].push_back({box, mapped->second, labels_[static_cast<size_t>(c.label)], c.score});
  }
  std::vector<Detection> detections;
  for (auto& [cls, list] : by_class) {
    std::vector<cv::Rect2d> boxes;
    std::vector<float> scores;
    for (const auto& d : list) {
      boxes.push_back(d.box);
      scores.push_back(static_cast<float>(d.score));
    }
    std::vector<int> keep;
    cv::dnn::NMSBoxes(boxes, scores, 0.0f, static_cast<float>(options_.nms_iou), keep);
    for (int i : keep) detections.push_back(list[static_cast<size_t>(i)]);
  }
  if (options_.rider_overlap > 0) detections = MergeRiders(std::move(detections), options_.rider_overlap);
  std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) {
    return a.score != b.score ? a.score > b.score : a.box.x < b.box.x;
  });
  return detections;
}

std::vector<Detection> MergeRiders(std::vector<Detection> d, double overlap) {
  std::vector<bool> rider(d.size(), false);
  for (auto& vehicle : d) {
    if (vehicle.cls != "cyclist") continue;
    int best = -1;
    double best_share = overlap;
    for (size_t k = 0; k < d.size(); ++k) {
      if (d[k].cls != "pedestrian" || rider[k]) continue;
      const double share = (d[k].box & vehicle.box).area() / vehicle.box.area();
      if (share >= best_share) best = static_cast<int>(k), best_share = share;
    }
    if (best < 0) continue;
    rider[static_cast<size_t>(best)] = true;
    vehicle.box |= d[static_cast<size_t>(best)].box;
    vehicle.score = std::max(vehicle.score, d[static_cast<size_t>(best)].score);
  }
  std::vector<Detection> out;
  for (size_t k = 0; k < d.size(); ++k)
    if (!rider[k]) out.push_back(std::move(d[k]));
  return out;
}

double IoU(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  const double uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

}  // namespace specht::detect
