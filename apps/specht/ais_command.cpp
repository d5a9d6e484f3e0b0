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
//       with `specht classify eval`. The cross-validation is crossval_command.cpp,
//       shared with `specht classify crossval`.
//   predict <model dir> <tracks.csv>... -o DIR   classes per vessel (objects.csv: the
//       mean of its windows' probabilities) and per window (windows.csv: its own
//       class and the class from the vessel's windows so far) with the model's own
//       preprocessing; the network combined with the forest beside it
//       (--network-only: the network alone).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include "commands.h"
#include "probability_csv.h"
#include "run_setup.h"
#include "specht/ais/dataset.h"
#include "specht/ais/decoder.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/metrics.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/data_dir.h"
#include "specht/io/report.h"

namespace specht::app {
namespace {

struct AisArgs {
  CommonArgs common;
  std::vector<std::string> inputs;
  std::string model_dir;
  bool network_only = false;
  TrainingArgs training;  // train
};

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- decode -------------------------------------------------------------------

struct DecodedPosition {
  int64_t mmsi;
  double t, lon, lat, sog, cog, heading;
};

std::string Num(double v, const char* fmt) {
  if (std::isnan(v)) return "";
  char b[32];
  std::snprintf(b, sizeof(b), fmt, v);
  return b;
}

int RunDecode(const AisArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& o = params.Get<ais::SentenceOptions>("ais_decoder");
  PrepareOutputDir(a.common, params);
  const std::string& out = a.common.out_dir;
  std::ofstream jsonl(out + "/messages.jsonl");
  std::vector<DecodedPosition> positions;
  std::map<int64_t, int> ship_type;
  int64_t without_time = 0;
  const double nan = std::nan("");
  auto on_message = [&](const ais::Message& m) {
    jsonl << m.ToJson().dump() << '\n';
    if (!m.complete) return;
    if (const auto t = m.Number("shiptype")) ship_type[m.mmsi] = static_cast<int>(*t);
    const bool position = m.type <= 3 || m.type == 18 || m.type == 19 || m.type == 27;
    const auto lon = m.Number("lon"), lat = m.Number("lat");
    if (!position || !lon || !lat) return;
    if (!m.time_s) {
      ++without_time;
      return;
    }
    positions.push_back({m.mmsi, *m.time_s, *lon, *lat, m.Number("speed").value_or(nan),
                         m.Number("course").value_or(nan), m.Number("heading").value_or(nan)});
  };
  io::RunReport report("ais decode");
  nlohmann::json files = nlohmann::json::array();
  int64_t emitted = 0, rejected = 0, sentences = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& path : a.inputs) {
    const ais::DecoderStats s = ais::DecodeFile(path, o, on_message);
    files.push_back({{"file", path}, {"stats", s.ToJson()}});
    emitted += s.emitted;
    rejected += s.RejectedTotal();
    sentences += s.sentences.sentences;
    std::printf("ais decode: %s: %lld sentences → %lld messages, %lld rejected\n", path.c_str(),
                static_cast<long long>(s.sentences.sentences), static_cast<long long>(s.emitted),
                static_cast<long long>(s.RejectedTotal()));
    for (const auto& [reason, n] : s.sentences.rejected)
      std::printf("    %-45s %lld\n", reason.c_str(), static_cast<long long>(n));
    for (const auto& [reason, n] : s.rejected_messages)
      std::printf("    %-45s %lld\n", reason.c_str(), static_cast<long long>(n));
  }
  const double seconds = Seconds(t0);
  jsonl.close();
  std::stable_sort(positions.begin(), positions.end(),
                   [](const auto& p, const auto& q) { return p.mmsi != q.mmsi ? p.mmsi < q.mmsi : p.t < q.t; });
  std::string csv = "mmsi,time,lon,lat,sog,cog,heading,ship_type\n";
  for (const auto& p : positions) {
    const auto st = ship_type.find(p.mmsi);
    csv += std::to_string(p.mmsi) + "," + Num(p.t, "%.3f") + "," + Num(p.lon, "%.7f") + "," + Num(p.lat, "%.7f") + "," +
           Num(p.sog, "%.1f") + "," + Num(p.cog, "%.1f") + "," + Num(p.heading, "%.0f") + "," +
           (st == ship_type.end() ? "" : std::to_string(st->second)) + "\n";
  }
  io::WriteTextAtomically(out + "/positions.csv", csv);
  auto& j = report.json();
  j["inputs"] = files;
  j["summary"] = {{"messages", emitted},
                  {"rejected", rejected},
                  {"positions", positions.size()},
                  {"positions_without_time", without_time},
                  {"vessels_with_ship_type", ship_type.size()},
                  {"sentences_per_s", sentences / std::max(1e-9, seconds)}};
  report.AddOutput("messages.jsonl");
  report.AddOutput("positions.csv");
  report.Write(out);
  std::printf("ais decode: %lld messages, %zu timed positions (%lld without a receive time), %.0f sentences/s\n",
              static_cast<long long>(emitted), positions.size(), static_cast<long long>(without_time),
              sentences / std::max(1e-9, seconds));
  return 0;
}

// ---- prepare ------------------------------------------------------------------

std::string DataDirOr(const CommonArgs& c) {
  const auto d = io::ResolveDataDir(c.data_dir);
  return d ? *d : "";
}

int RunPrepare(const AisArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& ais_o = params.Get<ais::AisOptions>("ais");
  const classify::PreprocessOptions o = params.Get<ais::AisPreprocessOptions>("ais_classify");
  const ais::Geography geo = ais::Geography::Load(ais_o, DataDirOr(a.common));
  PrepareOutputDir(a.common, params);
  const std::string& out = a.common.out_dir;
  ProgressLine progress("ais prepare", "points", !a.common.quiet);
  ais::PrepareReport r;
  const auto t0 = std::chrono::steady_clock::now();
  const classify::PreparedDataset d =
      ais::PrepareDataset(a.inputs, ais_o, o, geo, r, [&](long points, double f) { progress.Update(points, f); });
  const double seconds = Seconds(t0);
  progress.Finish();
  if (d.windows.size() == 0) {
    ThrowIfInterrupted("ais prepare");
    throw InputError("ais prepare: no window survived preprocessing");
  }
  classify::WritePrepared(d, out);
  const std::vector<std::string> steps = {"input", "split", "chunked", "moving"};
  classify::WriteStepCountsPng(
      r.counts, steps, ais::VesselClasses(),
      "sequences per class after each step (" + std::to_string(o.length) + " points, " + o.transform + ")",
      out + "/counts.png");
  io::RunReport report("ais prepare");
  auto& j = report.json();
  nlohmann::json files = nlohmann::json::array();
  for (const auto& [path, s] : r.files)
    files.push_back({{"file", path},
                     {"rows", s.rows},
                     {"vessels", s.vessels},
                     {"duplicates", s.duplicates},
                     {"skipped", s.skipped},
                     {"first_problem", s.first_problem}});
  j["inputs"] = files;
  j["geography"] = {{"coast_points", geo.coast_points()}, {"harbours", geo.harbours()}};
  j["counts"] = r.counts;
  j["vessels_per_class"] = r.vessels_per_class;
  j["excluded_vessels"] = r.excluded_vessels;
  j["windows"] = d.windows.size();
  j["timing"] = {{"seconds", seconds}, {"points", r.points}, {"points_per_s", r.points / std::max(1e-9, seconds)}};
  report.AddOutput("counts.png");
  if (InterruptRequested()) report.SetInterrupted(std::to_string(r.points) + " points");
  report.Write(out);
  std::printf("ais prepare: %ld points, %zu windows of %d × %d (%.0f points/s); %ld vessels of other or unknown type\n",
              r.points, d.windows.size(), d.windows.features, o.length, r.points / std::max(1e-9, seconds),
              r.excluded_vessels);
  std::vector<std::string> columns = ais::VesselClasses();
  if (r.vessels_per_class.count(ais::kUnlabelled)) columns.push_back(ais::kUnlabelled);
  std::printf("  %-8s", "step");
  for (const auto& c : columns) std::printf(" %15s", c.c_str());
  std::printf("\n");
  for (const auto& step : steps) {
    std::printf("  %-8s", step.c_str());
    for (const auto& c : columns) std::printf(" %15ld", r.counts[step].count(c) ? r.counts[step][c] : 0L);
    std::printf("\n");
  }
  std::printf("  %-8s", "vessels");
  for (const auto& c : columns) std::printf(" %15ld", r.vessels_per_class.count(c) ? r.vessels_per_class.at(c) : 0L);
  std::printf("\n");
  return InterruptExitCode();
}

// ---- predict ------------------------------------------------------------------

int RunPredict(const AisArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& ais_o = params.Get<ais::AisOptions>("ais");
  const classify::TrajectoryClassifier classifier =
      classify::TrajectoryClassifier::LoadDirectory(a.model_dir, a.network_only);
  const ais::Geography geo = ais::Geography::Load(ais_o, DataDirOr(a.common));
  PrepareOutputDir(a.common, params);
  const auto& classes = classifier.classes();
  const size_t k = classes.size();
  std::string objects = "mmsi,ship_type,label,windows,class" + ProbabilityHeader(classes) + "\n";
  // Per window: its own class and probabilities, and the class from the vessel's
  // windows so far (what an online classifier reports at that window's time).
  std::string per_window = "mmsi,window,t0,class,class_so_far" + ProbabilityHeader(classes) + "\n";
  std::vector<int> truth, predicted;
  long vessels = 0, windows = 0;
  char buf[32];
  for (const auto& path : a.inputs) {
    ais::VesselReader reader(path);
    ais::Vessel v;
    while (reader.Next(v)) {
      double cos_lat0 = 1;
      const classify::Trajectory t = ais::ToTrajectory(v, cos_lat0);
      const auto ws = classifier.Windows({t});
      if (ws.empty()) continue;
      const auto p = classifier.Classify(ws, geo.ForFrame(cos_lat0));
      const std::vector<std::string> ids(ws.size(), std::to_string(v.mmsi));
      const std::vector<float> so_far = classify::RunningMeanByObject(ids, p, static_cast<int>(k));
      const std::vector<int> own = classify::MostProbable(p, static_cast<int>(k));
      const std::vector<int> running = classify::MostProbable(so_far, static_cast<int>(k));
      for (size_t i = 0; i < ws.size(); ++i) {
        std::snprintf(buf, sizeof(buf), ",%.0f,", ws[i].t0_s);
        per_window += ids[i] + "," + std::to_string(i) + buf + classes[static_cast<size_t>(own[i])] + "," +
                      classes[static_cast<size_t>(running[i])];
        AppendProbabilities(per_window, p.data() + i * k, k);
        per_window += "\n";
      }
      // The vessel's class: the mean over all its windows (the last window's so far).
      const int best = running.back();
      objects += std::to_string(v.mmsi) + "," + (v.ship_type >= 0 ? std::to_string(v.ship_type) : "") + "," + t.label +
                 "," + std::to_string(ws.size()) + "," + classes[best];
      AppendProbabilities(objects, so_far.data() + so_far.size() - k, k);
      objects += "\n";
      const auto it = std::find(classes.begin(), classes.end(), t.label);
      if (it != classes.end()) truth.push_back(static_cast<int>(it - classes.begin())), predicted.push_back(best);
      ++vessels;
      windows += static_cast<long>(ws.size());
    }
  }
  io::WriteTextAtomically(a.common.out_dir + "/objects.csv", objects);
  io::WriteTextAtomically(a.common.out_dir + "/windows.csv", per_window);
  io::RunReport report("ais predict");
  auto& j = report.json();
  j["inputs"] = {{"model", a.model_dir}, {"tracks", a.inputs}};
  j["combination"] = classifier.combination();
  j["vessels"] = vessels;
  j["windows"] = windows;
  if (!truth.empty()) j["metrics_per_vessel"] = classify::Score(truth, predicted, static_cast<int>(k)).ToJson(classes);
  report.AddOutput("objects.csv");
  report.AddOutput("windows.csv");
  report.Write(a.common.out_dir);
  std::printf("ais predict: %ld vessels classified from %ld windows\n", vessels, windows);
  if (!truth.empty())
    std::printf("  labelled vessels: %zu, macro F1 per vessel %.3f\n", truth.size(),
                j["metrics_per_vessel"]["macro_f1"].get<double>());
  return 0;
}

}  // namespace

