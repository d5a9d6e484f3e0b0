#include "specht/eval/map_quality.h"

#include <algorithm>
#include <cmath>

#include <mrpt/maps/CSimplePointsMap.h>
#include <opencv2/imgproc.hpp>

#include "specht/core/statistics.h"

namespace specht::eval {
namespace {

constexpr float kOccupiedFree = 1.0f - 0.65f;  // cell value (p_free) below this is occupied

}  // namespace

WallThickness MeasureWallThickness(const mrpt::maps::COccupancyGridMap2D& grid) {
  const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
  cv::Mat occupied(h + 2, w + 2, CV_8U, cv::Scalar(0));  // 1-cell border of free space
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (grid.getCell(x, y) < kOccupiedFree) occupied.at<unsigned char>(y + 1, x + 1) = 255;
    }
  }
  cv::Mat dist;
  cv::distanceTransform(occupied, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  std::vector<double> thickness;
  double sum = 0;
  for (int y = 1; y <= h; ++y) {
    for (int x = 1; x <= w; ++x) {
      const float d = dist.at<float>(y, x);
      if (d <= 0) continue;
      bool ridge = true;
      for (int dy = -1; dy <= 1 && ridge; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dist.at<float>(y + dy, x + dx) > d) {
            ridge = false;
            break;
          }
        }
      }
      if (!ridge) continue;
      const double t = (2.0 * d - 1.0) * grid.getResolution();
      thickness.push_back(t);
      sum += t;
    }
  }
  WallThickness r;
  r.centre_cells = thickness.size();
  if (thickness.empty()) return r;
  r.mean_m = sum / thickness.size();
  r.p50_m = Percentile(thickness, 0.5);
  r.p90_m = Percentile(thickness, 0.9);
  r.p95_m = Percentile(thickness, 0.95);
  return r;
}

std::vector<Correction> RegisterAgainstGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                            const std::vector<slam::Keyframe>& keyframes,
                                            const slam::IcpOptions& icp_options) {
  mrpt::maps::CSimplePointsMap walls;
  for (unsigned y = 0; y < grid.getSizeY(); ++y) {
    for (unsigned x = 0; x < grid.getSizeX(); ++x) {
      if (grid.getCell(x, y) < kOccupiedFree) walls.insertPoint(grid.idx2x(x), grid.idx2y(y), 0);
    }
  }
  slam::IcpAligner icp(icp_options);
  std::vector<Correction> out;
  for (const auto& kf : keyframes) {
    const slam::IcpResult match = icp.Align(walls, slam::ScanToPoints(*kf.scan), kf.pose);
    const mrpt::poses::CPose2D delta = match.pose - kf.pose;
    out.push_back({delta.norm(), std::abs(mrpt::RAD2DEG(delta.phi())), match.goodness});
  }
  return out;
}

}  // namespace specht::eval
