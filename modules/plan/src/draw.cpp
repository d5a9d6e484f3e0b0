#include "specht/plan/draw.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace specht::plan {

cv::Mat DrawPlan(const DistanceMap& map, const CarOptions& car, const Path& path, const Pose& start, const Pose& goal,
                 double footprint_every_m, int min_width_px) {
  const int scale = std::max(1, static_cast<int>(std::ceil(static_cast<double>(min_width_px) / map.cols())));
  cv::Mat shade;
  cv::Mat near = cv::min(map.distances(), 2.0f) / 2.0f;  // 0 at obstacles, 1 from 2 m
  near.convertTo(shade, CV_8U, 55, 200);
  shade.setTo(0, map.obstacles() != 0);
  cv::Mat img;
  cv::cvtColor(shade, img, cv::COLOR_GRAY2BGR);
  cv::flip(img, img, 0);  // row 0 = the largest y
  cv::resize(img, img, {}, scale, scale, cv::INTER_NEAREST);
  const auto px = [&](double x, double y) {
    return cv::Point(static_cast<int>((x - map.origin_x()) / map.resolution() * scale),
                     static_cast<int>((map.rows() - (y - map.origin_y()) / map.resolution()) * scale));
  };
  const auto footprint = [&](const Pose& p, const cv::Scalar& colour, int thickness) {
    std::vector<cv::Point> poly;
    for (const auto& c : car.Corners(p)) poly.push_back(px(c.x, c.y));
    cv::polylines(img, poly, true, colour, thickness, cv::LINE_AA);
  };
  double since = footprint_every_m;
  for (size_t i = 1; i < path.points.size(); ++i) {
    const Pose &a = path.points[i - 1].pose, &b = path.points[i].pose;
    since += std::hypot(b.x - a.x, b.y - a.y);
    if (since >= footprint_every_m) footprint(b, cv::Scalar(160, 160, 160), 1), since = 0;
  }
  for (size_t i = 1; i < path.points.size(); ++i) {
    const Pose &a = path.points[i - 1].pose, &b = path.points[i].pose;
    const cv::Scalar colour = path.points[i].direction < 0 ? cv::Scalar(40, 40, 220) : cv::Scalar(220, 90, 20);
    cv::line(img, px(a.x, a.y), px(b.x, b.y), colour, 2, cv::LINE_AA);
  }
  footprint(start, cv::Scalar(40, 170, 40), 2);
  footprint(goal, cv::Scalar(200, 40, 200), 2);
  return img;
}

}  // namespace specht::plan
