// specht/classify/preprocess.h: trajectories to fixed-size, normalised feature
// windows, as in the vessel-classification paper
// (../shared/papers/classification-maritime-vessels-cnn.md §3), generic over the
// source (tracker output, AIS):
//   1. split a trajectory where the time between samples exceeds max_gap_s or the
//      squared distance between them exceeds max_jump_sq (position units²: m² for
//      map tracks, squared degrees for AIS); with max_jump_speed > 0 a long step
//      is only a jump if it also implies a faster speed (so the test holds for
//      any sampling interval, and position noise over short intervals is no jump);
//   2. cut each piece into windows of `length` points; a leftover shorter than
//      min_fill · length is dropped, a longer one zero-padded (after normalisation);
//   3. drop stationary windows: α = Σ|P_i − P_{i−1}| / n below stationary_threshold;
//   4. features per point (see FeatureNames), positions relative to the first point
//      or also rotated so the last point lies on the +x axis (rotate_to_zero);
//   5. min-max normalisation to [0, 1]: positions "local" (over the window),
//      "global" (bounds fitted on the training set and stored with the model) or
//      "fixed" (±position_extent around the first point, keeping the size); the
//      other features with fixed bounds: Δt by max_gap_s, speed by max_speed, course
//      by 2π (feature "course", measured from +x; "heading" takes two rows, ½ + ½ sin
//      and ½ + ½ cos of the course, which do not jump from 1 to 0 where the course
//      crosses +x), acceleration and turn rate symmetric around 0.5 by their caps,
//      map distances by their query caps. The object's category c (the same at every
//      point) takes 1 + 2K rows: u = c / category_cap, then for k = 0 … K−1
//      (K = category_frequencies) ½ + ½ sin(2π 2^k u) and ½ + ½ cos(2π 2^k u), so
//      that a network can tell apart codes a few units apart (a convolution on u
//      alone would need very steep weights; a forest splits u's ranges directly).
//      Features in log_scaled (Δt, map distances) map by log(1 + v) / log(1 + cap)
//      instead, for values spread over decades (AIS reports 2 s to hours apart).
#pragma once

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::classify {

struct TrajectoryPoint {
  double t_s = 0, x = 0, y = 0;
};

struct Trajectory {
  std::string object_id;
  std::string label;  // class name, empty when unknown
  std::vector<TrajectoryPoint> points;
  // A code the source gives the whole object, 0 when it has none (AIS: the flag
  // state, the MID of the MMSI, 201–775). Feature "category": its scaled value and
  // sine/cosine pairs (step 5 above).
  int category = 0;
};

// Section "classify".
struct PreprocessOptions {
  double max_gap_s = 2.0;
  double max_jump_sq = 25.0;
  double max_jump_speed = 0.0;
  int length = 60;
  double min_fill = 0.8;
  double stationary_threshold = 0.02;
  std::string transform = "relative_to_first";
  std::string normalisation = "local";
  double position_extent = 50.0;
  std::vector<std::string> features = {"x",     "y",         "dt",          "speed",   "course",
                                       "accel", "turn_rate", "dist_static", "dist_poi"};
  std::vector<std::string> log_scaled;
  double max_speed = 15.0;
  double max_accel = 10.0;
  double max_turn_rate = 3.0;
  double static_cap = 10.0;
  double poi_cap = 50.0;
  double category_cap = 1000.0;
  int category_frequencies = 0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("max_gap_s", max_gap_s, "split a trajectory where samples are further apart in time",
            Range::Of(0.01, 1e6).Log());
    v.Param("max_jump_sq", max_jump_sq, "…or in squared distance (position units²)", Range::Of(1e-12, 1e12).Log());
    v.Param("max_jump_speed", max_jump_speed, "…and (when > 0) implies a faster speed (units/s)", Range::Of(0.0, 1e9));
    v.Param("length", length, "points per window", Range::Of(4, 100000));
    v.Param("min_fill", min_fill, "a leftover shorter than this fraction of a window is dropped", Range::Of(0.0, 1.0));
    v.Param("stationary_threshold", stationary_threshold, "windows whose mean step is below are dropped",
            Range::Of(0.0, 1e6));
    v.Choice("transform", transform, {"relative_to_first", "rotate_to_zero"}, "position transform per window");
    v.Choice("normalisation", normalisation, {"local", "global", "fixed"},
             "positions: min-max over the window, over the dataset, or ±position_extent");
    v.Param("position_extent", position_extent, "half-width of the fixed normalisation (position units)",
            Range::Of(1e-9, 1e9).Log());
    v.Param(
        "features", features,
        "per-point features, from: x y dt speed course heading accel turn_rate dist_static dist_poi region_x region_y "
        "category");
    v.Param("log_scaled", log_scaled, "features scaled by log(1 + v) / log(1 + cap): any of dt dist_static dist_poi");
    v.Param("max_speed", max_speed, "speed normalisation bound (position units per s)", Range::Of(1e-9, 1e9).Log());
    v.Param("max_accel", max_accel, "acceleration bound (units/s²)", Range::Of(1e-9, 1e9).Log());
    v.Param("max_turn_rate", max_turn_rate, "turn-rate bound (rad/s)", Range::Of(1e-6, 1e3).Log());
    v.Param("static_cap", static_cap, "distance to the nearest static obstacle is capped here (m)",
            Range::Of(1e-3, 1e9).Log());
    v.Param("poi_cap", poi_cap, "distance to the nearest point of interest is capped here", Range::Of(1e-3, 1e9).Log());
    v.Param("category_cap", category_cap, "the object's category code is divided by this (feature category)",
            Range::Of(1.0, 1e9).Log());
    v.Param("category_frequencies", category_frequencies,
            "sine/cosine pairs encoding the category for the network (frequencies 1, 2, 4, … per category_cap)",
            Range::Of(0, 16));
  }
  std::vector<std::string> Relations() const;
};

