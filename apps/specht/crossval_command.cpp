// The options of the cross-validation `specht ais eval` and `specht classify crossval`
// share (pipeline/classifier_runs.h runs it).
#include "commands.h"

namespace specht::app {

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

void AddCrossValidationOptions(CLI::App& cmd, CrossValidationArgs& args, const pipeline::CrossValidationNames& names) {
  cmd.add_option("dataset", args.in.dataset, "a directory written by " + names.prepare)->required();
  cmd.add_option("--folds", args.in.folds, "number of folds")->check(CLI::Range(2, 50));
  cmd.add_option("--repeats", args.in.repeats,
                 "deal the " + names.objects + " to the folds this many times (seeds seed, seed + 1, …)")
      ->check(CLI::Range(1, 20));
  cmd.add_option("--train-fraction", args.in.train_fractions,
                 "train every model of a fold on this share of each class's training " + names.objects +
                     " (the same test folds, so --compare-to a run at 1 works); several, comma-separated, give a "
                     "learning curve: one run per share in <out>/share-<f>/, learning_curve.png")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--networks", args.in.networks,
                 "comma-separated network variants (" + pipeline::ModelVariantList() + ")");
  cmd.add_flag("--no-forest", args.in.no_forest, "skip the random-forest baseline");
  AddPseudoLabelOption(cmd, args.in.pseudo_labels);
  cmd.add_option("--train-on", args.in.train_on,
                 "another directory written by " + names.prepare +
                     " from the same tracks with shorter windows: "
                     "every model trains on its windows of the " +
                     names.objects + " outside the test fold (also of " + names.objects +
                     " too short for this dataset's windows) and scores a window by the mean over "
                     "the shorter windows within it; the folds stay this dataset's");
  cmd.add_option("--fine-tune", args.in.fine_tune,
                 "with --train-on: each convolutional network, once trained on the shorter windows, continues on "
                 "this dataset's training windows at this learning rate (e.g. 1e-4) and scores its windows itself "
                 "(the MLP and the forest keep the mean over the shorter windows); 0: off")
      ->check(CLI::Range(0.0, 0.999));
  cmd.add_option("--compare-to", args.in.compare_to,
                 "an earlier run's output directory on the same dataset, folds, repeats and seed: each model "
                 "compared with its earlier self fold by fold");
  AddCommonOptions(cmd, args.common, names.default_out);
}

}  // namespace specht::app
