#include "specht/slam/icp.h"

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/slam/CICP.h>

namespace specht::slam {

struct IcpAligner::Impl {
  mrpt::slam::CICP icp;
  IcpOptions options;
  std::vector<size_t> neighbours;  // scratch for the k-d tree queries
  std::vector<float> distances2;
};

namespace {

// Fewer pairs than this leave the refinement where ICP put the scan.
constexpr int kMinLinePairs = 10;
// Neighbours whose spread across their line exceeds this fraction of the spread along
// it are a corner or clutter, not a line.
constexpr double kMaxLineFlatness = 0.1;

// The point-to-line refinement of `pose` (see icp.h): Gauss–Newton on the Huber-weighted
// normal equations H δ = −g, H = Σ w J Jᵀ, g = Σ w J r.
mrpt::poses::CPose2D RefinePointToLine(const mrpt::maps::CSimplePointsMap& reference,
                                       const mrpt::maps::CSimplePointsMap& scan, mrpt::poses::CPose2D pose,
                                       const IcpOptions& o, std::vector<size_t>& idx, std::vector<float>& d2) {
  const size_t k = static_cast<size_t>(o.point_to_line_neighbours);
  if (reference.size() < k) return pose;
  const auto& xs = scan.getPointsBufferRef_x();
  const auto& ys = scan.getPointsBufferRef_y();
  const auto& rx = reference.getPointsBufferRef_x();
  const auto& ry = reference.getPointsBufferRef_y();
  const double gate2 = o.point_to_line_gate_m * o.point_to_line_gate_m, huber = 0.5 * o.point_to_line_gate_m;
  for (int it = 0; it < o.point_to_line_iterations; ++it) {
    const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    int pairs = 0;
    for (size_t i = 0; i < xs.size(); ++i) {
      const double qx = pose.x() + c * xs[i] - s * ys[i], qy = pose.y() + s * xs[i] + c * ys[i];
      reference.kdTreeNClosestPoint2DIdx(static_cast<float>(qx), static_cast<float>(qy), k, idx, d2);
      // The line's points stay within twice the gate of the scan point.
      if (d2[0] > gate2 || d2[k - 1] > 4 * gate2) continue;
      double mx = 0, my = 0;
      for (size_t j : idx) mx += rx[j], my += ry[j];
      mx /= k, my /= k;
      Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
      for (size_t j : idx) {
        const Eigen::Vector2d v(rx[j] - mx, ry[j] - my);
        spread += v * v.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(spread);
      if (eig.eigenvalues()(0) > kMaxLineFlatness * eig.eigenvalues()(1)) continue;
      const Eigen::Vector2d n = eig.eigenvectors().col(0);
      const double r = n.x() * (qx - mx) + n.y() * (qy - my);
      const double dx = -s * xs[i] - c * ys[i], dy = c * xs[i] - s * ys[i];
      const Eigen::Vector3d j(n.x(), n.y(), n.x() * dx + n.y() * dy);
      const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      h += w * j * j.transpose();
      g += w * r * j;
      ++pairs;
    }
    if (pairs < kMinLinePairs) break;
    const Eigen::Vector3d step = -h.ldlt().solve(g);
    if (!step.allFinite()) break;
    pose = mrpt::poses::CPose2D(pose.x() + step.x(), pose.y() + step.y(), mrpt::math::wrapToPi(pose.phi() + step.z()));
    if (step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-5) break;  // 0.1 mm, 0.0006°
  }
  return pose;
}

}  // namespace

IcpAligner::IcpAligner(const IcpOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  auto& o = impl_->icp.options;
  o.ICP_algorithm = mrpt::slam::icpClassic;
  o.maxIterations = options.max_iterations;
  o.thresholdDist = options.max_pair_distance_m;
  o.thresholdAng = mrpt::DEG2RAD(options.max_pair_angle_deg);
  o.ALFA = options.threshold_decay;
  o.smallestThresholdDist = options.min_pair_distance_m;
  o.corresponding_points_decimation = options.point_decimation;
  o.onlyUniqueRobust = false;
  o.skip_cov_calculation = true;
  o.skip_quality_calculation = true;
}

IcpAligner::~IcpAligner() = default;

IcpResult IcpAligner::Align(const mrpt::maps::CSimplePointsMap& reference, const mrpt::maps::CSimplePointsMap& scan,
                            const mrpt::poses::CPose2D& guess) {
  mrpt::slam::CICP::TReturnInfo info;
  const auto pdf = impl_->icp.Align(&reference, &scan, guess, info);
  mrpt::poses::CPose2D pose = pdf->getMeanVal();
  if (impl_->options.point_to_line_iterations > 0) {
    pose = RefinePointToLine(reference, scan, pose, impl_->options, impl_->neighbours, impl_->distances2);
  }
  return IcpResult{pose, info.goodness, static_cast<int>(info.nIterations)};
}

mrpt::maps::CSimplePointsMap ScanToPoints(const mrpt::obs::CObservation2DRangeScan& scan) {
  mrpt::maps::CSimplePointsMap points;
  points.insertionOptions.minDistBetweenLaserPoints = 0;
  points.insertionOptions.isPlanarMap = true;
  points.insertObservation(scan);
  return points;
}

mrpt::maps::CSimplePointsMap WithinRange(const mrpt::maps::CSimplePointsMap& points, double max_range_m) {
  mrpt::maps::CSimplePointsMap out;
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  for (size_t i = 0; i < xs.size(); ++i) {
    if (std::hypot(xs[i], ys[i]) <= max_range_m) out.insertPoint(xs[i], ys[i], 0);
  }
  return out;
}

}  // namespace specht::slam
