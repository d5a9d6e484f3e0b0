#include "specht/slam/graph_slam.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <thread>

#include "specht/slam/correlative_matcher.h"

namespace specht::slam {

using mrpt::maps::CSimplePointsMap;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

struct GraphSlam::Submap {
  size_t anchor = 0;         // keyframe whose frame the submap is in
  size_t last = 0;           // its last keyframe
  CPose2D centre_in_anchor;  // mean of its keyframe positions
  IndexedPoints points;      // in the anchor frame
  std::unique_ptr<CorrelativeMatcher> matcher;
};

namespace {

Eigen::Matrix3d Information(double sigma_m, double sigma_deg) {
  const double r = mrpt::DEG2RAD(sigma_deg);
  return Eigen::Vector3d(1 / (sigma_m * sigma_m), 1 / (sigma_m * sigma_m), 1 / (r * r)).asDiagonal();
}

// A loop's information with one direction of its position left (almost) free. The
// edge's position error is in the measurement's frame (pose_graph.h), the axis in the
// submap's, so there it is u = R(θ_z)ᵀ axis; with the isotropic Ω_t = I/σ² of
// Information(), Ω_t' = (I − (1 − ε) u uᵀ)/σ² keeps ε of it along u (σ 10⁴× larger)
// and stays positive definite.
Eigen::Matrix3d FreeAlong(Eigen::Matrix3d information, const Eigen::Vector2d& axis, double measurement_phi) {
  constexpr double kKept = 1e-8;
  const Eigen::Vector2d u = Eigen::Rotation2Dd(-measurement_phi) * axis.normalized();
  information.topLeftCorner<2, 2>() -= (1 - kKept) * information(0, 0) * u * u.transpose();
  return information;
}

double MillisSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

GraphSlam::GraphSlam(const SlamOptions& slam, const ScanMatchingOptions& matching, const LoopClosureOptions& loops,
                     const PoseGraphOptions& back_end, const TransformTree* frames, std::string base_frame)
    : slam_(slam),
      loops_(loops),
      back_end_(back_end),
      front_end_(matching, frames, std::move(base_frame)),
      icp_(matching.icp),
      second_icp_(matching.icp) {}

GraphSlam::~GraphSlam() = default;

void GraphSlam::Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation) {
  const size_t before = front_end_.keyframes().size();
  front_end_.Add(stamp, observation);
  if (const auto moved = front_end_.TakeMovedKeyframes()) OnKeyframesMoved(*moved, before);
  if (front_end_.keyframes().size() > before) OnKeyframe(front_end_.keyframes().size() - 1);
}

void GraphSlam::Continue(const std::vector<Keyframe>& saved, const PoseGraph2D& saved_graph, const CPose2D& start) {
  front_end_.Seed(saved, start);
  graph_ = saved_graph;
  seeded_ = saved.size();
  if (slam_.method != "graph" || !loops_.enabled) return;
  for (size_t k = 0; k < seeded_; ++k) {
    open_submap_.push_back(k);
    if (static_cast<int>(open_submap_.size()) >= loops_.keyframes_per_submap) FinishSubmap();
  }
  if (!open_submap_.empty()) FinishSubmap();  // the new keyframes start their own
}

void GraphSlam::OnKeyframe(size_t k) {
  const auto& kfs = front_end_.keyframes();
  graph_.nodes[static_cast<int>(k)] = kfs[k].pose;
  if (k > 0 && k != seeded_) {
    graph_.edges.push_back({static_cast<int>(k - 1), static_cast<int>(k), kfs[k].pose - kfs[k - 1].pose,
                            Information(slam_.odometry_sigma_m, slam_.odometry_sigma_deg), false});
  } else if (k > 0) {  // the first keyframe on a saved map: tied to the nearest saved one
    size_t nearest = 0;
    for (size_t i = 1; i < seeded_; ++i)
      if (kfs[i].pose.distanceTo(kfs[k].pose) < kfs[nearest].pose.distanceTo(kfs[k].pose)) nearest = i;
    graph_.edges.push_back({static_cast<int>(nearest), static_cast<int>(k), kfs[k].pose - kfs[nearest].pose,
                            Information(slam_.loop_sigma_m, slam_.loop_sigma_deg), true});
  }
  if (slam_.method != "graph" || !loops_.enabled) return;
  open_submap_.push_back(k);
  if (static_cast<int>(open_submap_.size()) >= loops_.keyframes_per_submap) {
    FinishSubmap();
    SearchOldKeyframes(*submaps_.back());
  }
  if (static_cast<int>(k) % loops_.search_every == 0) SearchLoops(k);
  if (loops_since_optimize_ >= loops_.optimize_every) OptimizeAndCorrect();
}

// The front end moved keyframes `first`.. rigidly (a recheck of a searched step):
// their nodes follow, the edge into `first` takes the new step, and a finished submap
// that holds keyframes on both sides of `first` is rebuilt. Loop edges stay: each
// measures one scan against one submap, whatever the chain between them.
void GraphSlam::OnKeyframesMoved(size_t first, size_t in_graph) {
  const auto& kfs = front_end_.keyframes();
  for (size_t j = first; j < in_graph; ++j) graph_.nodes[static_cast<int>(j)] = kfs[j].pose;
  for (auto& e : graph_.edges) {
    if (!e.robust && e.to == static_cast<int>(first) && e.from + 1 == e.to)
      e.measurement = kfs[first].pose - kfs[first - 1].pose;
  }
  for (auto& s : submaps_) {
    if (s->anchor < first && s->last >= first) {
      std::vector<size_t> members;
      for (size_t j = s->anchor; j <= s->last; ++j) members.push_back(j);
      s = BuildSubmap(members);
    }
  }
}

void GraphSlam::FinishSubmap() {
  submaps_.push_back(BuildSubmap(open_submap_));
  open_submap_.clear();
}

std::unique_ptr<GraphSlam::Submap> GraphSlam::BuildSubmap(const std::vector<size_t>& members) const {
  const auto& kfs = front_end_.keyframes();
  auto s = std::make_unique<Submap>();
  s->anchor = members.front();
  s->last = members.back();
  const CPose2D anchor = kfs[s->anchor].pose;
  double cx = 0, cy = 0;
  CSimplePointsMap points;
  for (size_t k : members) {
    const CPose2D in_anchor = kfs[k].pose - anchor;
    const CSimplePointsMap scan = WithinRange(ScanToPoints(*kfs[k].scan), loops_.submap_max_range_m);
    points.insertAnotherMap(&scan, CPose3D(in_anchor));
    cx += in_anchor.x(), cy += in_anchor.y();
  }
  s->centre_in_anchor = CPose2D(cx / members.size(), cy / members.size(), 0);
  s->points = IndexedPoints(Decimate(points, loops_.resolution_m / 2));
  s->matcher = std::make_unique<CorrelativeMatcher>(s->points.points(), loops_.resolution_m, loops_.window_m);
  return s;
}

void GraphSlam::SearchLoops(size_t k) {
  const CPose2D node = graph_.nodes.at(static_cast<int>(k));
  std::vector<std::pair<double, const Submap*>> nearest;
  for (const auto& s : submaps_) {
    if (s->last + loops_.exclude_recent_keyframes > k) continue;
    const CPose2D anchor = graph_.nodes.at(static_cast<int>(s->anchor));
    const double d = (anchor + s->centre_in_anchor).distanceTo(node);
    if (d <= loops_.search_radius_m) nearest.emplace_back(d, s.get());
  }
  std::sort(nearest.begin(), nearest.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  if (static_cast<int>(nearest.size()) > loops_.max_candidates) nearest.resize(loops_.max_candidates);
  std::vector<LoopCandidate> candidates;
  for (const auto& [d, s] : nearest) candidates.push_back({s, k});
  VerifyLoops(candidates);
}

// Cartographer's "constraints for old nodes": a submap sees a place whole only once it
// is finished, so a keyframe from long before that saw part of the place may match it
// although the submaps of its own time never matched the later keyframes (a room
// first seen through a door). Keyframes with a loop of their own are left out: their
// place is closed already, and searching them too only adds aliases
// (docs/slam-experiments.md, "Loops from old keyframes").
void GraphSlam::SearchOldKeyframes(const Submap& s) {
  if (loops_.old_keyframes_per_submap <= 0) return;
  const auto& kfs = front_end_.keyframes();
  const CPose2D centre = graph_.nodes.at(static_cast<int>(s.anchor)) + s.centre_in_anchor;
  std::vector<std::pair<double, size_t>> nearest;
  for (size_t j = 0; j + loops_.exclude_recent_keyframes <= s.anchor && j < kfs.size(); ++j) {
    if (j < closed_.size() && closed_[j]) continue;
    const double d = graph_.nodes.at(static_cast<int>(j)).distanceTo(centre);
    if (d <= loops_.search_radius_m) nearest.emplace_back(d, j);
  }
  std::sort(nearest.begin(), nearest.end());
  if (static_cast<int>(nearest.size()) > loops_.old_keyframes_per_submap)
    nearest.resize(loops_.old_keyframes_per_submap);
  std::vector<LoopCandidate> candidates;
  for (const auto& [d, j] : nearest) candidates.push_back({&s, j});
  VerifyLoops(candidates);
}

void GraphSlam::VerifyLoops(const std::vector<LoopCandidate>& candidates) {
  if (candidates.empty()) return;
  const auto t0 = std::chrono::steady_clock::now();
  const auto& kfs = front_end_.keyframes();
  // Each keyframe's scan and its decimated query, once however many submaps it meets.
  std::map<size_t, std::pair<CSimplePointsMap, CSimplePointsMap>> scans;
  for (const LoopCandidate& c : candidates) {
    if (scans.count(c.keyframe)) continue;
    CSimplePointsMap scan = ScanToPoints(*kfs[c.keyframe].scan);
    CSimplePointsMap query = Decimate(WithinRange(scan, loops_.submap_max_range_m), loops_.resolution_m);
    scans.emplace(c.keyframe, std::make_pair(std::move(scan), std::move(query)));
  }
  // A candidate's search and its ICP verification read only its own submap and the
  // scan: every other candidate runs on a second thread (with its own ICP). The edges
  // are added here in candidate order, so they do not depend on the threads.
  struct Verified {
    bool found = false;                        // the search scored min_score or more
    std::optional<CPose2D> accepted;           // ICP confirmed it: the loop's measurement
    std::optional<Eigen::Vector2d> free_axis;  // the direction it does not pin (submap frame)
  };
  std::vector<Verified> verified(candidates.size());
  auto verify = [&](size_t first, IcpAligner& icp) {
    for (size_t i = first; i < candidates.size(); i += 2) {
      const Submap& s = *candidates[i].submap;
      const auto& [scan, query] = scans.at(candidates[i].keyframe);
      const CPose2D guess =
          graph_.nodes.at(static_cast<int>(candidates[i].keyframe)) - graph_.nodes.at(static_cast<int>(s.anchor));
      const auto match =
          s.matcher->Match(query, guess, loops_.window_m, mrpt::DEG2RAD(loops_.window_deg), loops_.min_score);
      if (!match) continue;
      verified[i].found = true;
      const IcpResult refined = icp.Align(s.points, scan, match->pose);
      if (refined.goodness < loops_.min_icp_goodness || (refined.pose - match->pose).norm() > 2 * loops_.resolution_m)
        continue;
      // A match that slides along one direction (a corridor's walls) is as good
      // anywhere along it: there the loop says nothing, only across it.
      if (loops_.weak_axis_points > 0) {
        const WeakestAxis weakest = WeakestAxisOf(scan, refined);
        if (weakest.points < loops_.weak_axis_points) verified[i].free_axis = weakest.axis;
      }
      verified[i].accepted = refined.pose;
    }
  };
  std::optional<std::thread> second;
  if (candidates.size() > 1) second.emplace(verify, 1, std::ref(second_icp_));
  verify(0, icp_);
  if (second) second->join();
  for (size_t i = 0; i < candidates.size(); ++i) {
    ++stats_.loop_searches;
    stats_.loops_found += verified[i].found;
    if (!verified[i].accepted) continue;
    Eigen::Matrix3d information = Information(slam_.loop_sigma_m, slam_.loop_sigma_deg);
    if (verified[i].free_axis) {
      information = FreeAlong(information, *verified[i].free_axis, verified[i].accepted->phi());
      ++stats_.loops_free_along_axis;
    }
    graph_.edges.push_back({static_cast<int>(candidates[i].submap->anchor), static_cast<int>(candidates[i].keyframe),
                            *verified[i].accepted, information, true});
    ++stats_.loops_accepted;
    if (closed_.size() <= candidates[i].keyframe) closed_.resize(candidates[i].keyframe + 1, false);
    closed_[candidates[i].keyframe] = true;
    ++loops_since_optimize_;
  }
  stats_.loop_search_ms += MillisSince(t0);
}

void GraphSlam::OptimizeAndCorrect() {
  const auto t0 = std::chrono::steady_clock::now();
  const OptimizeSummary summary = Optimize(graph_, back_end_);
  stats_.final_chi2 = summary.final_chi2;
  std::vector<CPose2D> poses;
  poses.reserve(graph_.nodes.size());
  for (const auto& [id, pose] : graph_.nodes) poses.push_back(pose);
  front_end_.CorrectKeyframes(poses);
  ++stats_.optimizations;
  loops_since_optimize_ = 0;
  stats_.optimize_ms += MillisSince(t0);
}

void GraphSlam::Finish() {
  // The last submap is finished too when it holds half a submap or more, so the
  // place the run ends in is searched by the keyframes that saw it before.
  if (slam_.method == "graph" && loops_.enabled && loops_.old_keyframes_per_submap > 0 &&
      2 * open_submap_.size() >= static_cast<size_t>(loops_.keyframes_per_submap)) {
    FinishSubmap();
    SearchOldKeyframes(*submaps_.back());
  }
  if (stats_.loops_accepted > 0) OptimizeAndCorrect();
}

}  // namespace specht::slam
