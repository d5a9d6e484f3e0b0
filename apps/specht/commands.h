// apps/specht/commands.h: the subcommands of `specht`. Each registers its options
// and a callback that sets the exit code (0 ok, 1 runtime failure, 2 bad input).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "run_setup.h"
#include "specht/classify/crossval.h"
#include "specht/classify/model.h"
#include "specht/classify/trajectory_classifier.h"

namespace specht::app {

void AddReplayCommand(CLI::App& app, int& exit_code);
void AddParamsCommand(CLI::App& app, int& exit_code);
void AddEvalCommand(CLI::App& app, int& exit_code);
// `specht eval perception` (eval_perception_command.cpp), a subcommand of `eval`.
void AddEvalPerceptionCommand(CLI::App& eval, int& exit_code);
void AddSlamCommand(CLI::App& app, int& exit_code);
void AddConvertCommand(CLI::App& app, int& exit_code);
void AddSimCommand(CLI::App& app, int& exit_code);
void AddStereoCommand(CLI::App& app, int& exit_code);
void AddDetectCommand(CLI::App& app, int& exit_code);
void AddTrackCommand(CLI::App& app, int& exit_code);
void AddClassifyCommand(CLI::App& app, int& exit_code);
void AddTuneCommand(CLI::App& app, int& exit_code);
void AddPlanCommand(CLI::App& app, int& exit_code);
void AddRunCommand(CLI::App& app, int& exit_code);
void AddAisCommand(CLI::App& app, int& exit_code);
// `specht commands` (commands_command.cpp): the index of every command above; register it last.
void AddCommandsCommand(CLI::App& app, int& exit_code);

// What `classify train` and `ais train` train on.
struct TrainingArgs {
  std::string dataset;
  bool resume = false;
  classify::PseudoLabelOptions pseudo_labels;  // --pseudo-labels, --pseudo-label-rounds
  std::string train_on;  // a prepared dataset of shorter windows cut from the same tracks, or empty
  double fine_tune = 0;  // with train_on: the network's learning rate on the dataset's own windows after (0 = off)
};
// Registers the dataset argument, --resume, the pseudo-label options, --train-on and
// --fine-tune; `prepare` names the command that writes a dataset.
void AddTrainingOptions(CLI::App& cmd, TrainingArgs& args, const std::string& prepare);

// Trains the 1D ResNet and the random-forest baseline on a prepared dataset;
// shared by `classify train` and `ais train`. With pseudo-labels on, the network
// also learns from the dataset's unlabelled windows its teacher is sure of
// (classify::PseudoLabelOptions, SelfTrain). With train_on both models learn from
// the shorter windows of every object as `eval --train-on` trains them, the network
// is then optionally fine-tuned on the dataset's windows (--fine-tune), and the
// model classifies the dataset's windows as eval scored them
// (classify/trajectory_classifier.h).
int RunClassifierTraining(const CommonArgs& common, const params::Params& params, const classify::ModelOptions& o,
                          const TrainingArgs& args, const std::string& label);

// --pseudo-labels V and --pseudo-label-rounds R, for `ais eval`, `classify crossval`
// and both train commands.
void AddPseudoLabelOption(CLI::App& cmd, classify::PseudoLabelOptions& o);

// Cross-validation with folds disjoint by object on a prepared dataset
// (crossval_command.cpp); shared by `ais eval` and `classify crossval`.
struct CrossValidationArgs {
  CommonArgs common;
  std::string dataset, networks = "tiny,mlp";
  std::string compare_to;  // an earlier run's output directory, or empty
  int folds = 5, repeats = 1;
  // Shares of each class's training objects per fold: one run each; with more than
  // one, each run goes into <out>/share-<f>/ and the learning curve into <out>.
  std::vector<double> train_fractions = {1.0};
  bool no_forest = false;
  classify::PseudoLabelOptions pseudo_labels;  // off unless --pseudo-labels
  std::string train_on;                        // another prepared dataset whose windows the models train on, or empty
  double fine_tune = 0;  // with train_on: the networks' learning rate on this dataset's windows after (0 = off)
};
// How a command names things: "ais eval", "ais prepare", "MMSI" (what the folds are
// disjoint by), "vessels" (the objects), "specht-out/ais-eval".
struct CrossValidationNames {
  std::string command, prepare, key, objects, default_out;
};
// Registers the dataset argument, --folds, --repeats, --train-fraction, --networks,
// --no-forest, --pseudo-labels, --compare-to, --train-on, --fine-tune and the common options.
void AddCrossValidationOptions(CLI::App& cmd, CrossValidationArgs& args, const CrossValidationNames& names);
// Runs it with `base` for every network (variant replaced); writes report.json,
// report.md, a pooled confusion PNG per model and predictions.csv; prints the summary.
// With several train fractions, that per fraction, then a report with the curve
// ("learning_curve": each model's figures and pairs per share, at every scoring
// level) and a picture per level (learning_curve.png per window,
// learning_curve_per_object.png, learning_curve_with_history.png: each model's
// macro F1 against the share of training objects).
int RunCrossValidation(const CrossValidationArgs& a, const params::Params& params, const classify::ModelOptions& base,
                       const CrossValidationNames& names);

}  // namespace specht::app
