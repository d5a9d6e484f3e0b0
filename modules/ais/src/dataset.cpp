#include "specht/ais/dataset.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <thread>

#include "specht/classify/baseline.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"

namespace specht::ais {
namespace {

std::string UnderDataDir(const std::string& path, const std::string& data_dir) {
  return std::filesystem::path(path).is_absolute() || data_dir.empty() ? path : data_dir + "/" + path;
}

// One vessel's output, computed on a worker thread.
struct VesselWindows {
  std::vector<classify::Window> windows;
  std::vector<float> features, handcrafted;
  std::map<std::string, std::map<std::string, long>> counts;
};

VesselWindows Process(const Vessel& v, const classify::PreprocessOptions& o, const Geography& geo) {
  VesselWindows out;
  double cos_lat0 = 1;
  classify::Trajectory t = ToTrajectory(v, cos_lat0);
  if (t.label.empty()) t.label = kUnlabelled;  // only vessels of unknown type get here without a class
  out.windows = classify::MakeWindows({t}, o, &out.counts);
  const classify::MapFeatures map = geo.ForFrame(cos_lat0);
  for (const auto& w : out.windows) {
    const auto f = classify::Features(w, o, map);
    out.features.insert(out.features.end(), f.begin(), f.end());
    const auto h = classify::HandcraftedFeatures(w, map, o.features);
    out.handcrafted.insert(out.handcrafted.end(), h.begin(), h.end());
  }
  return out;
}

}  // namespace

AisPreprocessOptions::AisPreprocessOptions() {
  max_gap_s = 7200.0;
  max_jump_sq = 1e-4;                              // the paper's ≈ 1 km …
  max_jump_speed = 50 * kKnot / kMetresPerDegree;  // … when faster than 50 kn
  length = 60;
  min_fill = 0.8;
  stationary_threshold = 1e-4;  // ≈ 11 m per report on average
  transform = "relative_to_first";
  normalisation = "local";
  features = {"x",         "y",           "dt",       "speed",    "course",   "accel",
              "turn_rate", "dist_static", "dist_poi", "region_x", "region_y", "category"};
  log_scaled = {"dt", "dist_static", "dist_poi"};
  category_frequencies = 8;                   // MIDs 1 apart are 1/1000 of the range; 2^7 cycles separate neighbours
  max_speed = 30 * kKnot / kMetresPerDegree;  // 30 kn in degrees of latitude per second
  max_accel = 1 * kKnot / kMetresPerDegree;   // 1 kn/s
  max_turn_rate = 0.5;                        // rad/s
  static_cap = 20.0;                          // km, = ais.coast_cap_km
  poi_cap = 2500.0;                           // km, = ais.harbour_cap_km
}

AisModelOptions::AisModelOptions() {
  variant = "tiny";  // the paper's "shallow" trains far slower; docs/ais-experiments.md compares them
  epochs = 60;
  batch_size = 64;
  learning_rate = 2e-3;  // the paper doubles 1e-3 with batch normalisation
  input_noise = 0.0;     // the paper found no gain; σ 0.01 would drown Δt and the turn rate
  // Piecewise-linear encoding over 4 quantile bins: the best network on AIS, and 4
  // bins train fastest of the bin counts that score alike (docs/ais-experiments.md).
  input_bins = 4;
}

Geography::Geography(std::vector<GeoPoint> coast, std::vector<GeoPoint> harbours, double coast_cap_km,
                     double harbour_cap_km)
    : coast_(std::move(coast)),
      harbours_(std::move(harbours)),
      coast_cap_km_(coast_cap_km),
      harbour_cap_km_(harbour_cap_km) {}

Geography Geography::Load(const AisOptions& o, const std::string& data_dir) {
  auto coast = ReadShapefileVertices(UnderDataDir(o.coastline, data_dir));
  auto ports = ReadWorldPortIndex(UnderDataDir(o.ports, data_dir), o.harbour_sizes);
  if (ports.empty()) throw InputError("ais.harbour_sizes: no port of the World Port Index has one of these sizes");
  return Geography(std::move(coast), std::move(ports), o.coast_cap_km, o.harbour_cap_km);
}

classify::MapFeatures Geography::ForFrame(double cos_lat0) const {
  classify::MapFeatures m;
  m.distance_to_static = [this, cos_lat0](double x, double y) {
    return coast_.DistanceKm(x / cos_lat0, y, coast_cap_km_);
  };
  m.distance_to_poi = [this, cos_lat0](double x, double y) {
    return harbours_.DistanceKm(x / cos_lat0, y, harbour_cap_km_);
  };
  // Longitude and latitude scaled to [0, 1].
  m.region = [cos_lat0](double x, double y) {
    return std::array<double, 2>{(x / cos_lat0 + 180.0) / 360.0, (y + 90.0) / 180.0};
  };
  return m;
}

classify::Trajectory ToTrajectory(const Vessel& v, double& cos_lat0) {
  classify::Trajectory t;
  t.object_id = std::to_string(v.mmsi);
  t.label = ClassOfShipType(v.ship_type);
  t.category = FlagMid(v.mmsi);
  cos_lat0 = v.reports.empty() ? 1.0 : std::max(0.05, std::cos(v.reports.front().lat * M_PI / 180.0));
  t.points.reserve(v.reports.size());
  for (const auto& r : v.reports) t.points.push_back({r.t_s, r.lon * cos_lat0, r.lat});
  return t;
}

classify::PreparedDataset PrepareDataset(const std::vector<std::string>& files, const AisOptions& ais,
                                         const classify::PreprocessOptions& o, const Geography& geo,
                                         PrepareReport& report, const std::function<void(long, double)>& on_progress) {
  if (o.normalisation == "global")
    throw InputError("ais_classify.normalisation: AIS preparation streams vessels; use \"local\" or \"fixed\"");
  classify::PreparedDataset d;
  d.classes = VesselClasses();
  d.windows.features = classify::FeatureRows(o);
  d.windows.length = o.length;
  std::set<std::string> vessels_seen;

  for (const auto& path : files) {
    VesselReader reader(path);
    std::vector<Vessel> batch;
    auto flush = [&] {
      std::vector<VesselWindows> results(batch.size());
      const int threads = std::max(1, std::min<int>(ais.threads, static_cast<int>(batch.size())));
      std::vector<std::thread> workers;
      for (int k = 0; k < threads; ++k)
        workers.emplace_back([&, k] {
          for (size_t i = k; i < batch.size(); i += threads) results[i] = Process(batch[i], o, geo);
        });
      for (auto& w : workers) w.join();
      for (size_t i = 0; i < batch.size(); ++i) {
        auto& r = results[i];
        for (const auto& [step, per_class] : r.counts)
          for (const auto& [cls, n] : per_class) report.counts[step][cls] += n;
        if (r.windows.empty()) continue;
        const std::string& label = r.windows.front().label;
        if (vessels_seen.insert(r.windows.front().object_id).second) ++report.vessels_per_class[label];
        const auto known = std::find(d.classes.begin(), d.classes.end(), label);
        const int y = known == d.classes.end() ? -1 : static_cast<int>(known - d.classes.begin());
        for (const auto& w : r.windows) d.AddWindow(w, y);
        d.windows.x.insert(d.windows.x.end(), r.features.begin(), r.features.end());
        d.handcrafted.insert(d.handcrafted.end(), r.handcrafted.begin(), r.handcrafted.end());
      }
      batch.clear();
    };
    Vessel v;
    while (!InterruptRequested() && reader.Next(v)) {  // an interrupt keeps the vessels read
      report.points += static_cast<long>(v.reports.size());
      const bool unknown_type = v.ship_type <= 0;  // none reported, or 0 "not available"
      if (ClassOfShipType(v.ship_type).empty() && !(ais.unlabelled && unknown_type)) {
        ++report.excluded_vessels;
        continue;
      }
      batch.push_back(std::move(v));
      if (static_cast<int>(batch.size()) >= ais.batch_vessels) {
        flush();
        if (on_progress) on_progress(report.points, reader.Fraction());
      }
    }
    flush();
    report.files.emplace_back(path, reader.stats());
  }
  d.info = {{"features", o.features},
            {"length", o.length},
            {"counts", report.counts},
            {"with_map", true},
            {"vessels_per_class", report.vessels_per_class},
            {"preprocessing", classify::PreprocessingJson(o, {})}};
  return d;
}

}  // namespace specht::ais
