#include "specht/types/cost_grid.h"

#include <cmath>

namespace specht::types {

bool CostGrid::Cell(double x_m, double y_m, int& col, int& row) const {
  col = static_cast<int>(std::floor((x_m - origin_x_m) / resolution_m));
  row = static_cast<int>(std::floor((y_m - origin_y_m) / resolution_m));
  return col >= 0 && row >= 0 && col < cost.cols && row < cost.rows;
}

cv::Point2d CostGrid::Centre(int col, int row) const {
  return {origin_x_m + (col + 0.5) * resolution_m, origin_y_m + (row + 0.5) * resolution_m};
}

}  // namespace specht::types
