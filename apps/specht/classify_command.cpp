// `specht classify prepare|train|eval|crossval|predict`: the trajectory classifier (classify module).
//   prepare <tracks.csv>... [--scenario S.yaml]... -o DIR
//       object tracks (io/object_tracks.h; label = truth_class, else class) →
//       windows (section "classify"), with map features from the scenario whose name
//       is the second part of the track id ("s3/urban-crossing/t7": its true static
//       grid and parking bays as points of interest); writes dataset_io.h's files
//       and the class counts after each step.
//   train <dataset> -o DIR [--resume] [--train-on SHORTER [--fine-tune RATE]]
//       the 1D ResNet (section "classify_model") with a held-out validation split by
//       object, and the random-forest baseline on the same split; progress per
//       epoch; writes model.pt/.json, forest.yml, training.csv; checkpoint.pt after
//       every epoch (--resume continues from it). --train-on: both learn from the
//       shorter windows of every object and the model classifies the dataset's
//       windows by the mean over those within (as crossval --train-on scores them);
//       --fine-tune then tunes the network on the dataset's windows (fine_tuning.csv).
//   eval <model dir> <dataset> -o DIR   macro/weighted/per-class F1 of both and of the
//       two combined (mean probabilities), confusion
//       matrices as PNG, inference rate.
//   crossval <dataset> -o DIR [--folds 5] [--repeats 1] [--networks tiny,mlp]
//       k-fold cross-validation with folds disjoint by track (crossval_command.cpp,
//       as `ais eval`): every network, the forest and each network combined with
//       it, scored per window, per track and from the track's windows so far;
//       --repeats R deals the tracks to the folds R times.
//   predict <model dir> <tracks.csv>... [--scenario S.yaml]... -o DIR   classes of
//       new tracks with the model's own preprocessing, the network's probabilities
//       averaged with the forest's (--network-only: the network's): windows.csv (one row per
//       window) and objects.csv (per track, mean of its windows' probabilities).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "commands.h"
#include "probability_csv.h"
#include "run_setup.h"
#include "specht/classify/baseline.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/model.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/object_tracks.h"
#include "specht/io/report.h"
#include "specht/pipeline/map_features.h"
#include "specht/sim/scenario.h"