void AddAisCommand(CLI::App& app, int& exit_code) {
  CLI::App* cmd =
      app.add_subcommand("ais", "AIS vessel classification: decode NMEA, prepare, train, evaluate, predict");
  cmd->require_subcommand(1);

  auto dec = std::make_shared<AisArgs>();
  CLI::App* d = cmd->add_subcommand("decode", "NMEA 0183 AIS (!AIVDM/!AIVDO, gzip or plain) to messages and positions");
  d->add_option("nmea", dec->inputs, "NMEA log files")->required();
  AddCommonOptions(*d, dec->common, "specht-out/ais-decode");
  d->callback([dec, &exit_code] { exit_code = RunDecode(*dec); });

  auto prep = std::make_shared<AisArgs>();
  CLI::App* p = cmd->add_subcommand("prepare", "tabular AIS positions to the paper's feature windows");
  p->add_option("tracks", prep->inputs, "CSV files (mmsi,time,lon,lat[,ship_type]; NOAA; DMA), grouped by MMSI")
      ->required();
  AddCommonOptions(*p, prep->common, "specht-out/ais-data");
  p->callback([prep, &exit_code] { exit_code = RunPrepare(*prep); });

  auto train = std::make_shared<AisArgs>();
  CLI::App* t = cmd->add_subcommand("train", "train the 1D ResNet (section ais_model) and the random forest");
  AddTrainingOptions(*t, train->training, "ais prepare");
  AddCommonOptions(*t, train->common, "specht-out/ais-model");
  t->callback([train, &exit_code] {
    const params::Params params = LoadParams(train->common);
    exit_code = RunClassifierTraining(train->common, params, params.Get<ais::AisModelOptions>("ais_model"),
                                      train->training, "ais train");
  });

  auto ev = std::make_shared<CrossValidationArgs>();
  CLI::App* e = cmd->add_subcommand("eval", "cross-validation with folds disjoint by MMSI");
  const CrossValidationNames names{"ais eval", "ais prepare", "MMSI", "vessels", "specht-out/ais-eval"};
  AddCrossValidationOptions(*e, *ev, names);
  e->callback([ev, names, &exit_code] {
    const params::Params params = LoadParams(ev->common);
    exit_code = RunCrossValidation(*ev, params, params.Get<ais::AisModelOptions>("ais_model"), names);
  });

  auto pr = std::make_shared<AisArgs>();
  CLI::App* q = cmd->add_subcommand("predict", "classify vessels from tabular AIS with a trained model");
  q->add_option("model", pr->model_dir, "a directory written by ais train")->required();
  q->add_option("tracks", pr->inputs, "CSV files as for prepare")->required();
  q->add_flag("--network-only", pr->network_only, "the network alone (default: combined with the model's forest.yml)");
  AddCommonOptions(*q, pr->common, "specht-out/ais-predict");
  q->callback([pr, &exit_code] { exit_code = RunPredict(*pr); });
}

}  // namespace specht::app
