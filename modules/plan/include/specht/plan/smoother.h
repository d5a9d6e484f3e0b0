// specht/plan/smoother.h: smoothing a searched path by optimisation on Ceres, in the
// manner of an elastic band (Dolgov et al. 2008, §III-B). The path is resampled
// every `spacing_m`; the rear-axle positions x_i between fixed ends (start, goal,
// and every gear change — a cusp must stay where the search put it — each with its
// neighbour, which holds the end's heading) minimise
//   Σ w_smooth  · |x_{i−1} − 2 x_i + x_{i+1}|²                    smoothness
// + Σ w_clear   · Σ_discs max(0, r + margin + buffer − D(c_ij))²  clearance
// + Σ w_curv    · max(0, κ_i − κ_max)²                            curvature
// where c_ij are the footprint-disc centres at x_i with the heading of the path
// there, D the obstacle distance (bicubic interpolation of the distance map, so the
// solver sees its gradient), κ_i = Δφ_i / |x_{i+1} − x_i| the turning per metre.
// The result is accepted only if every pose is collision-free and within the
// steering limit (5 % slack for the discretisation); otherwise the input path is
// returned and `accepted` says why not.
#pragma once

#include <string>

#include "specht/plan/distance_map.h"
#include "specht/plan/path.h"

namespace specht::plan {

// Section "smoother".
struct SmootherOptions {
  bool enabled = true;
  double spacing_m = 0.3;
  double w_smooth = 1.0;
  double w_clear = 10.0;
  double w_curvature = 50.0;
  double clearance_buffer_m = 0.3;
  int max_iterations = 50;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("enabled", enabled, "smooth the searched path");
    v.Param("spacing_m", spacing_m, "spacing of the optimised points", Range::Of(0.05, 2.0));
    v.Param("w_smooth", w_smooth, "weight of the smoothness term", Range::Of(0.0, 1000.0));
    v.Param("w_clear", w_clear, "weight of the clearance term", Range::Of(0.0, 1000.0));
    v.Param("w_curvature", w_curvature, "weight of the curvature-limit term", Range::Of(0.0, 1000.0));
    v.Param("clearance_buffer_m", clearance_buffer_m, "clearance beyond the safety margin the smoother seeks",
            Range::Of(0.0, 5.0));
    v.Param("max_iterations", max_iterations, "solver iterations", Range::Of(1, 10000));
  }
};

struct SmoothResult {
  Path path;
  bool accepted = false;
  std::string note;  // why the smoothed path was not used
  double milliseconds = 0;
};

SmoothResult SmoothPath(const Path& path, const DistanceMap& map, const CarOptions& car, const SmootherOptions& o);

}  // namespace specht::plan