namespace specht::app {
namespace {

struct ClassifyArgs {
  CommonArgs common;
  std::vector<std::string> inputs, scenarios;
  std::string model_dir, dataset;
  bool network_only = false;
  TrainingArgs training;  // train
};

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

int RunPrepare(const ClassifyArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& o = params.Get<classify::PreprocessOptions>("classify");
  const auto maps = ScenarioMaps(a.scenarios);
  const std::vector<classify::Trajectory> trajectories = ReadTrajectories(a.inputs, true);
  PrepareOutputDir(a.common, params);
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
  classify::WritePrepared(d, a.common.out_dir);
  std::printf("classify prepare: %zu trajectories → %zu windows of %d × %d\n", trajectories.size(), windows.size(),
              d.windows.features, o.length);
  for (const auto& [step, per_class] : counts) {
    std::printf("  %-8s", step.c_str());
    for (const auto& [cls, n] : per_class) std::printf("  %s %ld", cls.c_str(), n);
    std::printf("\n");
  }
  return 0;
}

int RunEval(const ClassifyArgs& a) {
  const classify::Classifier model = classify::Classifier::Load(a.model_dir + "/model");
  const classify::ForestBaseline forest = classify::ForestBaseline::Load(a.model_dir + "/forest.yml");
  classify::PreparedDataset d = classify::ReadPrepared(a.dataset);
  // Labels by name in the model's classes.
  for (size_t i = 0; i < d.labels.size(); ++i) {
    const auto it = std::find(model.classes().begin(), model.classes().end(), d.labels[i]);
    d.windows.y[i] = it == model.classes().end() ? -1 : static_cast<int>(it - model.classes().begin());
  }
  io::MakeOutputDir(a.common.out_dir);
  const std::string& out = a.common.out_dir;
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
  j["inputs"] = {{"model", a.model_dir}, {"dataset", a.dataset}, {"windows", d.windows.size()}};
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

int RunPredict(const ClassifyArgs& a) {
  const classify::TrajectoryClassifier classifier =
      classify::TrajectoryClassifier::LoadDirectory(a.model_dir, a.network_only);
  const auto maps = ScenarioMaps(a.scenarios);
  const std::vector<classify::Trajectory> trajectories = ReadTrajectories(a.inputs, false);
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

  io::MakeOutputDir(a.common.out_dir);
  const std::string& out = a.common.out_dir;
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
  j["inputs"] = {{"model", a.model_dir}, {"tracks", a.inputs}, {"trajectories", trajectories.size()}};
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

}  // namespace

void AddTrainingOptions(CLI::App& cmd, TrainingArgs& args, const std::string& prepare) {
  cmd.add_option("dataset", args.dataset, "a directory written by " + prepare)->required();
  cmd.add_flag("--resume", args.resume, "continue from the output directory's checkpoint.pt");
  AddPseudoLabelOption(cmd, args.pseudo_labels);
  cmd.add_option("--train-on", args.train_on,
                 "another directory written by " + prepare +
                     " from the same tracks with shorter windows (a "
                     "divisor of this dataset's length): both models learn from its windows of every object, also "
                     "of objects too short for this dataset's windows, and the model classifies a window by the mean "
                     "over the shorter windows within it, as eval --train-on scores it");
  cmd.add_option("--fine-tune", args.fine_tune,
                 "with --train-on: the network, once trained on the shorter windows, continues on this dataset's "
                 "windows at this learning rate (e.g. 1e-4) and classifies them itself; 0: off")
      ->check(CLI::Range(0.0, 0.999));
}

namespace {

// One line per epoch of training.csv and fine_tuning.csv.
constexpr const char* kEpochHeader = "epoch,train_loss,validation_loss,validation_macro_f1,learning_rate,seconds\n";

// Logs an epoch to `log` and the progress line.
void LogEpoch(const classify::EpochReport& r, int epochs, std::string& log, ProgressLine& progress) {
  char line[160], note[120];
  std::snprintf(line, sizeof(line), "%d,%.5f,%.5f,%.4f,%.2e,%.2f\n", r.epoch, r.train_loss, r.validation_loss,
                r.validation_macro_f1, r.learning_rate, r.seconds);
  log += line;
  std::snprintf(note, sizeof(note), "loss %.4f val loss %.4f val F1 %.3f", r.train_loss, r.validation_loss,
                r.validation_macro_f1);
  progress.Update(r.epoch, static_cast<double>(r.epoch) / epochs, note);
}

// The datasets a training reads: the labelled windows, the unlabelled ones (for
// pseudo-labels) and, with --train-on, the shorter windows the models learn from;
// every combination of options that cannot work is refused before any training.
struct TrainingData {
  classify::PreparedDataset d, unlabelled, shorter;
  bool on_shorter = false;
  const classify::PreparedDataset& src() const { return on_shorter ? shorter : d; }  // what the models learn from
};

TrainingData ReadTrainingData(const TrainingArgs& a, const classify::ModelOptions& o) {
  a.pseudo_labels.Check();
  if (a.fine_tune > 0 && a.train_on.empty()) throw InputError("--fine-tune: goes with --train-on");
  if (!a.train_on.empty() && a.pseudo_labels.on()) throw InputError("--train-on: not with --pseudo-labels");
  if (a.fine_tune > 0 && o.variant == "mlp")
    throw InputError("--fine-tune: an mlp takes one window length, it cannot be fine-tuned (variant tiny, shallow, …)");
  TrainingData t;
  t.d = classify::ReadPrepared(a.dataset);
  t.unlabelled = classify::SplitOffUnlabelled(t.d);
  if (a.pseudo_labels.on() && t.unlabelled.windows.size() == 0)
    throw InputError(a.dataset + ": no unlabelled windows for --pseudo-labels (AIS: prepare with ais.unlabelled)");
  t.on_shorter = !a.train_on.empty();
  if (t.on_shorter) {
    t.shorter = classify::ReadPrepared(a.train_on);
    classify::SplitOffUnlabelled(t.shorter);
    const std::string problem = classify::ShorterWindowsProblem(t.d, t.shorter);
    if (!problem.empty()) throw InputError("--train-on " + a.train_on + ": " + problem);
  }
  return t;
}

// The network's and the forest's probabilities for the dataset's windows `rows` as
// the saved model gives them: with shorter windows the mean over those within each
// (WindowsWithin), unless the network was fine-tuned on the windows themselves.
std::pair<std::vector<float>, std::vector<float>> ModelProbabilities(const TrainingData& t,
                                                                     const classify::Classifier& network,
                                                                     const classify::ForestBaseline& forest,
                                                                     const std::vector<size_t>& rows, bool fine_tuned) {
  const int k = static_cast<int>(t.d.classes.size());
  if (!t.on_shorter)
    return {network.Predict(t.d.windows.Subset(rows)), forest.Probabilities(classify::HandcraftedRows(t.d, rows), k)};
  const auto within = classify::WindowsWithin(t.d, t.shorter);
  std::set<size_t> inside;
  for (size_t i : rows) inside.insert(within[i].begin(), within[i].end());
  const std::vector<size_t> short_rows(inside.begin(), inside.end());
  auto mean_within = [&](const std::vector<float>& p) { return classify::MeanWithin(p, short_rows, within, rows, k); };
  return {fine_tuned ? network.Predict(t.d.windows.Subset(rows))
                     : mean_within(network.Predict(t.shorter.windows.Subset(short_rows))),
          mean_within(forest.Probabilities(classify::HandcraftedRows(t.shorter, short_rows), k))};
}

}  // namespace

int RunClassifierTraining(const CommonArgs& common, const params::Params& params, const classify::ModelOptions& o,
                          const TrainingArgs& a, const std::string& label) {
  const TrainingData data = ReadTrainingData(a, o);
  const classify::PreparedDataset &d = data.d, &unlabelled = data.unlabelled, &src = data.src();
  const bool on_shorter = data.on_shorter;
  // Validation objects by a hash of the id (SplitByObject): the same objects in both
  // datasets, so a validation vessel's long windows are never tuned on either.
  std::vector<size_t> train_rows, val_rows, long_train_rows, long_val_rows;
  classify::SplitByObject(src.windows.object_ids, o.validation_fraction, o.seed, train_rows, val_rows);
  classify::SplitByObject(d.windows.object_ids, o.validation_fraction, o.seed, long_train_rows, long_val_rows);
  classify::Dataset labelled = src.windows.Subset(train_rows);
  if (o.distillation > 0) labelled.teacher = classify::OutOfFoldForest(src, train_rows, o.seed);
  const classify::Dataset val = src.windows.Subset(val_rows);
  PrepareOutputDir(common, params);
  const std::string& out = common.out_dir;

  // The forest first: it is the pseudo-labels' teacher.
  const int k = static_cast<int>(d.classes.size());
  classify::ForestBaseline forest(200, 12, o.seed);
  forest.Train(classify::HandcraftedRows(src, train_rows), labelled.y);
  forest.Save(out + "/forest.yml");

  // One network trained on `windows`; with several rounds each has its own checkpoint,
  // so --resume continues the round it stopped in (finished rounds return at once).
  const int rounds = a.pseudo_labels.on() ? a.pseudo_labels.rounds : 1;
  std::string log;
  size_t epochs = 0, trained_windows = 0, last_round_windows = 0;
  std::vector<std::string> checkpoints;
  const auto t0 = std::chrono::steady_clock::now();
  const classify::TrainNetwork train = [&](const classify::Dataset& windows, int round) {
    classify::Classifier model(o, src.windows.features, src.windows.length, d.classes);
    const std::string name = rounds > 1 ? label + " round " + std::to_string(round) : label;
    ProgressLine progress(name, "epochs", !common.quiet, 0.0);
    log = kEpochHeader;  // the last round's
    checkpoints.push_back(rounds > 1 ? "checkpoint-round" + std::to_string(round) + ".pt" : "checkpoint.pt");
    const std::string checkpoint = out + "/" + checkpoints.back();
    if (!a.resume) std::remove(checkpoint.c_str());
    const auto reports = model.Train(
        windows, val, [&](const classify::EpochReport& r) { LogEpoch(r, o.epochs, log, progress); }, checkpoint);
    progress.Finish();
    epochs += reports.size(), trained_windows += windows.size() * reports.size();
    last_round_windows = windows.size();
    return model;
  };
  std::vector<std::vector<long>> pseudo_per_round;
  classify::Classifier model =
      a.pseudo_labels.on()
          ? classify::SelfTrain(train, labelled, unlabelled, forest.Probabilities(unlabelled.handcrafted, k),
                                a.pseudo_labels, k, pseudo_per_round)
          : train(labelled, 1);
  // Fine-tuning (--fine-tune): on to the dataset's own windows, no checkpoint (a
  // resumed run tunes again from the trained network, to the same result).
  const classify::Dataset long_val = d.windows.Subset(long_val_rows);
  size_t tuned_epochs = 0;
  if (a.fine_tune > 0) {
    std::string tuning_log = kEpochHeader;
    ProgressLine progress(label + " fine-tuning", "epochs", !common.quiet, 0.0);
    const auto reports =
        model.FineTune(d.windows.Subset(long_train_rows), long_val, a.fine_tune,
                       [&](const classify::EpochReport& r) { LogEpoch(r, o.epochs, tuning_log, progress); });
    progress.Finish();
    tuned_epochs = reports.size(), trained_windows += long_train_rows.size() * reports.size();
    io::WriteTextAtomically(out + "/fine_tuning.csv", tuning_log);
  }
  const double train_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json extra = d.info;
  if (on_shorter) extra["input_preprocessing"] = data.shorter.info.at("preprocessing");
  model.Save(out + "/model", extra);
  io::WriteTextAtomically(out + "/training.csv", log);

  // Validation: the dataset's windows of the validation objects, scored as the saved model classifies them.
  const auto [network_p, forest_p] = ModelProbabilities(data, model, forest, long_val_rows, a.fine_tune > 0);
  const auto resnet = classify::Score(long_val.y, classify::MostProbable(network_p, k), k);
  const auto rf = classify::Score(long_val.y, classify::MostProbable(forest_p, k), k);
  io::RunReport report(label);
  auto& j = report.json();
  j["dataset"] = a.dataset;
  j["windows"] = {{"train", last_round_windows}, {"validation", val.size()}};  // pseudo-labelled ones included
  if (on_shorter) {
    j["train_on"] = {{"dataset", a.train_on},
                     {"length", src.windows.length},
                     {"fine_tune_learning_rate", a.fine_tune},
                     {"fine_tuning_windows", a.fine_tune > 0 ? long_train_rows.size() : 0},
                     {"fine_tuning_epochs", tuned_epochs}};
  }
  if (a.pseudo_labels.on()) {
    j["pseudo_labels"] = {{"votes", a.pseudo_labels.votes}, {"rounds", a.pseudo_labels.rounds},
                          {"classes", d.classes},           {"per_class", pseudo_per_round.back()},
                          {"per_round", pseudo_per_round},  {"unlabelled_windows", unlabelled.windows.size()}};
  }
  j["model"] = {{"variant", o.variant}, {"parameters", model.parameter_count()}, {"epochs", epochs}};
  j["validation"] = {
      {"windows", long_val.size()}, {"resnet", resnet.ToJson(d.classes)}, {"forest", rf.ToJson(d.classes)}};
  j["timing"] = {{"train_s", train_s}, {"train_windows_per_s", trained_windows / train_s}};
  for (const char* f : {"model.pt", "model.json", "forest.yml", "training.csv"}) report.AddOutput(f);
  if (a.fine_tune > 0) report.AddOutput("fine_tuning.csv");
  for (const auto& c : checkpoints) report.AddOutput(c);
  if (InterruptRequested()) report.SetInterrupted(std::to_string(epochs) + " epochs (continue with --resume)");
  report.Write(out);
  const std::string tuned = a.fine_tune > 0 ? " + " + std::to_string(tuned_epochs) + " fine-tuning" : "";
  std::printf(
      "%s: %zu epochs%s, %.1f s (%.0f windows/s); validation macro F1 (%zu windows): ResNet %.3f, forest %.3f\n",
      label.c_str(), epochs, tuned.c_str(), train_s, trained_windows / train_s, long_val.size(), resnet.macro_f1,
      rf.macro_f1);
  return InterruptExitCode();
}

void AddClassifyCommand(CLI::App& app, int& exit_code) {
  CLI::App* cmd =
      app.add_subcommand("classify", "trajectory classification: prepare windows, train, evaluate, predict");
  cmd->require_subcommand(1);
  auto prep = std::make_shared<ClassifyArgs>();
  CLI::App* p = cmd->add_subcommand("prepare", "object tracks (CSV) to feature windows");
  p->add_option("tracks", prep->inputs, "object-track CSV files (id,t_s,x_m,y_m[,class][,truth_class])")->required();
  p->add_option("--scenario", prep->scenarios, "scenario files for map features (matched by name in the ids)");
  AddCommonOptions(*p, prep->common, "specht-out/classify-data");
  p->callback([prep, &exit_code] { exit_code = RunPrepare(*prep); });

  auto train = std::make_shared<ClassifyArgs>();
  CLI::App* t = cmd->add_subcommand("train", "train the 1D ResNet and the random-forest baseline");
  AddTrainingOptions(*t, train->training, "classify prepare");
  AddCommonOptions(*t, train->common, "specht-out/classify-model");
  t->callback([train, &exit_code] {
    const params::Params params = LoadParams(train->common);
    exit_code = RunClassifierTraining(train->common, params, params.Get<classify::ModelOptions>("classify_model"),
                                      train->training, "classify train");
  });

  auto ev = std::make_shared<ClassifyArgs>();
  CLI::App* e = cmd->add_subcommand("eval", "F1 and confusion matrices on a prepared dataset");
  e->add_option("model", ev->model_dir, "a directory written by train")->required();
  e->add_option("dataset", ev->dataset, "a directory written by prepare")->required();
  AddCommonOptions(*e, ev->common, "specht-out/classify-eval");
  e->callback([ev, &exit_code] { exit_code = RunEval(*ev); });

  auto cv = std::make_shared<CrossValidationArgs>();
  CLI::App* c = cmd->add_subcommand("crossval", "k-fold cross-validation with folds disjoint by track");
  const CrossValidationNames names{"classify crossval", "classify prepare", "track", "tracks",
                                   "specht-out/classify-crossval"};
  AddCrossValidationOptions(*c, *cv, names);
  c->callback([cv, names, &exit_code] {
    const params::Params params = LoadParams(cv->common);
    exit_code = RunCrossValidation(*cv, params, params.Get<classify::ModelOptions>("classify_model"), names);
  });

  auto pr = std::make_shared<ClassifyArgs>();
  CLI::App* q = cmd->add_subcommand("predict", "classify object tracks (CSV) with a trained model");
  q->add_option("model", pr->model_dir, "a directory written by train")->required();
  q->add_option("tracks", pr->inputs, "object-track CSV files (id,t_s,x_m,y_m[,...])")->required();
  q->add_option("--scenario", pr->scenarios, "scenario files for map features (matched by name in the ids)");
  q->add_flag("--network-only", pr->network_only, "the network alone (default: combined with the model's forest.yml)");
  AddCommonOptions(*q, pr->common, "specht-out/classify-predict");
  q->callback([pr, &exit_code] { exit_code = RunPredict(*pr); });
}

}  // namespace specht::app
