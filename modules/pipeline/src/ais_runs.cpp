// AIS runs (ais_runs.h): NMEA decoding, dataset preparation and vessel
// classification, each writing its outputs and report.
#include "specht/pipeline/ais_runs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "internal/probability_csv.h"
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
#include "specht/io/report.h"
#include "specht/pipeline/run_directory.h"

namespace specht::pipeline {
namespace {

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

}  // namespace

int DecodeAis(const params::Params& params, const std::vector<std::string>& nmea, const std::string& out) {
  const auto& o = params.Get<ais::SentenceOptions>("ais_decoder");
  PrepareRunDirectory(out, params);
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
  for (const auto& path : nmea) {
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

int PrepareAisWindows(const params::Params& params, const std::vector<std::string>& tracks, const std::string& data_dir,
                      const std::string& out, bool quiet) {
  const auto& ais_o = params.Get<ais::AisOptions>("ais");
  const classify::PreprocessOptions o = params.Get<ais::AisPreprocessOptions>("ais_classify");
  const ais::Geography geo = ais::Geography::Load(ais_o, data_dir);
  PrepareRunDirectory(out, params);
  ProgressLine progress("ais prepare", "points", !quiet);
  ais::PrepareReport r;
  const auto t0 = std::chrono::steady_clock::now();
  const classify::PreparedDataset d =
      ais::PrepareDataset(tracks, ais_o, o, geo, r, [&](long points, double f) { progress.Update(points, f); });
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

int PredictVesselClasses(const params::Params& params, const std::string& model_dir,
                         const std::vector<std::string>& tracks, bool network_only, const std::string& data_dir,
                         const std::string& out) {
  const auto& ais_o = params.Get<ais::AisOptions>("ais");
  const classify::TrajectoryClassifier classifier =
      classify::TrajectoryClassifier::LoadDirectory(model_dir, network_only);
  const ais::Geography geo = ais::Geography::Load(ais_o, data_dir);
  PrepareRunDirectory(out, params);
  const auto& classes = classifier.classes();
  const size_t k = classes.size();
  std::string objects = "mmsi,ship_type,label,windows,class" + ProbabilityHeader(classes) + "\n";
  // Per window: its own class and probabilities, and the class from the vessel's
  // windows so far (what an online classifier reports at that window's time).
  std::string per_window = "mmsi,window,t0,class,class_so_far" + ProbabilityHeader(classes) + "\n";
  std::vector<int> truth, predicted;
  long vessels = 0, windows = 0;
  char buf[32];
  for (const auto& path : tracks) {
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
  io::WriteTextAtomically(out + "/objects.csv", objects);
  io::WriteTextAtomically(out + "/windows.csv", per_window);
  io::RunReport report("ais predict");
  auto& j = report.json();
  j["inputs"] = {{"model", model_dir}, {"tracks", tracks}};
  j["combination"] = classifier.combination();
  j["vessels"] = vessels;
  j["windows"] = windows;
  if (!truth.empty()) j["metrics_per_vessel"] = classify::Score(truth, predicted, static_cast<int>(k)).ToJson(classes);
  report.AddOutput("objects.csv");
  report.AddOutput("windows.csv");
  report.Write(out);
  std::printf("ais predict: %ld vessels classified from %ld windows\n", vessels, windows);
  if (!truth.empty())
    std::printf("  labelled vessels: %zu, macro F1 per vessel %.3f\n", truth.size(),
                j["metrics_per_vessel"]["macro_f1"].get<double>());
  return 0;
}

}  // namespace specht::pipeline
