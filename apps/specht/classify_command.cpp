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
//       k-fold cross-validation with folds disjoint by track (pipeline/classifier_runs.h,
//       as `ais eval`): every network, the forest and each network combined with
//       it, scored per window, per track and from the track's windows so far;
//       --repeats R deals the tracks to the folds R times.
//   predict <model dir> <tracks.csv>... [--scenario S.yaml]... -o DIR   classes of
//       new tracks with the model's own preprocessing, the network's probabilities
//       averaged with the forest's (--network-only: the network's): windows.csv (one row per
//       window) and objects.csv (per track, mean of its windows' probabilities).
#include "commands.h"
#include "specht/pipeline/classifier_runs.h"
#include "specht/pipeline/track_classification.h"

namespace specht::app {
namespace {

struct ClassifyArgs {
  CommonArgs common;
  std::vector<std::string> inputs, scenarios;
  std::string model_dir, dataset;
  bool network_only = false;
  pipeline::TrainingInputs training;  // train
};

}  // namespace

void AddTrainingOptions(CLI::App& cmd, pipeline::TrainingInputs& args, const std::string& prepare) {
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

void AddClassifyCommand(CLI::App& app, int& exit_code) {
  CLI::App* cmd =
      app.add_subcommand("classify", "trajectory classification: prepare windows, train, evaluate, predict");
  cmd->require_subcommand(1);
  auto prep = std::make_shared<ClassifyArgs>();
  CLI::App* p = cmd->add_subcommand("prepare", "object tracks (CSV) to feature windows");
  p->add_option("tracks", prep->inputs, "object-track CSV files (id,t_s,x_m,y_m[,class][,truth_class])")->required();
  p->add_option("--scenario", prep->scenarios, "scenario files for map features (matched by name in the ids)");
  AddCommonOptions(*p, prep->common, "specht-out/classify-data");
  p->callback([prep, &exit_code] {
    exit_code =
        pipeline::PrepareTrackWindows(LoadParams(prep->common), prep->inputs, prep->scenarios, prep->common.out_dir);
  });

  auto train = std::make_shared<ClassifyArgs>();
  CLI::App* t = cmd->add_subcommand("train", "train the 1D ResNet and the random-forest baseline");
  AddTrainingOptions(*t, train->training, "classify prepare");
  AddCommonOptions(*t, train->common, "specht-out/classify-model");
  t->callback([train, &exit_code] {
    const params::Params params = LoadParams(train->common);
    exit_code = pipeline::TrainClassifier(params, params.Get<classify::ModelOptions>("classify_model"), train->training,
                                          "classify train", train->common.out_dir, train->common.quiet);
  });

  auto ev = std::make_shared<ClassifyArgs>();
  CLI::App* e = cmd->add_subcommand("eval", "F1 and confusion matrices on a prepared dataset");
  e->add_option("model", ev->model_dir, "a directory written by train")->required();
  e->add_option("dataset", ev->dataset, "a directory written by prepare")->required();
  AddCommonOptions(*e, ev->common, "specht-out/classify-eval");
  e->callback(
      [ev, &exit_code] { exit_code = pipeline::EvaluateClassifier(ev->model_dir, ev->dataset, ev->common.out_dir); });

  auto cv = std::make_shared<CrossValidationArgs>();
  CLI::App* c = cmd->add_subcommand("crossval", "k-fold cross-validation with folds disjoint by track");
  const pipeline::CrossValidationNames names{"classify crossval", "classify prepare", "track", "tracks",
                                             "specht-out/classify-crossval"};
  AddCrossValidationOptions(*c, *cv, names);
  c->callback([cv, names, &exit_code] {
    const params::Params params = LoadParams(cv->common);
    exit_code = pipeline::RunCrossValidation(params, params.Get<classify::ModelOptions>("classify_model"), cv->in,
                                             names, cv->common.out_dir, cv->common.quiet);
  });

  auto pr = std::make_shared<ClassifyArgs>();
  CLI::App* q = cmd->add_subcommand("predict", "classify object tracks (CSV) with a trained model");
  q->add_option("model", pr->model_dir, "a directory written by train")->required();
  q->add_option("tracks", pr->inputs, "object-track CSV files (id,t_s,x_m,y_m[,...])")->required();
  q->add_option("--scenario", pr->scenarios, "scenario files for map features (matched by name in the ids)");
  q->add_flag("--network-only", pr->network_only, "the network alone (default: combined with the model's forest.yml)");
  AddCommonOptions(*q, pr->common, "specht-out/classify-predict");
  q->callback([pr, &exit_code] {
    exit_code =
        pipeline::PredictTrackClasses(pr->model_dir, pr->inputs, pr->scenarios, pr->network_only, pr->common.out_dir);
  });
}

}  // namespace specht::app
