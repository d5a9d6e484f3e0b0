#include "specht/slam/scan_matching.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <cmath>
#include <deque>
#include <map>

#include "internal/matching.h"
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
  CSimplePointsMap submap_points;                // the keyframes' points in the map frame
  std::optional<IndexedPoints> submap;           // their tree, built when the next scan needs it
  std::optional<IndexedPoints> submap_lines;     // their cell means (submap_resolution_m), likewise
  std::deque<CSimplePointsMap> keyframe_points;  // the last submap_keyframes, base frame
  std::deque<size_t> keyframe_poses;             // their indices into keyframes_
  internal::MotionPrior motion;
  std::map<size_t, std::unique_ptr<CorrelativeMatcher>> recheck_maps;  // per keyframe k: the keyframes before it
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
  bool searched = false;
  if (!m.keyframe_points.empty() && !points.empty()) {
    const bool weak = !m.motion.predicted_from_odometry();
    searched = weak && options_.search_without_odometry;
    const internal::MatchContext context{weak, last, m.motion.odometry_step(), SubmapLines()};
    const internal::MatchResult match =
        internal::MatchWithRecovery(m.icp, Submap(), points, guess, options_, stats_, context);
    pose = match.pose;
    matched = match.source != internal::MatchSource::kGuess;
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
    searched_.resize(keyframes_.size() - 1, false);
    searched_.push_back(searched);
    ++stats_.keyframes;
    m.keyframe_points.push_back(points);
    m.keyframe_poses.push_back(keyframes_.size() - 1);
    while (static_cast<int>(m.keyframe_points.size()) > options_.submap_keyframes) {
      m.keyframe_points.pop_front();
      m.keyframe_poses.pop_front();
    }
    scans_.push_back({stamp, keyframes_.size() - 1, CPose2D()});
    if (options_.recheck_keyframes > 0) RecheckSearchedSteps();
    RebuildSubmap();
  } else {
    scans_.push_back({stamp, keyframes_.size() - 1, since});
  }
  if (placeable) last_placed_ = scans_.size() - 1;
}

// Without odometry a step is only what the search made of one scan, and along a
// corridor a stop and a step of 2 m can score alike. The keyframes
// that follow see more: turning on the spot, they look back down the corridor. So as
// each new keyframe m arrives, every searched keyframe k with 2 ≤ m − k ≤ n
// (`recheck_keyframes`) is checked again, the oldest first: keyframes k..m are taken
// as one rigid scan (their points in k's frame, as the front end placed them) and
// searched against the keyframes before k (the local submap's span),
//   T* = argmax_T score(T ⊕ points(k..m)) − drive prior(pose_{k−1} → T),
// within ±recheck_window around pose_k. When T* scores recheck_min_gain above pose_k,
// and k's own scan fits T* at most recheck_own_max_loss worse than pose_k (else the
// group is torn by a later step, whose own check will find it; a single scan after a
// turn on the spot may fit a wrong place a little better than the right one, while
// the group fits the right one clearly), keyframe k and every later one are moved
// rigidly: pose_j ← T* ⊕ (pose_k⁻¹ ⊕ pose_j). At most one move per new keyframe.
void ScanMatchingMapper::RecheckSearchedSteps() {
  const int n = options_.recheck_keyframes;
  const size_t m = keyframes_.size() - 1;
  auto& maps = impl_->recheck_maps;
  while (!maps.empty() && maps.begin()->first + n < m) maps.erase(maps.begin());
  for (size_t k = m >= static_cast<size_t>(n) ? m - n : 1; k + 2 <= m; ++k) {
    if (k == 0 || !searched_[k]) continue;
    if (RecheckStep(k)) {
      maps.clear();  // every map after k holds moved keyframes
      return;
    }
  }
}

bool ScanMatchingMapper::RecheckStep(size_t k) {
  const double res = options_.recovery_resolution_m;
  auto& before = impl_->recheck_maps[k];
  if (!before) {
    const size_t first = k > static_cast<size_t>(options_.submap_keyframes) ? k - options_.submap_keyframes : 0;
    CSimplePointsMap points;
    for (size_t j = first; j < k; ++j) {
      const CSimplePointsMap scan = ScanToPoints(*keyframes_[j].scan);
      points.insertAnotherMap(&scan, CPose3D(keyframes_[j].pose));
    }
    before = std::make_unique<CorrelativeMatcher>(Decimate(points, res / 2), res, options_.recheck_window_m);
  }
  const CPose2D pose_k = keyframes_[k].pose;
  CSimplePointsMap group;
  for (size_t j = k; j < keyframes_.size(); ++j) {
    const CSimplePointsMap scan = ScanToPoints(*keyframes_[j].scan);
    group.insertAnotherMap(&scan, CPose3D(keyframes_[j].pose - pose_k));
  }
  const CSimplePointsMap query = Decimate(group, res);
  const DrivePrior prior{keyframes_[k - 1].pose, options_.search_drive_penalty, options_.search_drive_slack_m,
                         options_.search_drive_reverse};
  const double now = before->Score(query, pose_k, prior);
  const auto best = before->Match(query, pose_k, options_.recheck_window_m, mrpt::DEG2RAD(options_.recheck_window_deg),
                                  now + options_.recheck_min_gain, prior);
  if (!best) return false;
  const CSimplePointsMap own = Decimate(ScanToPoints(*keyframes_[k].scan), res);
  if (before->Score(own, best->pose) < before->Score(own, pose_k) - options_.recheck_own_max_loss) return false;
  // Scans between k − 1 and k were matched where k − 1's step left them: they go with k.
  for (size_t i = keyframes_[k - 1].scan_index + 1; i < keyframes_[k].scan_index; ++i) {
    ScanPose& sp = scans_[i];
    sp.from_keyframe = (keyframes_[sp.keyframe].pose + sp.from_keyframe) - pose_k;
    sp.keyframe = k;
  }
  for (size_t j = k; j < keyframes_.size(); ++j) keyframes_[j].pose = best->pose + (keyframes_[j].pose - pose_k);
  ++stats_.rechecked_steps;
  moved_ = moved_ ? std::min(*moved_, k) : k;
  return true;
}

