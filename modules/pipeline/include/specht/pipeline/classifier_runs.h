// specht/pipeline/classifier_runs.h: training and cross-validating the trajectory
// classifier (classify/) on a prepared dataset — what `specht classify train|crossval`
// and `specht ais train|eval` run, on robot tracks and on vessels alike.
//
// Training writes model.pt/.json (the 1D ResNet), forest.yml (the random-forest
// baseline on the same split), training.csv (one line per epoch), checkpoint.pt after
// every epoch (resume continues from it), fine_tuning.csv with fine_tune, and a
// report with the validation figures of both. Validation objects are chosen by a hash
// of their id, so the same objects are held out of every dataset cut from the same
// tracks.
//
// Cross-validation deals the objects (tracks, vessels) to folds, trains every network,
// the forest and each network combined with the forest on each fold, and scores them
// per window, per object (majority of its windows) and per window from the object's
// windows so far; each pair of models is compared fold by fold with the corrected
// resampled t-test (classify/crossval.h). It writes report.json, report.md, a pooled
// confusion PNG per model and predictions.csv (every window's test probabilities).
// With several train fractions: one run per share in <out>/share-<f>/, then the
// learning curve (report, learning_curve*.png, a console table per scoring level).
#pragma once

#include <string>
#include <vector>

#include "specht/classify/crossval.h"
#include "specht/classify/model.h"
#include "specht/core/params.h"

namespace specht::pipeline {

// What a training learns from.
struct TrainingInputs {
  std::string dataset;                         // a prepared dataset (classify/dataset_io.h)
  bool resume = false;                         // continue from the output directory's checkpoint
  classify::PseudoLabelOptions pseudo_labels;  // off unless votes > 0
  // A dataset of shorter windows cut from the same tracks (its length divides the
  // dataset's): both models learn from its windows of every object and the model
  // classifies a window by the mean over the shorter windows within it; or empty.
  std::string train_on;
  double fine_tune = 0;  // with train_on: the network's learning rate on the dataset's own windows after (0 = off)
};

// Trains the network of `options` and the forest on `in`, into `out_dir`: the datasets
// are read and every combination of inputs that cannot work is refused (InputError)
// before the directory is created. `label` names the run in the report and on the
// progress line ("classify train"). Returns 0, or 128 + the signal when interrupted
// (the checkpoint lets `resume` continue).
int TrainClassifier(const params::Params& params, const classify::ModelOptions& options, const TrainingInputs& in,
                    const std::string& label, const std::string& out_dir, bool quiet);

// What a cross-validation runs.
struct CrossValidationInputs {
  std::string dataset, networks = "tiny,mlp";  // networks: comma-separated variants
  std::string compare_to;                      // an earlier run's output directory, or empty
  int folds = 5, repeats = 1;
  // Shares of each class's training objects per fold: one run each; with more than
  // one, each run goes into <out>/share-<f>/ and the learning curve into <out>.
  std::vector<double> train_fractions = {1.0};
  bool no_forest = false;
  classify::PseudoLabelOptions pseudo_labels;  // off unless votes > 0
  std::string train_on;                        // another prepared dataset whose windows the models train on, or empty
  double fine_tune = 0;  // with train_on: the networks' learning rate on this dataset's windows after (0 = off)
};

// How a command names things: "ais eval", "ais prepare", "MMSI" (what the folds are
// disjoint by), "vessels" (the objects), "specht-out/ais-eval".
struct CrossValidationNames {
  std::string command, prepare, key, objects, default_out;
};

// The network variants, "tiny, shallow, …", for help texts and errors.
std::string ModelVariantList();

// Runs the cross-validation of `in` with `base` for every network (its variant
// replaced) into `out_dir` and prints the summary. Bad options fail before the data
// is read; a failed --compare-to throws InputError after this run's results are
// written. An interrupt writes the folds finished and rethrows core's Interrupted.
int RunCrossValidation(const params::Params& params, const classify::ModelOptions& base,
                       const CrossValidationInputs& in, const CrossValidationNames& names, const std::string& out_dir,
                       bool quiet);

}  // namespace specht::pipeline
