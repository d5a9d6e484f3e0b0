#include "internal/matching.h"

#include <cmath>

#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "specht/slam/correlative_matcher.h"

namespace specht::slam::internal {

using mrpt::maps::CSimplePointsMap;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::poses::CPose2D;

CObservation2DRangeScan::Ptr PrepareScan(const CObservation2DRangeScan& scan, const ScanMatchingOptions& options,
                                         const TransformTree* frames, const std::string& base_frame) {
  auto copy = std::make_shared<CObservation2DRangeScan>(scan);
  if (frames != nullptr && frames->Has(scan.sensorLabel) && frames->Has(base_frame)) {
    copy->sensorPose = frames->LookupStatic(base_frame, scan.sensorLabel);
  }
  for (size_t i = 0; i < copy->getScanSize(); ++i) {
    const float r = copy->getScanRange(i);
    if (!std::isfinite(r) || r < options.min_range_m || r > options.max_range_m) copy->setScanRangeValidity(i, false);
  }
  return copy;
}

CPose2D MatchWithRecovery(IcpAligner& icp, const CSimplePointsMap& reference, const CSimplePointsMap& points,
                          const CPose2D& guess, const ScanMatchingOptions& options, MappingStats& stats) {
  auto within_bounds = [&](const CPose2D& pose, const CPose2D& from) {
    const CPose2D correction = pose - from;
    return correction.norm() <= options.max_correction_m &&
           std::abs(correction.phi()) <= mrpt::DEG2RAD(options.max_correction_deg);
  };
  const IcpResult match = icp.Align(reference, points, guess);
  stats.icp_iterations += match.iterations;
  const bool icp_bounded = within_bounds(match.pose, guess);
  if (icp_bounded && match.goodness >= options.min_goodness) return match.pose;
  const bool icp_weak_ok = icp_bounded && match.goodness >= options.min_goodness / 2;
  if (options.recovery_window_m > 0) {
    const double res = options.recovery_resolution_m;
    const CorrelativeMatcher matcher(Decimate(reference, res / 2), res, options.recovery_window_m);
    const CSimplePointsMap query = Decimate(points, res);
    const auto coarse = matcher.Match(query, guess, options.recovery_window_m,
                                      mrpt::DEG2RAD(options.recovery_window_deg), options.recovery_min_score);
    if (coarse) {
      const IcpResult refined = icp.Align(reference, points, coarse->pose);
      if (refined.goodness >= options.min_goodness / 2 && within_bounds(refined.pose, coarse->pose) &&
          (!icp_weak_ok || matcher.Score(query, refined.pose) > matcher.Score(query, match.pose))) {
        ++stats.recovered_matches;
        return refined.pose;
      }
    }
  }
  if (icp_weak_ok) return match.pose;
  ++stats.rejected_matches;
  return guess;
}

bool MotionPrior::Consume(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation, MappingStats& stats) {
  if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(observation)) {
    ++stats.odometry;
    odom_now_ = odo->odometry;
    if (!have_odometry_) odom_at_last_scan_ = odom_now_;
    have_odometry_ = true;
    return true;
  }
  if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(observation)) {
    ++stats.imu;
    if (!imu->has(mrpt::obs::IMU_WZ)) return true;
    const double rate = imu->get(mrpt::obs::IMU_WZ);
    if (last_gyro_ && stamp > last_gyro_->first) {
      gyro_yaw_ += 0.5 * (rate + last_gyro_->second) * SecondsBetween(last_gyro_->first, stamp);
      ++gyro_samples_;
    }
    last_gyro_ = std::make_pair(stamp, rate);
    return true;
  }
  return false;
}

CPose2D MotionPrior::Predict(const CPose2D& last, bool use_odometry, bool use_imu) {
  CPose2D step = odom_now_ - odom_at_last_scan_;
  odom_at_last_scan_ = odom_now_;
  // Without odometry (or when it reports no motion at all), keep the last velocity.
  const bool moved = have_odometry_ && (step.norm() > 0 || step.phi() != 0);
  if (!(use_odometry && moved)) step = last_step_;
  if (use_imu && gyro_samples_ > 0) step = CPose2D(step.x(), step.y(), gyro_yaw_);
  gyro_yaw_ = 0;
  gyro_samples_ = 0;
  return last + step;
}

}  // namespace specht::slam::internal
