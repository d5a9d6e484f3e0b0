#include "scenario_map_features.h"

#include "specht/classify/map_features.h"
#include "specht/sim/world.h"

namespace specht::app {

classify::MapFeatures ScenarioMapFeatures(const sim::Scenario& s) {
  const auto grid = sim::World(s).TrueGrid(0.1);
  cv::Mat occupied(grid.getSizeY(), grid.getSizeX(), CV_8U);
  for (unsigned r = 0; r < grid.getSizeY(); ++r)
    for (unsigned c = 0; c < grid.getSizeX(); ++c) occupied.at<uint8_t>(r, c) = grid.getCell(c, r) < 0.5f;
  std::vector<cv::Point2d> pois;
  for (const auto& bay : s.bays) pois.push_back({bay.pose.x, bay.pose.y});
  return classify::GridMapFeatures(occupied, grid.getXMin(), grid.getYMin(), grid.getResolution(), pois);
}

}  // namespace specht::app
