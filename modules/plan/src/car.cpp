#include "specht/plan/car.h"

#include <cmath>

namespace specht::plan {

std::vector<std::string> CarOptions::Relations() const {
  std::vector<std::string> p;
  if (rear_overhang_m >= length_m) p.push_back("rear_overhang_m must be shorter than length_m");
  if (wheelbase_m > length_m) p.push_back("wheelbase_m cannot exceed length_m");
  return p;
}

double CarOptions::MinTurningRadius() const { return wheelbase_m / std::tan(max_steer_deg * M_PI / 180.0); }

static int DiscCount(const CarOptions& c) { return std::max(1, static_cast<int>(std::ceil(c.length_m / c.width_m))); }

std::vector<cv::Point2d> CarOptions::DiscCentres() const {
  const int n = DiscCount(*this);
  std::vector<cv::Point2d> out;
  for (int i = 0; i < n; ++i) out.push_back({-rear_overhang_m + (i + 0.5) * length_m / n, 0.0});
  return out;
}

double CarOptions::DiscRadius() const {
  const double half = length_m / (2.0 * DiscCount(*this));
  return std::hypot(half, width_m / 2);
}

DiscCover CarOptions::Discs() const {
  DiscCover d;
  for (const auto& c : DiscCentres()) d.offsets.push_back(c.x);
  d.radius = DiscRadius();
  d.margin = safety_margin_m;
  d.front = length_m - rear_overhang_m, d.rear = rear_overhang_m, d.half_width = width_m / 2;
  return d;
}

std::vector<cv::Point2d> CarOptions::Corners(const Pose& p) const {
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  std::vector<cv::Point2d> out;
  for (const auto& [lx, ly] : std::vector<std::pair<double, double>>{{-rear_overhang_m, -width_m / 2},
                                                                     {length_m - rear_overhang_m, -width_m / 2},
                                                                     {length_m - rear_overhang_m, width_m / 2},
                                                                     {-rear_overhang_m, width_m / 2}})
    out.push_back({p.x + c * lx - s * ly, p.y + s * lx + c * ly});
  return out;
}

}  // namespace specht::plan
