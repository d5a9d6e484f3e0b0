#include "internal/matching.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <thread>
#include <vector>

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

namespace {

// Whether `pose` lies within max_correction_m / max_correction_deg of `from`.
bool WithinCorrectionBounds(const CPose2D& pose, const CPose2D& from, const ScanMatchingOptions& options) {
  const CPose2D correction = pose - from;
  return correction.norm() <= options.max_correction_m &&
         std::abs(correction.phi()) <= mrpt::DEG2RAD(options.max_correction_deg);
}

// The correlative matcher's best pose around each of `centres` against `reference`,
// refined by ICP, and the best of those: nullopt when nothing scores `min_score`.
// `score` is on the correlative grid; a tie goes to the earlier centre. A refinement
// is refused for the coarse pose when it loses more than refine_max_loss of the
// coarse pose's score, and also when it pairs too few points or leaves the bounds if
// the coarse pose can stand on its own: always without odometry
// (`coarse_stands_anywhere`: the search is the only estimate, its score and drive
// prior vouch for it, and an ICP that slides along a corridor off a right coarse pose
// must not send the front end back to the constant-velocity guess), and
// after a rejected ICP match with odometry only when the coarse pose lies within the
// correction bounds of the guess (a wide search in a featureless corridor finds
// aliases turned by a right angle whose refinement fails). Otherwise a failed refinement discards the candidate. The
// grid is built on the first search and kept for the next from the same reference; the searches around several centres
// run in parallel (the grid is read-only; ICP refines on the calling thread).
struct SearchResult {
  CPose2D pose;
  double score = 0;
  double icp_score = 0;  // the score of `icp_pose` on the same grid
};
class Searcher {
 public:
  Searcher(IcpAligner& icp, const IndexedPoints& reference, const CSimplePointsMap& points,
           const ScanMatchingOptions& options, MappingStats& stats, const DrivePrior& prior)
      : icp_(icp), reference_(reference), points_(points), options_(options), stats_(stats), prior_(prior) {}

  std::optional<SearchResult> Around(const std::vector<CPose2D>& centres, double min_score, bool coarse_stands_anywhere,
                                     const std::optional<CPose2D>& icp_pose = std::nullopt) {
    const double res = options_.recovery_resolution_m;
    if (!matcher_) {
      matcher_.emplace(Decimate(reference_.points(), res / 2), res, options_.recovery_window_m);
      query_ = Decimate(points_, res);
    }
    // Centres after the first are searched on other threads while this one searches
    // the first and refines its pose (ICP stays on this thread).
    std::vector<std::optional<CorrelativeResult>> coarse(centres.size());
    auto search = [&](size_t i) {
      coarse[i] = matcher_->Match(query_, centres[i], options_.recovery_window_m,
                                  mrpt::DEG2RAD(options_.recovery_window_deg), min_score, prior_);
    };
    std::optional<SearchResult> best;
    auto refine = [&](size_t i) {
      if (!coarse[i]) return;
      const IcpResult refined = icp_.Align(reference_, points_, coarse[i]->pose);
      stats_.icp_iterations += refined.iterations;
      CPose2D pose = coarse[i]->pose;
      double score = coarse[i]->score;
      const bool refined_ok =
          refined.goodness >= options_.min_goodness / 2 && WithinCorrectionBounds(refined.pose, pose, options_);
      const bool coarse_stands = coarse_stands_anywhere || WithinCorrectionBounds(pose, centres[i], options_);
      if (!refined_ok && !coarse_stands) return;
      if (refined_ok) {
        const double refined_score = matcher_->Score(query_, refined.pose, prior_);
        if (refined_score >= (1 - options_.refine_max_loss) * score) pose = refined.pose, score = refined_score;
      }
      if (!best || score > best->score) {
        best = SearchResult{pose, score, icp_pose ? matcher_->Score(query_, *icp_pose, prior_) : 0.0};
      }
    };
    std::vector<std::thread> others;
    for (size_t i = 1; i < centres.size(); ++i) others.emplace_back(search, i);
    search(0);
    refine(0);
    for (auto& t : others) t.join();
    for (size_t i = 1; i < centres.size(); ++i) refine(i);
    return best;
  }

