#include "specht/pipeline/perception_eval.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <mrpt/obs/CObservationStereoImages.h>

#include "specht/core/error.h"
#include "specht/core/statistics.h"
#include "specht/eval/detection.h"
#include "specht/io/dataset.h"
#include "specht/pipeline/stereo_perception.h"

namespace specht::pipeline {
namespace {

struct AgentInView {
  int id = 0;
  std::string cls;  // driving class
  cv::Rect2d box;
  double visible = 0, range_m = 0;
};

std::string DrivingClass(const std::string& kitti) {
  std::string c = kitti;
  std::transform(c.begin(), c.end(), c.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return c;
}

// stereo/agents.csv: frame,t_s,id,class,sprite,x0_px,y0_px,x1_px,y1_px,visible,truncated,range_m
std::map<int, std::vector<AgentInView>> ReadAgentsInView(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open (write it with `specht sim` on a scenario with a camera)");
  std::string line;
  std::getline(in, line);
  if (line.rfind("frame,t_s,id,class,sprite,x0_px,y0_px,x1_px,y1_px,visible,truncated,range_m", 0) != 0)
    throw InputError(path + ":1: not the header of stereo/agents.csv");
  std::map<int, std::vector<AgentInView>> out;
  for (int n = 2; std::getline(in, line); ++n) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    if (f.size() != 12) throw InputError(path + ":" + std::to_string(n) + ": expected 12 fields, found " + std::to_string(f.size()));
    try {
      AgentInView a;
      a.id = std::stoi(f[2]);
      a.cls = DrivingClass(f[3]);
      const double x0 = std::stod(f[5]), y0 = std::stod(f[6]), x1 = std::stod(f[7]), y1 = std::stod(f[8]);
      a.box = cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
      a.visible = std::stod(f[9]);
      a.range_m = std::stod(f[11]);
      out[std::stoi(f[0])].push_back(a);
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(n) + ": a field is not a number");
    }
  }
  return out;
}

nlohmann::json Quantiles(std::vector<double> v) {
  if (v.empty()) return {{"count", 0}};
  std::sort(v.begin(), v.end());
  const auto q = [&](double p) { return v[static_cast<size_t>(p * (v.size() - 1))]; };
  return {{"count", v.size()}, {"p50", q(0.5)}, {"p90", q(0.9)}, {"max", v.back()}, {"mean", Mean(v)}};
}

// One model over every stereo frame of the drive.
nlohmann::json EvaluateModel(const std::string& sim_dir, const params::Params& params, const std::string& data_dir,
                             const std::string& model, const std::map<int, std::vector<AgentInView>>& truth,
                             const PerceptionEvalOptions& o, const std::function<void(double)>& progress) {
  // The shipped model's files and format; everything else (input size, thresholds,
  // class map) as the parameters say, so both models see the camera alike.
  detect::DetectorOptions detector = params.Get<detect::DetectorOptions>("detect");
  const detect::DetectorOptions shipped = detect::ShippedModel(model);
  detector.format = shipped.format, detector.model = shipped.model, detector.config = shipped.config;
  detector.labels = shipped.labels;
  if (shipped.format == "fastestdet_onnx")  // the ONNX graph has a fixed input size
    detector.input_width = shipped.input_width, detector.input_height = shipped.input_height;
  StereoPerception perception(params.Get<stereo::SgmOptions>("stereo"), detector,
                              params.Get<detect::FusionOptions>("fusion"), data_dir);
  eval::DetectionScorer scorer(o.iou);
  std::vector<double> abs_error_m, rel_error;
  auto source = io::OpenDataset(sim_dir + "/sim.rawlog");
  int frame = 0;
  const auto frames = static_cast<double>(truth.empty() ? 1 : truth.rbegin()->first + 1);
  while (auto obs = source->Next()) {
    const auto stereo = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(obs->data);
    if (!stereo) continue;
    const PerceivedFrame f = perception.Process(*stereo, mrpt::poses::CPose3D(), obs->stamp);
    std::vector<eval::TruthBox> boxes;
    const auto in_view = truth.find(frame);
    if (in_view != truth.end())
      for (const auto& a : in_view->second)
        boxes.push_back({a.cls, a.box, a.visible >= o.min_visible && a.box.height >= o.min_height_px, a.range_m});
    std::vector<eval::DetectedBox> detections;
    for (const auto& d : f.detections) detections.push_back({d.cls, d.box, d.score});
    const std::vector<int> found = scorer.AddFrame(boxes, detections);
    for (size_t i = 0; i < found.size(); ++i) {
      if (found[i] < 0 || f.obstacle_of[i] < 0) continue;
      const double truth_m = boxes[static_cast<size_t>(found[i])].range_m;
      const double err = f.obstacles[static_cast<size_t>(f.obstacle_of[i])].range_m - truth_m;
      abs_error_m.push_back(std::abs(err));
      rel_error.push_back(std::abs(err) / truth_m);
    }
    ++frame;
    if (progress) progress(std::min(1.0, frame / frames));
  }
  nlohmann::json j = scorer.ToJson();
  j["model"] = model;
  j["distance_abs_error_m"] = Quantiles(abs_error_m);
  j["distance_rel_error"] = Quantiles(rel_error);
  const auto& s = perception.stats();
  j["ms_per_frame"] = {{"stereo", s.stereo_ms / std::max(1L, s.frames)}, {"detect", s.detect_ms / std::max(1L, s.frames)}};
  return j;
}

}  // namespace

nlohmann::json EvaluatePerception(const std::string& sim_dir, const params::Params& params,
                                  const std::string& data_dir, const PerceptionEvalOptions& options,
                                  const std::function<void(double)>& progress) {
  const auto truth = ReadAgentsInView(sim_dir + "/stereo/agents.csv");
  nlohmann::json j = {{"sim_dir", sim_dir},
                      {"care", {{"min_visible", options.min_visible}, {"min_height_px", options.min_height_px}}}};
  for (size_t m = 0; m < options.models.size(); ++m) {
    const auto part = [&](double f) {
      if (progress) progress((m + f) / options.models.size());
    };
    j["detection"][options.models[m]] = EvaluateModel(sim_dir, params, data_dir, options.models[m], truth, options, part);
  }
  return j;
}

}  // namespace specht::pipeline
