#include "specht/eval/map_agreement.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPoint2D.h>

#include <cmath>

#include "specht/core/error.h"
#include "specht/slam/correlative_matcher.h"

namespace specht::eval {
namespace {

using mrpt::maps::COccupancyGridMap2D;
using mrpt::maps::CSimplePointsMap;

constexpr float kOccupiedPFree = 0.35f;  // p(occupied) ≥ 0.65

CSimplePointsMap OccupiedCells(const COccupancyGridMap2D& g) {
  CSimplePointsMap points;
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
      if (g.getCell(cx, cy) <= kOccupiedPFree) points.insertPoint(g.idx2x(cx), g.idx2y(cy));
  return points;
}

CSimplePointsMap Moved(const CSimplePointsMap& points, const mrpt::poses::CPose2D& t) {
  CSimplePointsMap out;
  for (size_t i = 0; i < points.size(); ++i) {
    float x, y;
    points.getPoint(i, x, y);
    const auto p = t + mrpt::poses::CPoint2D(x, y);
    out.insertPoint(p.x(), p.y());
  }
  return out;
}

// Share of `points` within `tol` of a point of `of` (its kd-tree answers).
double ShareWithin(const CSimplePointsMap& points, const CSimplePointsMap& of, double tol) {
  if (points.empty()) return 0;
  size_t near = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    float x, y, ox, oy, d2;
    points.getPoint(i, x, y);
    of.kdTreeClosestPoint2D(x, y, ox, oy, d2);
    near += d2 <= tol * tol;
  }
  return static_cast<double>(near) / points.size();
}

}  // namespace

MapAgreement CompareMaps(const COccupancyGridMap2D& ours, const COccupancyGridMap2D& theirs,
                         const MapAgreementOptions& o) {
  const CSimplePointsMap mine = OccupiedCells(ours), reference = OccupiedCells(theirs);
  if (mine.empty() || reference.empty())
    throw InputError(std::string("map comparison: ") + (mine.empty() ? "our" : "the reference") +
                     " map has no occupied cell");
  MapAgreement a;
  a.ours_occupied = mine.size(), a.theirs_occupied = reference.size();
  // Coarse over everything, then fine: the lattice's best is exact at each level.
  const CSimplePointsMap coarse_ref = slam::Decimate(reference, 0.1), coarse_mine = slam::Decimate(mine, 0.1);
  const slam::CorrelativeMatcher coarse(coarse_ref, 0.1, o.search_window_m);
  // Start from the reference's centre: its frame and ours share nothing else.
  float cx = 0, cy = 0;
  for (size_t i = 0; i < coarse_ref.size(); ++i) {
    float x, y;
    coarse_ref.getPoint(i, x, y);
    cx += x / coarse_ref.size(), cy += y / coarse_ref.size();
  }
  float mx = 0, my = 0;
  for (size_t i = 0; i < coarse_mine.size(); ++i) {
    float x, y;
    coarse_mine.getPoint(i, x, y);
    mx += x / coarse_mine.size(), my += y / coarse_mine.size();
  }
  const auto first = coarse.Match(coarse_mine, mrpt::poses::CPose2D(cx - mx, cy - my, 0), o.search_window_m, M_PI, 0);
  if (!first) throw InputError("map comparison: no alignment found");
  const slam::CorrelativeMatcher fine(slam::Decimate(reference, 0.05), 0.05, 0.5);
  const auto best = fine.Match(slam::Decimate(mine, 0.05), first->pose, 0.3, 2 * M_PI / 180, 0).value_or(*first);
  a.ours_in_theirs = best.pose, a.match_score = best.score;
  const CSimplePointsMap aligned = Moved(mine, best.pose);
  a.ours_within = ShareWithin(aligned, reference, o.tolerance_m);
  a.theirs_within = ShareWithin(reference, aligned, o.tolerance_m);
  // The reference cells our grid has seen (known: not p = 0.5), in our frame.
  mrpt::poses::CPose2D back = best.pose;
  back.inverse();
  const CSimplePointsMap in_ours = Moved(reference, back);
  CSimplePointsMap seen;
  for (size_t i = 0; i < in_ours.size(); ++i) {
    float x, y;
    in_ours.getPoint(i, x, y);
    const int gx = ours.x2idx(x), gy = ours.y2idx(y);
    if (gx < 0 || gy < 0 || gx >= static_cast<int>(ours.getSizeX()) || gy >= static_cast<int>(ours.getSizeY()))
      continue;
    if (std::abs(ours.getCell(gx, gy) - 0.5f) > 0.01f) seen.insertPoint(x, y);
  }
  a.theirs_seen = seen.size();
  a.theirs_within_seen = ShareWithin(seen, mine, o.tolerance_m);
  return a;
}

nlohmann::json ToJson(const MapAgreement& a) {
  return {{"alignment", {a.ours_in_theirs.x(), a.ours_in_theirs.y(), a.ours_in_theirs.phi() * 180 / M_PI}},
          {"match_score", a.match_score},
          {"ours_occupied_cells", a.ours_occupied},
          {"reference_occupied_cells", a.theirs_occupied},
          {"reference_cells_seen", a.theirs_seen},
          {"ours_within_tolerance", a.ours_within},
          {"reference_within_tolerance", a.theirs_within},
          {"reference_seen_within_tolerance", a.theirs_within_seen}};
}

}  // namespace specht::eval
