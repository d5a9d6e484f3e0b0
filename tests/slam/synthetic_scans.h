// Synthetic 2D laser scans for the SLAM tests: a 180° scanner ray-cast into
// axis-aligned boxes, and odometry at a given pose.
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "specht/core/time.h"

namespace specht::slam::synthetic {

// An axis-aligned box: a wall outline or a pillar.
struct Box {
  double x0, x1, y0, y1;
};

// Distance along a ray to the nearest side of any of the boxes (1e9 when none).
inline double RayCast(const std::vector<Box>& boxes, double x, double y, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double best = 1e9;
  for (const Box& b : boxes) {
    for (double wx : {b.x0, b.x1}) {
      if (std::abs(dx) < 1e-12) continue;
      const double t = (wx - x) / dx, hy = y + t * dy;
      if (t > 1e-9 && hy >= b.y0 && hy <= b.y1) best = std::min(best, t);
    }
    for (double wy : {b.y0, b.y1}) {
      if (std::abs(dy) < 1e-12) continue;
      const double t = (wy - y) / dy, hx = x + t * dx;
      if (t > 1e-9 && hx >= b.x0 && hx <= b.x1) best = std::min(best, t);
    }
  }
  return best;
}

// A 180°, 361-beam scan whose beam at world heading `angle` measures range(angle)
// (beyond 29 m: no return).
inline mrpt::obs::CObservation2DRangeScan::Ptr Scan180(const mrpt::poses::CPose2D& pose, Stamp stamp,
                                                       const std::function<double(double)>& range) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  const size_t n = 361;
  scan->aperture = static_cast<float>(M_PI);
  scan->rightToLeft = true;
  scan->maxRange = 30.0f;
  scan->resizeScan(n);
  for (size_t i = 0; i < n; ++i) {
    const double r = range(pose.phi() - M_PI / 2 + M_PI * static_cast<double>(i) / (n - 1));
    const bool valid = r > 0 && r < 29.0;
    scan->setScanRange(i, valid ? static_cast<float>(r) : 30.0f);
    scan->setScanRangeValidity(i, valid);
  }
  scan->timestamp = ToMrpt(stamp);
  scan->sensorLabel = "LASER";
  return scan;
}

inline mrpt::obs::CObservationOdometry::Ptr OdometryAt(const mrpt::poses::CPose2D& pose) {
  auto odo = mrpt::obs::CObservationOdometry::Create();
  odo->odometry = pose;
  return odo;
}

}  // namespace specht::slam::synthetic
