#include "specht/classify/trajectory_classifier.h"

#include "specht/core/error.h"

namespace specht::classify {

nlohmann::json PreprocessingJson(const PreprocessOptions& o, const PositionBounds& b) {
  return {{"options_yaml", params::ToYaml(o)}, {"position_bounds", {b.min_x, b.max_x, b.min_y, b.max_y}}};
}

TrajectoryClassifier TrajectoryClassifier::Load(const std::string& path, const std::string& forest_path) {
  nlohmann::json extra;
  Classifier model = Classifier::Load(path, &extra);
  const std::string where = path + ".json";
  if (!extra.contains("preprocessing"))
    throw InputError(where + ": the model carries no preprocessing (made before it was stored; re-run classify "
                             "prepare and train)");
  PositionBounds bounds;
  PreprocessOptions o;
  try {
    const auto& p = extra.at("preprocessing");
    o = params::FromYaml<PreprocessOptions>(p.at("options_yaml").get<std::string>(), where + " (preprocessing)");
    const auto b = p.at("position_bounds").get<std::vector<double>>();
    if (b.size() != 4) throw InputError(where + ": position_bounds needs 4 numbers");
    bounds = {b[0], b[1], b[2], b[3]};
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": preprocessing: " + e.what());
  }
  if (FeatureRows(o) != model.features() || o.length != model.length())
    throw InputError(where + ": the preprocessing makes windows of " + std::to_string(FeatureRows(o)) + " × " +
                     std::to_string(o.length) + ", the network takes " + std::to_string(model.features()) + " × " +
                     std::to_string(model.length()));
  TrajectoryClassifier classifier(std::move(model), std::move(o), bounds);
  if (!forest_path.empty()) classifier.forest_ = ForestBaseline::Load(forest_path);
  return classifier;
}

std::optional<Window> TrajectoryClassifier::LatestWindow(const Trajectory& t) const {
  if (t.points.empty()) return std::nullopt;
  std::vector<Trajectory> pieces = Split(t, options_);
  Trajectory& last = pieces.back();
  const size_t n = static_cast<size_t>(options_.length);
  if (last.points.size() > n) last.points.erase(last.points.begin(), last.points.end() - n);
  std::vector<Window> w = Chunk(last, options_);
  if (w.empty() || MeanStepLength(w[0].points) < options_.stationary_threshold) return std::nullopt;
  return std::move(w[0]);
}

std::vector<Window> TrajectoryClassifier::Windows(const std::vector<Trajectory>& trajectories) const {
  return MakeWindows(trajectories, options_);
}

std::vector<float> TrajectoryClassifier::Classify(const std::vector<Window>& windows, const MapFeatures& map) const {
  Dataset d;
  d.features = model_.features(), d.length = model_.length();
  std::vector<float> handcrafted;
  for (const auto& w : windows) {
    const auto f = Features(w, options_, map, bounds_);
    d.x.insert(d.x.end(), f.begin(), f.end());
    d.y.push_back(-1);
    d.object_ids.push_back(w.object_id);
    if (!forest_) continue;
    const auto h = HandcraftedFeatures(w, map, options_.features);
    handcrafted.insert(handcrafted.end(), h.begin(), h.end());
  }
  std::vector<float> p = model_.Predict(d);
  if (forest_) p = CombinedProbabilities(p, forest_->Probabilities(handcrafted, static_cast<int>(classes().size())));
  return p;
}

}  // namespace specht::classify
