#include "specht/slam/scan_matching.h"

#include <cmath>
#include <deque>

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "specht/slam/correlative_matcher.h"

namespace specht::slam {

using mrpt::maps::CSimplePointsMap;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

std::vector<std::string> ScanMatchingOptions::Relations() const {
  std::vector<std::string> problems;
  if (min_range_m >= max_range_m) problems.push_back("min_range_m must be below max_range_m");
  if (icp.min_pair_distance_m >= icp.max_pair_distance_m) {
    problems.push_back("icp.min_pair_distance_m must be below icp.max_pair_distance_m");
  }
  return problems;
}

std::vector<std::string> GridOptions::Relations() const {
  if (free_update != 0.0 && free_update <= 0.5) return {"free_update must be 0 (same as occupied_update) or above 0.5"};
  return {};
}

struct ScanMatchingMapper::Impl {
  explicit Impl(const IcpOptions& options) : icp(options) {}
  IcpAligner icp;
  CSimplePointsMap submap;
  std::deque<CSimplePointsMap> keyframe_points;  // the last submap_keyframes, base frame
  std::deque<size_t> keyframe_poses;             // their indices into keyframes_
  bool have_odometry = false;
  CPose2D odom_now;
  CPose2D odom_at_last_scan;
  CPose2D last_step;  // the matched motion between the last two scans
};


ScanMatchingMapper::ScanMatchingMapper(const ScanMatchingOptions& options, const TransformTree* frames,
                                       std::string base_frame)
    : impl_(std::make_unique<Impl>(options.icp)),
      options_(options),
      frames_(frames),
      base_frame_(std::move(base_frame)) {}

ScanMatchingMapper::~ScanMatchingMapper() = default;

void ScanMatchingMapper::Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation) {
  if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(observation)) {
    ++stats_.odometry;
    impl_->odom_now = odo->odometry;
    if (!impl_->have_odometry) impl_->odom_at_last_scan = odo->odometry;
    impl_->have_odometry = true;
  } else if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(observation)) {
    AddScan(stamp, *scan);
  } else {
    ++stats_.ignored;
  }
}

CObservation2DRangeScan::Ptr ScanMatchingMapper::Prepare(const CObservation2DRangeScan& scan) const {
  auto copy = std::make_shared<CObservation2DRangeScan>(scan);
  if (frames_ != nullptr && frames_->Has(scan.sensorLabel) && frames_->Has(base_frame_)) {
    copy->sensorPose = frames_->LookupStatic(base_frame_, scan.sensorLabel);
  }
  for (size_t i = 0; i < copy->getScanSize(); ++i) {
    const float r = copy->getScanRange(i);
    if (!std::isfinite(r) || r < options_.min_range_m || r > options_.max_range_m) {
      copy->setScanRangeValidity(i, false);
    }
  }
  return copy;
}

CPose2D ScanMatchingMapper::LastPose() const {
  if (scans_.empty()) return CPose2D();
  const ScanPose& last = scans_.back();
  return keyframes_[last.keyframe].pose + last.from_keyframe;
}

// ICP from the guess. A match pairing fewer than min_goodness of the points is
// doubted: when recovery is on, the correlative matcher searches around the guess and
// its refined pose competes with ICP's on the same likelihood score; otherwise (or
// when nothing scores) ICP's pose stands if at least half min_goodness paired, else
// the guess.
CPose2D ScanMatchingMapper::Match(const CSimplePointsMap& points, const CPose2D& guess) {
  Impl& m = *impl_;
  auto within_bounds = [&](const CPose2D& pose, const CPose2D& from) {
    const CPose2D correction = pose - from;
    return correction.norm() <= options_.max_correction_m &&
           std::abs(correction.phi()) <= mrpt::DEG2RAD(options_.max_correction_deg);
  };
  const IcpResult match = m.icp.Align(m.submap, points, guess);
  stats_.icp_iterations += match.iterations;
  const bool icp_bounded = within_bounds(match.pose, guess);
  if (icp_bounded && match.goodness >= options_.min_goodness) return match.pose;
  if (options_.recovery_window_m > 0) {
    const double res = options_.recovery_resolution_m;
    const CorrelativeMatcher matcher(Decimate(m.submap, res / 2), res, options_.recovery_window_m);
    const CSimplePointsMap query = Decimate(points, res);
    const auto coarse = matcher.Match(query, guess, options_.recovery_window_m,
                                      mrpt::DEG2RAD(options_.recovery_window_deg), options_.recovery_min_score);
    if (coarse) {
      const IcpResult refined = m.icp.Align(m.submap, points, coarse->pose);
      const bool icp_weak_ok = icp_bounded && match.goodness >= options_.min_goodness / 2;
      if (refined.goodness >= options_.min_goodness / 2 && within_bounds(refined.pose, coarse->pose) &&
          (!icp_weak_ok || matcher.Score(query, refined.pose) > matcher.Score(query, match.pose))) {
        ++stats_.recovered_matches;
        return refined.pose;
      }
    }
  }
  if (icp_bounded && match.goodness >= options_.min_goodness / 2) return match.pose;
  ++stats_.rejected_matches;
  return guess;
}

