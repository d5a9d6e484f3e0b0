#include "specht/slam/icp.h"

#include <cmath>

#include <mrpt/slam/CICP.h>

namespace specht::slam {

struct IcpAligner::Impl {
  mrpt::slam::CICP icp;
};

IcpAligner::IcpAligner(const IcpOptions& options) : impl_(std::make_unique<Impl>()) {
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
  return IcpResult{pdf->getMeanVal(), info.goodness, static_cast<int>(info.nIterations)};
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
