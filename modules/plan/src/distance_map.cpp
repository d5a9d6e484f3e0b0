#include "specht/plan/distance_map.h"

#include <cmath>

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/world/world_model.h"

namespace specht::plan {

DistanceMap::DistanceMap(const cv::Mat& obstacle, double origin_x, double origin_y, double resolution)
    : obstacle_(obstacle.clone()), origin_x_(origin_x), origin_y_(origin_y), resolution_(resolution) {
  if (obstacle.empty() || obstacle.type() != CV_8U || !(resolution > 0))
    throw InputError("plan: a distance map needs a non-empty 8-bit obstacle raster and a positive resolution");
  cv::Mat free = obstacle == 0;
  cv::distanceTransform(free, distance_, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  // Cell centre to the nearest obstacle cell's centre, less half a cell: the
  // distance to that cell's near edge, never more than the true clearance.
  distance_ = cv::max(distance_ * resolution - 0.5 * resolution, 0.0);
  distance_.setTo(0, obstacle != 0);
}

DistanceMap DistanceMap::FromGrid(const mrpt::maps::COccupancyGridMap2D& g, bool unknown_is_obstacle) {
  cv::Mat obstacle(static_cast<int>(g.getSizeY()), static_cast<int>(g.getSizeX()), CV_8U);
  for (int r = 0; r < obstacle.rows; ++r)
    for (int c = 0; c < obstacle.cols; ++c) {
      const float p_free = g.getCell(c, r);  // MRPT stores p(free)
      obstacle.at<uint8_t>(r, c) = p_free < 0.35f || (unknown_is_obstacle && std::abs(p_free - 0.5f) < 0.01f);
    }
  return DistanceMap(obstacle, g.getXMin(), g.getYMin(), g.getResolution());
}

DistanceMap DistanceMap::FromCost(const world::CostGrid& cost, bool unknown_is_obstacle) {
  cv::Mat obstacle = cost.cost == world::CostGrid::kLethal;
  if (unknown_is_obstacle) obstacle |= cost.cost == world::CostGrid::kUnknown;
  return DistanceMap(obstacle / 255, cost.origin_x_m, cost.origin_y_m, cost.resolution_m);
}

double DistanceMap::Distance(double x, double y) const {
  const int c = static_cast<int>(std::floor((x - origin_x_) / resolution_));
  const int r = static_cast<int>(std::floor((y - origin_y_) / resolution_));
  if (c < 0 || r < 0 || c >= distance_.cols || r >= distance_.rows) return 0.0;
  return distance_.at<float>(r, c);
}

bool DistanceMap::Contains(double x, double y) const {
  const double c = (x - origin_x_) / resolution_, r = (y - origin_y_) / resolution_;
  return c >= 0 && r >= 0 && c < distance_.cols && r < distance_.rows;
}

void CheckEndpoint(const DistanceMap& map, const CarOptions& car, const Pose& p, const std::string& what) {
  if (!map.Contains(p.x, p.y)) throw InputError("plan: the " + what + " is outside the map");
  if (!map.Free(car, p))
    throw InputError("plan: the car collides at the " + what + " (clearance " + std::to_string(map.Clearance(car, p)) +
                     " m, needs " + std::to_string(car.safety_margin_m) + ")");
}

// Smallest obstacle distance over samples of the footprint rectangle at the map's
// resolution (edges included); stops once a sample is at or below `stop_at`.
double DistanceMap::RectangleClearance(const DiscCover& discs, const Pose& p, double stop_at) const {
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  const int nx = static_cast<int>(std::ceil((discs.front + discs.rear) / resolution_));
  const int ny = static_cast<int>(std::ceil(2 * discs.half_width / resolution_));
  double least = INFINITY;
  for (int i = 0; i <= nx; ++i) {
    const double lx = -discs.rear + (discs.front + discs.rear) * i / nx;
    for (int j = 0; j <= ny; ++j) {
      const double ly = -discs.half_width + 2 * discs.half_width * j / ny;
      least = std::min(least, Distance(p.x + c * lx - s * ly, p.y + s * lx + c * ly));
      if (least <= stop_at) return least;
    }
  }
  return least;
}

double DistanceMap::Clearance(const DiscCover& discs, const Pose& p) const {
  return RectangleClearance(discs, p, -INFINITY);
}

bool DistanceMap::Free(const DiscCover& discs, const Pose& p) const {
  const double c = std::cos(p.theta), s = std::sin(p.theta), need = discs.radius + discs.margin;
  bool discs_free = true;
  for (const double d : discs.offsets)
    if (Distance(p.x + c * d, p.y + s * d) <= need) {
      discs_free = false;
      break;
    }
  return discs_free || RectangleClearance(discs, p, discs.margin) > discs.margin;
}

}  // namespace specht::plan
