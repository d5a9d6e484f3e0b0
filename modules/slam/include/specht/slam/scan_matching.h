// specht/slam/scan_matching.h: scan-matching odometry and occupancy-grid mapping
// from 2D laser scans and wheel odometry (the first mapping stage of `specht replay`;
// the graph-SLAM back end builds on its keyframes).
//
// For every scan:
//   guess_k   = pose_{k-1} ⊕ (odom_{k-1} ⊖ odom_k)^-1     (wheel odometry increment,
//                                                       its rotation from the gyro's
//                                                       yaw rate when an IMU reports)
//             = pose_{k-1} ⊕ (pose_{k-2} ⊖ pose_{k-1})^-1 (constant velocity, when the
//                                                       odometry reports no motion and
//                                                       has not moved on half the scans:
//                                                       absent, not a stop)
//   pose_k    = ICP(local submap, scan_k, guess_k)          (MRPT CICP, point-to-point,
//                                                       then point-to-line held to the
//                                                       odometry step's prior when
//                                                       `fuse_odometry`; icp.h)
// A constant-velocity guess may be off by a whole step: when `search_without_odometry`
// is on, the correlative matcher (below) searches around it first and ICP refines.
// The local submap holds the points of the last `submap_keyframes` keyframes in the
// map frame. The point-to-line refinement (icp.h) fits its lines to the submap's
// cell means at `submap_resolution_m` when that is set: stacked from many scans a wall
// is dense along it far beyond its noise across it, and the k points nearest a scan
// point then lie across the wall, fitting a "line" normal to it that ties the pose
// along the wall to the noise. A match is rejected (pose_k = guess_k) when fewer than `min_goodness`
// of the scan's points found a partner or when the correction exceeds
// `max_correction_m` / `max_correction_deg`. A scan becomes a keyframe when the car
// moved `keyframe_translation_m` or turned `keyframe_rotation_deg` since the last one;
// keyframes are what the grid is built from.
//
// Recovery: when ICP is rejected and `recovery_window_m` > 0, the scan is matched by
// the correlative matcher (branch and bound, correlative_matcher.h) against the local
// submap within ±recovery_window_m and ±recovery_window_deg of the guess, then refined
// by ICP. This carries logs with poor or no odometry. A scan of fewer than
// `recovery_min_points` points is not searched: a few returns (the car beside a truck
// that hides the walls) fit many poses in the window as well as the true one. Without odometry, an unmatched
// scan (pose_k = guess_k) neither becomes a keyframe, nor sets the velocity, nor is
// the next scan predicted from it (the last matched pose is): an unverified pose
// would blur the submap and be carried on to the next guess. And without odometry a
// constant-velocity guess may be wrong because the car stopped or turned on the spot:
// the last placed pose is searched around too, and the better score wins. These
// searches without odometry score with a drive prior (correlative_matcher.h): a wheeled
// car moves along its heading, so a pose that would have it slide sideways or back up
// (search_drive_*) loses score, which tells a corridor's step from its aliases.
// The search's score decides: ICP refines the searched pose to below a grid cell, but
// a refinement that scores less than (1 − refine_max_loss) of the searched pose on
// the same grid has slid into another minimum (turns on the spot of tens of degrees a
// scan end a few degrees off), and the searched pose is kept instead; so it is when ICP pairs too few
// points or leaves its bounds (after a rejected ICP match with odometry, only when
// the searched pose lies within the bounds of the odometry's guess).
// Recheck: a searched step is decided on one scan, and along a corridor a stop and a
// step of metres can score alike. As each of the next `recheck_keyframes` keyframes
// arrives, the searched keyframe and those after it are searched again as one rigid
// scan against the keyframes before it; when that fits recheck_min_gain better, they
// all move (see RecheckSearchedSteps in scan_matching.cpp). Graph SLAM's nodes follow
// (TakeMovedKeyframes).
//
// Every scan's pose is kept relative to the keyframe before it, so correcting the
// keyframes (graph SLAM) corrects every scan.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/trajectory.h"
#include "specht/core/transform_tree.h"
#include "specht/slam/icp.h"

