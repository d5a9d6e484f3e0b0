#include "specht/slam/localizer.h"

#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>

#include "internal/matching.h"
#include "specht/slam/correlative_matcher.h"

namespace specht::slam {

using mrpt::maps::CSimplePointsMap;
using mrpt::poses::CPose2D;

std::vector<std::string> LocalizationOptions::Relations() const {
  if (!initial_pose.empty() && initial_pose.size() != 3) return {"initial_pose needs [x_m, y_m, yaw_deg] or []"};
  return {};
}

std::vector<Keyframe> KeyframesFromGraph(const std::vector<mrpt::obs::CObservation2DRangeScan::Ptr>& scans,
                                         const std::vector<CPose2D>& poses) {
  std::vector<Keyframe> keyframes;
  for (size_t i = 0; i < scans.size() && i < poses.size(); ++i) {
    keyframes.push_back({i, FromMrpt(scans[i]->timestamp), poses[i], scans[i]});
  }
  return keyframes;
}

struct Localizer::Impl {
  Impl(const LocalizationOptions& l, const ScanMatchingOptions& m, const TransformTree* f, std::string b)
      : options(l), matching(m), frames(f), base_frame(std::move(b)), icp(m.icp) {}
  LocalizationOptions options;
  ScanMatchingOptions matching;
  const TransformTree* frames;
  std::string base_frame;
  IcpAligner icp;
  IndexedPoints map;                   // every keyframe's points, map frame
  std::optional<IndexedPoints> lines;  // their cell means (scan_matching.submap_resolution_m)
  internal::MotionPrior motion;
};

Localizer::Localizer(const std::vector<Keyframe>& map, const LocalizationOptions& options,
                     const ScanMatchingOptions& matching, const TransformTree* frames, std::string base_frame)
    : impl_(std::make_unique<Impl>(options, matching, frames, std::move(base_frame))) {
  CSimplePointsMap all;
  for (const Keyframe& kf : map) {
    const CSimplePointsMap points = ScanToPoints(*kf.scan);
    all.insertAnotherMap(&points, mrpt::poses::CPose3D(kf.pose));
  }
  impl_->map = IndexedPoints(Decimate(all, 0.02));
  if (matching.submap_resolution_m > 0) impl_->lines.emplace(CellMeans(all, matching.submap_resolution_m));
}

Localizer::~Localizer() = default;

void Localizer::Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation) {
  Impl& m = *impl_;
  if (m.motion.Consume(stamp, observation, stats_)) return;
  auto raw = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(observation);
  if (!raw) {
    ++stats_.ignored;
    return;
  }
  const auto scan = internal::PrepareScan(*raw, m.matching, m.frames, m.base_frame);
  const CSimplePointsMap points = ScanToPoints(*scan);
  const CPose2D last = trajectory_.empty() ? CPose2D() : CPose2D(trajectory_.back().pose);
  const CPose2D predicted = m.motion.Predict(last, m.matching.use_odometry, m.matching.use_imu);
  CPose2D guess = predicted;
  if (trajectory_.empty()) {
    const auto& p = m.options.initial_pose;
    if (p.size() == 3) {
      guess = CPose2D(p[0], p[1], mrpt::DEG2RAD(p[2]));
    } else {
      // Whole-map search: every position of the map, every heading.
      const auto& xs = m.map.points().getPointsBufferRef_x();
      const auto& ys = m.map.points().getPointsBufferRef_y();
      const auto [x0, x1] = std::minmax_element(xs.begin(), xs.end());
      const auto [y0, y1] = std::minmax_element(ys.begin(), ys.end());
      const double cx = (*x0 + *x1) / 2, cy = (*y0 + *y1) / 2;
      const double half = std::max(*x1 - *x0, *y1 - *y0) / 2 + 1.0;
      const CorrelativeMatcher global(Decimate(m.map.points(), m.options.global_resolution_m / 2),
                                      m.options.global_resolution_m, half);
      const auto found = global.Match(Decimate(points, m.options.global_resolution_m), CPose2D(cx, cy, 0), half, M_PI,
                                      m.options.global_min_score);
      if (found) {
        guess = found->pose;
        global_score_ = found->score;
      }
    }
  }
  internal::MatchContext context;
  context.lines = m.lines ? &*m.lines : nullptr;
  context.odometry_step = m.motion.odometry_step();
  const CPose2D pose = internal::MatchWithRecovery(m.icp, m.map, points, guess, m.matching, stats_, context).pose;
  if (!trajectory_.empty()) m.motion.SetLastStep(pose - last);
  ++stats_.scans;
  trajectory_.push_back({stamp, mrpt::poses::CPose3D(pose)});
}

}  // namespace specht::slam