std::optional<size_t> ScanMatchingMapper::TakeMovedKeyframes() {
  auto moved = moved_;
  moved_.reset();
  return moved;
}

Trajectory ScanMatchingMapper::trajectory() const {
  Trajectory t;
  t.reserve(scans_.size());
  for (const ScanPose& s : scans_) t.push_back({s.stamp, CPose3D(keyframes_[s.keyframe].pose + s.from_keyframe)});
  return t;
}

std::optional<StampedPose> ScanMatchingMapper::LatestPose() const {
  if (scans_.empty()) return std::nullopt;
  const ScanPose& s = scans_.back();
  return StampedPose{s.stamp, CPose3D(keyframes_[s.keyframe].pose + s.from_keyframe)};
}

void ScanMatchingMapper::CorrectKeyframes(const std::vector<CPose2D>& poses) {
  for (size_t i = 0; i < poses.size() && i < keyframes_.size(); ++i) keyframes_[i].pose = poses[i];
  impl_->recheck_maps.clear();
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
  m.submap_lines.reset();
}

const IndexedPoints& ScanMatchingMapper::Submap() {
  if (!impl_->submap) impl_->submap.emplace(impl_->submap_points);
  return *impl_->submap;
}

const IndexedPoints* ScanMatchingMapper::SubmapLines() {
  if (options_.submap_resolution_m <= 0) return nullptr;
  if (!impl_->submap_lines) impl_->submap_lines.emplace(CellMeans(impl_->submap_points, options_.submap_resolution_m));
  return &*impl_->submap_lines;
}

ScanMatchingOptions GoodOdometry(ScanMatchingOptions options) {
  options.fuse_odometry = true;
  options.prior_fraction = 0.03;
  options.prior_min_m = 0.005;
  options.submap_resolution_m = 0.08;
  options.recovery_window_m = 0.5;
  options.recovery_window_deg = 10;
  return options;
}

mrpt::maps::COccupancyGridMap2D EmptyGrid(const GridOptions& options) {
  return {-10.0f, 10.0f, -10.0f, 10.0f, static_cast<float>(options.resolution_m)};
}

mrpt::maps::COccupancyGridMap2D BuildGrid(const std::vector<Keyframe>& keyframes, const GridOptions& options) {
  mrpt::maps::COccupancyGridMap2D grid = EmptyGrid(options);
  InsertIntoGrid(keyframes, 0, options, grid);
  return grid;
}

void InsertIntoGrid(const std::vector<Keyframe>& keyframes, size_t from, const GridOptions& options,
                    mrpt::maps::COccupancyGridMap2D& grid) {
  auto& ins = grid.insertionOptions;
  ins.maxDistanceInsertion = static_cast<float>(options.max_insert_range_m);
  ins.maxOccupancyUpdateCertainty = static_cast<float>(options.occupied_update);
  ins.maxFreenessUpdateCertainty = static_cast<float>(options.free_update);
  ins.considerInvalidRangesAsFreeSpace = options.invalid_ranges_are_free;
  ins.wideningBeamsWithDistance = false;
  for (size_t i = from; i < keyframes.size(); ++i) {
    const Keyframe& kf = keyframes[i];
    // Grow the grid to hold every return of this scan before inserting it.
    const CPose3D robot(kf.pose);
    const double reach = std::min<double>(kf.scan->maxRange, options.max_insert_range_m) + 1.0;
    grid.resizeGrid(static_cast<float>(std::min<double>(grid.getXMin(), robot.x() - reach)),
                    static_cast<float>(std::max<double>(grid.getXMax(), robot.x() + reach)),
                    static_cast<float>(std::min<double>(grid.getYMin(), robot.y() - reach)),
                    static_cast<float>(std::max<double>(grid.getYMax(), robot.y() + reach)), 0.5f, false);
    grid.insertObservation(*kf.scan, robot);
  }
}

}  // namespace specht::slam
