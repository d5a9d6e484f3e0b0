#include "specht/classify/trajectory_classifier.h"

#include <filesystem>
#include <functional>
#include <sstream>

#include "specht/core/error.h"

namespace specht::classify {

nlohmann::json PreprocessingJson(const PreprocessOptions& o, const PositionBounds& b) {
  return {{"options_yaml", params::ToYaml(o)}, {"position_bounds", {b.min_x, b.max_x, b.min_y, b.max_y}}};
}

namespace {

// `key` of the model's extra JSON ("preprocessing", "input_preprocessing").
TrajectoryClassifier::Preprocessing ParsePreprocessing(const nlohmann::json& extra, const std::string& key,
                                                       const std::string& where) {
  TrajectoryClassifier::Preprocessing p;
  try {
    const auto& j = extra.at(key);
    p.options = params::FromYaml<PreprocessOptions>(j.at("options_yaml").get<std::string>(), where + " (" + key + ")");
    const auto b = j.at("position_bounds").get<std::vector<double>>();
    if (b.size() != 4) throw InputError(where + ": " + key + ".position_bounds needs 4 numbers");
    p.bounds = {b[0], b[1], b[2], b[3]};
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": " + key + ": " + e.what());
  }
  return p;
}

// The network's input: the windows' feature matrices, as at prepare.
Dataset Inputs(const std::vector<Window>& windows, const PreprocessOptions& o, const PositionBounds& bounds,
               const MapFeatures& map, const Classifier& model) {
  Dataset d;
  d.features = model.features(), d.length = model.length();
  for (const auto& w : windows) {
    const auto f = Features(w, o, map, bounds);
    d.x.insert(d.x.end(), f.begin(), f.end());
    d.y.push_back(-1);
    d.object_ids.push_back(w.object_id);
  }
  return d;
}

std::vector<float> Handcrafted(const std::vector<Window>& windows, const PreprocessOptions& o, const MapFeatures& map) {
  std::vector<float> rows;
  for (const auto& w : windows) {
    const auto h = HandcraftedFeatures(w, map, o.features);
    rows.insert(rows.end(), h.begin(), h.end());
  }
  return rows;
}

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Per window, the mean of `p` (one row per input window) over the input windows it
// owns; 1/classes each for a window that owns none.
std::vector<float> MeanPerOwner(const std::vector<float>& p, const std::vector<size_t>& owner, size_t windows,
                                size_t classes) {
  std::vector<double> sum(windows * classes, 0.0);
  std::vector<size_t> count(windows, 0);
  for (size_t j = 0; j < owner.size(); ++j) {
    ++count[owner[j]];
    for (size_t c = 0; c < classes; ++c) sum[owner[j] * classes + c] += p[j * classes + c];
  }
  std::vector<float> out(windows * classes, 1.0f / static_cast<float>(classes));
  for (size_t i = 0; i < windows; ++i)
    if (count[i])
      for (size_t c = 0; c < classes; ++c)
        out[i * classes + c] = static_cast<float>(sum[i * classes + c] / static_cast<double>(count[i]));
  return out;
}

}  // namespace

std::string ShorterWindowsProblem(const PreparedDataset& windows, const PreparedDataset& shorter) {
  if (windows.classes != shorter.classes) return "the datasets have other classes";
  auto options = [](const PreparedDataset& d, const std::string& which) {
    if (!d.info.contains("preprocessing"))
      throw InputError("the " + which + " dataset carries no preprocessing (prepare it again)");
    return ParsePreprocessing(d.info, "preprocessing", "the " + which + " dataset's dataset.json").options;
  };
  const PreprocessOptions w = options(windows, "scored");
  PreprocessOptions s = options(shorter, "shorter");
  if (s.length >= w.length || w.length % s.length != 0)
    return "its windows (" + std::to_string(s.length) + " points) must be shorter than " + std::to_string(w.length) +
           " and divide them";
  s.length = w.length;
  const std::vector<std::string> a = SplitLines(params::ToYaml(w)), b = SplitLines(params::ToYaml(s));
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] != b[i])
      return "the datasets were prepared differently beyond the window length: \"" + a[i] + "\" against \"" + b[i] +
             "\"";
  return a.size() == b.size() ? "" : "the datasets were prepared differently beyond the window length";
}

