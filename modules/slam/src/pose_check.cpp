#include "specht/slam/pose_check.h"

#include <algorithm>
#include <cmath>

namespace specht::slam {

std::vector<std::string> PoseCheckOptions::Relations() const {
  if (relocalized_above <= lost_below) return {"relocalized_above must be above lost_below"};
  return {};
}

namespace {

// The centres of the map's occupied cells (p(free) below 0.35, as the planner reads them).
mrpt::maps::CSimplePointsMap OccupiedCells(const mrpt::maps::COccupancyGridMap2D& map) {
  mrpt::maps::CSimplePointsMap points;
  for (unsigned r = 0; r < map.getSizeY(); ++r)
    for (unsigned c = 0; c < map.getSizeX(); ++c)
      if (map.getCell(c, r) < 0.35f) points.insertPointFast(map.idx2x(c), map.idx2y(r), 0);
  return points;
}

}  // namespace

PoseCheck::PoseCheck(const mrpt::maps::COccupancyGridMap2D& map, const PoseCheckOptions& options)
    : options_(options), map_(map) {
  const mrpt::maps::CSimplePointsMap cells = OccupiedCells(map);
  matcher_ =
      std::make_unique<CorrelativeMatcher>(cells, options.resolution_m, options.search_window_m, options.blur_cells);
  cells_ = IndexedPoints(cells);
}

std::optional<double> PoseCheck::Score(const mrpt::maps::CSimplePointsMap& points,
                                       const mrpt::poses::CPose2D& pose) const {
  if (static_cast<int>(points.size()) < options_.min_points) return std::nullopt;
  return matcher_->Score(points, pose);
}

std::optional<CorrelativeResult> PoseCheck::Relocalize(const mrpt::maps::CSimplePointsMap& points,
                                                       const mrpt::poses::CPose2D& guess) const {
  if (static_cast<int>(points.size()) < options_.min_points) return std::nullopt;
  const auto sparse = Decimate(points, options_.resolution_m);
  auto found = matcher_->Match(sparse, guess, options_.search_window_m, options_.search_window_deg * M_PI / 180,
                               options_.relocalized_above);
  if (!found) return std::nullopt;
  found->score = matcher_->Score(points, found->pose);  // on every point, as Score() judges a pose
  // The search's lattice (a cell, an angle step) is coarser than ICP's fit; ICP is
  // kept unless it paired too few points or slid beyond the lattice's reach.
  IcpAligner icp{IcpOptions{}};
  const IcpResult refined = icp.Align(cells_, points, found->pose);
  const mrpt::poses::CPose2D step = refined.pose - found->pose;
  if (refined.goodness >= 0.8 && std::hypot(step.x(), step.y()) <= 2 * options_.resolution_m &&
      std::abs(step.phi()) <= 2 * M_PI / 180)
    *found = {refined.pose, matcher_->Score(points, refined.pose)};
  if (found->score < options_.relocalized_above || !InFreeSpace(found->pose)) return std::nullopt;
  return found;
}

bool PoseCheck::InFreeSpace(const mrpt::poses::CPose2D& pose) const {
  const double res = map_.getResolution(), r = options_.free_radius_m;
  const int reach = static_cast<int>(std::ceil(r / res));
  const int c0 = map_.x2idx(pose.x()), r0 = map_.y2idx(pose.y());
  for (int dr = -reach; dr <= reach; ++dr)
    for (int dc = -reach; dc <= reach; ++dc) {
      if (std::hypot(dc * res, dr * res) > r) continue;
      const int c = c0 + dc, row = r0 + dr;
      if (c < 0 || row < 0 || c >= static_cast<int>(map_.getSizeX()) || row >= static_cast<int>(map_.getSizeY()))
        return false;  // off the map
      if (map_.getCell(c, row) < 0.35f) return false;
    }
  return true;
}

bool PoseMonitor::Add(std::optional<double> score) {
  if (!score) return lost();
  ++scored_;
  lowest_ = std::min(lowest_, *score);
  if (*score < options_.lost_below) {
    ++disagreeing_, ++disagreeing_total_;
  } else {
    disagreeing_ = 0;
  }
  return lost();
}

}  // namespace specht::slam
