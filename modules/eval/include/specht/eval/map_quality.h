// specht/eval/map_quality.h: how good an occupancy grid is, without ground truth.
//
// Wall thickness. A wall seen from consistent poses fills a band one or two cells
// wide; misregistered scans smear it into a thick band. On the mask of occupied cells
// (occupancy > 0.65, map_saver's threshold) the Euclidean distance transform D gives
// each occupied cell its distance to the nearest non-occupied cell. On the band's
// centre line (cells where D is a local maximum) the band is (2·D − 1) cells thick.
// We report percentiles of that thickness in metres.
//
// Registration correction. Scans are aligned by ICP to the occupied cells of a grid,
// starting from their estimated poses; the size of the ICP correction measures how
// far the estimate is from agreeing with the map.
#pragma once

#include <vector>

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose2D.h>

#include "specht/slam/scan_matching.h"

namespace specht::eval {

struct WallThickness {
  size_t centre_cells = 0;
  double mean_m = 0, p50_m = 0, p90_m = 0, p95_m = 0;
};

WallThickness MeasureWallThickness(const mrpt::maps::COccupancyGridMap2D& grid);

struct Correction {
  double translation_m = 0;
  double rotation_deg = 0;
  double goodness = 0;  // fraction of scan points that paired with the map
};

// One ICP alignment per keyframe against the grid's occupied cells.
std::vector<Correction> RegisterAgainstGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                            const std::vector<slam::Keyframe>& keyframes,
                                            const slam::IcpOptions& icp);

}  // namespace specht::eval
