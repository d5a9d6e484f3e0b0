#include "specht/classify/crossval.h"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <set>
#include <tuple>

#include "internal/object_hash.h"
#include "specht/classify/baseline.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"

namespace specht::classify {
namespace {

std::pair<double, double> MeanStd(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x;
  m /= std::max<size_t>(1, v.size());
  for (double x : v) s += (x - m) * (x - m);
  return {m, v.size() > 1 ? std::sqrt(s / (v.size() - 1)) : 0.0};
}

Scores Pool(const std::vector<Scores>& folds, int k) {
  std::vector<int> truth, predicted;
  for (const auto& s : folds)
    for (int t = 0; t < k; ++t)
      for (int p = 0; p < k; ++p) {
        truth.insert(truth.end(), s.confusion[t][p], t);
        predicted.insert(predicted.end(), s.confusion[t][p], p);
      }
  return Score(truth, predicted, k);
}

}  // namespace

void VoteByObject(const std::vector<std::string>& ids, const std::vector<int>& truth, const std::vector<int>& predicted,
                  int classes, std::vector<int>& object_truth, std::vector<int>& object_predicted) {
  std::map<std::string, std::pair<int, std::vector<int>>> votes;  // id → (truth, votes per class)
  for (size_t i = 0; i < ids.size(); ++i) {
    auto& v = votes[ids[i]];
    if (v.second.empty()) v = {truth[i], std::vector<int>(classes, 0)};
    if (predicted[i] >= 0 && predicted[i] < classes) ++v.second[predicted[i]];
  }
  object_truth.clear(), object_predicted.clear();
  for (const auto& [id, v] : votes) {
    object_truth.push_back(v.first);
    object_predicted.push_back(static_cast<int>(std::max_element(v.second.begin(), v.second.end()) - v.second.begin()));
  }
}

std::vector<float> RunningMeanByObject(const std::vector<std::string>& ids, const std::vector<float>& p, int classes) {
  const size_t k = static_cast<size_t>(classes);
  if (p.size() != ids.size() * k) throw InputError("RunningMeanByObject: probabilities must be windows × classes");
  std::map<std::string, std::pair<long, std::vector<double>>> sums;  // id → (windows so far, Σ p)
  std::vector<float> out(p.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    auto& [count, sum] = sums[ids[i]];
    if (sum.empty()) sum.assign(k, 0.0);
    ++count;
    for (size_t c = 0; c < k; ++c) {
      sum[c] += p[i * k + c];
      out[i * k + c] = static_cast<float>(sum[c] / static_cast<double>(count));
    }
  }
  return out;
}

std::vector<int> FoldsByObject(const std::vector<std::string>& ids, const std::vector<int>& labels, int folds,
                               int seed) {
  if (folds < 2) throw InputError("cross-validation needs at least 2 folds");
  // Each object's class (its first window's) and a seeded order within the class.
  std::map<int, std::vector<std::pair<uint64_t, std::string>>> by_class;
  std::set<std::string> seen;
  for (size_t i = 0; i < ids.size(); ++i)
    if (seen.insert(ids[i]).second) by_class[labels[i]].push_back({internal::ObjectHash(ids[i], seed), ids[i]});
  std::map<std::string, int> fold_of;
  int next = 0;
  for (auto& [cls, objects] : by_class) {
    std::sort(objects.begin(), objects.end());
    for (const auto& [hash, id] : objects) fold_of[id] = next++ % folds;  // continue the deal across classes
  }
  std::vector<int> out(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) out[i] = fold_of[ids[i]];
  return out;
}

std::vector<size_t> SubsampleObjects(const std::vector<std::string>& ids, const std::vector<int>& labels,
                                     const std::vector<size_t>& rows, double fraction, int seed) {
  if (!(fraction > 0 && fraction <= 1))
    throw InputError("train fraction must be in (0, 1], not " + std::to_string(fraction));
  std::map<int, std::vector<std::pair<uint64_t, std::string>>> by_class;  // class → (hash, id)
  std::set<std::string> seen;
  for (size_t i : rows)
    if (seen.insert(ids[i]).second) by_class[labels[i]].push_back({internal::MixedObjectHash(ids[i], seed), ids[i]});
  std::set<std::string> kept;
  for (auto& [cls, objects] : by_class) {
    std::sort(objects.begin(), objects.end());
    const auto keep = std::max<size_t>(1, static_cast<size_t>(std::ceil(fraction * objects.size() - 1e-9)));
    for (size_t j = 0; j < keep; ++j) kept.insert(objects[j].second);
  }
  std::vector<size_t> out;
  for (size_t i : rows)
    if (kept.count(ids[i])) out.push_back(i);
  return out;
}

namespace {

// Salt of the subsample's hash order, so that it is not the order of the deal to folds.
constexpr int kSubsampleSeedSalt = 7919;

// Training on another dataset's windows (CrossValidationOptions::train_on): its rows
// of every object outside the fold (`test_rows` of the scored `d`) to fit — none of
// a tested object's, also those within none of its scored windows — and the rows
// within the test windows to predict (ascending, each once).
void ShortRowsOfFold(const PreparedDataset& d, const PreparedDataset& src,
                     const std::vector<std::vector<size_t>>& within, const std::vector<size_t>& test_rows,
                     std::vector<size_t>& fit_rows, std::vector<size_t>& predict_rows) {
  std::set<std::string> tested;
  std::set<size_t> predicted;
  for (size_t i : test_rows) {
    predicted.insert(within[i].begin(), within[i].end());
    tested.insert(d.windows.object_ids[i]);
  }
  fit_rows.clear();
  for (size_t j = 0; j < src.windows.size(); ++j)
    if (!tested.count(src.windows.object_ids[j])) fit_rows.push_back(j);
  predict_rows.assign(predicted.begin(), predicted.end());
}

// One k-fold run of CrossValidate: repeat r, every seed raised by r.
// `within`: with o.train_on, each scored window's rows there (WindowsWithin).
void CrossValidateOnce(const PreparedDataset& d, const CrossValidationOptions& o, int r,
                       const PreparedDataset& unlabelled, const std::vector<std::vector<size_t>>& within,
                       const CrossValidationLog& log, CrossValidationResult& result) {
  const PreparedDataset& src = o.train_on ? *o.train_on : d;  // the windows the models train on and predict
  const int k = static_cast<int>(d.classes.size());
  const size_t kc = d.classes.size(), n = d.windows.size();
  const auto fold = FoldsByObject(d.windows.object_ids, d.windows.y, o.folds, o.seed + r);
  result.fold_of.insert(result.fold_of.end(), fold.begin(), fold.end());
  const bool pseudo_labels = o.pseudo_labels.on();
  char line[256];
  for (int f = 0; f < o.folds; ++f) {
    ThrowIfInterrupted("cross-validation");  // the folds finished are in the log
    const size_t slot = static_cast<size_t>(r) * o.folds + f;
    std::vector<size_t> train_rows, test_rows;
    for (size_t i = 0; i < fold.size(); ++i) (fold[i] == f ? test_rows : train_rows).push_back(i);
    if (o.train_fraction < 1)
      train_rows = SubsampleObjects(d.windows.object_ids, d.windows.y, train_rows, o.train_fraction,
                                    o.seed + r + kSubsampleSeedSalt);
    result.trained_windows[slot] = static_cast<long>(train_rows.size());
    std::set<std::string> trained;
    result.trained_objects[slot].assign(kc, 0);
    for (size_t i : train_rows)
      if (trained.insert(d.windows.object_ids[i]).second) ++result.trained_objects[slot][d.windows.y[i]];
    // The rows of `src` to train on and to predict; with train_on, a scored window's
    // probabilities are then the mean over its rows there.
    std::vector<size_t> fit_rows = train_rows, predict_rows = test_rows;
    if (o.train_on) ShortRowsOfFold(d, src, within, test_rows, fit_rows, predict_rows);
    auto scored = [&](const std::vector<float>& p) {
      return o.train_on ? MeanWithin(p, predict_rows, within, test_rows, k) : p;
    };
    Dataset train_all = src.windows.Subset(fit_rows);
    const Dataset test = d.windows.Subset(test_rows), predict = src.windows.Subset(predict_rows);
    // Scores a model's test probabilities three ways and keeps them.
    auto record = [&](const std::string& name, const std::vector<float>& probabilities) {
      const std::vector<int> predicted = MostProbable(probabilities, k);
      result.per_fold[slot][name] = Score(test.y, predicted, k);
      std::vector<int> ot, op;
      VoteByObject(test.object_ids, test.y, predicted, k, ot, op);
      result.per_fold_objects[slot][name] = Score(ot, op, k);
      result.per_fold_history[slot][name] =
          Score(test.y, MostProbable(RunningMeanByObject(test.object_ids, probabilities, k), k), k);
      auto all = result.probabilities[name].begin() + static_cast<long>(r * n * kc);
      for (size_t t = 0; t < test_rows.size(); ++t)
        std::copy_n(probabilities.begin() + static_cast<long>(t * kc), kc, all + static_cast<long>(test_rows[t] * kc));
      return result.per_fold[slot][name];
    };
    const std::string repeat =
        o.repeats > 1 ? "repeat " + std::to_string(r + 1) + "/" + std::to_string(o.repeats) + " " : "";
    // Work done, for the log's fraction (see CrossValidationLog).
    const double units_per_fold = o.networks.empty() ? 1.0 : static_cast<double>(o.networks.size());
    const double forest_units = o.networks.empty() ? 1.0 : 0.0;
    const double all_units = units_per_fold * o.folds * o.repeats;
    double units = units_per_fold * static_cast<double>(slot);
    auto report = [&](const std::string& name, const Scores& sc, const std::string& details, double work) {
      units += work;
      std::snprintf(line, sizeof(line), "%sfold %d/%d %-11s macro F1 %.3f weighted %.3f%s", repeat.c_str(), f + 1,
                    o.folds, name.c_str(), sc.macro_f1, sc.weighted_f1, details.c_str());
      if (log) log(line, units / all_units);
    };
    // The forest first: it is the pseudo-labels' teacher.
    ForestBaseline forest(200, 12, o.seed + r);
    if (o.forest) forest.Train(HandcraftedRows(src, fit_rows), train_all.y);
    const std::vector<float> forest_unlabelled =
        pseudo_labels ? forest.Probabilities(unlabelled.handcrafted, k) : std::vector<float>();
    if (std::any_of(o.networks.begin(), o.networks.end(), [](const auto& n) { return n.second.distillation > 0; }))
      train_all.teacher = OutOfFoldForest(src, fit_rows, o.seed + r + f);
    std::vector<std::pair<std::string, std::vector<float>>> network_probabilities;
    for (const auto& [name, network_options] : o.networks) {
      ModelOptions options = network_options;
      options.seed += r;
      std::vector<size_t> fit, val;
      SplitByObject(train_all.object_ids, options.validation_fraction, options.seed + f, fit, val);
      const Dataset fit_windows = train_all.Subset(fit), val_windows = train_all.Subset(val);
      size_t epochs = 0, pseudo = 0;
      const TrainNetwork train = [&](const Dataset& windows, int) {
        Classifier model(options, src.windows.features, src.windows.length, d.classes);
        epochs += model.Train(windows, val_windows).size();
        pseudo = windows.size() - fit_windows.size();
        return model;
      };
      const auto t0 = std::chrono::steady_clock::now();
      std::vector<std::vector<long>> per_round;
      Classifier model =
          pseudo_labels ? SelfTrain(train, fit_windows, unlabelled, forest_unlabelled, o.pseudo_labels, k, per_round)
                        : train(fit_windows, 1);
      // Fine-tuning (train_on): on to the scored dataset's own training windows, the
      // validation vessels split off as for the shorter ones.
      const bool tuned = o.fine_tune_learning_rate > 0 && options.variant != "mlp";
      size_t tuned_epochs = 0;
      if (tuned) {
        const Dataset long_train = d.windows.Subset(train_rows);
        std::vector<size_t> tune_fit, tune_val;
        SplitByObject(long_train.object_ids, options.validation_fraction, options.seed + f, tune_fit, tune_val);
        tuned_epochs =
            model.FineTune(long_train.Subset(tune_fit), long_train.Subset(tune_val), o.fine_tune_learning_rate).size();
      }
      ThrowIfInterrupted("cross-validation");  // a network cut short is not scored
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (pseudo_labels) {
        result.pseudo_labelled[slot] = per_round.front();  // the forest's: the same for every network
        if (o.pseudo_labels.rounds > 1) result.pseudo_labelled_by_round[slot][name] = per_round;
      }
      network_probabilities.emplace_back(name, tuned ? model.Predict(test) : scored(model.Predict(predict)));
      char details[192];
      std::string extra;
      if (pseudo_labels) extra = " + " + std::to_string(pseudo) + " pseudo-labelled";
      if (o.pseudo_labels.rounds > 1) extra += " in round " + std::to_string(o.pseudo_labels.rounds);
      const std::string tuning = tuned ? " + " + std::to_string(tuned_epochs) + " tuned on " +
                                             std::to_string(train_rows.size()) + " windows here"
                                       : "";
      std::snprintf(details, sizeof(details), " (%zu%s train, %zu test windows, %zu epochs%s, %.0f s)",
                    train_all.size(), extra.c_str(), tuned ? test.size() : predict.size(), epochs, tuning.c_str(), s);
      report(name, record(name, network_probabilities.back().second), details, 1.0);
    }
    if (o.forest) {
      // The forest's own answer is its most voted class (RTrees::predict's, tie
      // included: 0 of 19,331 AIS windows differ), so the trees run once.
      const std::vector<float> forest_probabilities =
          scored(forest.Probabilities(HandcraftedRows(src, predict_rows), k));
      report("forest", record("forest", forest_probabilities), "", forest_units);
      for (const auto& [name, p] : network_probabilities) {
        report(name + "+forest", record(name + "+forest", CombinedProbabilities(p, forest_probabilities)), "", 0.0);
      }
    }
  }
}

}  // namespace

std::vector<std::vector<size_t>> WindowsWithin(const PreparedDataset& scored, const PreparedDataset& short_windows) {
  if (!HasSpans(scored) || !HasSpans(short_windows))
    throw InputError(
        "windows within windows: both datasets need each window's time span (windows.csv t0_s, t1_s; "
        "prepare them again)");
  std::map<std::string, std::vector<size_t>> by_object;
  for (size_t j = 0; j < short_windows.windows.size(); ++j) by_object[short_windows.windows.object_ids[j]].push_back(j);
  std::vector<std::vector<size_t>> out(scored.windows.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const auto it = by_object.find(scored.windows.object_ids[i]);
    if (it == by_object.end()) continue;
    const double t0 = scored.t0_s[i], t1 = scored.t1_s[i];
    std::vector<size_t> overlapping;
    for (size_t j : it->second) {
      const double a = short_windows.t0_s[j], b = short_windows.t1_s[j];
      if (a >= t0 && b <= t1)
        out[i].push_back(j);
      else if (a <= t1 && b >= t0)
        overlapping.push_back(j);
    }
    if (out[i].empty()) out[i] = overlapping;
  }
  return out;
}

std::vector<float> MeanWithin(const std::vector<float>& p, const std::vector<size_t>& short_rows,
                              const std::vector<std::vector<size_t>>& within, const std::vector<size_t>& scored_rows,
                              int classes) {
  const size_t k = static_cast<size_t>(classes);
  std::map<size_t, size_t> at;
  for (size_t t = 0; t < short_rows.size(); ++t) at[short_rows[t]] = t;
  std::vector<float> out(scored_rows.size() * k, 1.0f / static_cast<float>(k));
  for (size_t t = 0; t < scored_rows.size(); ++t) {
    const auto& rows = within[scored_rows[t]];
    if (rows.empty()) continue;
    for (size_t c = 0; c < k; ++c) {
      double sum = 0;
      for (size_t j : rows) sum += p[at.at(j) * k + c];
      out[t * k + c] = static_cast<float>(sum / static_cast<double>(rows.size()));
    }
  }
  return out;
}

std::vector<float> OutOfFoldForest(const PreparedDataset& d, const std::vector<size_t>& rows, int seed) {
  const size_t k = d.classes.size();
  std::vector<std::string> ids;
  std::vector<int> labels;
  for (size_t i : rows) ids.push_back(d.windows.object_ids[i]), labels.push_back(d.windows.y[i]);
  const int folds = 5;
  const std::vector<int> fold = FoldsByObject(ids, labels, folds, seed + kSubsampleSeedSalt);
  std::vector<float> out(rows.size() * k);
  for (int g = 0; g < folds; ++g) {
    std::vector<size_t> fit, held, held_at;
    std::vector<int> fit_labels;
    for (size_t j = 0; j < rows.size(); ++j) {
      if (fold[j] == g) {
        held.push_back(rows[j]), held_at.push_back(j);
      } else {
        fit.push_back(rows[j]), fit_labels.push_back(labels[j]);
      }
    }
    if (held.empty()) continue;  // fewer objects than folds
    ForestBaseline forest(200, 12, seed);
    forest.Train(HandcraftedRows(d, fit), fit_labels);
    const std::vector<float> p = forest.Probabilities(HandcraftedRows(d, held), static_cast<int>(k));
    for (size_t t = 0; t < held.size(); ++t) std::copy_n(p.begin() + t * k, k, out.begin() + held_at[t] * k);
  }
  return out;
}

void PseudoLabelOptions::Check() const {
  if (votes < 0 || votes > 1)
    throw InputError("pseudo-labels: the teacher's share of votes must be in (0, 1], not " + std::to_string(votes));
  if (rounds < 1 || rounds > 5) throw InputError("pseudo-labels: rounds must be 1 to 5, not " + std::to_string(rounds));
}

Classifier SelfTrain(const TrainNetwork& train, const Dataset& labelled, const PreparedDataset& unlabelled,
                     const std::vector<float>& forest_probabilities, const PseudoLabelOptions& o, int classes,
                     std::vector<std::vector<long>>& per_round) {
  o.Check();
  if (!o.on()) throw InputError("pseudo-labels: self-training needs a share of votes in (0, 1]");
  per_round.assign(1, {});
  Dataset windows = labelled;
  windows.Append(PseudoLabelled(forest_probabilities, unlabelled, o.votes, classes, per_round.back()));
  Classifier network = train(windows, 1);
  for (int round = 2; round <= o.rounds; ++round) {
    const auto teacher = CombinedProbabilities(network.Predict(unlabelled.windows), forest_probabilities);
    per_round.emplace_back();
    windows = labelled;
    windows.Append(PseudoLabelled(teacher, unlabelled, o.votes, classes, per_round.back()));
    network = train(windows, round);
  }
  return network;
}

CrossValidationResult CrossValidate(const PreparedDataset& d, const CrossValidationOptions& o,
                                    const CrossValidationLog& log, const PreparedDataset& unlabelled) {
  if (o.repeats < 1) throw InputError("cross-validation needs at least 1 repeat");
  if (!(o.train_fraction > 0 && o.train_fraction <= 1))
    throw InputError("cross-validation: the train fraction must be in (0, 1], not " + std::to_string(o.train_fraction));
  o.pseudo_labels.Check();
  if (o.pseudo_labels.on() && !o.forest)
    throw InputError("pseudo-labels: the forest labels the unlabelled windows, so it cannot be skipped");
  if (o.pseudo_labels.on() && unlabelled.windows.size() == 0)
    throw InputError("pseudo-labels: the dataset has no unlabelled windows (AIS: prepare with ais.unlabelled)");
  for (int y : d.windows.y)
    if (y < 0 || y >= static_cast<int>(d.classes.size()))
      throw InputError("cross-validation: a window without a class among the labelled ones (SplitOffUnlabelled)");
  if (o.train_on) {
    if (o.train_on->classes != d.classes)
      throw InputError("cross-validation: the dataset to train on has other classes than the scored one");
    if (o.pseudo_labels.on() || o.train_fraction < 1)
      throw InputError(
          "cross-validation: training on another dataset's windows goes with neither pseudo-labels "
          "nor a train fraction");
    for (int y : o.train_on->windows.y)
      if (y < 0 || y >= static_cast<int>(d.classes.size()))
        throw InputError("cross-validation: a window without a class in the dataset to train on");
    if (o.fine_tune_learning_rate > 0 && o.train_on->windows.features != d.windows.features)
      throw InputError("cross-validation: fine-tuning needs the same features in both datasets (" +
                       std::to_string(o.train_on->windows.features) + " and " + std::to_string(d.windows.features) +
                       ")");
  } else if (o.fine_tune_learning_rate > 0) {
    throw InputError("cross-validation: fine-tuning continues a model of another dataset's windows (train_on)");
  }
  if (!(o.fine_tune_learning_rate >= 0 && o.fine_tune_learning_rate < 1))
    throw InputError("cross-validation: the fine-tuning learning rate must be in [0, 1)");
  CrossValidationResult result;
  result.folds = o.folds;
  for (const auto& [name, options] : o.networks) result.models.push_back(name);
  if (o.forest) {
    result.models.push_back("forest");
    for (const auto& [name, options] : o.networks) result.models.push_back(name + "+forest");
  }
  const size_t slots = static_cast<size_t>(o.folds) * o.repeats;
  result.per_fold.resize(slots);
  result.per_fold_objects.resize(slots);
  result.per_fold_history.resize(slots);
  result.trained_windows.assign(slots, 0);
  result.trained_objects.resize(slots);
  if (o.pseudo_labels.on()) result.pseudo_labelled.resize(slots), result.pseudo_labelled_by_round.resize(slots);
  for (const auto& name : result.models)
    result.probabilities[name].assign(o.repeats * d.windows.size() * d.classes.size(), 0.0f);
  const auto within = o.train_on ? WindowsWithin(d, *o.train_on) : std::vector<std::vector<size_t>>();
  for (int r = 0; r < o.repeats; ++r) CrossValidateOnce(d, o, r, unlabelled, within, log, result);
  const int k = static_cast<int>(d.classes.size());
  for (const auto& name : result.models) {
    std::vector<Scores> folds;
    for (const auto& per : result.per_fold) folds.push_back(per.at(name));
    result.pooled[name] = Pool(folds, k);
  }
  return result;
}

namespace {

// `per_fold` holds whole repeats of `folds` folds each.
nlohmann::json Summary(const std::vector<std::map<std::string, Scores>>& per_fold, const std::string& name,
                       const std::vector<std::string>& classes, int folds_per_repeat) {
  std::vector<double> macro, weighted;
  std::vector<std::vector<double>> per_class(classes.size());
  nlohmann::json folds = nlohmann::json::array();
  for (const auto& per : per_fold) {
    const Scores& s = per.at(name);
    macro.push_back(s.macro_f1);
    weighted.push_back(s.weighted_f1);
    for (size_t c = 0; c < classes.size(); ++c)
      if (s.support[c] > 0) per_class[c].push_back(s.f1[c]);
    folds.push_back({{"macro_f1", s.macro_f1}, {"weighted_f1", s.weighted_f1}, {"accuracy", s.accuracy}});
  }
  const auto [mm, ms] = MeanStd(macro);
  const auto [wm, ws] = MeanStd(weighted);
  nlohmann::json pc = nlohmann::json::object();
  for (size_t c = 0; c < classes.size(); ++c) {
    const auto [m, s] = MeanStd(per_class[c]);
    pc[classes[c]] = {{"mean", m}, {"std", s}};
  }
  nlohmann::json repeats = nlohmann::json::array();
  const auto per_repeat = static_cast<long>(std::max(1, folds_per_repeat));
  for (long first = 0; first < static_cast<long>(macro.size()); first += per_repeat) {
    const long end = std::min(static_cast<long>(macro.size()), first + per_repeat);
    repeats.push_back({{"macro_f1", MeanStd({macro.begin() + first, macro.begin() + end}).first},
                       {"weighted_f1", MeanStd({weighted.begin() + first, weighted.begin() + end}).first}});
  }
  return {{"macro_f1", {{"mean", mm}, {"std", ms}}},
          {"weighted_f1", {{"mean", wm}, {"std", ws}}},
          {"per_class_f1", pc},
          {"folds", folds},
          {"repeats", repeats}};
}

// ρ of the corrected t-test: the mean over folds of n_test / n_train.
double TestToTrainRatio(const std::vector<std::pair<long, long>>& test_train) {
  double sum = 0;
  for (const auto& [test, train] : test_train) {
    if (train <= 0) throw InputError("paired comparison: a fold without training windows");
    sum += static_cast<double>(test) / static_cast<double>(train);
  }
  if (test_train.empty()) throw InputError("paired comparison: no fold sizes recorded");
  return sum / static_cast<double>(test_train.size());
}

// The corrected resampled t-test of PairedComparison's comment, from its mean and
// standard deviation over `folds` folds.
void CorrectedResampledTTest(PairedComparison& c, double rho) {
  const int n = c.folds;
  if (n < 2) throw InputError("paired comparison: at least 2 folds");
  const double sigma = std::sqrt((1.0 / n + rho) * c.std_difference * c.std_difference);
  const boost::math::students_t t_dist(n - 1);
  if (sigma <= 0) {
    c.corrected_t = 0, c.p_value = c.mean_difference == 0 ? 1 : 0;
    c.interval_low = c.interval_high = c.mean_difference;
    return;
  }
  c.corrected_t = c.mean_difference / sigma;
  c.p_value = 2 * boost::math::cdf(boost::math::complement(t_dist, std::abs(c.corrected_t)));
  const double half = boost::math::quantile(boost::math::complement(t_dist, 0.025)) * sigma;
  c.interval_low = c.mean_difference - half, c.interval_high = c.mean_difference + half;
}

// Per fold: objects tested (the per-object scores' support) and trained on.
std::vector<std::pair<long, long>> ObjectFoldSizes(const CrossValidationResult& r) {
  if (r.models.empty() || r.per_fold_objects.empty() || r.trained_objects.size() != r.per_fold_objects.size())
    throw InputError("cross-validation result: objects tested and trained on per fold not recorded");
  std::vector<std::pair<long, long>> sizes;
  for (size_t slot = 0; slot < r.per_fold_objects.size(); ++slot) {
    const std::vector<long>& support = r.per_fold_objects[slot].at(r.models.front()).support;
    sizes.emplace_back(std::accumulate(support.begin(), support.end(), 0L),
                       std::accumulate(r.trained_objects[slot].begin(), r.trained_objects[slot].end(), 0L));
  }
  return sizes;
}

}  // namespace

std::string ReportKey(ScoreLevel level) {
  switch (level) {
    case ScoreLevel::kObject:
      return "per_object";
    case ScoreLevel::kHistory:
      return "with_history";
    case ScoreLevel::kWindow:
      break;
  }
  return "";
}

std::string PairedKey(ScoreLevel level) {
  const std::string key = ReportKey(level);
  return key.empty() ? "paired" : "paired_" + key;
}

const std::vector<std::map<std::string, Scores>>& CrossValidationResult::PerFold(ScoreLevel level) const {
  switch (level) {
    case ScoreLevel::kObject:
      return per_fold_objects;
    case ScoreLevel::kHistory:
      return per_fold_history;
    case ScoreLevel::kWindow:
      break;
  }
  return per_fold;
}

std::vector<double> CrossValidationResult::MacroF1PerFold(const std::string& model, ScoreLevel level) const {
  std::vector<double> f1;
  for (const auto& per : PerFold(level)) f1.push_back(per.at(model).macro_f1);
  return f1;
}

std::vector<std::pair<long, long>> CrossValidationResult::FoldSizes(ScoreLevel level) const {
  if (level == ScoreLevel::kObject) return ObjectFoldSizes(*this);
  const size_t repeats = folds > 0 ? per_fold.size() / static_cast<size_t>(folds) : 0;
  if (repeats == 0 || fold_of.size() % repeats != 0) return {};
  const size_t windows = fold_of.size() / repeats;
  std::vector<std::pair<long, long>> sizes(per_fold.size(), {0, static_cast<long>(windows)});
  for (size_t i = 0; i < fold_of.size(); ++i) {
    if (fold_of[i] < 0 || fold_of[i] >= folds)
      throw InputError("cross-validation result: window " + std::to_string(i % windows) + " in fold " +
                       std::to_string(fold_of[i]) + " of " + std::to_string(folds));
    auto& [test, train] = sizes[(i / windows) * static_cast<size_t>(folds) + static_cast<size_t>(fold_of[i])];
    ++test, --train;
  }
  if (trained_windows.size() == sizes.size())
    for (size_t slot = 0; slot < sizes.size(); ++slot) sizes[slot].second = trained_windows[slot];
  return sizes;
}

PairedComparison CrossValidationResult::Compare(const std::string& a, const std::string& b, ScoreLevel level) const {
  return CompareFolds(a, b, MacroF1PerFold(a, level), MacroF1PerFold(b, level), FoldSizes(level));
}

PairedComparison CompareFolds(const std::string& a, const std::string& b, const std::vector<double>& macro_a,
                              const std::vector<double>& macro_b,
                              const std::vector<std::pair<long, long>>& test_train_windows) {
  if (macro_a.size() != macro_b.size() || macro_a.size() != test_train_windows.size())
    throw InputError("paired comparison of " + a + " and " + b + ": " + std::to_string(macro_a.size()) + " against " +
                     std::to_string(macro_b.size()) + " folds, " + std::to_string(test_train_windows.size()) +
                     " fold sizes");
  PairedComparison c;
  c.a = a, c.b = b;
  std::vector<double> d;
  for (size_t i = 0; i < macro_a.size(); ++i) {
    d.push_back(macro_a[i] - macro_b[i]);
    c.ahead += d.back() > 0;
    c.behind += d.back() < 0;
  }
  std::tie(c.mean_difference, c.std_difference) = MeanStd(d);
  c.folds = static_cast<int>(d.size());
  CorrectedResampledTTest(c, TestToTrainRatio(test_train_windows));
  return c;
}

namespace {

// The earlier run's fold sizes at `level` for CompareWithEarlier, after checking that
// its folds tested the windows this run's did: this run's tested counts, and per
// fold the smaller of the two runs' training sets (the larger ρ).
std::vector<std::pair<long, long>> EarlierFoldSizes(const CrossValidationResult& result, const nlohmann::json& earlier,
                                                    const std::string& where, ScoreLevel level) {
  std::vector<std::pair<long, long>> windows;
  try {
    windows = earlier.at("fold_windows").get<std::vector<std::pair<long, long>>>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": field \"fold_windows\" missing or not pairs of counts (" + e.what() + ")");
  }
  const std::vector<std::pair<long, long>> here = result.FoldSizes();
  bool same_tests = windows.size() == here.size();
  for (size_t i = 0; same_tests && i < windows.size(); ++i) same_tests = windows[i].first == here[i].first;
  if (!same_tests)
    throw InputError(where +
                     ": its folds test other windows than this run's (\"fold_windows\" differs): "
                     "not the same dataset, folds, repeats and seed");
  if (level != ScoreLevel::kObject) {
    for (size_t i = 0; i < windows.size(); ++i) windows[i].second = std::min(windows[i].second, here[i].second);
    return windows;
  }
  std::vector<std::pair<long, long>> objects = result.FoldSizes(ScoreLevel::kObject);
  const auto trained = earlier.find("fold_objects_trained");
  if (trained == earlier.end() || !trained->is_array() || trained->size() != objects.size())
    throw InputError(where + ": field \"fold_objects_trained\" missing or not one entry per fold");
  for (size_t i = 0; i < objects.size(); ++i) {
    long before = 0;
    try {
      for (long n : (*trained)[i].get<std::vector<long>>()) before += n;
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where + ": fold_objects_trained[" + std::to_string(i) + "]: " + e.what());
    }
    objects[i].second = std::min(objects[i].second, before);
  }
  return objects;
}

}  // namespace

