// Shared by the SLAM front end and the localizer: preparing a scan and matching it
// against a reference point cloud (ICP, with the correlative recovery).
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>

#include "specht/core/time.h"
#include "specht/core/transform_tree.h"
#include "specht/slam/icp.h"
#include "specht/slam/scan_matching.h"

namespace specht::slam::internal {

// A copy of the scan with the mount from `frames` (when it names the sensor) and the
// returns outside [min_range_m, max_range_m] marked invalid.
mrpt::obs::CObservation2DRangeScan::Ptr PrepareScan(const mrpt::obs::CObservation2DRangeScan& scan,
                                                    const ScanMatchingOptions& options, const TransformTree* frames,
                                                    const std::string& base_frame);

// How a match was settled.
enum class MatchSource { kIcp, kRecovered, kGuess };
struct MatchResult {
  mrpt::poses::CPose2D pose;
  MatchSource source = MatchSource::kGuess;
};

// What a match knows besides the scan: whether the guess is weak (no odometry behind
// it), where the car was, and the odometry step the guess came from.
struct MatchContext {
  bool guess_is_weak = false;
  std::optional<mrpt::poses::CPose2D> last;
  std::optional<mrpt::poses::CPose2D> odometry_step;
  const IndexedPoints* lines = nullptr;  // what the point-to-line refinement fits lines to (icp.h)
};

// ICP from the guess. A match pairing fewer than min_goodness of the points is
// doubted: when recovery is on, the correlative matcher searches around the guess and
// its refined pose competes with ICP's on the same likelihood score; otherwise (or
// when nothing scores) ICP's pose stands if at least half min_goodness paired, else
// the guess. A weak guess is searched around first when `search_without_odometry` is
// on, and so is `last` (where the car was: without odometry it may have stopped or
// turned on the spot); the better score wins. Those searches score with the drive
// prior from `last` (options search_drive_*; correlative_matcher.h's DrivePrior).
// With `fuse_odometry` and an odometry step, the guess is a prior of the step's
// information (PriorInformation): inside ICP's point-to-line refinement (icp.h), or,
// with the refinement off, fused with ICP's pose after it (FuseWithPrior). Counts
// into `stats`.
MatchResult MatchWithRecovery(IcpAligner& icp, const IndexedPoints& reference,
                              const mrpt::maps::CSimplePointsMap& points, const mrpt::poses::CPose2D& guess,
                              const ScanMatchingOptions& options, MappingStats& stats,
                              const MatchContext& context = {});

// The information of a scan alignment, point to line: with n_i the normal of the
// surface at scan point p_i (from its beam neighbours) turned into the map frame,
//   J_i = [n_iᵀ, n_iᵀ R'(θ) p_i],   H = Σ J_iᵀ J_i / σ².
// Along a straight corridor H has no translational information along the walls.
Eigen::Matrix3d MatchInformation(const mrpt::maps::CSimplePointsMap& points, const mrpt::poses::CPose2D& pose,
                                 double point_sigma_m);

// The match fused with a prior of information Ω (map frame, x y θ), linearised at
// the match:  x = x_m ⊞ (H + Ω)⁻¹ Ω (x_prior ⊟ x_m).
mrpt::poses::CPose2D FuseWithPrior(const mrpt::poses::CPose2D& match, const Eigen::Matrix3d& match_information,
                                   const mrpt::poses::CPose2D& prior, const Eigen::Matrix3d& prior_information);

// Motion between scans: the wheel-odometry increment since the last scan when the
// odometry moved (or reported a stop: no motion from odometry that moved on at least
// half of the scans so far), else the last matched step (constant velocity); when a gyro
// reported since the last scan, its integrated yaw rate replaces the step's rotation:
//   Δθ = Σ ½ (ω_k + ω_{k−1}) (t_k − t_{k−1})   over the IMU samples since the last scan.
class MotionPrior {
 public:
  // Takes odometry (CObservationOdometry) and gyro yaw rate (CObservationIMU);
  // returns whether the observation was one of those.
  bool Consume(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation, MappingStats& stats);
  // The guess for a new scan after `last`; starts the next interval.
  mrpt::poses::CPose2D Predict(const mrpt::poses::CPose2D& last, bool use_odometry, bool use_imu);
  void SetLastStep(const mrpt::poses::CPose2D& step) { last_step_ = step; }
  // Whether the last prediction came from wheel odometry, and the step it predicted.
  bool predicted_from_odometry() const { return from_odometry_; }
  const mrpt::poses::CPose2D& predicted_step() const { return predicted_step_; }
  // The odometry step the last prediction came from (none: constant velocity).
  std::optional<mrpt::poses::CPose2D> odometry_step() const {
    return from_odometry_ ? std::optional(predicted_step_) : std::nullopt;
  }

 private:
  bool have_odometry_ = false;
  mrpt::poses::CPose2D odom_now_, odom_at_last_scan_, last_step_;
  std::optional<std::pair<Stamp, double>> last_gyro_;  // stamp, yaw rate
  double gyro_yaw_ = 0;                                // integrated since the last scan
  int gyro_samples_ = 0;
  bool from_odometry_ = false;
  long scans_ = 0, moved_scans_ = 0;  // predictions made, and those the odometry moved in
  mrpt::poses::CPose2D predicted_step_;
};

// The information of a wheel-odometry step as a prior: σ_t = fraction·|Δ| + min_m in
// every direction (isotropic, so it needs no rotation into the map frame),
// σ_θ = fraction·(|Δθ| + |Δ|) + min_deg.
Eigen::Matrix3d PriorInformation(const mrpt::poses::CPose2D& step, const ScanMatchingOptions& options);

}  // namespace specht::slam::internal
