// specht/slam/correlative_matcher.h: a scan matcher robust to large initial error,
// for loop closure and for front-end recovery (branch and bound over a multi-
// resolution grid, as Cartographer's FastCorrelativeScanMatcher2D; Olson 2009).
//
// The map is a likelihood grid L over cells c: L(c) = exp(−d(c)² / 2σ²), d the
// distance from c to the nearest map point, σ = `blur_cells` cells. A candidate pose
// (x, y, θ) scores the mean of L over the scan's points moved by it:
//   score(x, y, θ) = 1/N Σ_i L(cell(R(θ) s_i + (x, y)))
// Search: every angle θ0 + kδθ within ±window (δθ so that the farthest point moves
// by about one cell: δθ = acos(1 − r²/2d²) with r the cell size, d the range), every
// translation within ±window. Branch and bound over translations: level h keeps
//   P_h(c) = max_{0≤u,v<2^h} L(c + (u, v)),
// so the mean of P_h over the points bounds every translation in the 2^h × 2^h block
// below a candidate. Candidates are expanded best first; a branch whose bound is not
// above the best leaf found is cut. The result is the exact best-scoring pose on the
// search lattice.
//
// With a DrivePrior the score loses what the motion from `from` to the pose cannot
// be for a wheeled robot between two scans (DrivePrior::ExcessM below); the bound of a
// block then loses the least excess over the block, so the search stays exact.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace specht::slam {

struct CorrelativeResult {
  mrpt::poses::CPose2D pose;  // of the scan in the map's frame
  double score = 0;           // mean likelihood of the scan points, in [0, 1]
};

// What a wheeled robot (differential drive or car) can do between two scans. On an
// arc the chord from `from` to the pose points along the mean heading
//   φ̄ = φ_from + wrap(φ − φ_from) / 2,
// so the motion's sideways part ℓ = −sin φ̄ Δx + cos φ̄ Δy is zero and its forward
// part f = cos φ̄ Δx + sin φ̄ Δy is not negative unless the robot reverses. A match
// loses weight_per_m of score per metre of
//   excess = max(0, |ℓ| − slack_m) + (reverse ? 0 : max(0, −f − slack_m)).
// Without odometry this is what tells a corridor's step forward from its aliases
// beside or behind the robot.
struct DrivePrior {
  mrpt::poses::CPose2D from;  // where the robot was (map frame)
  double weight_per_m = 0;    // score lost per metre of excess; 0 = no prior
  double slack_m = 0.2;       // sideways / backward motion allowed freely (several arcs, wheel slip)
  bool reverse = false;       // whether the robot may back up between scans

  // cos φ̄ and sin φ̄ for heading φ: the same for every position, so a search computes
  // them once per angle.
  struct Axes {
    double c = 1, s = 0;
  };
  Axes AxesAt(double phi) const;

  // Excess (m) of the pose (x, y, φ).
  double ExcessM(double x, double y, double phi) const;
  // The least excess over positions in [x0, x1] × [y0, y1] at heading φ (a lower bound).
  double MinExcessM(double x0, double x1, double y0, double y1, double phi) const;
  double MinExcessM(double x0, double x1, double y0, double y1, const Axes& axes) const;
};

class CorrelativeMatcher {
 public:
  // Builds the likelihood grid and its max pyramid for `map_points` (in the map
  // frame) with cells of `resolution_m`, padded so that translations up to
  // `max_window_m` stay inside. Throws std::invalid_argument unless resolution_m and
  // blur_cells are positive.
  CorrelativeMatcher(const mrpt::maps::CSimplePointsMap& map_points, double resolution_m, double max_window_m,
                     double blur_cells = 1.0);

  // Best pose within ±window_m, ±window_rad of `guess` whose score reaches
  // `min_score`, or nullopt. `scan` is in the scan's own frame.
  // With `prior`, the score is the likelihood less the prior's penalty.
  std::optional<CorrelativeResult> Match(const mrpt::maps::CSimplePointsMap& scan, const mrpt::poses::CPose2D& guess,
                                         double window_m, double window_rad, double min_score,
                                         const DrivePrior& prior = {}) const;

  // Score of one pose (less the prior's penalty), as Match scores it.
  double Score(const mrpt::maps::CSimplePointsMap& scan, const mrpt::poses::CPose2D& pose,
               const DrivePrior& prior = {}) const;

  // Bytes held by the grid pyramid.
  size_t MemoryBytes() const;

 private:
  struct Level {
    std::vector<uint8_t> cells;  // likelihood × 255, row-major, width_ × height_
  };
  uint8_t At(int level, int cx, int cy) const;

  double resolution_;
  double x0_, y0_;  // world coordinates of cell (0, 0)'s corner
  int width_ = 0, height_ = 0;
  std::vector<Level> levels_;  // levels_[h] = P_h
};

// Keeps at most one point per cell of `cell_m` (the first), for fast scoring.
mrpt::maps::CSimplePointsMap Decimate(const mrpt::maps::CSimplePointsMap& points, double cell_m);

// One point per cell of `cell_m`: the mean of the points in it (a voxel filter). A
// submap stacked from many scans is dense along a wall far beyond its noise across it;
// the means keep the wall's line and bound the density.
mrpt::maps::CSimplePointsMap CellMeans(const mrpt::maps::CSimplePointsMap& points, double cell_m);

}  // namespace specht::slam
