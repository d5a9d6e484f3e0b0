// specht/types/cost_grid.h: the planner's cost grid, in the map frame, on ROS
// costmap_2d values (the world model's cost layer, world/world_model.h, says how
// each value arises):
//   254 lethal, 253 inscribed (the car's centre there means a collision),
//   252 … 1 within a safety margin, 0 free, 255 unknown.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace specht::types {

struct CostGrid {
  double origin_x_m = 0, origin_y_m = 0, resolution_m = 0.1;
  cv::Mat cost;  // CV_8UC1, row = y index, column = x index
  static constexpr uint8_t kLethal = 254, kInscribed = 253, kUnknown = 255, kFree = 0;
  // The cell of a map point (false outside the grid).
  bool Cell(double x_m, double y_m, int& col, int& row) const;
  cv::Point2d Centre(int col, int row) const;
};

}  // namespace specht::types
