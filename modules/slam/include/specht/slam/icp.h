// specht/slam/icp.h: 2D ICP with specht's options, and the conversion of a laser scan
// to points in the car's frame.
//
// Two stages. Point-to-point ICP (MRPT CICP) minimises Σ |R(θ) s_i + t − m_j(i)|²
// over (t, θ), pairing each scan point s_i with its nearest map point m_j(i) closer
// than a threshold that starts at max_pair_distance_m and shrinks by threshold_decay
// each time the estimate settles, down to min_pair_distance_m. It converges from far,
// but a scan point seldom lies exactly where a map point was sampled, so the pairs
// pull along the walls too and the optimum sits a few centimetres off.
//
// Point-to-line refinement (Censi, PL-ICP, ICRA 2008) then minimises the distance of
// each scan point to the line through its map neighbours:
//   Σ ρ( n_i · (R(θ) s_i + t − μ_i) )²
// where μ_i, n_i are the mean and normal (least-eigenvalue direction) of the
// point_to_line_neighbours map points nearest to R s_i + t, kept only when the nearest
// lies within point_to_line_gate_m and the neighbours lie on a line; ρ is Huber's
// loss with its corner at half the gate. Gauss–Newton, with the Jacobian of one
// residual J_i = (n_x, n_y, n · ∂(R s_i)/∂θ), ∂(R s)/∂θ = (−sinθ s_x − cosθ s_y,
// cosθ s_x − sinθ s_y).
//
// Two starts. When ICP ends more than half the gate or 1° from the guess, the guess
// is refined as well, and the pose with the lower truncated cost Σ min(r_i², gate²)
// over all scan points (a point with no line near costs gate²) wins, the guess's on
// a tie: where the lines pin one direction only (a corridor), point-to-point ICP
// slides along it after whatever its pairs pull at (clutter, a person walking).
//
// With a prior (the odometry's guess μ and its information Ω, map frame x y θ) the
// refinement minimises
//   Σ ρ(r_i)² + σ² (x ⊟ μ)ᵀ Ω (x ⊟ μ),   σ = IcpPrior::point_sigma_m,
// i.e. the residuals of points known to σ against the prior, both as information:
// H += σ² Ω, g += σ² Ω (x ⊟ μ), and the two starts are compared with the prior's term
// in their cost. Along a corridor the lines carry no information, so there the prior
// holds the pose where the odometry put it instead of letting the step drift with the
// noise (and with the points at the scan's far end that find no line yet, which would
// otherwise favour a pose short of the true one); across it the lines outweigh it.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "specht/core/params.h"
#include "specht/slam/indexed_points.h"

namespace specht::slam {

// MRPT CICP settings (section "scan_matching.icp").
struct IcpOptions {
  int max_iterations = 80;
  double max_pair_distance_m = 0.6;   // initial matching distance (CICP thresholdDist)
  double max_pair_angle_deg = 5.0;    // angular part of the matching distance (thresholdAng)
  double threshold_decay = 0.6;       // ALFA: thresholds shrink by this on convergence
  double min_pair_distance_m = 0.05;  // smallest threshold before stopping
  int point_decimation = 3;           // use every n-th point of the scan as a query
  int point_to_line_iterations = 10;  // Gauss–Newton steps of the refinement; 0 = off
  double point_to_line_gate_m = 0.1;  // pair a scan point only this close to the map
  int point_to_line_neighbours = 5;   // map points a line is fitted to

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("max_iterations", max_iterations, "ICP iterations per alignment", Range::Of(5, 500));
    v.Param("max_pair_distance_m", max_pair_distance_m, "initial point pairing distance", Range::Of(0.05, 3.0).Log());
    v.Param("max_pair_angle_deg", max_pair_angle_deg, "angular term of the pairing distance", Range::Of(0.0, 20.0));
    v.Param("threshold_decay", threshold_decay, "pairing distance factor on convergence", Range::Of(0.1, 0.95));
    v.Param("min_pair_distance_m", min_pair_distance_m, "smallest pairing distance", Range::Of(0.005, 0.5).Log());
    v.Param("point_decimation", point_decimation, "pair every n-th scan point", Range::Of(1, 20));
    v.Param("point_to_line_iterations", point_to_line_iterations,
            "Gauss-Newton steps of the point-to-line refinement after ICP; 0 = off", Range::Of(0, 100));
    v.Param("point_to_line_gate_m", point_to_line_gate_m, "point-to-line: pair a scan point only this close to the map",
            Range::Of(0.01, 1.0).Log());
    v.Param("point_to_line_neighbours", point_to_line_neighbours, "point-to-line: map points a line is fitted to",
            Range::Of(3, 20));
  }
};

struct IcpPrior {
  mrpt::poses::CPose2D pose;                              // μ, in the reference's frame
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  // Ω, x y θ
  double point_sigma_m = 0.03;                            // σ of one scan point against its line
};

struct IcpResult {
  mrpt::poses::CPose2D pose;  // of the scan's frame in the reference's frame
  double goodness = 0;        // fraction of scan points that found a partner
  int iterations = 0;
  // Which scan points had a line near them in the reference at `pose` (empty without
  // the point-to-line refinement): what WeakestAxis counts.
  std::vector<bool> line_paired;
};

class IcpAligner {
 public:
  explicit IcpAligner(const IcpOptions& options);
  ~IcpAligner();
  IcpAligner(const IcpAligner&) = delete;
  IcpAligner& operator=(const IcpAligner&) = delete;

  // The pose of `scan` in `reference`'s frame, from `guess`; the point-to-line
  // refinement holds it to `prior` and fits its lines to `lines` (the same frame),
  // when given, else to `reference`.
  IcpResult Align(const IndexedPoints& reference, const mrpt::maps::CSimplePointsMap& scan,
                  const mrpt::poses::CPose2D& guess, const IcpPrior* prior = nullptr,
                  const IndexedPoints* lines = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// How firmly `scan`, aligned as `result` says, pins the translation along the
// direction it pins least, v = argmin Σ (n_i·v)² over the scan's own surface normals
// n_i (chords of 0.2 m between beams) at the points the reference holds
// (result.line_paired; every point when empty). A straight corridor gives about 0
// points (every normal across it), a room tens or hundreds. Computed on request: only
// the corridor settings use it.
struct WeakestAxis {
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();  // v, unit, reference frame
  int points = 0;                                   // scan points whose normal lies within 60° of v
};
WeakestAxis WeakestAxisOf(const mrpt::maps::CSimplePointsMap& scan, const IcpResult& result);

// The valid returns of a scan as points in the car's frame (sensor mount applied).
mrpt::maps::CSimplePointsMap ScanToPoints(const mrpt::obs::CObservation2DRangeScan& scan);

// The points within max_range_m of the frame's origin.
mrpt::maps::CSimplePointsMap WithinRange(const mrpt::maps::CSimplePointsMap& points, double max_range_m);

}  // namespace specht::slam