std::vector<PairedComparison> CompareWithEarlier(const CrossValidationResult& result, const nlohmann::json& earlier,
                                                 const std::string& where, ScoreLevel level) {
  const std::vector<std::pair<long, long>> sizes = EarlierFoldSizes(result, earlier, where, level);
  const auto models = earlier.find("models");
  const std::string key = ReportKey(level);
  std::vector<PairedComparison> out;
  for (const auto& name : result.models) {
    if (models == earlier.end() || !models->contains(name)) continue;
    const std::string field = "models." + name + (key.empty() ? "" : "." + key) + ".folds";
    std::vector<double> before;
    try {
      const nlohmann::json& m = key.empty() ? models->at(name) : models->at(name).at(key);
      for (const auto& fold : m.at("folds")) before.push_back(fold.at("macro_f1").get<double>());
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where + ": " + field + ": " + e.what());
    }
    const std::vector<double> now = result.MacroF1PerFold(name, level);
    if (before.size() != now.size())
      throw InputError(where + ": " + field + " has " + std::to_string(before.size()) + " folds, this run " +
                       std::to_string(now.size()));
    out.push_back(CompareFolds(name, name + " (earlier)", now, before, sizes));
  }
  if (out.empty()) throw InputError(where + ": none of this run's models is in it");
  return out;
}

