#include "specht/pipeline/map_features.h"

#include "specht/classify/map_features.h"
#include "specht/sim/world.h"

namespace specht::pipeline {

classify::MapFeatures GridMapFeatures(const mrpt::maps::COccupancyGridMap2D& grid,
                                      std::vector<cv::Point2d> points_of_interest) {
  cv::Mat occupied(static_cast<int>(grid.getSizeY()), static_cast<int>(grid.getSizeX()), CV_8U);
  for (unsigned r = 0; r < grid.getSizeY(); ++r)
    for (unsigned c = 0; c < grid.getSizeX(); ++c) occupied.at<uint8_t>(r, c) = grid.getCell(c, r) < 0.5f;
  return classify::GridMapFeatures(occupied, grid.getXMin(), grid.getYMin(), grid.getResolution(),
                                   std::move(points_of_interest));
}

classify::MapFeatures ScenarioMapFeatures(const sim::Scenario& s) {
  std::vector<cv::Point2d> bays;
  for (const auto& bay : s.bays) bays.push_back({bay.pose.x, bay.pose.y});
  return GridMapFeatures(sim::World(s).TrueGrid(0.1), std::move(bays));
}

}  // namespace specht::pipeline
