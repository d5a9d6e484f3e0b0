#include "specht/slam/scan_matching.h"

#include <cmath>
#include <deque>

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "internal/matching.h"

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
  CSimplePointsMap submap_points;       // the keyframes' points in the map frame
  std::optional<IndexedPoints> submap;  // their tree, built when the next scan needs it
  std::deque<CSimplePointsMap> keyframe_points;  // the last submap_keyframes, base frame
  std::deque<size_t> keyframe_poses;             // their indices into keyframes_
  internal::MotionPrior motion;
};


ScanMatchingMapper::ScanMatchingMapper(const ScanMatchingOptions& options, const TransformTree* frames,
                                       std::string base_frame)
    : impl_(std::make_unique<Impl>(options.icp)),
      options_(options),
      frames_(frames),
      base_frame_(std::move(base_frame)) {}

ScanMatchingMapper::~ScanMatchingMapper() = default;

void ScanMatchingMapper::Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation) {
  if (impl_->motion.Consume(stamp, observation, stats_)) {
    return;
  } else if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(observation)) {
    AddScan(stamp, *scan);
  } else {
    ++stats_.ignored;
  }
}

void ScanMatchingMapper::Seed(std::vector<Keyframe> saved, const CPose2D& start) {
  keyframes_ = std::move(saved);
  start_ = start;
}

CPose2D ScanMatchingMapper::LastPlacedPose() const {
  if (!last_placed_) return start_;
  const ScanPose& s = scans_[*last_placed_];
  return keyframes_[s.keyframe].pose + s.from_keyframe;
}

void ScanMatchingMapper::AddScan(Stamp stamp, const CObservation2DRangeScan& raw) {
  Impl& m = *impl_;
  const auto scan = internal::PrepareScan(raw, options_, frames_, base_frame_);
  const CSimplePointsMap points = ScanToPoints(*scan);

  // The map frame starts at the first scan (or at start_ in a seeded map).
  // An unplaced scan's pose is a guess nothing verified: predict from the last placed one.
  const CPose2D last = LastPlacedPose();
  const CPose2D predicted = m.motion.Predict(last, options_.use_odometry, options_.use_imu);
  const CPose2D guess = scans_.empty() ? start_ : predicted;
  CPose2D pose = guess;
  bool matched = false;
  if (!m.keyframe_points.empty() && !points.empty()) {
    const bool weak = !m.motion.predicted_from_odometry();
    const internal::MatchResult match =
        internal::MatchWithRecovery(m.icp, Submap(), points, guess, options_, stats_, weak, last);
    pose = match.pose;
    matched = match.source != internal::MatchSource::kGuess;
    // Where the scan leaves a direction unconstrained (a corridor), the odometry decides it.
    if (options_.fuse_odometry && match.source == internal::MatchSource::kIcp && m.motion.predicted_from_odometry()) {
      pose = internal::FuseWithPrior(pose, internal::MatchInformation(points, pose, options_.point_sigma_m), guess,
                                     internal::PriorInformation(m.motion.predicted_step(), options_));
    }
  }
  // An unmatched scan says nothing about the velocity: do not carry the guess on.
  const bool follows_placed = last_placed_ && *last_placed_ + 1 == scans_.size();
  if (!scans_.empty()) m.motion.SetLastStep(matched && follows_placed ? pose - last : CPose2D());
  ++stats_.scans;

  const bool first = m.keyframe_points.empty();
  const CPose2D since = first ? CPose2D() : pose - keyframes_.back().pose;
  // A scan placed at a guess no odometry backs would only blur the submap.
  const bool placeable = first || matched || m.motion.predicted_from_odometry();
  if (placeable && (first || since.norm() >= options_.keyframe_translation_m ||
      std::abs(since.phi()) >= mrpt::DEG2RAD(options_.keyframe_rotation_deg))) {
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
  if (placeable) last_placed_ = scans_.size() - 1;
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
  CSimplePointsMap& submap = m.submap_points;
  submap.clear();
  // One allocation: each insertAnotherMap reserves exactly what it adds, so without
  // this the buffers are reallocated and copied once per keyframe.
  size_t total = 0;
  for (const CSimplePointsMap& points : m.keyframe_points) total += points.size();
  submap.reserve(total);
  for (size_t i = 0; i < m.keyframe_points.size(); ++i) {
    submap.insertAnotherMap(&m.keyframe_points[i], CPose3D(keyframes_[m.keyframe_poses[i]].pose));
  }
  // An optimisation often rebuilds the points again before any scan is matched:
  // the tree waits for the next scan.
  m.submap.reset();
}

const IndexedPoints& ScanMatchingMapper::Submap() {
  if (!impl_->submap) impl_->submap.emplace(impl_->submap_points);
  return *impl_->submap;
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
