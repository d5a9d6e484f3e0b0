// specht/slam/indexed_points.h: a fixed 2D point cloud with a k-d tree over it, for
// the exact nearest-neighbour queries of scan matching.
//
// Why not MRPT's own tree (nanoflann inside CPointsMap)? The SLAM front end matches
// every scan against a local submap of ~20,000 points that changes with every
// keyframe, so the tree is rebuilt about once per scan, and nanoflann's build is a
// large share of the front end's time. This tree is a balanced median split kept
// implicitly in one array (node = the median element of its range, left and right
// halves its children), built with std::nth_element, which is cheaper than
// nanoflann's build (bench/point_index_bench has both). Its queries are bounded by a
// radius, which is all scan matching needs, and are somewhat slower than nanoflann's:
// a tree rebuilt per scan and queried ~10,000 times wins on the build.
//
// Queries are exact: the nearest point (or k nearest) with squared distance below a
// bound, distances computed in float as nanoflann does, (qx − px)² + (qy − py)². The
// far side of a split is visited only when (q − split)² < the current bound, which
// loses nothing: every point there is at least that far.
//
// MRPT's ICP (CICP) pairs points through CMetricMap::determineMatching2D; this class
// overrides it to pair through its own tree, with MRPT's arithmetic (points moved in
// float as MRPT 2.5 moves them, its distance gate, ratio and mean squared distance),
// so CICP sees the same pairs it would from CPointsMap. One difference: MRPT pairs
// nothing when the bounding boxes of the two clouds do not overlap; this pairs by
// distance alone.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace specht::slam {

class IndexedPoints : private mrpt::maps::CSimplePointsMap {
 public:
  struct Neighbour {
    uint32_t index = 0;   // into points()
    float distance2 = 0;  // squared distance to the query
  };

  IndexedPoints() = default;
  explicit IndexedPoints(const mrpt::maps::CSimplePointsMap& points);

  const mrpt::maps::CSimplePointsMap& points() const { return *this; }
  size_t size() const { return CSimplePointsMap::size(); }
  bool empty() const { return size() == 0; }

  // The nearest point with squared distance below `bound2`; nullopt if none is.
  std::optional<Neighbour> Nearest(float x, float y, float bound2) const;

  // The (up to) k nearest points with squared distance below `bound2`, nearest first.
  void Nearest(float x, float y, size_t k, float bound2, std::vector<Neighbour>& out) const;

  // Every point with squared distance below `bound2`, in no particular order.
  void Within(float x, float y, float bound2, std::vector<Neighbour>& out) const;

  // The cloud as MRPT's ICP takes its reference map (pairs through this tree).
  const mrpt::maps::CMetricMap& AsIcpReference() const { return *this; }

 private:
  struct TreePoint {
    float x, y;
    uint32_t index;
  };
  struct Box {
    float x0, x1, y0, y1;
  };
  void Build(size_t lo, size_t hi, Box box);

  void determineMatching2D(const mrpt::maps::CMetricMap* other_map, const mrpt::poses::CPose2D& other_pose,
                           mrpt::tfest::TMatchingPairList& pairs, const mrpt::maps::TMatchingParams& params,
                           mrpt::maps::TMatchingExtraResults& extra) const override;

  std::vector<TreePoint> tree_;  // the points in tree order
  std::vector<uint8_t> axis_;    // split axis of the node at each position: 0 x, 1 y
};

}  // namespace specht::slam
