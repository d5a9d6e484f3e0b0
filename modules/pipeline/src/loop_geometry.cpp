#include "internal/loop_geometry.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace specht::pipeline::internal {

Box CarBox(const plan::CarOptions& car, const plan::Pose& p) {
  const double ahead = car.length_m / 2 - car.rear_overhang_m;
  return {p.x + ahead * std::cos(p.theta), p.y + ahead * std::sin(p.theta), p.theta, car.length_m / 2, car.width_m / 2};
}

std::vector<cv::Point2d> Corners(const Box& b) {
  const double c = std::cos(b.theta), s = std::sin(b.theta);
  std::vector<cv::Point2d> out;
  for (const auto& [lx, ly] : {std::pair{b.hl, b.hw}, {-b.hl, b.hw}, {-b.hl, -b.hw}, {b.hl, -b.hw}})
    out.push_back({b.x + c * lx - s * ly, b.y + s * lx + c * ly});
  return out;
}

double PointToBox(const cv::Point2d& p, const Box& b) {
  const double c = std::cos(b.theta), s = std::sin(b.theta), dx = p.x - b.x, dy = p.y - b.y;
  const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
  return std::hypot(std::max(std::abs(lx) - b.hl, 0.0), std::max(std::abs(ly) - b.hw, 0.0));
}

// For separated convex shapes the nearest points include a vertex of one of them.
double BoxToBox(const Box& a, const Box& b) {
  double d = std::min(PointToBox({a.x, a.y}, b), PointToBox({b.x, b.y}, a)) > 0 ? INFINITY : 0.0;
  for (const auto& p : Corners(a)) d = std::min(d, PointToBox(p, b));
  for (const auto& p : Corners(b)) d = std::min(d, PointToBox(p, a));
  return d;
}

double OutlineClearance(const plan::DistanceMap& map, const Box& b) {
  const auto c = Corners(b);
  double d = INFINITY;
  for (size_t k = 0; k < 4; ++k) {
    const cv::Point2d a = c[k], e = c[(k + 1) % 4];
    const int n = std::max(2, static_cast<int>(std::hypot(e.x - a.x, e.y - a.y) / 0.05));
    for (int i = 0; i <= n; ++i) d = std::min(d, map.Distance(a.x + (e.x - a.x) * i / n, a.y + (e.y - a.y) * i / n));
  }
  return d;
}

}  // namespace specht::pipeline::internal
