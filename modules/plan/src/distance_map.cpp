#include "specht/plan/distance_map.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/types/cost_grid.h"

namespace specht::plan {

DistanceMap::DistanceMap(const cv::Mat& obstacle, double origin_x, double origin_y, double resolution)
    : obstacle_(obstacle.clone()), origin_x_(origin_x), origin_y_(origin_y), resolution_(resolution) {
  if (obstacle.empty() || obstacle.type() != CV_8U || !(resolution > 0))
    throw InputError("plan: a distance map needs a non-empty 8-bit obstacle raster and a positive resolution");
  // A ring of obstacle cells around the raster: the map's edge is a wall for the
  // distances inside as it is for lookups outside (0).
  cv::Mat free;
  cv::copyMakeBorder(obstacle == 0, free, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::distanceTransform(free, distance_, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  distance_ = distance_(cv::Rect(1, 1, obstacle.cols, obstacle.rows)).clone();
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

DistanceMap DistanceMap::FromCost(const types::CostGrid& cost, bool unknown_is_obstacle) {
  cv::Mat obstacle = cost.cost == types::CostGrid::kLethal;
  if (unknown_is_obstacle) obstacle |= cost.cost == types::CostGrid::kUnknown;
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

// The footprint rectangle sampled at the map's resolution (edges included): sample
// (i, j), 0 ≤ i ≤ nx, 0 ≤ j ≤ ny, sits at body coordinates (−rear + i·sx, −w/2 + j·sy).
struct DistanceMap::FootprintSamples {
  double c, s, x, y, rear, half_width, sx, sy;
  int nx, ny;
  // c, s: cos θ and sin θ of the pose (the caller may have them already).
  FootprintSamples(const DiscCover& discs, const Pose& p, double c, double s, double resolution)
      : c(c),
        s(s),
        x(p.x),
        y(p.y),
        rear(discs.rear),
        half_width(discs.half_width),
        nx(static_cast<int>(std::ceil((discs.front + discs.rear) / resolution))),
        ny(static_cast<int>(std::ceil(2 * discs.half_width / resolution))) {
    sx = (discs.front + discs.rear) / nx, sy = 2 * discs.half_width / ny;
  }
  double X(int i, int j) const { return x + c * (-rear + i * sx) - s * (-half_width + j * sy); }
  double Y(int i, int j) const { return y + s * (-rear + i * sx) + c * (-half_width + j * sy); }
};

double DistanceMap::Clearance(const DiscCover& discs, const Pose& p) const {
  const FootprintSamples f(discs, p, std::cos(p.theta), std::sin(p.theta), resolution_);
  double least = INFINITY;
  for (int i = 0; i <= f.nx; ++i)
    for (int j = 0; j <= f.ny; ++j) least = std::min(least, Distance(f.X(i, j), f.Y(i, j)));
  return least;
}

// Whether every sample in [i0, i1] × [j0, j1] lies farther than `need` from obstacles,
// without reading them all. With q the block's middle sample and r the distance from
// q to the block's farthest corner: the exact Euclidean transform is 1-Lipschitz
// between cell centres and a point lies within half a cell diagonal of its cell's
// centre, so every sample p of the block has
//   D(p) ≥ D(q) − |p − q| − res·√2 ≥ D(q) − r − res·√2.
// When that bound exceeds `need` (and the block keeps clear of the map's edge, beyond
// which D is 0) the block is free; otherwise it is split along its longer side.
// Same answer as reading every sample; most footprints need a handful of reads.
bool DistanceMap::SamplesFree(const FootprintSamples& f, int i0, int i1, int j0, int j1, double need) const {
  const int im = (i0 + i1) / 2, jm = (j0 + j1) / 2;
  const double x = f.X(im, jm), y = f.Y(im, jm), d = Distance(x, y);
  if (d <= need) return false;
  if (i0 == i1 && j0 == j1) return true;
  const double r = std::hypot(std::max(im - i0, i1 - im) * f.sx, std::max(jm - j0, j1 - jm) * f.sy);
  const double slack = r + resolution_ * std::sqrt(2.0);
  const double to_edge = std::min(
      {x - origin_x_, origin_x_ + cols() * resolution_ - x, y - origin_y_, origin_y_ + rows() * resolution_ - y});
  if (d - slack > need && to_edge > slack) return true;
  if ((i1 - i0) * f.sx >= (j1 - j0) * f.sy)
    return SamplesFree(f, i0, im, j0, j1, need) && (im + 1 > i1 || SamplesFree(f, im + 1, i1, j0, j1, need));
  return SamplesFree(f, i0, i1, j0, jm, need) && (jm + 1 > j1 || SamplesFree(f, i0, i1, jm + 1, j1, need));
}

bool DistanceMap::Free(const DiscCover& discs, const Pose& p) const {
  const double c = std::cos(p.theta), s = std::sin(p.theta), need = discs.radius + discs.margin;
  bool discs_free = true;
  for (const double d : discs.offsets)
    if (Distance(p.x + c * d, p.y + s * d) <= need) {
      discs_free = false;
      break;
    }
  if (discs_free) return true;
  const FootprintSamples f(discs, p, c, s, resolution_);
  return SamplesFree(f, 0, f.nx, 0, f.ny, discs.margin);
}

}  // namespace specht::plan
