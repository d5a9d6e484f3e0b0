// specht/slam/graph_slam.h: graph SLAM on 2D laser scans and wheel odometry.
//
//   front end   ScanMatchingMapper: each scan matched (ICP) against a local submap,
//               seeded by odometry; keyframes by motion.
//   submaps     consecutive keyframes grouped `keyframes_per_submap` at a time,
//               anchored at their first keyframe; a finished submap keeps its points
//               in the anchor's frame and a branch-and-bound correlative matcher.
//   loops       every `search_every` keyframes, finished submaps whose centre lies
//               within `search_radius_m` of the keyframe (and that do not hold any of
//               the last `exclude_recent_keyframes`) are searched within ±window_m,
//               ±window_deg (the candidates split over two threads); a
//               match scoring `min_score` or more, refined by ICP with goodness
//               `min_icp_goodness` or more, becomes a loop edge anchor → keyframe
//               under a robust loss.
//   old nodes   a submap once finished, and the last one at Finish() when half
//               full, is in turn searched by `old_keyframes_per_submap` (4; 0: off)
//               earlier keyframes nearest its centre that have no loop of their own yet
//               (Cartographer's constraints for old nodes): a place is whole in a
//               submap only once finished, and a keyframe that saw part of it long
//               before may match it although the submaps of its own time never
//               matched the later keyframes.
//   back end    nodes = keyframes, edges = consecutive front-end matches and loops;
//               optimised on Ceres (pose_graph_optimizer.h) after every
//               `optimize_every` new loops and at Finish(); the front end is then
//               corrected, so later scans match against the corrected map.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/pose_graph.h"
#include "specht/slam/pose_graph_optimizer.h"
#include "specht/slam/scan_matching.h"

namespace specht::slam {

// Section "loop_closure".
struct LoopClosureOptions {
  bool enabled = true;
  int keyframes_per_submap = 20;
  double submap_max_range_m = 15.0;
  double resolution_m = 0.1;
  int search_every = 1;
  double search_radius_m = 10.0;
  int exclude_recent_keyframes = 40;
  int max_candidates = 6;
  int old_keyframes_per_submap = 4;
  double window_m = 3.0;
  double window_deg = 30.0;
  double min_score = 0.55;
  double min_icp_goodness = 0.75;
  int weak_axis_points = 0;
  int optimize_every = 3;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("enabled", enabled, "search for loop closures (off: scan-matching odometry only)");
    v.Param("keyframes_per_submap", keyframes_per_submap, "keyframes grouped into one submap", Range::Of(2, 500));
    v.Param("submap_max_range_m", submap_max_range_m, "returns farther than this stay out of submaps",
            Range::Of(2.0, 100.0));
    v.Param("resolution_m", resolution_m, "cell size of the loop-closure matcher grid", Range::Of(0.02, 0.5).Log());
    v.Param("search_every", search_every, "search loops from every n-th keyframe", Range::Of(1, 100));
    v.Param("search_radius_m", search_radius_m, "candidate submaps have their centre within this distance",
            Range::Of(1.0, 100.0));
    v.Param("exclude_recent_keyframes", exclude_recent_keyframes,
            "submaps holding one of the last n keyframes are not loop candidates", Range::Of(1, 10000));
    v.Param("max_candidates", max_candidates, "submaps searched per keyframe (nearest first)", Range::Of(1, 50));
    v.Param("old_keyframes_per_submap", old_keyframes_per_submap,
            "a finished submap is searched by this many earlier keyframes without a loop of their own "
            "(nearest first; 0: none)",
            Range::Of(0, 1000));
    v.Param("window_m", window_m, "linear half-width of the loop search", Range::Of(0.1, 20.0));
    v.Param("window_deg", window_deg, "angular half-width of the loop search", Range::Of(1.0, 180.0));
    v.Param("min_score", min_score, "accept a loop match from this mean likelihood", Range::Of(0.2, 0.99));
    v.Param("min_icp_goodness", min_icp_goodness, "accept a loop when ICP pairs this fraction of points",
            Range::Of(0.1, 1.0));
    v.Param("weak_axis_points", weak_axis_points,
            "a loop whose scan pins the direction its ICP fit pins least (icp.h) with fewer points constrains "
            "only the other directions (a straight corridor pins its length hardly at all; 0: off)",
            Range::Of(0, 1000));
    v.Param("optimize_every", optimize_every, "optimise the graph after this many new loops", Range::Of(1, 1000));
  }
};

