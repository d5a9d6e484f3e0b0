#include "specht/pipeline/perception_eval.h"

#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPoint2D.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "specht/classify/metrics.h"
#include "specht/core/error.h"
#include "specht/core/statistics.h"
#include "specht/eval/detection.h"
#include "specht/eval/mot.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/dataset.h"
#include "specht/io/object_tracks.h"
#include "specht/io/trajectory_io.h"
#include "specht/pipeline/perception.h"
#include "specht/pipeline/stereo_perception.h"
#include "specht/sim/camera.h"
#include "specht/sim/simulator.h"

namespace specht::pipeline {
namespace {

struct AgentInView {
  int id = 0;
  double t_s = 0;
  std::string cls;  // driving class
  cv::Rect2d box;
  double visible = 0, range_m = 0;
};

std::vector<std::string> Fields(const std::string& csv_line) {
  std::vector<std::string> f;
  std::stringstream ss(csv_line);
  for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
  return f;
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
    const std::vector<std::string> f = Fields(line);
    if (f.size() != 12)
      throw InputError(path + ":" + std::to_string(n) + ": expected 12 fields, found " + std::to_string(f.size()));
    try {
      AgentInView a;
      a.id = std::stoi(f[2]);
      a.t_s = std::stod(f[1]);
      a.cls = sim::DrivingClassOf(f[3]);
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

nlohmann::json Quantiles(const std::vector<double>& v) {
  if (v.empty()) return {{"count", 0}};
  return {{"count", v.size()},
          {"p50", Percentile(v, 0.5)},
          {"p90", Percentile(v, 0.9)},
          {"max", Percentile(v, 1.0)},
          {"mean", Mean(v)}};
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
                              params.Get<detect::FusionOptions>("fusion"), data_dir,
                              params.Get<PerceptionOptions>("perception").stereo_downsample);
  eval::DetectionScorer scorer(o.iou), any_class(o.iou);  // the second: found whatever the class
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
    for (auto& b : boxes) b.cls = "object";
    for (auto& d : detections) d.cls = "object";
    any_class.AddFrame(boxes, detections);
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
  j["any_class"] = any_class.ToJson()["all"];
  j["distance_abs_error_m"] = Quantiles(abs_error_m);
  j["distance_rel_error"] = Quantiles(rel_error);
  const auto& s = perception.stats();
  j["ms_per_frame"] = {{"stereo", s.stereo_ms / std::max(1L, s.frames)},
                       {"detect", s.detect_ms / std::max(1L, s.frames)}};
  return j;
}

// The key of a 10 Hz time: agents.csv and the camera frames share them.
long Tenth(double t_s) { return std::lround(t_s * 10); }

struct AgentAt {
  std::string cls;
  double x_m = 0, y_m = 0;
};

// agents.csv: time_s,id,class,x_m,y_m,… at 10 Hz.
std::map<long, std::map<int, AgentAt>> ReadAgentPositions(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the agents' truth");
  std::string line;
  std::getline(in, line);
  std::map<long, std::map<int, AgentAt>> out;
  for (int n = 2; std::getline(in, line); ++n) {
    const std::vector<std::string> f = Fields(line);
    if (f.size() < 5) throw InputError(path + ":" + std::to_string(n) + ": expected at least 5 fields");
    try {
      out[Tenth(std::stod(f[0]))][std::stoi(f[1])] = {f[2], std::stod(f[3]), std::stod(f[4])};
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(n) + ": a field is not a number");
    }
  }
  return out;
}

// classify/metrics.h's scores (macro F1 over the classes in the truth) of
// (predicted, true) class pairs.
nlohmann::json ClassScores(const std::vector<std::pair<std::string, std::string>>& pairs) {
  std::set<std::string> names;
  for (const auto& [p, t] : pairs) names.insert(p), names.insert(t);
  const std::vector<std::string> classes(names.begin(), names.end());
  const auto index = [&](const std::string& c) {
    return static_cast<int>(std::lower_bound(classes.begin(), classes.end(), c) - classes.begin());
  };
  std::vector<int> truth, predicted;
  for (const auto& [p, t] : pairs) predicted.push_back(index(p)), truth.push_back(index(t));
  nlohmann::json j = classify::Score(truth, predicted, static_cast<int>(classes.size())).ToJson(classes);
  j["tracks"] = pairs.size();
  return j;
}

// (predicted, true) class pairs of the perceived tracks, one per track that followed
// an agent (against the class of the agent it followed most), by three answers:
//   vote        the detections' vote: the class most of the track's rows carry;
//   classifier  the most probable class of the trajectory classifier's mean over the
//               rows it classified (tracks it never classified are left out);
//   combined    the most probable of the mean of the vote's row shares and the
//               classifier's mean (the vote alone where the classifier gave nothing).
struct TrackClassPairs {
  std::vector<std::pair<std::string, std::string>> vote, classifier, combined;
};

std::string MostProbable(const std::map<std::string, double>& p) {
  return std::max_element(p.begin(), p.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
}

TrackClassPairs ClassPairs(const std::vector<io::ObjectSample>& tracks, const std::vector<io::ObjectSample>& truth,
                           const std::map<std::string, std::string>& truth_of_hypothesis) {
  struct Rows {
    std::map<std::string, double> votes, probabilities;
    long rows = 0, classified = 0;
  };
  std::map<std::string, Rows> by_track;
  for (const auto& s : tracks) {
    Rows& r = by_track[s.id];
    ++r.rows, r.votes[s.cls] += 1;
    if (!s.class_probabilities.empty()) ++r.classified;
    for (const auto& [cls, p] : s.class_probabilities) r.probabilities[cls] += p;
  }
  std::map<std::string, std::string> truth_class;
  for (const auto& s : truth) truth_class[s.id] = s.cls;
  TrackClassPairs out;
  for (const auto& [hyp, agent] : truth_of_hypothesis) {
    const auto it = by_track.find(hyp);
    if (it == by_track.end()) continue;
    const Rows& r = it->second;
    const std::string& cls = truth_class[agent];
    out.vote.push_back({MostProbable(r.votes), cls});
    if (r.classified == 0) {
      out.combined.push_back(out.vote.back());
      continue;
    }
    out.classifier.push_back({MostProbable(r.probabilities), cls});
    std::map<std::string, double> both;
    for (const auto& [c, n] : r.votes) both[c] += 0.5 * n / r.rows;
    for (const auto& [c, p] : r.probabilities) both[c] += 0.5 * p / r.classified;
    out.combined.push_back({MostProbable(both), cls});
  }
  return out;
}

}  // namespace

nlohmann::json EvaluatePerceivedTracks(const std::string& sim_dir, const std::string& replay_dir,
                                       const PerceptionEvalOptions& o) {
  const auto in_view = ReadAgentsInView(sim_dir + "/stereo/agents.csv");
  const auto positions = ReadAgentPositions(sim_dir + "/agents.csv");
  const Trajectory estimate = io::ReadTum(replay_dir + "/trajectory.tum");
  const Trajectory reference = io::ReadTum(sim_dir + "/ground_truth.tum");
  const eval::AteResult ate = eval::AbsoluteTrajectoryError2D(estimate, reference, 0.05);
  const double epoch_s = sim::Simulator::kEpochNs * 1e-9;

  // Truth at every camera frame: each agent present, care when it shows as the
  // detection's care boxes do and is within range.
  std::vector<io::ObjectSample> truth;
  for (const auto& [frame, agents] : in_view) {
    const double t = agents.front().t_s;
    const auto present = positions.find(Tenth(t));
    if (present == positions.end()) continue;
    std::map<int, bool> care;
    for (const auto& a : agents)
      care[a.id] = a.visible >= o.min_visible && a.box.height >= o.min_height_px && a.range_m <= o.max_range_m;
    for (const auto& [id, p] : present->second)
      truth.push_back({std::to_string(id), t, p.x_m, p.y_m, p.cls, "", !care[id], {}});
  }
  // Tracks into the truth's frame, at the camera frames' times.
  std::vector<io::ObjectSample> tracks = io::ReadObjectTracks(replay_dir + "/tracks.csv");
  for (auto& s : tracks) {
    const mrpt::poses::CPoint2D p = ate.alignment + mrpt::poses::CPoint2D(s.x_m, s.y_m);
    s.x_m = p.x(), s.y_m = p.y();
    s.t_s = Tenth(s.t_s - epoch_s) / 10.0;
  }
  const eval::MotResult mot = eval::EvaluateMot(truth, tracks, o.match_threshold_m);
  const TrackClassPairs classes = ClassPairs(tracks, truth, mot.truth_of_hypothesis);
  return {{"mot", mot.ToJson()},
          {"class_detector_vote", ClassScores(classes.vote)},
          {"class_classifier", ClassScores(classes.classifier)},
          {"class_combined", ClassScores(classes.combined)},
          {"slam_ate_rmse_m", ate.rmse_m},
          {"care", {{"max_range_m", o.max_range_m}, {"match_threshold_m", o.match_threshold_m}}}};
}

nlohmann::json EvaluatePerception(const std::string& sim_dir, const params::Params& params, const std::string& data_dir,
                                  const PerceptionEvalOptions& options, const std::function<void(double)>& progress) {
  const auto truth = ReadAgentsInView(sim_dir + "/stereo/agents.csv");
  nlohmann::json j = {{"sim_dir", sim_dir},
                      {"care", {{"min_visible", options.min_visible}, {"min_height_px", options.min_height_px}}}};
  for (size_t m = 0; m < options.models.size(); ++m) {
    const auto part = [&](double f) {
      if (progress) progress((m + f) / options.models.size());
    };
    j["detection"][options.models[m]] =
        EvaluateModel(sim_dir, params, data_dir, options.models[m], truth, options, part);
  }
  return j;
}

}  // namespace specht::pipeline