TrajectoryClassifier TrajectoryClassifier::Load(const std::string& path, const std::string& forest_path) {
  nlohmann::json extra;
  Classifier model = Classifier::Load(path, &extra);
  const std::string where = path + ".json";
  if (!extra.contains("preprocessing"))
    throw InputError(where +
                     ": the model carries no preprocessing (made before it was stored; re-run classify "
                     "prepare and train)");
  Preprocessing windows = ParsePreprocessing(extra, "preprocessing", where);
  std::optional<Preprocessing> inputs;
  if (extra.contains("input_preprocessing")) {
    inputs = ParsePreprocessing(extra, "input_preprocessing", where);
    if (inputs->options.length >= windows.options.length || windows.options.length % inputs->options.length != 0)
      throw InputError(where + ": the input windows (" + std::to_string(inputs->options.length) +
                       " points) must be shorter than the windows (" + std::to_string(windows.options.length) +
                       ") and divide them");
  }
  // The network takes the windows, or (trained on shorter windows, not fine-tuned) the input windows.
  const PreprocessOptions& takes =
      inputs && model.length() == inputs->options.length ? inputs->options : windows.options;
  if (FeatureRows(takes) != model.features() || takes.length != model.length())
    throw InputError(where + ": the preprocessing makes windows of " + std::to_string(FeatureRows(takes)) + " × " +
                     std::to_string(takes.length) + ", the network takes " + std::to_string(model.features()) + " × " +
                     std::to_string(model.length()));
  TrajectoryClassifier classifier(std::move(model), std::move(windows), std::move(inputs));
  if (!forest_path.empty()) classifier.forest_ = ForestBaseline::Load(forest_path);
  return classifier;
}

TrajectoryClassifier TrajectoryClassifier::LoadDirectory(const std::string& dir, bool network_only) {
  const std::string forest = dir + "/forest.yml";
  const bool combine = !network_only && std::filesystem::exists(forest);
  return Load(dir + "/model", combine ? forest : "");
}

std::optional<Window> TrajectoryClassifier::LatestWindow(const Trajectory& t) const {
  if (t.points.empty()) return std::nullopt;
  const PreprocessOptions& o = windows_.options;
  std::vector<Trajectory> pieces = Split(t, o);
  Trajectory& last = pieces.back();
  const size_t n = static_cast<size_t>(o.length);
  if (last.points.size() > n) last.points.erase(last.points.begin(), last.points.end() - n);
  std::vector<Window> w = Chunk(last, o);
  if (w.empty() || MeanStepLength(w[0].points) < o.stationary_threshold) return std::nullopt;
  return std::move(w[0]);
}

std::vector<Window> TrajectoryClassifier::Windows(const std::vector<Trajectory>& trajectories) const {
  return MakeWindows(trajectories, windows_.options);
}

std::vector<float> TrajectoryClassifier::Classify(const std::vector<Window>& windows, const MapFeatures& map) const {
  const size_t k = classes().size();
  // The input windows each window owns (see the header), when the models take shorter ones.
  std::vector<Window> pieces;
  std::vector<size_t> owner;
  if (inputs_) {
    const PreprocessOptions& in = inputs_->options;
    for (size_t i = 0; i < windows.size(); ++i) {
      const Window& w = windows[i];
      for (auto& piece : Chunk(Trajectory{w.object_id, w.label, w.points, w.category}, in)) {
        if (MeanStepLength(piece.points) < in.stationary_threshold) continue;
        pieces.push_back(std::move(piece));
        owner.push_back(i);
      }
    }
  }
  auto over_pieces = [&](const std::function<std::vector<float>()>& predict) {
    return MeanPerOwner(pieces.empty() ? std::vector<float>() : predict(), owner, windows.size(), k);
  };
  const std::vector<float> p =
      !inputs_ || model_.length() == windows_.options.length
          ? model_.Predict(Inputs(windows, windows_.options, windows_.bounds, map, model_))
          : over_pieces([&] { return model_.Predict(Inputs(pieces, inputs_->options, inputs_->bounds, map, model_)); });
  if (!forest_) return p;
  const int classes = static_cast<int>(k);
  const std::vector<float> forest =
      inputs_ ? over_pieces([&] { return forest_->Probabilities(Handcrafted(pieces, inputs_->options, map), classes); })
              : forest_->Probabilities(Handcrafted(windows, windows_.options, map), classes);
  return CombinedProbabilities(p, forest);
}

}  // namespace specht::classify
