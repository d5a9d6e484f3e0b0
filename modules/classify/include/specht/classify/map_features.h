// specht/classify/map_features.h: map features from an occupancy raster and a list
// of points of interest (for the car: the static layer of the shared map and, e.g.,
// parking bays and crossings).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "specht/classify/preprocess.h"

namespace specht::classify {

// `occupied`: CV_8U, non-zero on occupied cells, row = y index; cell (c, r) covers
// [origin + c·res, origin + (c+1)·res). Distances come from one Euclidean distance
// transform (OpenCV, exact), looked up per query; outside the raster the nearest
// border cell's value is used.
MapFeatures GridMapFeatures(const cv::Mat& occupied, double origin_x, double origin_y, double resolution,
                            std::vector<cv::Point2d> points_of_interest);

}  // namespace specht::classify
