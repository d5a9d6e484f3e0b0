#include "specht/plan/smoother.h"

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>

#include <chrono>
#include <cmath>

namespace specht::plan {
namespace {

using Grid = ceres::Grid2D<float, 1>;
using Interpolator = ceres::BiCubicInterpolator<Grid>;

// |a − 2b + c|
struct SmoothCost {
  double w;
  template <class T>
  bool operator()(const T* a, const T* b, const T* c, T* r) const {
    r[0] = T(w) * (a[0] - T(2) * b[0] + c[0]);
    r[1] = T(w) * (a[1] - T(2) * b[1] + c[1]);
    return true;
  }
};

// Footprint discs at b, heading along (c − a) (reversed when driving backwards).
struct ClearCost {
  const Interpolator* distance;
  double w, need, origin_x, origin_y, resolution;
  int direction;
  std::vector<double> offsets;  // disc centres along the car's axis
  template <class T>
  bool operator()(const T* a, const T* b, const T* c, T* r) const {
    T dx = T(direction) * (c[0] - a[0]), dy = T(direction) * (c[1] - a[1]);
    const T norm = ceres::sqrt(dx * dx + dy * dy + T(1e-12));
    dx /= norm, dy /= norm;
    for (size_t k = 0; k < offsets.size(); ++k) {
      const T x = b[0] + T(offsets[k]) * dx, y = b[1] + T(offsets[k]) * dy;
      T d;
      distance->Evaluate((y - T(origin_y)) / T(resolution) - T(0.5), (x - T(origin_x)) / T(resolution) - T(0.5), &d);
      const T gap = T(need) - d;
      r[k] = gap > T(0) ? T(w) * gap : T(0);
    }
    return true;
  }
};

// Turning per metre at b (chord angle over mean chord length) above κ_max.
struct CurvatureCost {
  double w, kappa_max;
  template <class T>
  bool operator()(const T* a, const T* b, const T* c, T* r) const {
    const T ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - b[0], vy = c[1] - b[1];
    const T turn = ceres::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    const T len = T(0.5) * (ceres::sqrt(ux * ux + uy * uy + T(1e-12)) + ceres::sqrt(vx * vx + vy * vy + T(1e-12)));
    const T excess = ceres::abs(turn) / len - T(kappa_max);
    r[0] = excess > T(0) ? T(w) * excess : T(0);
    return true;
  }
};

// The path split at its cusps (a cusp ends one stretch and starts the next), each
// stretch resampled every `spacing` with both of its ends kept.
std::vector<std::vector<PathPoint>> Stretches(const Path& path, double spacing) {
  const auto& p = path.points;
  std::vector<size_t> bounds = {0};
  for (size_t i = 2; i < p.size(); ++i)
    if (p[i].direction != p[i - 1].direction) bounds.push_back(i - 1);
  bounds.push_back(p.size() - 1);
  std::vector<std::vector<PathPoint>> out;
  for (size_t k = 0; k + 1 < bounds.size(); ++k) {
    if (bounds[k + 1] <= bounds[k]) continue;
    std::vector<PathPoint> stretch = {p[bounds[k]]};
    stretch.front().direction = p[bounds[k] + 1].direction;
    double since = 0;
    for (size_t i = bounds[k] + 1; i <= bounds[k + 1]; ++i) {
      since += std::hypot(p[i].pose.x - p[i - 1].pose.x, p[i].pose.y - p[i - 1].pose.y);
      if (i == bounds[k + 1] || since >= spacing) stretch.push_back(p[i]), since = 0;
    }
    out.push_back(std::move(stretch));
  }
  return out;
}

}  // namespace

SmoothResult SmoothPath(const Path& path, const DistanceMap& map, const CarOptions& car, const SmootherOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  SmoothResult result;
  result.path = path;
  if (!o.enabled || path.points.size() < 3) {
    result.note = o.enabled ? "too short to smooth" : "disabled";
    return result;
  }
  const cv::Mat& d = map.distances();
  const Grid grid(reinterpret_cast<const float*>(d.data), 0, d.rows, 0, d.cols);
  const Interpolator distance(grid);
  std::vector<double> offsets;
  for (const auto& c : car.DiscCentres()) offsets.push_back(c.x);
  const double need = car.DiscRadius() + car.safety_margin_m + o.clearance_buffer_m;
  const double kappa_max = 1.0 / car.MinTurningRadius();

  Path smoothed;
  for (const auto& stretch : Stretches(path, o.spacing_m)) {
    const int direction = stretch.back().direction;
    std::vector<std::array<double, 2>> x;
    for (const auto& p : stretch) x.push_back({p.pose.x, p.pose.y});
    if (x.size() >= 3) {
      ceres::Problem problem;
      for (size_t i = 1; i + 1 < x.size(); ++i) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SmoothCost, 2, 2, 2, 2>(new SmoothCost{o.w_smooth}),
                                 nullptr, x[i - 1].data(), x[i].data(), x[i + 1].data());
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ClearCost, ceres::DYNAMIC, 2, 2, 2>(
                                     new ClearCost{&distance, o.w_clear, need, map.origin_x(), map.origin_y(),
                                                   map.resolution(), direction, offsets},
                                     static_cast<int>(offsets.size())),
                                 nullptr, x[i - 1].data(), x[i].data(), x[i + 1].data());
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CurvatureCost, 1, 2, 2, 2>(
                                     new CurvatureCost{o.w_curvature, 0.9 * kappa_max}),
                                 nullptr, x[i - 1].data(), x[i].data(), x[i + 1].data());
      }
      // The ends and their neighbours stay: the end poses' headings (start, goal,
      // cusps) are set by the two points at each end.
      for (size_t i : {size_t{0}, size_t{1}, x.size() - 2, x.size() - 1})
        if (i < x.size() && problem.HasParameterBlock(x[i].data())) problem.SetParameterBlockConstant(x[i].data());
      ceres::Solver::Options so;
      so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      so.max_num_iterations = o.max_iterations;
      so.num_threads = 1;
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
    }
    // Headings from the smoothed positions (the ends keep theirs).
    for (size_t i = 0; i < x.size(); ++i) {
      PathPoint p = stretch[i];
      if (i > 0 && i + 1 < x.size())
        p.pose.theta = std::atan2(direction * (x[i + 1][1] - x[i - 1][1]), direction * (x[i + 1][0] - x[i - 1][0]));
      p.pose.x = x[i][0], p.pose.y = x[i][1];
      if (!smoothed.points.empty() && i == 0) continue;  // the cusp is already there
      smoothed.points.push_back(p);
    }
  }
  result.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  for (const auto& p : smoothed.points)
    if (!map.Free(car, p.pose)) {
      result.note = "the smoothed path collides; kept the searched one";
      return result;
    }
  if (smoothed.MaxCurvature() > kappa_max * 1.05) {
    result.note = "the smoothed path turns tighter than the car can (" + std::to_string(smoothed.MaxCurvature()) +
                  " > " + std::to_string(kappa_max) + " 1/m); kept the searched one";
    return result;
  }
  result.path = std::move(smoothed);
  result.accepted = true;
  return result;
}

}  // namespace specht::plan
