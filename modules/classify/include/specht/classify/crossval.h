// specht/classify/crossval.h: k-fold cross-validation with folds disjoint by object
// (no vessel or track in both training and test), stratified by class: each
// class's objects, in a seeded hash order, are dealt round-robin to the folds.
//
// Per fold: every network of `networks` is trained on the other folds (with its own
// validation split by object for early stopping) and tested on the fold; the
// random-forest baseline too when `forest` is set, and then each network combined
// with it ("<network>+forest", CombinedProbabilities). Scores are reported per fold and
// as mean ± std over folds; confusion matrices are summed over folds. Besides the
// per-window scores (the paper's), each object is classified by the majority of
// its windows' predictions (ties: the lower class index) and scored per object, and
// each window is scored once more from its object's history: the mean class
// probabilities of that window and every earlier window of the same object (the
// vessel's class from its track so far, as an online classifier would give it).
//
// Repeated cross-validation: with repeats R > 1 the whole k-fold run is done R
// times, repeat r with every seed raised by r (the deal of objects to folds, each
// network's weights, shuffling and validation split, the forest), so repeat r is
// exactly the single run with seed + r. Figures are then mean ± std over all R · k
// folds, and each repeat's mean is reported too: on few objects per class the deal
// alone moves the figures (AIS: the forest's macro F1 0.75–0.80 over three deals).
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/model.h"