void ScanMatchingMapper::AddScan(Stamp stamp, const CObservation2DRangeScan& raw) {
  Impl& m = *impl_;
  const auto scan = Prepare(raw);
  const CSimplePointsMap points = ScanToPoints(*scan);

  CPose2D guess;
  if (!scans_.empty()) {
    const CPose2D last = LastPose();
    const CPose2D odometry_step = m.odom_now - m.odom_at_last_scan;
    const bool odometry_moved = m.have_odometry && (odometry_step.norm() > 0 || odometry_step.phi() != 0);
    // Without odometry (or when it reports no motion at all), keep the last velocity.
    guess = options_.use_odometry && odometry_moved ? last + odometry_step : last + m.last_step;
  }
  m.odom_at_last_scan = m.odom_now;

  const CPose2D pose = !keyframes_.empty() && !points.empty() ? Match(points, guess) : guess;
  if (!scans_.empty()) m.last_step = pose - LastPose();
  ++stats_.scans;

  const bool first = keyframes_.empty();
  const CPose2D since = first ? CPose2D() : pose - keyframes_.back().pose;
  if (first || since.norm() >= options_.keyframe_translation_m ||
      std::abs(since.phi()) >= mrpt::DEG2RAD(options_.keyframe_rotation_deg)) {
    keyframes_.push_back({scans_.size(), stamp, pose, scan});
    ++stats_.keyframes;
    m.keyframe_points.push_back(points);
    m.keyframe_poses.push_back(keyframes_.size() - 1);
    while (static_cast<int>(m.keyframe_points.size()) > options_.submap_keyframes) {
      m.keyframe_points.pop_front();
      m.keyframe_poses.pop_front();
    }
    RebuildSubmap();
    scans_.push_back({stamp, keyframes_.size() - 1, CPose2D()});
  } else {
    scans_.push_back({stamp, keyframes_.size() - 1, since});
  }
}

Trajectory ScanMatchingMapper::trajectory() const {
  Trajectory t;
  t.reserve(scans_.size());
  for (const ScanPose& s : scans_) t.push_back({s.stamp, CPose3D(keyframes_[s.keyframe].pose + s.from_keyframe)});
  return t;
}

void ScanMatchingMapper::CorrectKeyframes(const std::vector<CPose2D>& poses) {
  for (size_t i = 0; i < poses.size() && i < keyframes_.size(); ++i) keyframes_[i].pose = poses[i];
  RebuildSubmap();
}

void ScanMatchingMapper::RebuildSubmap() {
  Impl& m = *impl_;
  m.submap.clear();
  for (size_t i = 0; i < m.keyframe_points.size(); ++i) {
    m.submap.insertAnotherMap(&m.keyframe_points[i], CPose3D(keyframes_[m.keyframe_poses[i]].pose));
  }
}

mrpt::maps::COccupancyGridMap2D BuildGrid(const std::vector<Keyframe>& keyframes, const GridOptions& options) {
  const float res = static_cast<float>(options.resolution_m);
  mrpt::maps::COccupancyGridMap2D grid(-10.0f, 10.0f, -10.0f, 10.0f, res);
  auto& ins = grid.insertionOptions;
  ins.maxDistanceInsertion = static_cast<float>(options.max_insert_range_m);
  ins.maxOccupancyUpdateCertainty = static_cast<float>(options.occupied_update);
  ins.maxFreenessUpdateCertainty = static_cast<float>(options.free_update);
  ins.considerInvalidRangesAsFreeSpace = options.invalid_ranges_are_free;
  ins.wideningBeamsWithDistance = false;
  for (const Keyframe& kf : keyframes) {
    // Grow the grid to hold every return of this scan before inserting it.
    const CPose3D robot(kf.pose);
    const double reach = std::min<double>(kf.scan->maxRange, options.max_insert_range_m) + 1.0;
    grid.resizeGrid(static_cast<float>(std::min<double>(grid.getXMin(), robot.x() - reach)),
                    static_cast<float>(std::max<double>(grid.getXMax(), robot.x() + reach)),
                    static_cast<float>(std::min<double>(grid.getYMin(), robot.y() - reach)),
                    static_cast<float>(std::max<double>(grid.getYMax(), robot.y() + reach)), 0.5f, false);
    grid.insertObservation(*kf.scan, robot);
  }
  return grid;
}

}  // namespace specht::slam