std::vector<PairedComparison> CrossValidationResult::PairedComparisons(ScoreLevel level) const {
  std::vector<PairedComparison> all;
  for (size_t i = 0; i < models.size(); ++i)
    for (size_t k = i + 1; k < models.size(); ++k) all.push_back(Compare(models[i], models[k], level));
  return all;
}

nlohmann::json PairedComparisonsJson(const std::vector<PairedComparison>& comparisons) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& c : comparisons)
    j[c.a + " vs " + c.b] = {
        {"macro_f1_difference", {{"mean", c.mean_difference}, {"std", c.std_difference}}},
        {"corrected_t_test",
         {{"t", c.corrected_t}, {"p_value", c.p_value}, {"interval_95", {c.interval_low, c.interval_high}}}},
        {"folds_ahead", c.ahead},
        {"folds_behind", c.behind},
        {"folds", c.folds}};
  return j;
}

nlohmann::json CrossValidationResult::ToJson(const std::vector<std::string>& classes) const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& name : models) {
    j[name] = Summary(per_fold, name, classes, folds);
    j[name]["pooled"] = pooled.at(name).ToJson(classes);
    for (ScoreLevel level : {ScoreLevel::kObject, ScoreLevel::kHistory})
      j[name][ReportKey(level)] = Summary(PerFold(level), name, classes, folds);
  }
  return j;
}

}  // namespace specht::classify