namespace specht::classify {

// Majority vote of each object's window predictions: (truth, predicted) per object.
void VoteByObject(const std::vector<std::string>& object_ids, const std::vector<int>& truth,
                  const std::vector<int>& predicted, int classes, std::vector<int>& object_truth,
                  std::vector<int>& object_predicted);

// Per window, the mean probabilities (windows × classes, row-major) of its object's
// windows up to and including it, in the order given (time order within an object,
// as `prepare` writes them).
std::vector<float> RunningMeanByObject(const std::vector<std::string>& object_ids,
                                       const std::vector<float>& probabilities, int classes);

// Fold index (0 … folds−1) of every window.
std::vector<int> FoldsByObject(const std::vector<std::string>& object_ids, const std::vector<int>& labels, int folds,
                               int seed);

// The rows of `rows` whose objects are among the first ⌈fraction · n_c⌉ (at least
// one) of each class's n_c objects there, in a seeded hash order of their ids,
// returned in their order in `rows`. Stratified, so a small class keeps its share, and nested: for
// one seed and `rows`, a smaller fraction keeps a subset of a larger one's objects
// (a learning curve adds objects rather than drawing new ones). InputError unless
// fraction is in (0, 1].
std::vector<size_t> SubsampleObjects(const std::vector<std::string>& object_ids, const std::vector<int>& labels,
                                     const std::vector<size_t>& rows, double fraction, int seed);

// Distillation's teacher (ModelOptions::distillation): for each of `rows`, the class
// probabilities (its trees' vote fractions) of a forest that did not see the row's
// object, from 5 folds by object within `rows`. Out of fold, so that the network
// learns what the forest answers for vessels it has not seen, not how well it
// remembers the training ones (a forest's own training windows get near one-hot
// votes: the labels again). rows.size() × classes, row-major.
std::vector<float> OutOfFoldForest(const PreparedDataset& d, const std::vector<size_t>& rows, int seed);

// Self-training with pseudo-labels (Lee 2013, "Pseudo-label: the simple and efficient
// semi-supervised learning method"; the teacher here is another model, as in Xie et
// al. 2020's noisy student): windows without a class (objects never tested, e.g.
// AIS vessels of unknown type) are labelled in each fold by the forest trained on
// that fold's training windows, and those it gives at least `votes` of its trees'
// votes join every network's training windows with the voted class. With
// `rounds` R > 1 the student teaches in turn (noisy student's iteration): round r
// trains a fresh network of the same options on the labelled windows and the
// unlabelled ones that round r − 1's network combined with the forest
// (CombinedProbabilities) gives at least `votes`; the last round's network is the
// one scored. The networks' validation windows (early stopping) stay labelled
// ones, and the forest itself is trained on labelled windows only. More objects is
// what the small classes lack (AIS: 58–81 labelled vessels each; 514 of unknown type).
struct PseudoLabelOptions {
  double votes = 0;  // 0: off; else in (0, 1], needs the forest
  int rounds = 1;    // 1 … 5
  bool on() const { return votes > 0; }
  void Check() const;  // InputError when out of range
};

// For each window of `scored`, the rows of `short_windows` (another dataset cut from
// the same tracks, e.g. 60-point windows beside 360-point ones) of the same object
// that lie within its time span; where none does (the stationary filter dropped
// them), those that overlap it; else none. Both datasets need spans (HasSpans).
std::vector<std::vector<size_t>> WindowsWithin(const PreparedDataset& scored, const PreparedDataset& short_windows);

// Per window of `scored_rows` (rows of the scored dataset), the mean of `p` — class
// probabilities, one row of `classes` per entry of `short_rows`, the shorter dataset's
// rows that were predicted — over its rows in `within` (WindowsWithin); 1/classes
// each for a window with none (a miss, mostly). Every row of within[scored_rows[t]]
// must be among `short_rows`.
std::vector<float> MeanWithin(const std::vector<float>& p, const std::vector<size_t>& short_rows,
                              const std::vector<std::vector<size_t>>& within, const std::vector<size_t>& scored_rows,
                              int classes);

// A learning curve's point: every model of a fold trains on a share of each class's
// training objects (SubsampleObjects), tested on the same fold as with all of them,
// so a run at 0.5 compares with a run at 1 fold by fold (--compare-to).
//
// Training on shorter windows (`train_on`): the folds are dealt over the scored
// dataset's objects as always, but every model trains on `train_on`'s windows of
// the objects outside the test fold — including the objects that have no scored
// window at all (at 360 points 247 AIS vessels have a window, at 60 points 1,352:
// the long windows leave most vessels, and most of each small class, out) — and a
// scored window's probabilities are the mean of the model's over its WindowsWithin.
// A long sequence is thus classified by a model of its short pieces; the
// corrected t-test's ρ still counts the scored dataset's windows (or objects), so
// its comparisons stay those of a plain run on the same folds.
//
// Fine-tuning (`fine_tune_learning_rate` > 0, with train_on): each convolutional
// network, once trained on the shorter windows, continues on the scored dataset's
// training windows of the fold at that rate (Classifier::FineTune; its validation
// objects split off as for the shorter ones) and scores the test windows itself —
// transfer from every object's short pieces to the long windows of the few objects
// that have them, which a forest cannot do. The MLP (its input length is fixed) and
// the forest keep the mean over the shorter windows.
struct CrossValidationOptions {
  int folds = 5;
  int repeats = 1;
  int seed = 1;
  double train_fraction = 1;                                   // (0, 1]
  std::vector<std::pair<std::string, ModelOptions>> networks;  // name → options
  bool forest = true;
  PseudoLabelOptions pseudo_labels;
  const PreparedDataset* train_on = nullptr;  // see above; the same classes, spans in both
  double fine_tune_learning_rate = 0;         // see above; 0 = off
};

// Trains one network on `labelled` and pseudo-labelled windows of `unlabelled`,
// round by round as PseudoLabelOptions says (`o` must be on), and returns the last
// round's. `train` trains and returns a fresh network on the windows it is given
// (round 1, 2, …); `forest_probabilities` are the forest's (trained on labelled
// windows) for the unlabelled windows, size × classes: round 1's teacher, and half
// of every later one's. `per_round` gets each round's pseudo-labels per class.
using TrainNetwork = std::function<Classifier(const Dataset& windows, int round)>;
Classifier SelfTrain(const TrainNetwork& train, const Dataset& labelled, const PreparedDataset& unlabelled,
                     const std::vector<float>& forest_probabilities, const PseudoLabelOptions& o, int classes,
                     std::vector<std::vector<long>>& per_round);

// Two models scored on the same folds, compared fold by fold: the difference
// d_i = F1_a,i − F1_b,i of each fold's macro F1, its mean and standard deviation
// over the n folds, and in how many folds a is ahead (d_i > 0) or behind (d_i < 0).
// The folds' own spread (which vessels a fold holds) cancels in d_i, so a mean
// difference can be clear while both models' ± overlap. The folds are not
// independent (their training sets overlap; over repeats they are the same windows
// dealt again), so the count of folds won only describes, and a plain paired t-test
// would be far too confident. The test given is the corrected resampled t-test
// (Nadeau & Bengio 2003, "Inference for the generalization error"; for repeated
// k-fold, Bouckaert & Frank 2004), which widens the variance of the mean by the
// test-to-training size ratio ρ to account for that overlap:
//   σ² = (1/n + ρ) · s²,   s² = Σ (d_i − d̄)² / (n − 1),   ρ = mean_i n_test,i / n_train,i
//   t = d̄ / σ  with n − 1 degrees of freedom;  p = 2 · P(T_{n−1} > |t|);
//   95 % interval d̄ ± t_{0.975, n−1} · σ.
// With s = 0 the interval is the point d̄ and p is 1 when d̄ = 0, else 0.
struct PairedComparison {
  std::string a, b;
  double mean_difference = 0, std_difference = 0;
  int ahead = 0, behind = 0, folds = 0;
  double corrected_t = 0, p_value = 1, interval_low = 0, interval_high = 0;  // see above
};

// The three ways a run scores its models (see the top of this file): per window
// (the paper's), per object by majority vote, per window from its object's history.
// Models are compared fold by fold at each. An object-level comparison's fold
// sizes (the t-test's ρ) count objects: tested in the fold, trained on.
enum class ScoreLevel { kWindow, kObject, kHistory };
inline constexpr ScoreLevel kScoreLevels[] = {ScoreLevel::kWindow, ScoreLevel::kObject, ScoreLevel::kHistory};

// The level's key in a report: under each model its figures ("" for per window:
// the model's own fields), and its comparisons under "paired" + suffix
// ("paired", "paired_per_object", "paired_with_history").
std::string ReportKey(ScoreLevel level);
std::string PairedKey(ScoreLevel level);

// Per fold entries are indexed repeat · folds + fold; per window entries
// repeat · windows + window.
struct CrossValidationResult {
  std::vector<std::string> models;  // in report order
  int folds = 0;                    // folds in one repeat (the repeat count is per_fold.size() / folds)
  std::vector<std::map<std::string, Scores>> per_fold;          // fold → model → scores per window
  std::vector<std::map<std::string, Scores>> per_fold_objects;  // … per object (majority vote)
  std::vector<std::map<std::string, Scores>> per_fold_history;  // … per window, from its object's history
  std::map<std::string, Scores> pooled;  // summed confusion over all folds (a window once per repeat)
  std::vector<int> fold_of;              // per repeat and window: the fold it was tested in
  // Per fold: the labelled windows its models trained on (the networks' validation
  // windows included); fewer than the other folds' windows with a train_fraction < 1.
  std::vector<long> trained_windows;
  std::vector<std::vector<long>> trained_objects;  // per fold and class: the objects trained on
  // Per fold: the unlabelled windows pseudo-labelled with each class (empty when
  // off), by the forest (round 1) and, with more rounds, per network and round.
  std::vector<std::vector<long>> pseudo_labelled;
  std::vector<std::map<std::string, std::vector<std::vector<long>>>> pseudo_labelled_by_round;
  // Per model, repeat and window: the class probabilities from the fold that tested
  // it (repeats × windows × classes, row-major; the forest's are its vote fractions).
  std::map<std::string, std::vector<float>> probabilities;
  // Per model: macro/weighted F1 mean ± std over folds, per-class F1 mean ± std,
  // pooled confusion, per-fold figures, each repeat's mean macro and weighted F1
  // ("repeats"); the same per object under "per_object" and from each object's
  // history under "with_history".
  nlohmann::json ToJson(const std::vector<std::string>& classes) const;
  // The per fold scores of a level.
  const std::vector<std::map<std::string, Scores>>& PerFold(ScoreLevel level) const;
  // Per fold, in fold order: windows tested (from fold_of) and windows trained on
  // (trained_windows; the other folds' windows when it is empty); the corrected
  // t-test's ratio ρ. At the object level: objects tested (the per-object scores'
  // support) and objects trained on (trained_objects); InputError when those are
  // not recorded.
  std::vector<std::pair<long, long>> FoldSizes(ScoreLevel level = ScoreLevel::kWindow) const;
  // A model's macro F1 at a level in every fold, in fold order.
  std::vector<double> MacroF1PerFold(const std::string& model, ScoreLevel level = ScoreLevel::kWindow) const;
  // Model `a` against model `b` fold by fold (macro F1 at the level); see
  // PairedComparison.
  PairedComparison Compare(const std::string& a, const std::string& b, ScoreLevel level = ScoreLevel::kWindow) const;
  // Every pair of models (a before b in report order).
  std::vector<PairedComparison> PairedComparisons(ScoreLevel level = ScoreLevel::kWindow) const;
};

// Per-fold macro F1 of two models on the same folds (fold i: macro_a[i],
// macro_b[i], and its test and training window counts), compared as PairedComparison
// says.
PairedComparison CompareFolds(const std::string& a, const std::string& b, const std::vector<double>& macro_a,
                              const std::vector<double>& macro_b,
                              const std::vector<std::pair<long, long>>& test_train_windows);

// This run's models against the same models of an earlier run on the same folds,
// from the earlier run's report (its "fold_windows" and each model's per-fold
// "macro_f1" under "models", or under "models.<model>.<ReportKey(level)>"): pairs
// "<model>" vs "<model> (earlier)", so a change is judged on the folds both runs
// saw rather than against the folds' spread. The runs may train on different
// shares of the folds' objects (train_fraction); each fold's ρ is then the larger
// of the two runs' (the smaller training set: the wider interval; at the object
// level from the earlier "fold_objects_trained", per fold and class). Throws
// InputError naming `where` when the folds test other windows or no model is in
// both.
std::vector<PairedComparison> CompareWithEarlier(const CrossValidationResult& result, const nlohmann::json& earlier,
                                                 const std::string& where, ScoreLevel level = ScoreLevel::kWindow);

// The comparisons keyed "a vs b".
nlohmann::json PairedComparisonsJson(const std::vector<PairedComparison>& comparisons);

// Receives one line per model and fold, and the fraction of the whole run done, for
// an ETA (the networks trained so far over all to train, the forest and the
// combinations taking seconds beside them; the forests when there is no network).
using CrossValidationLog = std::function<void(const std::string& line, double fraction_done)>;

// `log` may be empty. `d` holds labelled windows only (SplitOffUnlabelled);
// `unlabelled` the windows for pseudo-labels (used only when o.pseudo_labels is on).
CrossValidationResult CrossValidate(const PreparedDataset& d, const CrossValidationOptions& o,
                                    const CrossValidationLog& log = {}, const PreparedDataset& unlabelled = {});

}  // namespace specht::classify
