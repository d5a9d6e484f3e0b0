// Training and cross-validation runs of the trajectory classifier on prepared
// datasets (classifier_runs.h), shared by `specht classify` and `specht ais`.
#include "specht/pipeline/classifier_runs.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "internal/probability_csv.h"
#include "specht/classify/baseline.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/report.h"
#include "specht/pipeline/run_directory.h"

namespace specht::pipeline {
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

TrainingData ReadTrainingData(const TrainingInputs& a, const classify::ModelOptions& o) {
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

int TrainClassifier(const params::Params& params, const classify::ModelOptions& o, const TrainingInputs& a,
                    const std::string& label, const std::string& out, bool quiet) {
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
  PrepareRunDirectory(out, params);

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
    ProgressLine progress(name, "epochs", !quiet, 0.0);
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
    ProgressLine progress(label + " fine-tuning", "epochs", !quiet, 0.0);
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

namespace {

std::vector<std::string> SplitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string x; std::getline(in, x, ',');)
    if (!x.empty()) out.push_back(x);
  return out;
}

// predictions.csv: per window, repeat and model, the fold that tested it, the truth,
// the prediction and the class probabilities (join with the dataset's windows.csv by
// index).
void WritePredictions(const classify::CrossValidationResult& result, const classify::PreparedDataset& d,
                      const std::string& path) {
  const size_t k = d.classes.size(), n = d.windows.size();
  std::string csv = "index,object_id,repeat,fold,model,truth,predicted" + ProbabilityHeader(d.classes) + "\n";
  for (const auto& name : result.models) {
    const std::vector<float>& p = result.probabilities.at(name);
    const std::vector<int> predicted = classify::MostProbable(p, static_cast<int>(k));
    for (size_t row = 0; row < p.size() / k; ++row) {
      const size_t i = row % n;
      csv += std::to_string(i) + ',' + d.windows.object_ids[i] + ',' + std::to_string(row / n) + ',' +
             std::to_string(result.fold_of[row]) + ',' + name + ',' + d.classes[static_cast<size_t>(d.windows.y[i])] +
             ',' + d.classes[static_cast<size_t>(predicted[row])];
      AppendProbabilities(csv, p.data() + row * k, k);
      csv += '\n';
    }
  }
  io::WriteTextAtomically(path, csv);
}

// The network variants, "tiny, shallow, …", for the help and for errors.
}  // namespace

std::string ModelVariantList() {
  std::string list;
  for (const auto& v : classify::ModelVariants()) list += (list.empty() ? "" : ", ") + v;
  return list;
}

namespace {

classify::CrossValidationOptions OptionsOf(const CrossValidationInputs& a, const classify::ModelOptions& base) {
  classify::CrossValidationOptions cv;
  cv.folds = a.folds;
  cv.repeats = a.repeats;
  cv.seed = base.seed;
  cv.forest = !a.no_forest;
  cv.pseudo_labels = a.pseudo_labels;
  if (a.fine_tune > 0 && a.train_on.empty()) throw InputError("--fine-tune: goes with --train-on");
  cv.fine_tune_learning_rate = a.fine_tune;
  for (const auto& variant : SplitList(a.networks)) {
    classify::ModelOptions m = base;
    m.variant = variant;
    const auto& known = classify::ModelVariants();
    if (std::find(known.begin(), known.end(), variant) == known.end())
      throw InputError("--networks: unknown variant \"" + variant + "\" (" + ModelVariantList() + ")");
    cv.networks.push_back({variant, m});
  }
  return cv;
}

// Fold-by-fold comparisons under a title, one line each.
void PrintPaired(const std::string& title, const std::vector<classify::PairedComparison>& comparisons) {
  if (comparisons.empty()) return;
  int width = 26;  // the longest "a vs b", for aligned columns
  for (const auto& c : comparisons) width = std::max(width, static_cast<int>((c.a + " vs " + c.b).size()));
  std::printf(
      "  %-*s macro F1 per fold, first minus second (mean ± std); folds ahead / behind; "
      "corrected resampled t-test: p, 95 %% interval\n",
      width, title.c_str());
  for (const auto& c : comparisons) {
    const std::string pair = c.a + " vs " + c.b;
    std::printf("  %-*s %+.3f ± %.3f  %2d / %2d of %-2d  p %.3f  [%+.3f, %+.3f]\n", width, pair.c_str(),
                c.mean_difference, c.std_difference, c.ahead, c.behind, c.folds, c.p_value, c.interval_low,
                c.interval_high);
  }
}

// An earlier run's report.json for --compare-to, checked up front against what this
// run will deal (dataset size, folds, repeats, seed) so a mismatch fails before the
// training, not after it.
nlohmann::json ReadEarlierReport(const std::string& dir, const nlohmann::json& expected) {
  const std::string path = dir + "/report.json";
  std::ifstream in(path);
  if (!in) throw InputError("--compare-to: cannot read " + path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  for (const auto& [field, value] : expected.items())
    if (!j.contains(field) || j[field] != value)
      throw InputError(path + ": \"" + field + "\" is " + (j.contains(field) ? j[field].dump() : "missing") +
                       " there and " + value.dump() + " here: not the same folds");
  // The fold sizes of the corrected t-test, per window and per object (older reports lack them).
  for (const char* field : {"fold_windows", "fold_objects_trained"})
    if (!j.contains(field))
      throw InputError(path + ": no \"" + field + "\" (the fold sizes; older reports lack them): run it again");
  return j;
}

// A model's figures at a scoring level in a report: per window its own fields, else
// those under ReportKey(level).
const nlohmann::json& AtLevel(const nlohmann::json& model, classify::ScoreLevel level) {
  const std::string key = classify::ReportKey(level);
  return key.empty() ? model : model.at(key);
}

// A scoring level in words: per window (the paper's), per object (majority of its
// windows), per window from the object's windows so far. `label` heads its console
// tables, `axis` says on a figure what one macro F1 scores.
struct LevelWords {
  std::string label, axis;
};
LevelWords WordsOf(classify::ScoreLevel level, const CrossValidationNames& names) {
  switch (level) {
    case classify::ScoreLevel::kObject:
      return {names.objects, "macro F1 over " + names.objects + " (majority of their windows)"};
    case classify::ScoreLevel::kHistory:
      return {"so far", "macro F1 per window, from the windows so far"};
    case classify::ScoreLevel::kWindow:
      break;
  }
  return {"windows", "macro F1 per window"};
}

// Pairs of models (or of this run and an earlier one) compared at each scoring level.
using PairedByLevel = std::vector<std::pair<classify::ScoreLevel, std::vector<classify::PairedComparison>>>;

// The console summary: one table per scoring level, each pair of models fold by
// fold, this run against an earlier one, then each repeat's mean.
void PrintSummary(const classify::CrossValidationResult& result, const classify::PreparedDataset& d,
                  const nlohmann::json& models, const PairedByLevel& paired, const PairedByLevel& earlier,
                  const std::string& compare_to, const CrossValidationNames& names, const std::string& scheme,
                  int repeats) {
  std::printf("%s: %zu windows, %s\n", names.command.c_str(), d.windows.size(), scheme.c_str());
  for (classify::ScoreLevel level : classify::kScoreLevels) {
    std::printf("  %-14s %17s %17s", WordsOf(level, names).label.c_str(), "macro F1", "weighted F1");
    for (const auto& c : d.classes) std::printf(" %14s", c.substr(0, 14).c_str());
    std::printf("\n");
    for (const auto& name : result.models) {
      const auto& m = AtLevel(models.at(name), level);
      std::printf("  %-14s %8.3f ± %.3f %8.3f ± %.3f", name.c_str(), m["macro_f1"]["mean"].get<double>(),
                  m["macro_f1"]["std"].get<double>(), m["weighted_f1"]["mean"].get<double>(),
                  m["weighted_f1"]["std"].get<double>());
      for (const auto& c : d.classes) std::printf(" %14.3f", m["per_class_f1"][c]["mean"].get<double>());
      std::printf("\n");
    }
  }
  // The same folds for every model: their fold-by-fold difference is free of the
  // folds' own spread, which dominates each model's ±; the corrected t-test allows
  // for the folds' overlapping training sets (classify::PairedComparison).
  for (const auto& [level, comparisons] : paired) PrintPaired("paired, " + WordsOf(level, names).label, comparisons);
  for (const auto& [level, comparisons] : earlier)
    PrintPaired("against " + compare_to + ", " + WordsOf(level, names).label, comparisons);
  if (repeats > 1) {  // how far the deal of objects to folds alone moves the figures
    std::printf("  %-14s macro F1 (weighted) of each repeat's folds, per window\n", "repeats");
    for (const auto& name : result.models) {
      std::printf("  %-14s", name.c_str());
      for (const auto& r : models[name]["repeats"])
        std::printf(" %.3f (%.3f)", r["macro_f1"].get<double>(), r["weighted_f1"].get<double>());
      std::printf("\n");
    }
  }
}

// One cross-validation run at one share of the training objects, written to `out`.
// Returns its report; a failed --compare-to goes to `comparison_error` (the run's
// results are written all the same).
nlohmann::json RunAtShare(const CrossValidationInputs& a, classify::CrossValidationOptions cv, double train_fraction,
                          const std::string& out, const classify::PreparedDataset& d,
                          const classify::PreparedDataset& unlabelled, const params::Params& params,
                          const CrossValidationNames& names, bool quiet, std::string& comparison_error) {
  cv.train_fraction = train_fraction;
  // What decides the folds: the same in an earlier run means the same folds.
  const nlohmann::json deal = {
      {"windows", d.windows.size()}, {"folds", a.folds}, {"repeats", a.repeats}, {"seed", cv.seed}};
  const nlohmann::json earlier_report = a.compare_to.empty() ? nlohmann::json() : ReadEarlierReport(a.compare_to, deal);
  PrepareRunDirectory(out, params);
  const auto t0 = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::vector<std::string> finished;  // the folds' lines: on an interrupt, what the report keeps
  const auto log = [&](const std::string& line, double fraction) {
    finished.push_back(line);
    const double elapsed = seconds();
    if (!quiet)
      std::fprintf(stderr, "%s: %s (%.0f s, ETA %s)\n", names.command.c_str(), line.c_str(), elapsed,
                   FormatEta(elapsed, fraction).c_str());
  };
  classify::CrossValidationResult result;
  try {
    result = classify::CrossValidate(d, cv, log, unlabelled);
  } catch (const Interrupted& e) {
    io::RunReport report(names.command);
    report.SetInterrupted(std::to_string(finished.size()) + " fold results");
    report.json()["dataset"] = a.dataset;
    report.json().update(deal);
    report.json()["finished"] = finished;
    report.Write(out);
    throw;
  }
  io::RunReport report(names.command);
  auto& j = report.json();
  j["dataset"] = a.dataset;
  j.update(deal);
  j["train_fraction"] = train_fraction;
  if (!a.train_on.empty()) j["train_on"] = a.train_on;
  if (a.fine_tune > 0) j["fine_tune_learning_rate"] = a.fine_tune;
  j["fold_windows"] = result.FoldSizes();
  j["fold_objects_trained"] = result.trained_objects;  // per fold and class
  j["unlabelled_windows"] = unlabelled.windows.size();
  if (cv.pseudo_labels.on()) {
    j["pseudo_labels"] = {{"votes", cv.pseudo_labels.votes},
                          {"rounds", cv.pseudo_labels.rounds},
                          {"classes", d.classes},
                          {"per_fold", result.pseudo_labelled}};
    if (cv.pseudo_labels.rounds > 1) j["pseudo_labels"]["per_fold_network_round"] = result.pseudo_labelled_by_round;
  }
  j["models"] = result.ToJson(d.classes);
  PairedByLevel paired, earlier;
  for (classify::ScoreLevel level : classify::kScoreLevels) {
    paired.emplace_back(level, result.PairedComparisons(level));
    j[classify::PairedKey(level)] = classify::PairedComparisonsJson(paired.back().second);
  }
  // A comparison that fails (the earlier folds held other windows) must not cost
  // this run's results: they are written first, the error raised after.
  if (!a.compare_to.empty()) {
    j["compared_to"] = {{"run", a.compare_to}};
    try {
      for (classify::ScoreLevel level : classify::kScoreLevels) {
        earlier.emplace_back(
            level, classify::CompareWithEarlier(result, earlier_report, a.compare_to + "/report.json", level));
        j["compared_to"][classify::PairedKey(level)] = classify::PairedComparisonsJson(earlier.back().second);
      }
    } catch (const InputError& e) {
      comparison_error = e.what();
      j["compared_to"]["error"] = comparison_error;
    }
  }
  j["timing"] = {{"seconds", seconds()}};
  std::string scheme = std::to_string(a.folds) + "-fold CV" +
                       (a.repeats > 1 ? " × " + std::to_string(a.repeats) : std::string()) + " by " + names.key;
  if (train_fraction < 1) {
    char share[96];
    std::snprintf(share, sizeof(share), ", trained on %.0f %% of each class's %s", 100 * train_fraction,
                  names.objects.c_str());
    scheme += share;
  }
  for (const auto& name : result.models) {
    classify::WriteConfusionPng(result.pooled.at(name), d.classes, name + ": " + scheme + ", pooled",
                                out + "/confusion_" + name + ".png");
    report.AddOutput("confusion_" + name + ".png");
  }
  WritePredictions(result, d, out + "/predictions.csv");
  report.AddOutput("predictions.csv");
  report.Write(out);
  PrintSummary(result, d, j["models"], paired, earlier, a.compare_to, names, scheme, a.repeats);
  return j;
}

// "0.25" for a share's directory and the curve's labels.
std::string ShareName(double fraction) {
  char s[32];
  std::snprintf(s, sizeof(s), "%g", fraction);
  return s;
}

// The learning curve from each share's report: per share its mean training windows
// and objects a fold, per model and scoring level the macro and weighted F1 (mean ±
// std over folds; per window the model's own fields, else under ReportKey(level)),
// and the pairs of models at each level (under PairedKey(level)).
nlohmann::json LearningCurve(const std::vector<std::pair<double, nlohmann::json>>& runs) {
  nlohmann::json curve = nlohmann::json::array();
  for (const auto& [fraction, j] : runs) {
    double trained = 0;
    for (const auto& fold : j["fold_windows"]) trained += fold[1].get<double>();
    const double folds = static_cast<double>(std::max<size_t>(1, j["fold_windows"].size()));
    nlohmann::json point = {{"train_fraction", fraction}, {"trained_windows_per_fold", trained / folds}};
    // Per class, the objects trained on in a fold (mean over folds): what a share means.
    for (size_t c = 0; c < j["fold_objects_trained"][0].size(); ++c) {
      double objects = 0;
      for (const auto& fold : j["fold_objects_trained"]) objects += fold[c].get<double>();
      point["trained_objects_per_fold"].push_back(objects / folds);
    }
    for (classify::ScoreLevel level : classify::kScoreLevels) {
      const std::string key = classify::ReportKey(level);
      for (const auto& [name, m] : j["models"].items()) {
        const nlohmann::json figures = {{"macro_f1", AtLevel(m, level)["macro_f1"]},
                                        {"weighted_f1", AtLevel(m, level)["weighted_f1"]}};
        if (key.empty())
          point["models"][name].update(figures);
        else
          point["models"][name][key] = figures;
      }
      point[classify::PairedKey(level)] = j[classify::PairedKey(level)];
    }
    curve.push_back(point);
  }
  return curve;
}

// One scoring level of the learning curve: its picture (learning_curve[_<level>].png)
// and its console table, each model's macro F1 at each share, then whether a gap
// closes as the training set grows: the models on their own (no combinations)
// compared fold by fold, share by share.
void WriteLearningCurveLevel(const nlohmann::json& curve, classify::ScoreLevel level, const std::string& title,
                             const std::string& out, const CrossValidationNames& names, io::RunReport& report) {
  const std::string key = classify::ReportKey(level);
  const std::string png = "learning_curve" + (key.empty() ? std::string() : "_" + key) + ".png";
  const LevelWords words = WordsOf(level, names);
  std::map<std::string, std::vector<classify::CurvePoint>> curves;
  for (const auto& point : curve)
    for (const auto& [name, m] : point["models"].items())
      curves[name].push_back({point["train_fraction"].get<double>(),
                              AtLevel(m, level)["macro_f1"]["mean"].get<double>(),
                              AtLevel(m, level)["macro_f1"]["std"].get<double>()});
  classify::WriteLearningCurvePng(curves, title, words.axis + ", mean and std over folds", out + "/" + png);
  report.AddOutput(png);
  std::printf("learning curve, %s: macro F1 (mean ± std over folds) at each share of the training %s\n",
              words.label.c_str(), names.objects.c_str());
  for (const auto& point : curve) {
    const auto& objects = point["trained_objects_per_fold"];
    std::printf("  share %-5s %7.0f windows, %3.0f–%.0f %s a class a fold",
                ShareName(point["train_fraction"].get<double>()).c_str(),
                point["trained_windows_per_fold"].get<double>(),
                std::min_element(objects.begin(), objects.end())->get<double>(),
                std::max_element(objects.begin(), objects.end())->get<double>(), names.objects.c_str());
    for (const auto& [name, m] : point["models"].items())
      std::printf("  %s %.3f ± %.3f", name.c_str(), AtLevel(m, level)["macro_f1"]["mean"].get<double>(),
                  AtLevel(m, level)["macro_f1"]["std"].get<double>());
    std::printf("\n");
  }
  const std::string paired = classify::PairedKey(level);
  bool header = false;
  for (const auto& [pair, unused] : curve.back()[paired].items()) {
    if (pair.find('+') != std::string::npos) continue;
    if (!header) std::printf("  macro F1 fold by fold, first minus second, at each share (corrected t-test's p)\n");
    header = true;
    std::printf("  %-16s", pair.c_str());
    for (const auto& point : curve) {
      const auto& c = point[paired][pair];
      std::printf("  %+.3f (%d/%d ahead, p %.2f)", c["macro_f1_difference"]["mean"].get<double>(),
                  c["folds_ahead"].get<int>(), c["folds"].get<int>(), c["corrected_t_test"]["p_value"].get<double>());
    }
    std::printf("\n");
  }
}

// How the scored windows lie over the shorter ones of --train-on.
void PrintWithin(const classify::PreparedDataset& d, const classify::PreparedDataset& train_on, const std::string& dir,
                 const CrossValidationNames& names) {
  const auto within = classify::WindowsWithin(d, train_on);
  size_t none = 0, total = 0;
  for (const auto& rows : within) none += rows.empty(), total += rows.size();
  std::set<std::string> scored(d.windows.object_ids.begin(), d.windows.object_ids.end());
  std::set<std::string> all(train_on.windows.object_ids.begin(), train_on.windows.object_ids.end());
  std::fprintf(stderr,
               "%s: training on %s: %zu windows of %d points from %zu %s (%zu of them scored here); "
               "%.1f of them within a window here on average, %zu windows here with none (scored 1/classes)\n",
               names.command.c_str(), dir.c_str(), train_on.windows.size(), train_on.windows.length, all.size(),
               names.objects.c_str(), scored.size(), within.empty() ? 0.0 : double(total) / within.size(), none);
}

}  // namespace

int RunCrossValidation(const params::Params& params, const classify::ModelOptions& base, const CrossValidationInputs& a,
                       const CrossValidationNames& names, const std::string& out, bool quiet) {
  std::vector<double> fractions = a.train_fractions;
  std::sort(fractions.begin(), fractions.end());
  fractions.erase(std::unique(fractions.begin(), fractions.end()), fractions.end());
  for (double f : fractions)
    if (!(f > 0 && f <= 1)) throw InputError("--train-fraction: " + ShareName(f) + " is not in (0, 1]");
  if (fractions.empty()) throw InputError("--train-fraction: no share given");
  classify::CrossValidationOptions cv = OptionsOf(a, base);  // bad options fail before the data is read
  classify::PreparedDataset d = classify::ReadPrepared(a.dataset);
  const classify::PreparedDataset unlabelled = classify::SplitOffUnlabelled(d);  // never scored
  classify::PreparedDataset train_on;
  if (!a.train_on.empty()) {
    train_on = classify::ReadPrepared(a.train_on);
    classify::SplitOffUnlabelled(train_on);
    cv.train_on = &train_on;
    PrintWithin(d, train_on, a.train_on, names);
  }
  std::string comparison_error;
  if (fractions.size() == 1) {
    RunAtShare(a, cv, fractions[0], out, d, unlabelled, params, names, quiet, comparison_error);
  } else {
    PrepareRunDirectory(out, params);
    std::vector<std::pair<double, nlohmann::json>> runs;
    for (double f : fractions) {
      if (!quiet) std::fprintf(stderr, "%s: learning curve, share %s\n", names.command.c_str(), ShareName(f).c_str());
      std::string error;
      runs.emplace_back(
          f, RunAtShare(a, cv, f, out + "/share-" + ShareName(f), d, unlabelled, params, names, quiet, error));
      if (comparison_error.empty()) comparison_error = error;
    }
    io::RunReport report(names.command);
    auto& j = report.json();
    j["dataset"] = a.dataset;
    j["learning_curve"] = LearningCurve(runs);
    for (double f : fractions) report.AddOutput("share-" + ShareName(f) + "/report.json");
    const std::string title = names.command + ": macro F1 against the share of each class's training " + names.objects +
                              " (" + std::to_string(a.folds) + "-fold CV" +
                              (a.repeats > 1 ? " x " + std::to_string(a.repeats) : std::string()) + ")";
    for (classify::ScoreLevel level : classify::kScoreLevels)
      WriteLearningCurveLevel(j["learning_curve"], level, title, out, names, report);
    report.Write(out);
  }
  if (!comparison_error.empty())
    throw InputError(comparison_error + " (this run's results are written to " + out + ")");
  return 0;
}

}  // namespace specht::pipeline