 private:
  IcpAligner& icp_;
  const IndexedPoints& reference_;
  const CSimplePointsMap& points_;
  const ScanMatchingOptions& options_;
  MappingStats& stats_;
  const DrivePrior prior_;
  std::optional<CorrelativeMatcher> matcher_;
  CSimplePointsMap query_;
};

// Solution remapping (Zhang, Kaess & Singh, ICRA 2016): along a direction v the scan
// pins hardly at all, ICP's update is noise or a pull towards no motion (point to
// point, identical corridor scans pair with themselves), so the guess keeps it:
//   t = t_icp + v vᵀ (t_guess − t_icp),   θ = θ_icp.
CPose2D KeepGuessAlong(const Eigen::Vector2d& v, const CPose2D& match, const CPose2D& guess) {
  const double along = v.x() * (guess.x() - match.x()) + v.y() * (guess.y() - match.y());
  return CPose2D(match.x() + along * v.x(), match.y() + along * v.y(), match.phi());
}

}  // namespace

MatchResult MatchWithRecovery(IcpAligner& icp, const IndexedPoints& reference, const CSimplePointsMap& points,
                              const CPose2D& guess, const ScanMatchingOptions& options, MappingStats& stats,
                              const MatchContext& context) {
  const bool recovery =
      options.recovery_window_m > 0 && points.size() >= static_cast<size_t>(options.recovery_min_points);
  const auto& last = context.last;
  // A guess no odometry backs (constant velocity) may be off by a whole step:
  // search around it before ICP, which would settle in the nearest minimum.
  const bool search_first = recovery && context.guess_is_weak && options.search_without_odometry;
  // Without odometry, only what a wheeled robot can do tells a step from its aliases.
  DrivePrior drive;
  if (context.guess_is_weak && last) {
    drive = {*last, options.search_drive_penalty, options.search_drive_slack_m, options.search_drive_reverse};
  }
  Searcher search(icp, reference, points, options, stats, drive);
  if (search_first) {
    std::vector<CPose2D> centres = {guess};
    const bool guess_moved = last && (guess.distanceTo(*last) > 0 || guess.phi() != last->phi());
    if (guess_moved) centres.push_back(*last);
    const auto found = search.Around(centres, options.search_min_score, /*coarse_stands_anywhere=*/true);
    if (found) {
      ++stats.recovered_matches;
      return {found->pose, MatchSource::kRecovered};
    }
  }
  // Where the scan leaves a direction unconstrained (a corridor), the odometry decides it.
  std::optional<IcpPrior> prior;
  if (options.fuse_odometry && context.odometry_step) {
    prior = IcpPrior{guess, PriorInformation(*context.odometry_step, options), options.point_sigma_m};
  }
  const bool prior_in_icp = prior && options.icp.point_to_line_iterations > 0;
  const IcpResult match = icp.Align(reference, points, guess, prior_in_icp ? &*prior : nullptr, context.lines);
  stats.icp_iterations += match.iterations;
  // An accepted ICP pose; with the refinement off the prior is fused with it here.
  const auto accepted = [&]() -> MatchResult {
    if (!prior && options.degenerate_axis_points > 0) {
      const WeakestAxis weakest = WeakestAxisOf(points, match);
      if (weakest.points < options.degenerate_axis_points) {
        ++stats.degenerate_matches;
        return {KeepGuessAlong(weakest.axis, match.pose, guess), MatchSource::kIcp};
      }
    }
    if (!prior || prior_in_icp) return {match.pose, MatchSource::kIcp};
    return {FuseWithPrior(match.pose, MatchInformation(points, match.pose, options.point_sigma_m), guess,
                          prior->information),
            MatchSource::kIcp};
  };
  const bool icp_bounded = WithinCorrectionBounds(match.pose, guess, options);
  if (icp_bounded && match.goodness >= options.min_goodness) return accepted();
  const bool icp_weak_ok = icp_bounded && match.goodness >= options.min_goodness / 2;
  // (After a search first, searching again from the same guess would find the same.)
  if (recovery && !search_first) {
    const auto found = search.Around({guess}, options.recovery_min_score, /*coarse_stands_anywhere=*/false, match.pose);
    if (found && (!icp_weak_ok || found->score > found->icp_score)) {
      ++stats.recovered_matches;
      return {found->pose, MatchSource::kRecovered};
    }
  }
  if (icp_weak_ok) return accepted();
  ++stats.rejected_matches;
  return {guess, MatchSource::kGuess};
}

