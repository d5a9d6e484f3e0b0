#include "specht/classify/map_features.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace specht::classify {

MapFeatures GridMapFeatures(const cv::Mat& occupied, double origin_x, double origin_y, double resolution,
                            std::vector<cv::Point2d> pois) {
  auto distance = std::make_shared<cv::Mat>();
  cv::Mat free_cells = occupied == 0;
  cv::distanceTransform(free_cells, *distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  MapFeatures f;
  f.distance_to_static = [distance, origin_x, origin_y, resolution](double x, double y) {
    const int c = std::clamp(static_cast<int>(std::floor((x - origin_x) / resolution)), 0, distance->cols - 1);
    const int r = std::clamp(static_cast<int>(std::floor((y - origin_y) / resolution)), 0, distance->rows - 1);
    return distance->at<float>(r, c) * resolution;
  };
  auto points = std::make_shared<std::vector<cv::Point2d>>(std::move(pois));
  f.distance_to_poi = [points](double x, double y) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : *points) best = std::min(best, std::hypot(p.x - x, p.y - y));
    return points->empty() ? 0.0 : best;
  };
  return f;
}

}  // namespace specht::classify
