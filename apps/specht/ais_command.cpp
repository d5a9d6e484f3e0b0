// `specht ais decode|prepare|train|eval|predict`: vessel classification from AIS
// (ais module; ../shared/papers/classification-maritime-vessels-cnn.md).
//   decode <nmea>... -o DIR      NMEA 0183 → messages.jsonl (gpsd-style objects),
//       positions.csv (mmsi,time,lon,lat,sog,cog,heading,ship_type; grouped by MMSI,
//       for prepare; only reports with a receive time), counts and rejections by
//       reason in report.json.
//   prepare <tracks.csv>... -o DIR   tabular AIS (positions.h layouts) → windows
//       (sections "ais", "ais_classify"), class counts after each step (counts.png,
//       the paper's Figure 3), dataset files as classify writes them.
//   train <dataset> -o DIR [--resume] [--train-on SHORTER [--fine-tune RATE]]   the 1D
//       ResNet (section "ais_model") and the random forest, as `classify train`
//       (--train-on: the model `eval --train-on [--fine-tune]` measures).
//   eval <dataset> -o DIR [--folds 5] [--repeats 1] [--networks tiny,mlp]
//       cross-validation with folds disjoint by MMSI: per model (each network, the
//       forest, each network combined with the forest) macro/weighted F1 mean ± std,
//       per-class F1, pooled confusion matrices (PNG), scored per window, per vessel
//       and per window from the vessel's windows so far; every window's test
//       probabilities in predictions.csv. --repeats R deals the vessels to the folds
//       R times (seeds seed … seed + R − 1) and reports over all R · k folds and
//       each deal's mean. A trained model is scored on a dataset
//       with `specht classify eval`. The cross-validation is pipeline/classifier_runs.h,
//       shared with `specht classify crossval`.
//   predict <model dir> <tracks.csv>... -o DIR   classes per vessel (objects.csv: the
//       mean of its windows' probabilities) and per window (windows.csv: its own
//       class and the class from the vessel's windows so far) with the model's own
//       preprocessing; the network combined with the forest beside it
//       (--network-only: the network alone).
#include "commands.h"
#include "specht/ais/dataset.h"
#include "specht/pipeline/ais_runs.h"
#include "specht/pipeline/classifier_runs.h"

namespace specht::app {
namespace {

struct AisArgs {
  CommonArgs common;
  std::vector<std::string> inputs;
  std::string model_dir;
  bool network_only = false;
  pipeline::TrainingInputs training;  // train
};

}  // namespace

void AddAisCommand(CLI::App& app, int& exit_code) {
  CLI::App* cmd =
      app.add_subcommand("ais", "AIS vessel classification: decode NMEA, prepare, train, evaluate, predict");
  cmd->require_subcommand(1);

  auto dec = std::make_shared<AisArgs>();
  CLI::App* d = cmd->add_subcommand("decode", "NMEA 0183 AIS (!AIVDM/!AIVDO, gzip or plain) to messages and positions");
  d->add_option("nmea", dec->inputs, "NMEA log files")->required();
  AddCommonOptions(*d, dec->common, "specht-out/ais-decode");
  d->callback([dec, &exit_code] {
    exit_code = pipeline::DecodeAis(LoadParams(dec->common), dec->inputs, dec->common.out_dir);
  });

  auto prep = std::make_shared<AisArgs>();
  CLI::App* p = cmd->add_subcommand("prepare", "tabular AIS positions to the paper's feature windows");
  p->add_option("tracks", prep->inputs, "CSV files (mmsi,time,lon,lat[,ship_type]; NOAA; DMA), grouped by MMSI")
      ->required();
  AddCommonOptions(*p, prep->common, "specht-out/ais-data");
  p->callback([prep, &exit_code] {
    exit_code = pipeline::PrepareAisWindows(LoadParams(prep->common), prep->inputs, DataDir(prep->common),
                                            prep->common.out_dir, prep->common.quiet);
  });

  auto train = std::make_shared<AisArgs>();
  CLI::App* t = cmd->add_subcommand("train", "train the 1D ResNet (section ais_model) and the random forest");
  AddTrainingOptions(*t, train->training, "ais prepare");
  AddCommonOptions(*t, train->common, "specht-out/ais-model");
  t->callback([train, &exit_code] {
    const params::Params params = LoadParams(train->common);
    exit_code = pipeline::TrainClassifier(params, params.Get<ais::AisModelOptions>("ais_model"), train->training,
                                          "ais train", train->common.out_dir, train->common.quiet);
  });

  auto ev = std::make_shared<CrossValidationArgs>();
  CLI::App* e = cmd->add_subcommand("eval", "cross-validation with folds disjoint by MMSI");
  const pipeline::CrossValidationNames names{"ais eval", "ais prepare", "MMSI", "vessels", "specht-out/ais-eval"};
  AddCrossValidationOptions(*e, *ev, names);
  e->callback([ev, names, &exit_code] {
    const params::Params params = LoadParams(ev->common);
    exit_code = pipeline::RunCrossValidation(params, params.Get<ais::AisModelOptions>("ais_model"), ev->in, names,
                                             ev->common.out_dir, ev->common.quiet);
  });

  auto pr = std::make_shared<AisArgs>();
  CLI::App* q = cmd->add_subcommand("predict", "classify vessels from tabular AIS with a trained model");
  q->add_option("model", pr->model_dir, "a directory written by ais train")->required();
  q->add_option("tracks", pr->inputs, "CSV files as for prepare")->required();
  q->add_flag("--network-only", pr->network_only, "the network alone (default: combined with the model's forest.yml)");
  AddCommonOptions(*q, pr->common, "specht-out/ais-predict");
  q->callback([pr, &exit_code] {
    exit_code = pipeline::PredictVesselClasses(LoadParams(pr->common), pr->model_dir, pr->inputs, pr->network_only,
                                               DataDir(pr->common), pr->common.out_dir);
  });
}

}  // namespace specht::app
