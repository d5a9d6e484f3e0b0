// Classification of object tracks (track_classification.h): windows cut from
// io/object_tracks.h files with their scenes' map features, a trained model scored on
// a prepared dataset, and new tracks classified.
#include "specht/pipeline/track_classification.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>

#include "internal/probability_csv.h"
#include "specht/classify/baseline.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/model.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/object_tracks.h"
#include "specht/io/report.h"
#include "specht/pipeline/map_features.h"
#include "specht/pipeline/run_directory.h"
#include "specht/sim/scenario.h"

namespace specht::pipeline {
namespace {

std::map<std::string, classify::MapFeatures> ScenarioMaps(const std::vector<std::string>& paths) {
  std::map<std::string, classify::MapFeatures> maps;
  for (const auto& path : paths) {
    const sim::Scenario s = sim::LoadScenario(path);
    maps[s.name] = pipeline::ScenarioMapFeatures(s);
  }
  return maps;
}

std::string ScenarioOf(const std::string& id) {
  const size_t a = id.find('/'), b = a == std::string::npos ? a : id.find('/', a + 1);
  return b == std::string::npos ? "" : id.substr(a + 1, b - a - 1);
}

// Object tracks (io/object_tracks.h) grouped by id and sorted by time; label =
// truth_class, else class. With `labelled_only`, tracks without a label (or
// labelled "none": never matched to a truth object) are left out.
std::vector<classify::Trajectory> ReadTrajectories(const std::vector<std::string>& paths, bool labelled_only) {
  std::map<std::string, classify::Trajectory> by_id;
  for (const auto& path : paths) {
    const std::vector<io::ObjectSample> samples = io::ReadObjectTracks(path);
    if (samples.empty()) throw InputError(path + ": no track rows (only a header): nothing to classify");
    for (const auto& s : samples) {
      auto& t = by_id[s.id];
      t.object_id = s.id;
      t.label = s.truth_cls.empty() ? s.cls : s.truth_cls;
      t.points.push_back({s.t_s, s.x_m, s.y_m});
    }
  }
  std::vector<classify::Trajectory> trajectories;
  for (auto& [id, t] : by_id) {
    if (labelled_only && (t.label.empty() || t.label == "none")) continue;
    std::stable_sort(t.points.begin(), t.points.end(), [](auto& p, auto& q) { return p.t_s < q.t_s; });
    trajectories.push_back(std::move(t));
  }
  return trajectories;
}

const classify::MapFeatures& MapOf(const std::map<std::string, classify::MapFeatures>& maps, const std::string& id) {
  static const classify::MapFeatures none;
  const auto m = maps.find(ScenarioOf(id));
  return m == maps.end() ? none : m->second;
}

}  // namespace

int PrepareTrackWindows(const params::Params& params, const std::vector<std::string>& tracks,
                        const std::vector<std::string>& scenarios, const std::string& out) {
  const auto& o = params.Get<classify::PreprocessOptions>("classify");
  const auto maps = ScenarioMaps(scenarios);
  const std::vector<classify::Trajectory> trajectories = ReadTrajectories(tracks, true);
  PrepareRunDirectory(out, params);
  std::map<std::string, std::map<std::string, long>> counts;
  const auto windows = classify::MakeWindows(trajectories, o, &counts);
  if (windows.empty()) throw InputError("classify prepare: no window survived preprocessing");
  const classify::PositionBounds bounds = classify::FitPositionBounds(windows, o);
  std::set<std::string> class_set;
  for (const auto& w : windows) class_set.insert(w.label);
  classify::PreparedDataset d;
  d.classes.assign(class_set.begin(), class_set.end());
  d.windows.features = classify::FeatureRows(o);
  d.windows.length = o.length;
  for (const auto& w : windows) {
    const classify::MapFeatures& map = MapOf(maps, w.object_id);
    const auto f = classify::Features(w, o, map, bounds);
    d.windows.x.insert(d.windows.x.end(), f.begin(), f.end());
    const auto h = classify::HandcraftedFeatures(w, map, o.features);
    d.handcrafted.insert(d.handcrafted.end(), h.begin(), h.end());
    d.AddWindow(w, static_cast<int>(std::find(d.classes.begin(), d.classes.end(), w.label) - d.classes.begin()));
  }
  d.info = {{"features", o.features},
            {"length", o.length},
            {"counts", counts},
            {"with_map", !maps.empty()},
            {"preprocessing", classify::PreprocessingJson(o, bounds)}};
  classify::WritePrepared(d, out);
  std::printf("classify prepare: %zu trajectories → %zu windows of %d × %d\n", trajectories.size(), windows.size(),
              d.windows.features, o.length);
  for (const auto& [step, per_class] : counts) {
    std::printf("  %-8s", step.c_str());
    for (const auto& [cls, n] : per_class) std::printf("  %s %ld", cls.c_str(), n);
    std::printf("\n");
  }
  return 0;
}

int EvaluateClassifier(const std::string& model_dir, const std::string& dataset, const std::string& out) {
  const classify::Classifier model = classify::Classifier::Load(model_dir + "/model");
  const classify::ForestBaseline forest = classify::ForestBaseline::Load(model_dir + "/forest.yml");
  classify::PreparedDataset d = classify::ReadPrepared(dataset);
  // Labels by name in the model's classes.
  for (size_t i = 0; i < d.labels.size(); ++i) {
    const auto it = std::find(model.classes().begin(), model.classes().end(), d.labels[i]);
    d.windows.y[i] = it == model.classes().end() ? -1 : static_cast<int>(it - model.classes().begin());
  }
  io::MakeOutputDir(out);
  const int k = static_cast<int>(model.classes().size());
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<float> network_p = model.Predict(d.windows);
  const double infer_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<float> forest_p = forest.Probabilities(d.handcrafted, k);
  const auto resnet = classify::Score(d.windows.y, classify::MostProbable(network_p, k), k);
  const auto rf = classify::Score(d.windows.y, classify::MostProbable(forest_p, k), k);  // = RTrees::predict
  const auto both =
      classify::Score(d.windows.y, classify::MostProbable(classify::CombinedProbabilities(network_p, forest_p), k), k);
  classify::WriteConfusionPng(resnet, model.classes(), "1D ResNet (" + model.options().variant + ")",
                              out + "/confusion_resnet.png");
  classify::WriteConfusionPng(rf, model.classes(), "random forest baseline", out + "/confusion_forest.png");
  classify::WriteConfusionPng(both, model.classes(), "ResNet + forest (mean probabilities)",
                              out + "/confusion_combined.png");
  io::RunReport report("classify eval");
  auto& j = report.json();
  j["inputs"] = {{"model", model_dir}, {"dataset", dataset}, {"windows", d.windows.size()}};
  j["metrics"] = {{"resnet", resnet.ToJson(model.classes())},
                  {"forest", rf.ToJson(model.classes())},
                  {"resnet+forest", both.ToJson(model.classes())}};
  j["timing"] = {{"inference_windows_per_s", d.windows.size() / std::max(1e-9, infer_s)}};
  for (const char* f : {"confusion_resnet.png", "confusion_forest.png", "confusion_combined.png"}) report.AddOutput(f);
  report.Write(out);
  std::printf(
      "classify eval: %zu windows; macro F1 ResNet %.3f (weighted %.3f), forest %.3f (weighted %.3f), both %.3f "
      "(weighted %.3f)\n",
      d.windows.size(), resnet.macro_f1, resnet.weighted_f1, rf.macro_f1, rf.weighted_f1, both.macro_f1,
      both.weighted_f1);
  for (int c = 0; c < k; ++c)
    std::printf("  %-12s F1 ResNet %.3f  forest %.3f  both %.3f  (%ld windows)\n", model.classes()[c].c_str(),
                resnet.f1[c], rf.f1[c], both.f1[c], resnet.support[c]);
  return 0;
}

int PredictTrackClasses(const std::string& model_dir, const std::vector<std::string>& tracks,
                        const std::vector<std::string>& scenarios, bool network_only, const std::string& out) {
  const classify::TrajectoryClassifier classifier =
      classify::TrajectoryClassifier::LoadDirectory(model_dir, network_only);
  const auto maps = ScenarioMaps(scenarios);
  const std::vector<classify::Trajectory> trajectories = ReadTrajectories(tracks, false);
  const std::vector<classify::Window> windows = classifier.Windows(trajectories);
  // Windows of one scenario share its map, so classify scenario by scenario.
  const auto& classes = classifier.classes();
  const size_t k = classes.size();
  std::vector<float> p(windows.size() * k);
  std::map<std::string, std::vector<size_t>> by_scenario;
  for (size_t i = 0; i < windows.size(); ++i) by_scenario[ScenarioOf(windows[i].object_id)].push_back(i);
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& [scenario, rows] : by_scenario) {
    std::vector<classify::Window> group;
    for (size_t i : rows) group.push_back(windows[i]);
    const auto q = classifier.Classify(group, MapOf(maps, group.front().object_id));
    for (size_t j = 0; j < rows.size(); ++j) std::copy_n(q.begin() + j * k, k, p.begin() + rows[j] * k);
  }
  const double infer_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  io::MakeOutputDir(out);
  const std::string header = ProbabilityHeader(classes);
  std::string window_csv = "object_id,t0_s,t1_s,class" + header + "\n";
  std::vector<int> truth, predicted;
  const std::vector<int> most_probable = classify::MostProbable(p, static_cast<int>(k));
  std::vector<std::string> ids;
  char buf[64];
  for (size_t i = 0; i < windows.size(); ++i) {
    const auto& w = windows[i];
    const int best = most_probable[i];
    std::snprintf(buf, sizeof(buf), ",%.3f,%.3f,", w.t0_s, w.points.back().t_s);
    window_csv += w.object_id + buf + classes[best];
    AppendProbabilities(window_csv, p.data() + i * k, k);
    window_csv += "\n";
    ids.push_back(w.object_id);
    const auto it = std::find(classes.begin(), classes.end(), w.label);
    if (it != classes.end()) truth.push_back(static_cast<int>(it - classes.begin())), predicted.push_back(best);
  }
  // An object's class: the mean of all its windows' probabilities, which is the
  // running mean at its last window.
  const std::vector<float> so_far = classify::RunningMeanByObject(ids, p, static_cast<int>(k));
  std::map<std::string, std::pair<size_t, long>> last_and_count;  // id → (last window, windows)
  for (size_t i = 0; i < ids.size(); ++i) {
    auto& [last, count] = last_and_count[ids[i]];
    last = i, ++count;
  }
  std::string object_csv = "object_id,windows,class" + header + "\n";
  std::map<std::string, long> per_class;
  for (const auto& [id, last_count] : last_and_count) {
    const float* mean = so_far.data() + last_count.first * k;
    const int best = static_cast<int>(std::max_element(mean, mean + k) - mean);
    ++per_class[classes[best]];
    object_csv += id + "," + std::to_string(last_count.second) + "," + classes[best];
    AppendProbabilities(object_csv, mean, k);
    object_csv += "\n";
  }
  io::WriteTextAtomically(out + "/windows.csv", window_csv);
  io::WriteTextAtomically(out + "/objects.csv", object_csv);
  io::RunReport report("classify predict");
  auto& j = report.json();
  j["inputs"] = {{"model", model_dir}, {"tracks", tracks}, {"trajectories", trajectories.size()}};
  j["combination"] = classifier.combination();
  j["windows"] = windows.size();
  j["objects_per_class"] = per_class;
  j["timing"] = {{"inference_windows_per_s", windows.size() / std::max(1e-9, infer_s)}};
  if (!truth.empty())  // the tracks carried labels: score the windows that had one
    j["metrics"] = classify::Score(truth, predicted, static_cast<int>(k)).ToJson(classes);
  report.AddOutput("windows.csv");
  report.AddOutput("objects.csv");
  report.Write(out);
  std::printf("classify predict: %zu tracks → %zu windows, %zu objects classified\n", trajectories.size(),
              windows.size(), last_and_count.size());
  for (const auto& [cls, n] : per_class) std::printf("  %-12s %ld\n", cls.c_str(), n);
  if (!truth.empty())
    std::printf("  labelled windows: %zu, macro F1 %.3f\n", truth.size(), j["metrics"]["macro_f1"].get<double>());
  return 0;
}

}  // namespace specht::pipeline
