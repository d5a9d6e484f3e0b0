// specht/slam/localizer.h: localization on a saved map (no mapping).
//
// The map is the keyframes of a SLAM run: their scans at their optimised poses,
// merged into one point cloud in the map frame. Each new scan is matched against it:
//   guess_k = pose_{k-1} ⊕ odometry increment (constant velocity without odometry)
//   pose_k  = ICP(map, scan_k, guess_k), or, when ICP pairs fewer than min_goodness
//             of the points, the correlative matcher within ±recovery window (then ICP).
// The first pose comes from `initial_pose` or, when it is empty, from a global search
// of the whole map (branch and bound over every position and heading).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/trajectory.h"
#include "specht/slam/scan_matching.h"

namespace specht::slam {

// Section "localization".
struct LocalizationOptions {
  std::vector<double> initial_pose;  // [x_m, y_m, yaw_deg] in the map frame; empty = global search
  double global_resolution_m = 0.1;
  double global_min_score = 0.5;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("initial_pose", initial_pose,
            "starting pose [x_m, y_m, yaw_deg] in the map frame; [] = search the whole map");
    v.Param("global_resolution_m", global_resolution_m, "cell size of the whole-map search",
            Range::Of(0.05, 1.0).Log());
    v.Param("global_min_score", global_min_score, "accept a whole-map match from this mean likelihood",
            Range::Of(0.1, 0.99));
  }
  std::vector<std::string> Relations() const;
};

// A saved map's keyframes (poses in the map frame, scans with their mounts).
std::vector<Keyframe> KeyframesFromGraph(const std::vector<mrpt::obs::CObservation2DRangeScan::Ptr>& scans,
                                         const std::vector<mrpt::poses::CPose2D>& poses);

class Localizer {
 public:
  Localizer(const std::vector<Keyframe>& map, const LocalizationOptions& options, const ScanMatchingOptions& matching,
            const TransformTree* frames, std::string base_frame);
  ~Localizer();
  Localizer(const Localizer&) = delete;
  Localizer& operator=(const Localizer&) = delete;

  void Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation);
  const Trajectory& trajectory() const { return trajectory_; }
  const MappingStats& stats() const { return stats_; }
  // Score of the global search that set the first pose (nullopt: initial_pose given).
  std::optional<double> global_score() const { return global_score_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Trajectory trajectory_;
  MappingStats stats_;
  std::optional<double> global_score_;
};

}  // namespace specht::slam
