// Where the car believes it is in the closed loop (its box centre in the map frame):
//   truth  the simulator's pose (the oracle, for side-by-side runs)
//   slam   graph SLAM (slam/graph_slam.h) on the simulated LiDAR, odometry and IMU,
//          mapping from scratch; its frame starts at the first scan, which is taken
//          at the scenario's start pose (the car is told where it starts on the
//          site's map). Between scans: the latest scan's pose carried forward by the
//          odometry since that scan.
//   map    localisation on a prior map of the site (slam/localizer.h: ICP against
//          the map's points, seeded by odometry, starting at the scenario's start
//          pose): the map an earlier mapping drive left (LoopSlamConfig::site_map),
//          or else a survey of the static world — 360° scans taken every
//          survey_spacing_m over its free space — as a mapping drive would leave.
// Whatever the mode, the believed pose is correction ⊕ the estimate: the correction
// (map ← the estimator's frame, identity at the start) is what a relocalisation on the
// prior map sets (Relocalize), and what a kidnap corrupts: at kidnap_at_s (≥ 0) the
// believed pose jumps by (kidnap_m ahead, kidnap_deg) and moves on from there with the
// estimate, as after a wrong relocalisation.
// The truth mode reads the oracle's pose (Oracle); the others never see the truth:
// what the believed pose is scored against is the referee's (closed_loop.cpp).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/pipeline/closed_loop.h"
#include "specht/sim/simulator.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/localizer.h"

namespace specht::pipeline::internal {

struct Kidnap {
  double at_s = -1, ahead_m = 0, yaw_deg = 0;
};

class LoopLocalization {
 public:
  LoopLocalization(const std::string& mode, const sim::Scenario& scenario, const LoopSlamConfig& config, Kidnap kidnap);
  ~LoopLocalization();
  // Whether Observe uses what it is given (not in the truth mode).
  bool UsesObservations() const { return slam_ || localizer_; }
  // Every observation the simulator makes, in order.
  void Observe(Stamp t, const mrpt::obs::CObservation::Ptr& observation);
  // The truth mode: the simulator's pose of the box centre now (the oracle).
  void Oracle(const sim::Pose2& truth) { oracle_ = truth; }
  // Once per control step (at `t_s` of the drive), before the pose is read: applies
  // the kidnap when it is due.
  void Tick(double t_s);
  // The scan of the latest pose (AtLatestScan) lies at `found` on the prior map: from
  // now on the believed pose follows the estimate from there.
  void Relocalize(const sim::Pose2& found);
  // The believed pose now.
  sim::Pose2 Believed() const;
  // The believed pose at the latest scan (where the LiDAR map inserts it).
  sim::Pose2 AtLatestScan() const;
  nlohmann::json ToJson() const;  // mode, scans, loops, relocalisations
  // slam: the map drawn so far, the graph finished (Finish), moved into the scenario's
  // frame, the car's footprint at every keyframe free; none in the other modes. Call
  // once, at the end of the drive.
  std::shared_ptr<const MapArtefact> DrawnMap(const std::string& site, const slam::GridOptions& grid);

 private:
  // The estimate, before the correction: now, and at the latest scan.
  mrpt::poses::CPose2D Estimate() const;
  mrpt::poses::CPose2D EstimateAtScan() const;
  std::string mode_;
  mrpt::poses::CPose2D start_;
  Kidnap kidnap_;
  double car_length_m_, car_width_m_;  // the footprint a drawn map clears
  bool kidnapped_ = false;
  mrpt::poses::CPose2D correction_;  // map ← the estimator's frame
  int relocalizations_ = 0;
  std::unique_ptr<slam::GraphSlam> slam_;
  std::unique_ptr<slam::Localizer> localizer_;
  long scans_ = 0;
  mrpt::poses::CPose2D at_scan_;                      // the pose of the latest scan (SLAM's frame or the map's)
  mrpt::poses::CPose2D odometry_, odometry_at_scan_;  // the odometry pose, now and at that scan
  Stamp scan_stamp_;
  sim::Pose2 oracle_{};
};

}  // namespace specht::pipeline::internal
