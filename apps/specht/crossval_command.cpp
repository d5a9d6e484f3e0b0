// Cross-validation of a prepared dataset with folds disjoint by object, shared by
// `specht ais eval` (objects are vessels, by MMSI) and `specht classify crossval`
// (objects are tracks): per model (each network, the forest, each network combined
// with the forest) macro/weighted F1 mean ± std, per-class F1, pooled confusion
// matrices (PNG), scored per window, per object and per window from the object's
// windows so far; each pair of models compared fold by fold; every window's test
// probabilities in predictions.csv.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "commands.h"
#include "probability_csv.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/report.h"

namespace specht::app {
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
std::string VariantList() {
  std::string list;
  for (const auto& v : classify::ModelVariants()) list += (list.empty() ? "" : ", ") + v;
  return list;
}

classify::CrossValidationOptions OptionsOf(const CrossValidationArgs& a, const classify::ModelOptions& base) {
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
      throw InputError("--networks: unknown variant \"" + variant + "\" (" + VariantList() + ")");
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

}  // namespace

void AddPseudoLabelOption(CLI::App& cmd, classify::PseudoLabelOptions& o) {
  cmd.add_option("--pseudo-labels", o.votes,
                 "self-training: the dataset's unlabelled windows that the forest (trained on the labelled ones) "
                 "gives at least this share of its votes join the network's training windows with its class (0: off)")
      ->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--pseudo-label-rounds", o.rounds,
                 "with --pseudo-labels: from round 2 on a fresh network learns from the pseudo-labels of the "
                 "previous round's network combined with the forest (noisy student); each round costs a training")
      ->check(CLI::Range(1, 5));
}

void AddCrossValidationOptions(CLI::App& cmd, CrossValidationArgs& args, const CrossValidationNames& names) {
  cmd.add_option("dataset", args.dataset, "a directory written by " + names.prepare)->required();
  cmd.add_option("--folds", args.folds, "number of folds")->check(CLI::Range(2, 50));
  cmd.add_option("--repeats", args.repeats,
                 "deal the " + names.objects + " to the folds this many times (seeds seed, seed + 1, …)")
      ->check(CLI::Range(1, 20));
  cmd.add_option("--train-fraction", args.train_fractions,
                 "train every model of a fold on this share of each class's training " + names.objects +
                     " (the same test folds, so --compare-to a run at 1 works); several, comma-separated, give a "
                     "learning curve: one run per share in <out>/share-<f>/, learning_curve.png")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--networks", args.networks, "comma-separated network variants (" + VariantList() + ")");
  cmd.add_flag("--no-forest", args.no_forest, "skip the random-forest baseline");
  AddPseudoLabelOption(cmd, args.pseudo_labels);
  cmd.add_option("--train-on", args.train_on,
                 "another directory written by " + names.prepare +
                     " from the same tracks with shorter windows: "
                     "every model trains on its windows of the " +
                     names.objects + " outside the test fold (also of " + names.objects +
                     " too short for this dataset's windows) and scores a window by the mean over "
                     "the shorter windows within it; the folds stay this dataset's");
  cmd.add_option("--fine-tune", args.fine_tune,
                 "with --train-on: each convolutional network, once trained on the shorter windows, continues on "
                 "this dataset's training windows at this learning rate (e.g. 1e-4) and scores its windows itself "
                 "(the MLP and the forest keep the mean over the shorter windows); 0: off")
      ->check(CLI::Range(0.0, 0.999));
  cmd.add_option("--compare-to", args.compare_to,
                 "an earlier run's output directory on the same dataset, folds, repeats and seed: each model "
                 "compared with its earlier self fold by fold");
  AddCommonOptions(cmd, args.common, names.default_out);
}

namespace {

// One cross-validation run at one share of the training objects, written to `out`.
// Returns its report; a failed --compare-to goes to `comparison_error` (the run's
// results are written all the same).
nlohmann::json RunAtShare(const CrossValidationArgs& a, classify::CrossValidationOptions cv, double train_fraction,
                          const std::string& out, const classify::PreparedDataset& d,
                          const classify::PreparedDataset& unlabelled, const params::Params& params,
                          const CrossValidationNames& names, std::string& comparison_error) {
  cv.train_fraction = train_fraction;
  // What decides the folds: the same in an earlier run means the same folds.
  const nlohmann::json deal = {
      {"windows", d.windows.size()}, {"folds", a.folds}, {"repeats", a.repeats}, {"seed", cv.seed}};
  const nlohmann::json earlier_report = a.compare_to.empty() ? nlohmann::json() : ReadEarlierReport(a.compare_to, deal);
  CommonArgs common = a.common;
  common.out_dir = out;
  PrepareOutputDir(common, params);
  const auto t0 = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::vector<std::string> finished;  // the folds' lines: on an interrupt, what the report keeps
  const auto log = [&](const std::string& line, double fraction) {
    finished.push_back(line);
    const double elapsed = seconds();
    if (!a.common.quiet)
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

int RunCrossValidation(const CrossValidationArgs& a, const params::Params& params, const classify::ModelOptions& base,
                       const CrossValidationNames& names) {
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
  const std::string& out = a.common.out_dir;
  std::string comparison_error;
  if (fractions.size() == 1) {
    RunAtShare(a, cv, fractions[0], out, d, unlabelled, params, names, comparison_error);
  } else {
    PrepareOutputDir(a.common, params);
    std::vector<std::pair<double, nlohmann::json>> runs;
    for (double f : fractions) {
      if (!a.common.quiet)
        std::fprintf(stderr, "%s: learning curve, share %s\n", names.command.c_str(), ShareName(f).c_str());
      std::string error;
      runs.emplace_back(f, RunAtShare(a, cv, f, out + "/share-" + ShareName(f), d, unlabelled, params, names, error));
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

}  // namespace specht::app
