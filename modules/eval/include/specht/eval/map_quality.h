// specht/eval/map_quality.h: how good an occupancy grid is, without ground truth.
//
// Wall thickness. A wall seen from consistent poses fills a band one or two cells
// wide; misregistered scans smear it into a thick band. On the mask of occupied cells
// (occupancy > 0.65, map_saver's threshold) the Euclidean distance transform D gives
// each occupied cell its distance to the nearest non-occupied cell. On the band's
// centre line (cells where D is a local maximum) the band is (2·D − 1) cells thick.
// We report percentiles of that thickness in metres.
//
// Mean map entropy (Razlaw et al. 2015, "Evaluation of registration methods for
// sparse 3D laser scans"). The keyframe scans are placed at their poses as one point
// cloud; for each point p with at least `min_neighbours` points q within
// `radius_m`, Σ(p) is their sample covariance and
//   h(p) = ½ ln det(2πe (Σ(p) + ε²I))   (the entropy of a Gaussian, in nats;
//                                        ε = 1 mm keeps a synthetic straight wall finite)
// and the map's entropy is the mean of h over those points. A wall seen twice from
// poses that disagree by δ widens its neighbourhoods by δ (lower is sharper). Placed
// at the reference's poses, the same scans tell how consistent the reference is:
// where the estimate's map is the sharper one, part of the error against the
// reference is the reference's own. (A broken map scores well where its passes no
// longer overlap: it says nothing about loops that were missed.)
//
// Registration correction. Scans are aligned by ICP to the occupied cells of a grid,
// starting from their estimated poses; the size of the ICP correction measures how
// far the estimate is from agreeing with the map.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose2D.h>

#include <vector>

#include "specht/core/trajectory.h"
#include "specht/slam/scan_matching.h"

namespace specht::eval {

struct WallThickness {
  size_t centre_cells = 0;
  double mean_m = 0, p50_m = 0, p90_m = 0, p95_m = 0;
};

WallThickness MeasureWallThickness(const mrpt::maps::COccupancyGridMap2D& grid);

struct MapEntropyOptions {
  double radius_m = 0.3;      // neighbourhood of each point
  int min_neighbours = 5;     // points with fewer are left out
  double max_range_m = 10;    // returns farther than this are left out (sparse, noisy)
  size_t max_points = 20000;  // h is averaged over at most this many points, every k-th of the cloud
};

struct MapEntropy {
  double mean_nats = 0;  // mean of h over the points used
  size_t points = 0;     // points averaged (with min_neighbours)
};

MapEntropy MeanMapEntropy(const std::vector<slam::Keyframe>& keyframes, const MapEntropyOptions& options = {});

// The keyframes whose stamp has a reference pose within max_dt_s, as (at the
// estimate's poses, at the reference's poses): the same scans, two placements.
std::pair<std::vector<slam::Keyframe>, std::vector<slam::Keyframe>> KeyframesAtReference(
    const std::vector<slam::Keyframe>& keyframes, const Trajectory& reference, double max_dt_s);

struct Correction {
  double translation_m = 0;
  double rotation_deg = 0;
  double goodness = 0;  // fraction of scan points that paired with the map
};

// One ICP alignment per keyframe against the grid's occupied cells.
std::vector<Correction> RegisterAgainstGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                            const std::vector<slam::Keyframe>& keyframes, const slam::IcpOptions& icp);

}  // namespace specht::eval
