#include "specht/eval/map_quality.h"

#include <mrpt/maps/CSimplePointsMap.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "specht/eval/trajectory_error.h"
#include "specht/slam/indexed_points.h"

namespace specht::eval {
namespace {

constexpr float kOccupiedFree = 1.0f - 0.65f;  // cell value (p_free) below this is occupied
// The wall-thickness transform runs on bands of this many rows (a 9,000-cell-wide
// grid's transform would hold 200 MB at once), overlapping by enough rows to measure a
// wall up to 2·kWallBandOverlap cells thick exactly.
constexpr int kWallBandRows = 512;
constexpr int kWallBandOverlap = 64;

}  // namespace

WallThickness MeasureWallThickness(const mrpt::maps::COccupancyGridMap2D& grid) {
  const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
  std::vector<float> thickness;  // one per centre-line cell: millions on a building's grid
  double sum = 0;
  // In bands of rows, each with kWallBandOverlap rows either side: the distance of a
  // cell whose nearest non-occupied cell lies within the overlap is the whole grid's.
  for (int first = 0; first < h; first += kWallBandRows) {
    const int last = std::min(h, first + kWallBandRows) - 1;
    const int lo = std::max(0, first - kWallBandOverlap), hi = std::min(h - 1, last + kWallBandOverlap);
    cv::Mat occupied(hi - lo + 3, w + 2, CV_8U, cv::Scalar(0));  // 1-cell border of free space
    for (int y = lo; y <= hi; ++y) {
      for (int x = 0; x < w; ++x) {
        if (grid.getCell(x, y) < kOccupiedFree) occupied.at<unsigned char>(y - lo + 1, x + 1) = 255;
      }
    }
    cv::Mat dist;
    cv::distanceTransform(occupied, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    for (int y = first - lo + 1; y <= last - lo + 1; ++y) {
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
        const float t = static_cast<float>((2.0 * d - 1.0) * grid.getResolution());
        thickness.push_back(t);
        sum += t;
      }
    }
  }
  WallThickness r;
  r.centre_cells = thickness.size();
  if (thickness.empty()) return r;
  r.mean_m = sum / thickness.size();
  // In place (Percentile would copy the vector each time); nearest rank as Percentile.
  auto at = [&](double q) {
    const size_t k = std::min(thickness.size() - 1, static_cast<size_t>(q * (thickness.size() - 1) + 0.5));
    std::nth_element(thickness.begin(), thickness.begin() + k, thickness.end());
    return static_cast<double>(thickness[k]);
  };
  r.p50_m = at(0.5);
  r.p90_m = at(0.9);
  r.p95_m = at(0.95);
  return r;
}

MapEntropy MeanMapEntropy(const std::vector<slam::Keyframe>& keyframes, const MapEntropyOptions& options) {
  mrpt::maps::CSimplePointsMap cloud;
  for (const auto& kf : keyframes) {
    const mrpt::maps::CSimplePointsMap scan = slam::WithinRange(slam::ScanToPoints(*kf.scan), options.max_range_m);
    cloud.insertAnotherMap(&scan, mrpt::poses::CPose3D(kf.pose));
  }
  const slam::IndexedPoints indexed(cloud);
  const auto& xs = cloud.getPointsBufferRef_x();
  const auto& ys = cloud.getPointsBufferRef_y();
  const float bound2 = static_cast<float>(options.radius_m * options.radius_m);
  const double two_pi_e = 2.0 * M_PI * M_E;
  std::vector<slam::IndexedPoints::Neighbour> near;
  double sum = 0;
  MapEntropy r;
  const size_t most = std::max<size_t>(1, options.max_points);
  const size_t stride = std::max<size_t>(1, (xs.size() + most - 1) / most);
  for (size_t i = 0; i < xs.size(); i += stride) {
    indexed.Within(xs[i], ys[i], bound2, near);
    if (static_cast<int>(near.size()) < options.min_neighbours) continue;
    double mx = 0, my = 0;
    for (const auto& n : near) mx += xs[n.index], my += ys[n.index];
    mx /= near.size(), my /= near.size();
    double sxx = 0, syy = 0, sxy = 0;
    for (const auto& n : near) {
      const double dx = xs[n.index] - mx, dy = ys[n.index] - my;
      sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
    }
    // det(2πe Σ) = (2πe)² det Σ, with Σ + ε²I (ε = 1 mm, below any laser's noise) so
    // that the exactly collinear points of a synthetic wall stay finite.
    const double k = static_cast<double>(near.size()), eps2 = 1e-6;
    const double det = (sxx / k + eps2) * (syy / k + eps2) - (sxy / k) * (sxy / k);
    sum += 0.5 * std::log(two_pi_e * two_pi_e * det);
    ++r.points;
  }
  if (r.points > 0) r.mean_nats = sum / r.points;
  return r;
}

std::pair<std::vector<slam::Keyframe>, std::vector<slam::Keyframe>> KeyframesAtReference(
    const std::vector<slam::Keyframe>& keyframes, const Trajectory& reference, double max_dt_s) {
  Trajectory at_keyframes;
  for (const auto& kf : keyframes) at_keyframes.push_back({kf.stamp, mrpt::poses::CPose3D(kf.pose)});
  std::pair<std::vector<slam::Keyframe>, std::vector<slam::Keyframe>> out;
  for (const auto& [k, r] : AssociateByTime(at_keyframes, reference, max_dt_s)) {
    out.first.push_back(keyframes[k]);
    out.second.push_back(keyframes[k]);
    out.second.back().pose = mrpt::poses::CPose2D(reference[r].pose);
  }
  return out;
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
  const slam::IndexedPoints indexed(walls);
  slam::IcpAligner icp(icp_options);
  std::vector<Correction> out;
  for (const auto& kf : keyframes) {
    const slam::IcpResult match = icp.Align(indexed, slam::ScanToPoints(*kf.scan), kf.pose);
    const mrpt::poses::CPose2D delta = match.pose - kf.pose;
    out.push_back({delta.norm(), std::abs(mrpt::RAD2DEG(delta.phi())), match.goodness});
  }
  return out;
}

}  // namespace specht::eval