namespace specht::slam {

// Section "scan_matching".
struct ScanMatchingOptions {
  bool use_odometry = true;
  bool use_imu = true;
  double min_range_m = 0.1;
  double max_range_m = 30.0;
  double keyframe_translation_m = 0.3;
  double keyframe_rotation_deg = 10.0;
  int submap_keyframes = 60;
  double submap_resolution_m = 0.0;
  double min_goodness = 0.6;
  int degenerate_axis_points = 0;
  double max_correction_m = 1.0;
  double max_correction_deg = 20.0;
  double recovery_window_m = 2.0;
  double recovery_window_deg = 75.0;
  double recovery_resolution_m = 0.1;
  double recovery_min_score = 0.5;
  int recovery_min_points = 100;
  double refine_max_loss = 0.1;
  bool search_without_odometry = true;
  double search_min_score = 0.3;
  double search_drive_penalty = 0.1;
  double search_drive_slack_m = 0.2;
  bool search_drive_reverse = false;
  int recheck_keyframes = 10;
  double recheck_window_m = 3.0;
  double recheck_window_deg = 1.0;
  double recheck_min_gain = 0.05;
  double recheck_own_max_loss = 0.05;
  bool fuse_odometry = false;
  double point_sigma_m = 0.03;
  double prior_fraction = 0.1;
  double prior_min_m = 0.02;
  double prior_min_deg = 1.0;
  IcpOptions icp;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("use_odometry", use_odometry, "seed each match with the wheel-odometry increment");
    v.Param("use_imu", use_imu, "take the rotation between scans from the gyro's yaw rate when an IMU reports");
    v.Param("min_range_m", min_range_m, "ignore returns closer than this", Range::Of(0.0, 2.0));
    v.Param("max_range_m", max_range_m, "ignore returns farther than this", Range::Of(1.0, 200.0));
    v.Param("keyframe_translation_m", keyframe_translation_m, "new keyframe after this much travel",
            Range::Of(0.02, 3.0).Log());
    v.Param("keyframe_rotation_deg", keyframe_rotation_deg, "new keyframe after this much turning",
            Range::Of(1.0, 90.0).Log());
    v.Param("submap_keyframes", submap_keyframes, "keyframes in the local submap scans are matched against",
            Range::Of(1, 500));
    v.Param("submap_resolution_m", submap_resolution_m,
            "the point-to-line refinement fits its lines to the mean of the submap's (or localisation map's) "
            "points in each cell of this size; 0 = to every point",
            Range::Of(0.0, 0.5));
    v.Param("min_goodness", min_goodness, "reject a match when fewer than this fraction of points paired",
            Range::Of(0.0, 1.0));
    v.Param("degenerate_axis_points", degenerate_axis_points,
            "along a direction fewer than this many scan points pin in an ICP match (icp.h: a straight corridor's "
            "walls), the guess's position stands (0: off; unused with fuse_odometry, whose prior decides)",
            Range::Of(0, 1000));
    v.Param("max_correction_m", max_correction_m, "reject a match that moves the guess further than this",
            Range::Of(0.05, 10.0));
    v.Param("max_correction_deg", max_correction_deg, "reject a match that turns the guess more than this",
            Range::Of(1.0, 180.0));
    v.Param("recovery_window_m", recovery_window_m,
            "after a rejected match, search this far around the guess (correlative matcher); 0 = off",
            Range::Of(0.0, 5.0));
    v.Param("recovery_window_deg", recovery_window_deg, "angular half-width of the recovery search",
            Range::Of(1.0, 180.0));
    v.Param("recovery_resolution_m", recovery_resolution_m, "cell size of the recovery search grid",
            Range::Of(0.02, 0.5).Log());
    v.Param("recovery_min_score", recovery_min_score, "accept a recovery match from this mean likelihood",
            Range::Of(0.1, 0.95));
    v.Param("recovery_min_points", recovery_min_points,
            "search only scans with at least this many points (fewer score high at aliases too)", Range::Of(0, 2000));
    v.Param("refine_max_loss", refine_max_loss,
            "searches: keep the searched pose when ICP's refinement of it scores less than (1 − this) of its "
            "score on the search grid; 1 = always take ICP's",
            Range::Of(0.0, 1.0));
    v.Param("search_without_odometry", search_without_odometry,
            "when the odometry reports no motion, search around the constant-velocity guess and where the car "
            "was (correlative matcher) before ICP");
    v.Param("search_min_score", search_min_score,
            "accept a search without odometry from this score (mean likelihood less the drive prior's penalty; "
            "the guess it replaces is only the last step repeated)",
            Range::Of(0.1, 0.95));
    v.Param("search_drive_penalty", search_drive_penalty,
            "searches without odometry: score lost per metre the car would have moved sideways (or backwards, "
            "unless search_drive_reverse) beyond the slack; 0 = off",
            Range::Of(0.0, 1.0));
    v.Param("search_drive_slack_m", search_drive_slack_m,
            "searches without odometry: sideways or backward motion between scans that costs nothing",
            Range::Of(0.0, 2.0));
    v.Param("search_drive_reverse", search_drive_reverse,
            "searches without odometry: the car may back up between scans at no cost");
    v.Param("recheck_keyframes", recheck_keyframes,
            "without odometry: a searched keyframe's step is searched again as each of the next n keyframes "
            "arrives, with all of them as one rigid scan against the keyframes before it; 0 = off",
            Range::Of(0, 100));
    v.Param("recheck_window_m", recheck_window_m, "linear half-width of that search", Range::Of(0.1, 10.0));
    v.Param("recheck_window_deg", recheck_window_deg,
            "angular half-width of that search (small: it is for steps along a corridor, whose walls fix the heading)",
            Range::Of(0.0, 45.0));
    v.Param("recheck_min_gain", recheck_min_gain,
            "move the keyframes when the best pose scores this much above where they are", Range::Of(0.0, 1.0));
    v.Param("recheck_own_max_loss", recheck_own_max_loss,
            "a recheck does not move the keyframes when the checked keyframe's own scan would score more than "
            "this below where it is (the group is torn by a later step, whose own check will find it)",
            Range::Of(0.0, 1.0));
    v.Param("fuse_odometry", fuse_odometry,
            "hold each ICP match to the odometry step by its information, inside the point-to-line refinement "
            "(corridors: odometry decides the direction the scan cannot; GoodOdometry)");
    v.Param("point_sigma_m", point_sigma_m, "std. dev. of a scan point against its surface (match information)",
            Range::Of(0.005, 0.5).Log());
    v.Param("prior_fraction", prior_fraction, "odometry std. dev. as a fraction of the step",
            Range::Of(0.001, 1.0).Log());
    v.Param("prior_min_m", prior_min_m, "odometry std. dev. floor, translation", Range::Of(0.001, 1.0).Log());
    v.Param("prior_min_deg", prior_min_deg, "odometry std. dev. floor, rotation", Range::Of(0.01, 20.0).Log());
    v.Group("icp", icp);
  }
  std::vector<std::string> Relations() const;
};

