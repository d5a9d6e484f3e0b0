#include "specht/plan/path.h"

#include <cmath>
#include <cstdio>

namespace specht::plan {
double Path::Length() const {
  double s = 0;
  for (size_t i = 1; i < points.size(); ++i)
    s += std::hypot(points[i].pose.x - points[i - 1].pose.x, points[i].pose.y - points[i - 1].pose.y);
  return s;
}

int Path::GearChanges() const {
  int n = 0;
  for (size_t i = 1; i < points.size(); ++i) n += points[i].direction != points[i - 1].direction;
  return n;
}

double Path::MaxCurvature() const {
  double k = 0;
  for (size_t i = 1; i + 1 < points.size(); ++i) {
    if (points[i - 1].direction != points[i].direction || points[i].direction != points[i + 1].direction) continue;
    const Pose &a = points[i - 1].pose, &b = points[i].pose, &c = points[i + 1].pose;
    const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y;
    const double mean = 0.5 * (std::hypot(ux, uy) + std::hypot(vx, vy));
    if (mean > 1e-6) k = std::max(k, std::abs(std::atan2(ux * vy - uy * vx, ux * vx + uy * vy)) / mean);
  }
  return k;
}

std::string Path::ToCsv() const {
  std::string out = "x_m,y_m,theta_rad,direction\n";
  char buf[96];
  for (const auto& p : points) {
    std::snprintf(buf, sizeof(buf), "%.4f,%.4f,%.5f,%d\n", p.pose.x, p.pose.y, p.pose.theta, p.direction);
    out += buf;
  }
  return out;
}

}  // namespace specht::plan
