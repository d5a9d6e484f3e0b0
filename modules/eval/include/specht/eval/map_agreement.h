// specht/eval/map_agreement.h: how well an occupancy grid agrees with a reference
// grid of the same place drawn in another frame (a team's own map_server map).
//
// Occupied cells (p(occupied) ≥ 0.65, map_server's threshold) become points at their
// centres. Alignment: the correlative matcher (slam/correlative_matcher.h) finds the
// rigid motion T that puts our points on the reference's best, over every heading
// and ±search_window_m, at 0.1 m cells, then again at 0.05 m within ±0.3 m and ±2°.
// Agreement after alignment, with tolerance τ:
//   ours_within    share of our occupied cells within τ of a reference one
//   theirs_within  share of the reference's occupied cells within τ of one of ours
//   theirs_within_seen  the same over the reference cells where our grid is known
//                  (a short drive sees part of a floor its reference covers whole)
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose2D.h>

#include <nlohmann/json.hpp>

namespace specht::eval {

struct MapAgreementOptions {
  double tolerance_m = 0.1;
  double search_window_m = 40;
};

struct MapAgreement {
  mrpt::poses::CPose2D ours_in_theirs;  // T: our map frame in the reference's
  double match_score = 0;               // the aligned points' mean likelihood, [0, 1]
  size_t ours_occupied = 0, theirs_occupied = 0, theirs_seen = 0;
  double ours_within = 0, theirs_within = 0, theirs_within_seen = 0;
};

// Throws InputError when either grid holds no occupied cell.
MapAgreement CompareMaps(const mrpt::maps::COccupancyGridMap2D& ours, const mrpt::maps::COccupancyGridMap2D& theirs,
                         const MapAgreementOptions& options = {});

nlohmann::json ToJson(const MapAgreement& a);

}  // namespace specht::eval
