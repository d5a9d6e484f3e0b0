// Hand-made maps for the planner tests: a w × h metre raster at 0.1 m with a wall
// around it and boxes, and the exact rectangular footprint check (not the
// planners' disc cover).
#pragma once

#include <opencv2/imgproc.hpp>
#include <vector>

#include "specht/plan/path.h"

namespace specht::plan {

inline constexpr double kRes = 0.1;

// A w × h metre map with a wall around it; boxes are (x0, y0, x1, y1) in metres.
inline cv::Mat Map(double w, double h, const std::vector<cv::Rect2d>& boxes = {}) {
  cv::Mat m(static_cast<int>(h / kRes), static_cast<int>(w / kRes), CV_8U, cv::Scalar(0));
  cv::rectangle(m, {0, 0}, {m.cols - 1, m.rows - 1}, cv::Scalar(1), 1);
  for (const auto& b : boxes)
    cv::rectangle(
        m, cv::Point(static_cast<int>(b.x / kRes), static_cast<int>(b.y / kRes)),
        cv::Point(static_cast<int>((b.x + b.width) / kRes) - 1, static_cast<int>((b.y + b.height) / kRes) - 1),
        cv::Scalar(1), cv::FILLED);
  return m;
}

// Cells of obstacle under the exact footprint rectangle at each path pose.
inline int Overlaps(const cv::Mat& obstacles, const CarOptions& car, const Path& path) {
  int hits = 0;
  for (const auto& p : path.points) {
    cv::Mat footprint(obstacles.size(), CV_8U, cv::Scalar(0));
    std::vector<cv::Point> poly;
    for (const auto& c : car.Corners(p.pose))
      poly.push_back({static_cast<int>(c.x / kRes), static_cast<int>(c.y / kRes)});
    cv::fillConvexPoly(footprint, poly, cv::Scalar(1));
    hits += cv::countNonZero(footprint & obstacles) > 0;
  }
  return hits;
}

}  // namespace specht::plan
