// specht/ais/dataset.h: the vessel paper's dataset from tabular AIS
// (../shared/papers/classification-maritime-vessels-cnn.md §3): vessels → trajectories
// → segments (gaps in time or space) → fixed-length windows → stationary filter →
// features (position, Δt, speed, course, distance to coast, distance to the
// closest harbour) → normalisation. The windowing and features are the classify
// module's (classify/preprocess.h), configured by section "ais_classify".
//
// Positions: each vessel is put in the equirectangular frame of its first report,
// x = lon · cos φ0, y = lat, both in degrees of latitude (≈ 111.2 km), so speeds
// and the squared-degree jump threshold mean the same in both axes.
//
// Streaming: vessels are read one at a time (positions.h), processed in batches on
// `threads` threads and appended in input order, so memory holds one batch of
// input plus the output windows, and the result does not depend on the threads.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "specht/ais/geo.h"
#include "specht/ais/positions.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"
#include "specht/core/params.h"

namespace specht::ais {

// Section "ais": geography and the preparation's execution.
struct AisOptions {
  std::string coastline = "ais/geo/GSHHS_l_coastline.shp";
  std::string ports = "ais/geo/wpi-UpdatedPub150.csv.gz";
  std::vector<std::string> harbour_sizes = {"Large"};
  double coast_cap_km = 20.0;
  double harbour_cap_km = 2500.0;
  int threads = 2;
  int batch_vessels = 64;
  bool unlabelled = false;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("coastline", coastline, "coastline shapefile (relative paths: under the data directory)");
    v.Param("ports", ports, "World Port Index CSV (relative paths: under the data directory)");
    v.Param("harbour_sizes", harbour_sizes,
            "WPI 'Harbor Size' values kept (the paper: the 140 major harbours ≈ Large); empty keeps all");
    v.Param("coast_cap_km", coast_cap_km, "distance to coast is capped here (paper: 20 km)", Range::Of(0.1, 20000.0));
    v.Param("harbour_cap_km", harbour_cap_km, "distance to harbour is capped here (paper: 2500 km)",
            Range::Of(1.0, 20000.0));
    v.Param("threads", threads, "worker threads for preparation", Range::Of(1, 256).Fixed());
    v.Param("batch_vessels", batch_vessels, "vessels per parallel batch", Range::Of(1, 100000).Fixed());
    v.Param("unlabelled", unlabelled,
            "also prepare the vessels of unknown ship type (none or 0), labelled \"unlabelled\": never scored, "
            "for `ais eval --pseudo-labels`");
  }
};

// Section "ais_classify": the classify module's preprocessing with the AIS
// defaults. The paper's thresholds (2 h gap, 1e-4 squared-degree jump ≈ 1 km)
// were set for ≈ 10 s reporting, where 1 km between reports means ≈ 200 kn. The
// shipped data reports every 10–300 s with many gaps of minutes to hours, where a
// fixed 1 km cuts every fast vessel's track (a 300 s report interval at 12 kn is
// 1.9 km). So the gap stays at 2 h, and a step longer than the paper's 1 km is a
// jump only when it also implies more than 50 kn (max_jump_speed). Windows are 60 reports by default
// (≈ 10 min to 5 h here): a fishing vessel has ≈ 190 reports in this data, so
// 360-point windows leave 14 fishing vessels in all (README). Features: the
// paper's (position, Δt, speed, course, distance to coast and harbour) plus
// acceleration, turn rate, the region (longitude, latitude) and the flag state
// (feature "category": the MID of the MMSI, FlagMid, / 1000, and 8 sine/cosine
// pairs of it for the network); Δt and the distances log-scaled.
struct AisPreprocessOptions : classify::PreprocessOptions {
  AisPreprocessOptions();
};

// Section "ais_model": the classifier. Default variant "tiny", the one
// cross-validated here (README), with its inputs encoded over 4 quantile bins
// (input_bins); the paper's best, "shallow", is one --set away.
struct AisModelOptions : classify::ModelOptions {
  AisModelOptions();
};

// Distance-to-coast and distance-to-harbour lookups (thread-safe).
class Geography {
 public:
  Geography(std::vector<GeoPoint> coast, std::vector<GeoPoint> harbours, double coast_cap_km, double harbour_cap_km);
  // Reads the files named by the options; relative paths are under `data_dir`.
  static Geography Load(const AisOptions& o, const std::string& data_dir);
  // Map features for a vessel in the frame of ToTrajectory (x = lon·cos φ0).
  classify::MapFeatures ForFrame(double cos_lat0) const;
  size_t coast_points() const { return coast_.size(); }
  size_t harbours() const { return harbours_.size(); }

 private:
  NearestGeoPoint coast_, harbours_;
  double coast_cap_km_, harbour_cap_km_;
};

// The label of a vessel of unknown ship type, prepared with ais.unlabelled (its
// windows read back with class index −1).
inline const std::string kUnlabelled = "unlabelled";

// A vessel as a trajectory in its own equirectangular frame; label = its class,
// category = its flag (FlagMid).
classify::Trajectory ToTrajectory(const Vessel& v, double& cos_lat0);

struct PrepareReport {
  std::map<std::string, std::map<std::string, long>> counts;  // step → class → count
  std::map<std::string, long> vessels_per_class;              // vessels with ≥ 1 window (and kUnlabelled)
  long excluded_vessels = 0;  // other ship types, and unknown ones unless ais.unlabelled
  long points = 0;
  std::vector<std::pair<std::string, PositionStats>> files;
};

// Prepares the windows of every labelled vessel in `files` (and with ais.unlabelled
// of every vessel of unknown type, as kUnlabelled). `on_progress` (may be
// empty) gets the points read so far and the fraction of the current file.
classify::PreparedDataset PrepareDataset(const std::vector<std::string>& files, const AisOptions& ais,
                                         const classify::PreprocessOptions& o, const Geography& geo,
                                         PrepareReport& report,
                                         const std::function<void(long points, double fraction)>& on_progress = {});

}  // namespace specht::ais