// The settings for a car whose wheel odometry is good to a few percent of a step (the
// simulator's, a typical small car's): the odometry step is a prior inside ICP
// (`fuse_odometry`) at 3 % of the step with a 5 mm floor, and the lines are fitted to
// the submap's 8 cm cell means. On a straight street the stacked submap otherwise
// lets the pose slide with the noise along the walls. A rejected match is searched
// again only within ±0.5 m and ±10° of the odometry's guess (the recovery window):
// good odometry is not wrong by more between two scans, while a wide search lets a
// few returns (a car waiting beside a passing truck) turn the pose by 90°. Not the defaults: on logs whose
// odometry drifts tens of metres so tight a prior breaks loops, and on thinned logs the
// cell means are coarser than the submap itself (docs/slam-experiments.md,
// 2026-12-03). params/good-odometry.yaml holds the same values (a test checks).
ScanMatchingOptions GoodOdometry(ScanMatchingOptions options);

// Section "grid": the occupancy grid built from keyframes (MRPT COccupancyGridMap2D).
struct GridOptions {
  double resolution_m = 0.05;
  double max_insert_range_m = 25.0;
  double occupied_update = 0.65;  // per-hit occupancy probability (maxOccupancyUpdateCertainty)
  double free_update = 0.0;       // per-pass freeness probability (maxFreenessUpdateCertainty; 0 = same)
  bool invalid_ranges_are_free = false;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("resolution_m", resolution_m, "cell size", Range::Of(0.01, 1.0).Log());
    v.Param("max_insert_range_m", max_insert_range_m, "returns beyond this do not update the grid",
            Range::Of(1.0, 200.0));
    v.Param("occupied_update", occupied_update, "occupancy probability a hit adds to its cell", Range::Of(0.51, 0.99));
    v.Param("free_update", free_update, "freeness probability a pass adds to a cell (0 = as occupied_update)",
            Range::Of(0.0, 0.99));
    v.Param("invalid_ranges_are_free", invalid_ranges_are_free,
            "treat max-range / invalid beams as free space along the beam");
  }
  std::vector<std::string> Relations() const;
};

