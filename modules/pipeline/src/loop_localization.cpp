#include "internal/loop_localization.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>

#include "specht/core/error.h"

namespace specht::pipeline::internal {
namespace {

using mrpt::poses::CPose2D;

CPose2D ToMrpt(const sim::Pose2& p) { return CPose2D(p.x, p.y, p.yaw_rad); }
sim::Pose2 FromMrpt(const CPose2D& p) { return {p.x(), p.y(), p.phi()}; }
CPose2D Inverse(CPose2D p) {
  p.inverse();
  return p;
}

// The survey: 360° scans of the static world from every free point of a grid.
std::vector<slam::Keyframe> Survey(const sim::Scenario& scenario, double spacing_m) {
  const sim::World world(scenario);
  const auto grid = world.TrueGrid(0.1);
  constexpr int kBeams = 720;
  constexpr double kRange = 30;
  std::vector<slam::Keyframe> keyframes;
  for (double y = grid.getYMin() + spacing_m / 2; y < grid.getYMax(); y += spacing_m)
    for (double x = grid.getXMin() + spacing_m / 2; x < grid.getXMax(); x += spacing_m) {
      if (world.Blocked({x, y})) continue;
      auto scan = mrpt::obs::CObservation2DRangeScan::Create();
      scan->aperture = static_cast<float>(2 * M_PI * (kBeams - 1) / kBeams);
      scan->rightToLeft = true;
      scan->maxRange = kRange;
      scan->resizeScan(kBeams);
      for (int i = 0; i < kBeams; ++i) {
        const double a = -scan->aperture / 2 + scan->aperture * i / (kBeams - 1);
        const double r = world.RayCast({x, y}, a, kRange, {});
        scan->setScanRange(i, static_cast<float>(std::isfinite(r) ? r : kRange));
        scan->setScanRangeValidity(i, std::isfinite(r));
      }
      keyframes.push_back({keyframes.size(), Stamp{}, mrpt::poses::CPose2D(x, y, 0), scan});
    }
  return keyframes;
}

// The cells under the car's box at `centre` marked free: where the car stood holds
// no obstacle, though its own LiDAR, mounted on it, never sees the ground it covers
// (the start pose's cells would stay unknown, and a plan from there fail).
void ClearFootprint(const CPose2D& centre, double length_m, double width_m, mrpt::maps::COccupancyGridMap2D& grid) {
  const double reach = std::hypot(length_m, width_m) / 2;
  const int x0 = std::max(0, grid.x2idx(centre.x() - reach)),
            x1 = std::min<int>(grid.getSizeX() - 1, grid.x2idx(centre.x() + reach));
  const int y0 = std::max(0, grid.y2idx(centre.y() - reach)),
            y1 = std::min<int>(grid.getSizeY() - 1, grid.y2idx(centre.y() + reach));
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx) {
      const CPose2D cell(grid.idx2x(cx), grid.idx2y(cy), 0);
      const CPose2D local = cell - centre;  // the cell's centre in the car's frame
      if (std::abs(local.x()) <= length_m / 2 && std::abs(local.y()) <= width_m / 2) grid.setCell(cx, cy, 1.0f);
    }
}

}  // namespace

LoopLocalization::LoopLocalization(const std::string& mode, const sim::Scenario& scenario, const LoopSlamConfig& c,
                                   Kidnap kidnap)
    : mode_(mode),
      start_(ToMrpt(scenario.ego.start)),
      kidnap_(kidnap),
      car_length_m_(scenario.ego.model.length_m),
      car_width_m_(scenario.ego.model.width_m) {
  if (mode == "slam") {
    slam_ = std::make_unique<slam::GraphSlam>(c.slam, c.matching, c.loops, c.graph, nullptr, "base_link");
  } else if (mode == "map") {
    slam::LocalizationOptions options;
    options.initial_pose = {start_.x(), start_.y(), start_.phi() * 180 / M_PI};
    localizer_ =
        std::make_unique<slam::Localizer>(c.site_map ? c.site_map->keyframes : Survey(scenario, c.survey_spacing_m),
                                          options, c.matching, nullptr, "base_link");
    at_scan_ = start_;  // until the first scan is placed
    start_ = {};        // its poses are in the map frame already
  } else if (mode != "truth")
    throw InputError("closed_loop.localization: unknown mode '" + mode + "'");
}
LoopLocalization::~LoopLocalization() = default;

