// `specht classify prepare|train|eval|crossval|predict`: the trajectory classifier (classify module).
//   prepare <tracks.csv>... [--scenario S.yaml]... -o DIR
//       object tracks (io/object_tracks.h; label = truth_class, else class) →
//       windows (section "classify"), with map features from the scenario whose name
//       is the second part of the track id ("s3/urban-crossing/t7": its true static
//       grid and parking bays as points of interest); writes dataset_io.h's files
//       and the class counts after each step.
//   train <dataset> -o DIR [--resume]   the 1D ResNet (section "classify_model") with a
//       held-out validation split by object, and the random-forest baseline on the
//       same split; progress per epoch; writes model.pt/.json, forest.yml,
//       training.csv; checkpoint.pt after every epoch (--resume continues from it).
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
#include "scenario_map_features.h"
#include "specht/classify/baseline.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/model.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/object_tracks.h"
#include "specht/io/report.h"
#include "specht/sim/scenario.h"

namespace specht::app {
namespace {

struct ClassifyArgs {
  CommonArgs common;
  std::vector<std::string> inputs, scenarios;
  std::string model_dir, dataset;
  bool resume = false, network_only = false;
  classify::PseudoLabelOptions pseudo_labels;  // train --pseudo-labels, --pseudo-label-rounds
};

std::map<std::string, classify::MapFeatures> ScenarioMaps(const std::vector<std::string>& paths) {
  std::map<std::string, classify::MapFeatures> maps;
  for (const auto& path : paths) {
    const sim::Scenario s = sim::LoadScenario(path);
    maps[s.name] = ScenarioMapFeatures(s);
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
  for (const auto& path : paths)
    for (const auto& s : io::ReadObjectTracks(path)) {
      auto& t = by_id[s.id];
      t.object_id = s.id;
      t.label = s.truth_cls.empty() ? s.cls : s.truth_cls;
      t.points.push_back({s.t_s, s.x_m, s.y_m});
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
  const classify::TrajectoryClassifier classifier = LoadTrainedClassifier(a.model_dir, a.network_only);
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
    std::printf("  labelled windows: %zu, macro F1 %.3f\n", truth.size(),
                j["metrics"]["macro_f1"].get<double>());
  return 0;
}

}  // namespace

int RunClassifierTraining(const CommonArgs& common, const params::Params& params, const classify::ModelOptions& o,
                          const std::string& dataset, bool resume, const classify::PseudoLabelOptions& pseudo_labels,
                          const std::string& label) {
  pseudo_labels.Check();
  classify::PreparedDataset d = classify::ReadPrepared(dataset);
  const classify::PreparedDataset unlabelled = classify::SplitOffUnlabelled(d);
  if (pseudo_labels.on() && unlabelled.windows.size() == 0)
    throw InputError(dataset + ": no unlabelled windows for --pseudo-labels (AIS: prepare with ais.unlabelled)");
  std::vector<size_t> train_rows, val_rows;
  classify::SplitByObject(d.windows.object_ids, o.validation_fraction, o.seed, train_rows, val_rows);
  classify::Dataset labelled = d.windows.Subset(train_rows);
  if (o.distillation > 0) labelled.teacher = classify::OutOfFoldForest(d, train_rows, o.seed);
  const classify::Dataset val = d.windows.Subset(val_rows);
  PrepareOutputDir(common, params);
  const std::string& out = common.out_dir;

  // The forest first: it is the pseudo-labels' teacher.
  const int k = static_cast<int>(d.classes.size());
  classify::ForestBaseline forest(200, 12, o.seed);
  forest.Train(classify::HandcraftedRows(d, train_rows), labelled.y);
  forest.Save(out + "/forest.yml");

  // One network trained on `windows`; with several rounds each has its own checkpoint,
  // so --resume continues the round it stopped in (finished rounds return at once).
  const int rounds = pseudo_labels.on() ? pseudo_labels.rounds : 1;
  std::string log;
  size_t epochs = 0, trained_windows = 0, last_round_windows = 0;
  std::vector<std::string> checkpoints;
  const auto t0 = std::chrono::steady_clock::now();
  const classify::TrainNetwork train = [&](const classify::Dataset& windows, int round) {
    classify::Classifier model(o, d.windows.features, d.windows.length, d.classes);
    const std::string name = rounds > 1 ? label + " round " + std::to_string(round) : label;
    ProgressLine progress(name, "epochs", !common.quiet, 0.0);
    log = "epoch,train_loss,validation_loss,validation_macro_f1,learning_rate,seconds\n";  // the last round's
    checkpoints.push_back(rounds > 1 ? "checkpoint-round" + std::to_string(round) + ".pt" : "checkpoint.pt");
    const std::string checkpoint = out + "/" + checkpoints.back();
    if (!resume) std::remove(checkpoint.c_str());
    const auto reports = model.Train(windows, val, [&](const classify::EpochReport& r) {
      char line[160], note[120];
      std::snprintf(line, sizeof(line), "%d,%.5f,%.5f,%.4f,%.2e,%.2f\n", r.epoch, r.train_loss, r.validation_loss,
                    r.validation_macro_f1, r.learning_rate, r.seconds);
      log += line;
      std::snprintf(note, sizeof(note), "loss %.4f val loss %.4f val F1 %.3f", r.train_loss, r.validation_loss,
                    r.validation_macro_f1);
      progress.Update(r.epoch, static_cast<double>(r.epoch) / o.epochs, note);
    }, checkpoint);
    progress.Finish();
    epochs += reports.size(), trained_windows += windows.size() * reports.size();
    last_round_windows = windows.size();
    return model;
  };
  std::vector<std::vector<long>> pseudo_per_round;
  const classify::Classifier model =
      pseudo_labels.on() ? classify::SelfTrain(train, labelled, unlabelled, forest.Probabilities(unlabelled.handcrafted, k),
                                               pseudo_labels, k, pseudo_per_round)
                         : train(labelled, 1);
  const double train_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  model.Save(out + "/model", d.info);
  io::WriteTextAtomically(out + "/training.csv", log);

  const auto resnet = classify::Score(val.y, model.PredictClasses(val), k);
  const auto rf = classify::Score(val.y, forest.Predict(classify::HandcraftedRows(d, val_rows)), k);
  io::RunReport report(label);
  auto& j = report.json();
  j["dataset"] = dataset;
  j["windows"] = {{"train", last_round_windows}, {"validation", val.size()}};  // pseudo-labelled ones included
  if (pseudo_labels.on()) {
    j["pseudo_labels"] = {{"votes", pseudo_labels.votes},   {"rounds", pseudo_labels.rounds},
                          {"classes", d.classes},           {"per_class", pseudo_per_round.back()},
                          {"per_round", pseudo_per_round}, {"unlabelled_windows", unlabelled.windows.size()}};
  }
  j["model"] = {{"variant", o.variant}, {"parameters", model.parameter_count()}, {"epochs", epochs}};
  j["validation"] = {{"resnet", resnet.ToJson(d.classes)}, {"forest", rf.ToJson(d.classes)}};
  j["timing"] = {{"train_s", train_s}, {"train_windows_per_s", trained_windows / train_s}};
  for (const char* f : {"model.pt", "model.json", "forest.yml", "training.csv"}) report.AddOutput(f);
  for (const auto& c : checkpoints) report.AddOutput(c);
  report.Write(out);
  std::printf("%s: %zu epochs, %.1f s (%.0f windows/s); validation macro F1: ResNet %.3f, forest %.3f\n", label.c_str(),
              epochs, train_s, trained_windows / train_s, resnet.macro_f1, rf.macro_f1);
  return 0;
}

classify::TrajectoryClassifier LoadTrainedClassifier(const std::string& model_dir, bool network_only) {
  const std::string forest = model_dir + "/forest.yml";
  const bool combine = !network_only && std::filesystem::exists(forest);
  return classify::TrajectoryClassifier::Load(model_dir + "/model", combine ? forest : "");
}

void AddClassifyCommand(CLI::App& app, int& exit_code) {
  CLI::App* cmd = app.add_subcommand("classify", "trajectory classification: prepare windows, train, evaluate, predict");
  cmd->require_subcommand(1);
  auto prep = std::make_shared<ClassifyArgs>();
  CLI::App* p = cmd->add_subcommand("prepare", "object tracks (CSV) to feature windows");
  p->add_option("tracks", prep->inputs, "object-track CSV files (id,t_s,x_m,y_m[,class][,truth_class])")->required();
  p->add_option("--scenario", prep->scenarios, "scenario files for map features (matched by name in the ids)");
  AddCommonOptions(*p, prep->common, "specht-out/classify-data");
  p->callback([prep, &exit_code] { exit_code = RunPrepare(*prep); });

  auto train = std::make_shared<ClassifyArgs>();
  CLI::App* t = cmd->add_subcommand("train", "train the 1D ResNet and the random-forest baseline");
  t->add_option("dataset", train->dataset, "a directory written by prepare")->required();
  t->add_flag("--resume", train->resume, "continue from the output directory's checkpoint.pt");
  AddPseudoLabelOption(*t, train->pseudo_labels);
  AddCommonOptions(*t, train->common, "specht-out/classify-model");
  t->callback([train, &exit_code] {
    const params::Params params = LoadParams(train->common);
    exit_code = RunClassifierTraining(train->common, params, params.Get<classify::ModelOptions>("classify_model"),
                                      train->dataset, train->resume, train->pseudo_labels, "classify train");
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