// The features a window can carry, in their canonical names.
const std::vector<std::string>& FeatureNames();
// Rows of a window's feature matrix: one per feature, 2 for "heading",
// 1 + 2·category_frequencies for "category".
int FeatureRows(const PreprocessOptions& o);

// Map features at a position: distance to the nearest occupied static cell (the
// analogue of distance-to-coast) and to the nearest point of interest (of
// distance-to-harbour), and where on the map the point is, normalised to [0, 1]²
// (features region_x, region_y: the absolute position the window transforms
// remove). Unset members give 0.
struct MapFeatures {
  std::function<double(double x, double y)> distance_to_static;
  std::function<double(double x, double y)> distance_to_poi;
  std::function<std::array<double, 2>(double x, double y)> region;
};

struct Window {
  std::string object_id, label;
  int category = 0;  // the trajectory's
  double t0_s = 0;
  int valid = 0;                        // points before the zero padding
  std::vector<TrajectoryPoint> points;  // the raw points (valid of them)
};

// Steps 1–3. Throws InputError on a trajectory with a non-finite value or time that
// goes backwards (naming the object and the sample index).
std::vector<Trajectory> Split(const Trajectory& t, const PreprocessOptions& o);
std::vector<Window> Chunk(const Trajectory& t, const PreprocessOptions& o);
double MeanStepLength(const std::vector<TrajectoryPoint>& points);
// The whole chain for many trajectories; `counts` (when given) receives the number
// of trajectories/windows per class after each step ("input", "split", "chunked",
// "moving") — the paper's Figure 3.
std::vector<Window> MakeWindows(const std::vector<Trajectory>& trajectories, const PreprocessOptions& o,
                                std::map<std::string, std::map<std::string, long>>* counts = nullptr);

// Step 4 position transforms, in place.
void RelativeToFirst(std::vector<TrajectoryPoint>& points);
void RotateToZero(std::vector<TrajectoryPoint>& points);  // after RelativeToFirst

// Position bounds for global normalisation.
struct PositionBounds {
  double min_x = 0, max_x = 1, min_y = 0, max_y = 1;
};

// Steps 4–5: a FeatureRows × length matrix (row-major, feature-major), zero-padded.
// `global` is used when normalisation is "global".
std::vector<float> Features(const Window& w, const PreprocessOptions& o, const MapFeatures& map,
                            const PositionBounds& global = {});
// Bounds of the transformed positions over windows (global normalisation).
PositionBounds FitPositionBounds(const std::vector<Window>& windows, const PreprocessOptions& o);

}  // namespace specht::classify
