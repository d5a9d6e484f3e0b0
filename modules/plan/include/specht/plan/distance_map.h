// specht/plan/distance_map.h: distance from every cell to the nearest obstacle, in
// metres — the one structure collision checks, the search heuristic and the
// smoother's clearance term read. Built once per map (OpenCV's exact Euclidean
// distance transform, O(cells)); a lookup is one array read.
//
// Obstacles are the occupied cells of an occupancy grid (MRPT, p(occupied) above
// 0.65) or the lethal cells of the world model's cost layer; unknown cells count
// as obstacles unless told otherwise (a car should not plan through the unseen).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "specht/plan/car.h"

namespace mrpt::maps {
class COccupancyGridMap2D;
}
namespace specht::types {
struct CostGrid;
}

namespace specht::plan {

class DistanceMap {
 public:
  // `obstacle`: CV_8U, non-zero on obstacle cells, row = y index.
  DistanceMap(const cv::Mat& obstacle, double origin_x, double origin_y, double resolution);
  static DistanceMap FromGrid(const mrpt::maps::COccupancyGridMap2D& grid, bool unknown_is_obstacle = true);
  static DistanceMap FromCost(const types::CostGrid& cost, bool unknown_is_obstacle = true);

  // Metres to the nearest obstacle from the cell containing (x, y); 0 outside the map
  // (the map's edge is a wall).
  double Distance(double x, double y) const;
  bool Contains(double x, double y) const;
  // Whether the car's footprint is free at `pose` with the safety margin: the disc
  // cover first (a few lookups), the rectangle itself where the discs say no
  // (its samples at the map's resolution, skipped in blocks the distance field
  // proves clear).
  bool Free(const DiscCover& discs, const Pose& pose) const;
  bool Free(const CarOptions& car, const Pose& pose) const { return Free(car.Discs(), pose); }
  // Distance from the footprint rectangle to the nearest obstacle (0: touching or
  // overlapping), to the map's resolution.
  double Clearance(const DiscCover& discs, const Pose& pose) const;
  double Clearance(const CarOptions& car, const Pose& pose) const { return Clearance(car.Discs(), pose); }

  double origin_x() const { return origin_x_; }
  double origin_y() const { return origin_y_; }
  double resolution() const { return resolution_; }
  int cols() const { return distance_.cols; }
  int rows() const { return distance_.rows; }
  const cv::Mat& distances() const { return distance_; }  // CV_32F, metres
  const cv::Mat& obstacles() const { return obstacle_; }

 private:
  struct FootprintSamples;
  bool SamplesFree(const FootprintSamples& f, int i0, int i1, int j0, int j1, double need) const;
  cv::Mat obstacle_, distance_;
  double origin_x_, origin_y_, resolution_;
};

// A planner's start or goal must lie on the map with the footprint free: throws
// InputError naming `what` ("start", "goal") and the clearance found otherwise.
void CheckEndpoint(const DistanceMap& map, const CarOptions& car, const Pose& pose, const std::string& what);

}  // namespace specht::plan