struct Keyframe {
  size_t scan_index = 0;  // index into the trajectory
  Stamp stamp;
  mrpt::poses::CPose2D pose;                     // base_link in the map frame
  mrpt::obs::CObservation2DRangeScan::Ptr scan;  // with its sensor pose on base_link
};

struct MappingStats {
  long scans = 0;
  long odometry = 0;
  long imu = 0;
  long ignored = 0;  // observations of other kinds
  long keyframes = 0;
  long rejected_matches = 0;    // ICP matches rejected (and not recovered)
  long recovered_matches = 0;   // rejected by ICP, recovered by the correlative matcher
  long rechecked_steps = 0;     // searched steps moved by a recheck with the keyframes after them
  long degenerate_matches = 0;  // ICP matches whose weakest direction the guess decided
  long icp_iterations = 0;
};

class ScanMatchingMapper {
 public:
  // `frames` (may be null) supplies sensor mounts that override those in the data.
  ScanMatchingMapper(const ScanMatchingOptions& options, const TransformTree* frames, std::string base_frame);
  ~ScanMatchingMapper();
  ScanMatchingMapper(const ScanMatchingMapper&) = delete;
  ScanMatchingMapper& operator=(const ScanMatchingMapper&) = delete;

  // Odometry (CObservationOdometry) and 2D scans are used; other kinds are counted.
  void Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation);

  // One pose per scan: its keyframe's pose composed with the scan's offset from it.
  Trajectory trajectory() const;
  // The latest scan's pose (what trajectory().back() would be, without the copy).
  std::optional<StampedPose> LatestPose() const;
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  // The first keyframe a recheck moved (with every later one) since the last call, if any.
  std::optional<size_t> TakeMovedKeyframes();
  const MappingStats& stats() const { return stats_; }

  // Replaces the keyframe poses (e.g. after pose-graph optimisation); later scans are
  // matched against the corrected local submap.
  void CorrectKeyframes(const std::vector<mrpt::poses::CPose2D>& poses);

  // Continuing a saved map: its keyframes come first (indices 0..n−1), the next
  // scan is placed at `start` (in the saved map's frame, e.g. from localization)
  // and the local submap starts afresh from it. Call before the first Add.
  void Seed(std::vector<Keyframe> saved, const mrpt::poses::CPose2D& start);

 private:
  struct ScanPose {
    Stamp stamp;
    size_t keyframe = 0;                 // the keyframe at or before this scan
    mrpt::poses::CPose2D from_keyframe;  // this scan's pose seen from that keyframe
  };
  void AddScan(Stamp stamp, const mrpt::obs::CObservation2DRangeScan& scan);
  mrpt::poses::CPose2D LastPlacedPose() const;
  void RebuildSubmap();
  void RecheckSearchedSteps();
  bool RecheckStep(size_t k);
  const IndexedPoints& Submap();       // the submap's tree, built on first use after a rebuild
  const IndexedPoints* SubmapLines();  // its cell means for the point-to-line refinement (null: off)

  struct Impl;
  std::unique_ptr<Impl> impl_;
  ScanMatchingOptions options_;
  const TransformTree* frames_;
  std::string base_frame_;
  std::vector<ScanPose> scans_;
  std::optional<size_t> last_placed_;  // the last scan matched or moved by odometry (not a bare guess)
  std::vector<Keyframe> keyframes_;
  std::vector<bool> searched_;   // per keyframe: its step came from a search without odometry
  std::optional<size_t> moved_;  // first keyframe a recheck moved, not yet taken
  mrpt::poses::CPose2D start_;   // where the first scan is placed (the origin unless seeded)
  MappingStats stats_;
};

// An empty grid (20 m square about the origin; InsertIntoGrid grows it).
mrpt::maps::COccupancyGridMap2D EmptyGrid(const GridOptions& options);
// The occupancy grid of the given keyframes at their poses.
mrpt::maps::COccupancyGridMap2D BuildGrid(const std::vector<Keyframe>& keyframes, const GridOptions& options);
// Inserts keyframes[from…] into `grid` (grown to hold them), as BuildGrid does: a map
// kept up to date as keyframes come, rebuilt only when their poses move.
void InsertIntoGrid(const std::vector<Keyframe>& keyframes, size_t from, const GridOptions& options,
                    mrpt::maps::COccupancyGridMap2D& grid);

}  // namespace specht::slam
