// specht/slam/pose_check.h: does a believed pose agree with a prior map of the site,
// and where on that map is the scan when it does not (relocalisation)?
//
// Whatever estimates the pose (graph SLAM from the start, localisation on a map, an
// oracle with an injected fault), a scan taken at the true pose lands on the map's
// walls and one taken at a wrong pose does not. The check scores each scan at the
// believed pose with the correlative matcher's likelihood (correlative_matcher.h):
//   score(pose) = 1/N Σ_i L(cell(pose ⊕ s_i)),  L(c) = exp(−d(c)² / 2σ²),
// d the distance from cell c to the nearest occupied cell of the map, σ = blur_cells
// cells, N the scan's points (returns on tracked road users removed before). At the
// true pose L is about 1 for every point on a mapped wall; what the map does not hold
// (an untracked car, a wall built since) lowers it, so one low score says little.
// The pose is declared lost after `lost_after_scans` consecutive scans score below
// `lost_below` (a scan of fewer than `min_points` points gives no verdict: a few
// returns fit many poses). Relocalisation is a branch-and-bound search of the map
// within ±search_window_m, ±search_window_deg of the believed pose (exact on its
// lattice: a cell, and an angle step that moves the farthest point by a cell), refined
// by ICP against the map's occupied cells (icp.h) — kept when it scores no less than
// the searched pose; it is accepted when its pose scores `relocalized_above` or more —
// well above `lost_below`, so that a found pose is one the check would keep.
// The monitor is independent of the estimator: it reads only the scan, the pose and
// the map, as AMCL's or Nav2's localisation health checks do.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/slam/correlative_matcher.h"
#include "specht/slam/icp.h"
#include "specht/slam/indexed_points.h"

namespace specht::slam {

// Section "pose_check".
struct PoseCheckOptions {
  bool enabled = true;
  double resolution_m = 0.1;
  double blur_cells = 2.0;
  double lost_below = 0.5;
  int lost_after_scans = 5;
  int min_points = 100;
  double free_radius_m = 0.5;
  double search_window_m = 8.0;
  double search_window_deg = 30.0;
  double relocalized_above = 0.7;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("enabled", enabled,
            "check every scan at the believed pose against the prior map, stop when the pose is lost and "
            "relocalise (closed loop on a prior map)");
    v.Param("resolution_m", resolution_m, "cell size of the likelihood grid and of the relocalisation search",
            Range::Of(0.02, 0.5).Log());
    v.Param("blur_cells", blur_cells, "σ of the likelihood around the map's occupied cells, in cells",
            Range::Of(0.5, 10.0));
    v.Param("lost_below", lost_below, "a scan disagrees with the map when it scores below this", Range::Of(0.0, 1.0));
    v.Param("lost_after_scans", lost_after_scans, "the pose is lost after this many disagreeing scans in a row",
            Range::Of(1, 1000));
    v.Param("min_points", min_points, "a scan of fewer points gives no verdict and is not searched",
            Range::Of(1, 10000));
    v.Param("free_radius_m", free_radius_m,
            "relocalisation: the found pose lies at least this far from the map's occupied cells (the car stands "
            "in free space; an alias inside a wall is refused)",
            Range::Of(0.0, 5.0));
    v.Param("search_window_m", search_window_m, "relocalisation: search this far around the believed pose",
            Range::Of(0.1, 50.0));
    v.Param("search_window_deg", search_window_deg, "relocalisation: angular half-width of the search",
            Range::Of(1.0, 180.0));
    v.Param("relocalized_above", relocalized_above, "relocalisation: accept a pose scoring this or more",
            Range::Of(0.0, 1.0));
  }
  std::vector<std::string> Relations() const;
};

class PoseCheck {
 public:
  // `map`: the prior map (its occupied cells are what scans should land on); it must
  // outlive the check.
  PoseCheck(const mrpt::maps::COccupancyGridMap2D& map, const PoseCheckOptions& options);

  // The agreement of `points` (in the frame of `pose`) with the map at `pose`, in
  // [0, 1]; nullopt when there are fewer than min_points.
  std::optional<double> Score(const mrpt::maps::CSimplePointsMap& points, const mrpt::poses::CPose2D& pose) const;
  // Where on the map `points` fit best near `guess`, when that scores relocalized_above.
  std::optional<CorrelativeResult> Relocalize(const mrpt::maps::CSimplePointsMap& points,
                                              const mrpt::poses::CPose2D& guess) const;
  const PoseCheckOptions& options() const { return options_; }

 private:
  bool InFreeSpace(const mrpt::poses::CPose2D& pose) const;
  PoseCheckOptions options_;
  const mrpt::maps::COccupancyGridMap2D& map_;
  std::unique_ptr<CorrelativeMatcher> matcher_;
  IndexedPoints cells_;  // the occupied cells' centres, for the refinement
};

// Whether the pose is lost: the verdicts of successive scans, in order.
class PoseMonitor {
 public:
  explicit PoseMonitor(const PoseCheckOptions& options) : options_(options) {}
  // One scan's score (nullopt: no verdict). Returns whether the pose is now lost.
  bool Add(std::optional<double> score);
  bool lost() const { return disagreeing_ >= options_.lost_after_scans; }
  void Reset() { disagreeing_ = 0; }
  // Every verdict so far: scans scored, their lowest score, scans below lost_below.
  long scored() const { return scored_; }
  long disagreeing_total() const { return disagreeing_total_; }
  double lowest() const { return lowest_; }

 private:
  PoseCheckOptions options_;
  int disagreeing_ = 0;
  long scored_ = 0, disagreeing_total_ = 0;
  double lowest_ = 1.0;
};

}  // namespace specht::slam