void LoopLocalization::Observe(Stamp t, const mrpt::obs::CObservation::Ptr& o) {
  if (!UsesObservations()) return;
  if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
    odometry_ = odo->odometry;
    if (t == scan_stamp_) odometry_at_scan_ = odometry_;  // the odometry of the scan's own instant
  }
  if (slam_) slam_->Add(t, o);
  if (localizer_) localizer_->Add(t, o);
  const long scans = slam_ ? slam_->front_end_stats().scans : static_cast<long>(localizer_->trajectory().size());
  if (scans > scans_) {
    scans_ = scans;
    const mrpt::poses::CPose3D p = slam_ ? slam_->LatestPose()->pose : localizer_->trajectory().back().pose;
    at_scan_ = mrpt::poses::CPose2D(p.x(), p.y(), p.yaw());
    odometry_at_scan_ = odometry_, scan_stamp_ = t;
  }
}

std::shared_ptr<const MapArtefact> LoopLocalization::DrawnMap(const std::string& site, const slam::GridOptions& grid) {
  if (!slam_ || slam_->keyframes().empty()) return nullptr;
  slam_->Finish();
  auto map = std::make_shared<MapArtefact>();
  map->site = site;
  map->graph = slam_->graph();
  for (auto& [id, pose] : map->graph.nodes) pose = start_ + pose;  // SLAM's frame → the scenario's
  map->keyframes = slam_->keyframes();
  for (size_t i = 0; i < map->keyframes.size(); ++i) {  // node i is keyframe i, as ReadMapArtefact reads them
    const auto node = map->graph.nodes.find(static_cast<int>(i));
    map->keyframes[i].pose = node != map->graph.nodes.end() ? node->second : start_ + map->keyframes[i].pose;
  }
  map->grid = slam::BuildGrid(map->keyframes, grid);
  for (const auto& kf : map->keyframes) ClearFootprint(kf.pose, car_length_m_, car_width_m_, map->grid);
  return map;
}

CPose2D LoopLocalization::Estimate() const {
  if (!UsesObservations()) return ToMrpt(oracle_);
  return start_ + at_scan_ + (odometry_ - odometry_at_scan_);
}

CPose2D LoopLocalization::EstimateAtScan() const {
  if (!UsesObservations()) return ToMrpt(oracle_);
  return start_ + at_scan_;
}

void LoopLocalization::Tick(double t_s) {
  if (kidnapped_ || kidnap_.at_s < 0 || t_s < kidnap_.at_s) return;
  kidnapped_ = true;
  // correction' ⊕ estimate = believed ⊕ offset
  const CPose2D believed = correction_ + Estimate();
  correction_ = believed + CPose2D(kidnap_.ahead_m, 0, kidnap_.yaw_deg * M_PI / 180) + Inverse(Estimate());
}

void LoopLocalization::Relocalize(const sim::Pose2& found) {
  correction_ = ToMrpt(found) + Inverse(EstimateAtScan());  // correction' ⊕ estimate at the scan = found
  ++relocalizations_;
}

sim::Pose2 LoopLocalization::Believed() const { return FromMrpt(correction_ + Estimate()); }

sim::Pose2 LoopLocalization::AtLatestScan() const { return FromMrpt(correction_ + EstimateAtScan()); }

nlohmann::json LoopLocalization::ToJson() const {
  nlohmann::json j = {{"mode", mode_}, {"relocalizations", relocalizations_}};
  if (localizer_) j["scans"] = scans_;
  if (slam_) {
    j["scans"] = scans_;
    j["loops_accepted"] = slam_->stats().loops_accepted;
  }
  return j;
}

}  // namespace specht::pipeline::internal