// Section "slam".
struct SlamOptions {
  std::string method = "graph";
  double odometry_sigma_m = 0.03;
  double odometry_sigma_deg = 0.5;
  double loop_sigma_m = 0.05;
  double loop_sigma_deg = 1.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("method", method, {"graph", "scan_matching"},
             "graph: graph SLAM with loop closure; scan_matching: front end only");
    v.Param("odometry_sigma_m", odometry_sigma_m, "std. dev. of a front-end match, translation",
            Range::Of(0.001, 1.0).Log());
    v.Param("odometry_sigma_deg", odometry_sigma_deg, "std. dev. of a front-end match, rotation",
            Range::Of(0.01, 20.0).Log());
    v.Param("loop_sigma_m", loop_sigma_m, "std. dev. of a loop closure, translation", Range::Of(0.001, 1.0).Log());
    v.Param("loop_sigma_deg", loop_sigma_deg, "std. dev. of a loop closure, rotation", Range::Of(0.01, 20.0).Log());
  }
};

struct GraphSlamStats {
  long loop_searches = 0;          // (keyframe, submap) pairs searched
  long loops_found = 0;            // matches above min_score
  long loops_accepted = 0;         // also verified by ICP: edges in the graph
  long loops_free_along_axis = 0;  // accepted, but pinned too weakly along one direction: free there
  long optimizations = 0;
  double optimize_ms = 0;
  double loop_search_ms = 0;
  double final_chi2 = 0;
};

class GraphSlam {
 public:
  GraphSlam(const SlamOptions& slam, const ScanMatchingOptions& matching, const LoopClosureOptions& loops,
            const PoseGraphOptions& back_end, const TransformTree* frames, std::string base_frame);
  ~GraphSlam();
  GraphSlam(const GraphSlam&) = delete;
  GraphSlam& operator=(const GraphSlam&) = delete;

  // Continuing a saved map (`specht slam --continue`): its keyframes and pose graph
  // (node i = keyframe i) are taken over and cut into loop-closure submaps; the
  // first new keyframe is placed at `start` (the saved map's frame) and tied to the
  // nearest saved node with a loop-closure edge, so later loops against the saved
  // submaps pull the new part into the old. Call before the first Add.
  void Continue(const std::vector<Keyframe>& saved, const PoseGraph2D& saved_graph, const mrpt::poses::CPose2D& start);

  void Add(Stamp stamp, const mrpt::obs::CObservation::Ptr& observation);
  // Final optimisation (when there are loops); call once after the last observation.
  void Finish();

  Trajectory trajectory() const { return front_end_.trajectory(); }
  std::optional<StampedPose> LatestPose() const { return front_end_.LatestPose(); }
  const std::vector<Keyframe>& keyframes() const { return front_end_.keyframes(); }
  const MappingStats& front_end_stats() const { return front_end_.stats(); }
  const GraphSlamStats& stats() const { return stats_; }
  const PoseGraph2D& graph() const { return graph_; }

 private:
  struct Submap;
  struct LoopCandidate {
    const Submap* submap;
    size_t keyframe;
  };
  void OnKeyframe(size_t k);
  void SearchLoops(size_t k);
  void SearchOldKeyframes(const Submap& s);
  void VerifyLoops(const std::vector<LoopCandidate>& candidates);
  void FinishSubmap();
  std::unique_ptr<Submap> BuildSubmap(const std::vector<size_t>& members) const;
  void OnKeyframesMoved(size_t first, size_t in_graph);
  void OptimizeAndCorrect();

  SlamOptions slam_;
  LoopClosureOptions loops_;
  PoseGraphOptions back_end_;
  ScanMatchingMapper front_end_;
  IcpAligner icp_;
  IcpAligner second_icp_;  // loop verification on the second thread
  PoseGraph2D graph_;
  std::vector<std::unique_ptr<Submap>> submaps_;
  std::vector<size_t> open_submap_;  // keyframes of the submap being filled
  int loops_since_optimize_ = 0;
  std::vector<bool> closed_;  // keyframes with a loop edge of their own
  size_t seeded_ = 0;         // keyframes taken over from a saved map
  GraphSlamStats stats_;
};

}  // namespace specht::slam
