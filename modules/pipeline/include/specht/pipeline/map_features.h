// specht/pipeline/map_features.h: the trajectory classifier's map features
// (classify/map_features.h) of an occupancy grid — distance to its occupied cells —
// and of a simulated scene: its true grid at 0.1 m with its parking bays as points
// of interest (what `specht classify` and `specht track --model` use).
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <opencv2/core.hpp>
#include <vector>

#include "specht/classify/preprocess.h"
#include "specht/sim/scenario.h"

namespace specht::pipeline {

// Occupied = probability of free below 0.5 (unknown cells are 0.5, not occupied).
classify::MapFeatures GridMapFeatures(const mrpt::maps::COccupancyGridMap2D& grid,
                                      std::vector<cv::Point2d> points_of_interest = {});

classify::MapFeatures ScenarioMapFeatures(const sim::Scenario& scenario);

}  // namespace specht::pipeline