Eigen::Matrix3d MatchInformation(const CSimplePointsMap& points, const CPose2D& pose, double point_sigma_m) {
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t i = 1; i + 1 < xs.size(); ++i) {
    // Neighbours on the same surface only (within 0.3 m).
    const double tx = xs[i + 1] - xs[i - 1], ty = ys[i + 1] - ys[i - 1], len = std::hypot(tx, ty);
    if (len < 1e-6 || len > 0.3) continue;
    const double nx = -ty / len, ny = tx / len;               // normal, scan frame
    const double wx = c * nx - s * ny, wy = s * nx + c * ny;  // normal, map frame
    // d(R p)/dθ = (−s x − c y, c x − s y)
    const double dx = -s * xs[i] - c * ys[i], dy = c * xs[i] - s * ys[i];
    const Eigen::Vector3d j(wx, wy, wx * dx + wy * dy);
    h += j * j.transpose();
  }
  return h / (point_sigma_m * point_sigma_m);
}

CPose2D FuseWithPrior(const CPose2D& match, const Eigen::Matrix3d& match_information, const CPose2D& prior,
                      const Eigen::Matrix3d& prior_information) {
  const Eigen::Vector3d delta(prior.x() - match.x(), prior.y() - match.y(),
                              mrpt::math::wrapToPi(prior.phi() - match.phi()));
  const Eigen::Vector3d step = (match_information + prior_information).ldlt().solve(prior_information * delta);
  if (!step.allFinite()) return match;
  return CPose2D(match.x() + step.x(), match.y() + step.y(), mrpt::math::wrapToPi(match.phi() + step.z()));
}

Eigen::Matrix3d PriorInformation(const CPose2D& step, const ScanMatchingOptions& options) {
  const double dist = step.norm();
  const double sigma_t = options.prior_fraction * dist + options.prior_min_m;
  const double sigma_r = options.prior_fraction * (std::abs(step.phi()) + dist) + mrpt::DEG2RAD(options.prior_min_deg);
  return Eigen::Vector3d(1 / (sigma_t * sigma_t), 1 / (sigma_t * sigma_t), 1 / (sigma_r * sigma_r)).asDiagonal();
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

// Odometry that moved on fewer scans than this is not yet trusted to report a stop.
constexpr long kMinMovedScans = 10;

CPose2D MotionPrior::Predict(const CPose2D& last, bool use_odometry, bool use_imu) {
  CPose2D step = odom_now_ - odom_at_last_scan_;
  odom_at_last_scan_ = odom_now_;
  // Without odometry, keep the last velocity. Odometry that reports no motion is a
  // stop when it moved on at least half of the scans so far (and on kMinMovedScans);
  // else it is taken as absent (a log whose odometry lines hold zeros, or a few jumps).
  const bool moved = have_odometry_ && (step.norm() > 0 || step.phi() != 0);
  ++scans_;
  moved_scans_ += moved;
  const bool live = moved_scans_ >= kMinMovedScans && 2 * moved_scans_ >= scans_;
  from_odometry_ = use_odometry && (moved || live);  // live: it moved, so there is odometry
  if (!from_odometry_) step = last_step_;
  if (use_imu && gyro_samples_ > 0) step = CPose2D(step.x(), step.y(), gyro_yaw_);
  gyro_yaw_ = 0;
  gyro_samples_ = 0;
  predicted_step_ = step;
  return last + step;
}

}  // namespace specht::slam::internal
