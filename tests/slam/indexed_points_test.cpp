// IndexedPoints against brute force and against MRPT's own matching: the front end's
// results depend on these queries being exact, not approximately right.
#include "specht/slam/indexed_points.h"

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace specht::slam {
namespace {

using mrpt::maps::CSimplePointsMap;

// Walls seen many times (dense clusters along lines, as a submap of overlapping
// scans), scattered clutter, and exact duplicates.
CSimplePointsMap SubmapLike(std::mt19937& rng, int n) {
  std::uniform_real_distribution<float> u(-10.0f, 10.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  CSimplePointsMap points;
  for (int i = 0; i < n; ++i) {
    const float t = u(rng);
    switch (i % 4) {
      case 0:
        points.insertPoint(t, 3.0f + noise(rng), 0);
        break;  // a wall along x
      case 1:
        points.insertPoint(-4.0f + noise(rng), t, 0);
        break;  // a wall along y
      case 2:
        points.insertPoint(u(rng), u(rng), 0);
        break;  // clutter
      default:
        points.insertPoint(t, 0.5f * t + noise(rng), 0);
        break;  // a slanted wall
    }
  }
  for (int i = 0; i < n / 20; ++i) {  // duplicates, as where two keyframes coincide
    float x, y, z;
    points.getPoint(static_cast<size_t>(i) * 7 % points.size(), x, y, z);
    points.insertPoint(x, y, z);
  }
  return points;
}

std::vector<float> BruteForceDistances2(const CSimplePointsMap& points, float qx, float qy) {
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  std::vector<float> d2(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) {
    const float dx = qx - xs[i], dy = qy - ys[i];
    d2[i] = dx * dx + dy * dy;
  }
  std::sort(d2.begin(), d2.end());
  return d2;
}

TEST(IndexedPointsTest, NearestAndKNearestEqualBruteForce) {
  std::mt19937 rng(7);
  const CSimplePointsMap cloud = SubmapLike(rng, 5000);
  const IndexedPoints indexed(cloud);
  ASSERT_EQ(indexed.size(), cloud.size());
  std::uniform_real_distribution<float> u(-12.0f, 12.0f);
  std::vector<IndexedPoints::Neighbour> near;
  for (int q = 0; q < 2000; ++q) {
    const float qx = u(rng), qy = u(rng);
    const std::vector<float> truth = BruteForceDistances2(cloud, qx, qy);
    for (const float bound2 : {0.01f, 0.25f, 4.0f, 1e9f}) {
      const auto nearest = indexed.Nearest(qx, qy, bound2);
      ASSERT_EQ(nearest.has_value(), truth[0] < bound2) << qx << "," << qy << " bound² " << bound2;
      if (nearest) {
        EXPECT_EQ(nearest->distance2, truth[0]);
        float x, y, z;
        cloud.getPoint(nearest->index, x, y, z);
        EXPECT_EQ((qx - x) * (qx - x) + (qy - y) * (qy - y), truth[0]);  // the index names that point
      }
      indexed.Nearest(qx, qy, 5, bound2, near);
      const size_t within = static_cast<size_t>(std::lower_bound(truth.begin(), truth.end(), bound2) - truth.begin());
      ASSERT_EQ(near.size(), std::min<size_t>(5, within));
      for (size_t i = 0; i < near.size(); ++i) EXPECT_EQ(near[i].distance2, truth[i]) << "neighbour " << i;
      if (bound2 > 1.0f) continue;  // (every point within 2 m or more: slow to compare, nothing new)
      indexed.Within(qx, qy, bound2, near);
      std::vector<float> found;
      for (const auto& n : near) found.push_back(n.distance2);
      std::sort(found.begin(), found.end());
      EXPECT_EQ(found, std::vector<float>(truth.begin(), truth.begin() + static_cast<long>(within)));
    }
  }
}

TEST(IndexedPointsTest, EmptyAndTinyCloudsAnswer) {
  const IndexedPoints none;
  EXPECT_FALSE(none.Nearest(0, 0, 1e9f).has_value());
  std::vector<IndexedPoints::Neighbour> near{{1, 1.0f}};
  none.Nearest(0, 0, 3, 1e9f, near);
  EXPECT_TRUE(near.empty());
  CSimplePointsMap two;
  two.insertPoint(1, 0, 0);
  two.insertPoint(0, 2, 0);
  const IndexedPoints indexed(two);
  ASSERT_TRUE(indexed.Nearest(0, 0, 1e9f).has_value());
  EXPECT_EQ(indexed.Nearest(0, 0, 1e9f)->index, 0u);
  indexed.Nearest(0, 0, 3, 1e9f, near);
  ASSERT_EQ(near.size(), 2u);
  EXPECT_EQ(near[1].index, 1u);
  EXPECT_FLOAT_EQ(near[1].distance2, 4.0f);
}

// MRPT's ICP pairs through determineMatching2D: ours must give it exactly the pairs,
// ratio and mean squared distance MRPT's own CPointsMap gives, over the gates, pivots,
// decimations and poses ICP uses (and point counts that are not a multiple of 4, for
// an SSE path that would treat the last points apart).
TEST(IndexedPointsTest, PairsExactlyAsMrptsOwnMatching) {
  std::mt19937 rng(11);
  const CSimplePointsMap cloud = SubmapLike(rng, 4000);
  const IndexedPoints indexed(cloud);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int compared_pairs = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const CSimplePointsMap scan = SubmapLike(rng, 361 + trial % 4);
    const mrpt::poses::CPose2D pose(u(rng), u(rng), 0.3 * u(rng));
    mrpt::maps::TMatchingParams params;
    params.maxDistForCorrespondence = static_cast<float>(0.05 + 0.3 * (1 + u(rng)));
    params.maxAngularDistForCorrespondence = static_cast<float>(0.05 * (1 + u(rng)));
    params.decimation_other_map_points = 1 + trial % 3;
    params.offset_other_map_points = trial % params.decimation_other_map_points;
    params.angularDistPivotPoint = mrpt::math::TPoint3D(pose.x(), pose.y(), 0);
    mrpt::tfest::TMatchingPairList ours, theirs;
    mrpt::maps::TMatchingExtraResults ours_extra, theirs_extra;
    indexed.AsIcpReference().determineMatching2D(&scan, pose, ours, params, ours_extra);
    cloud.determineMatching2D(&scan, pose, theirs, params, theirs_extra);
    ASSERT_EQ(ours.size(), theirs.size()) << "trial " << trial;
    for (size_t i = 0; i < ours.size(); ++i) {
      EXPECT_EQ(ours[i].localIdx, theirs[i].localIdx);
      EXPECT_EQ(ours[i].global.x, theirs[i].global.x);  // duplicates may differ in index, not place
      EXPECT_EQ(ours[i].global.y, theirs[i].global.y);
      EXPECT_EQ(ours[i].local.x, theirs[i].local.x);
      EXPECT_EQ(ours[i].errorSquareAfterTransformation, theirs[i].errorSquareAfterTransformation);
    }
    EXPECT_EQ(ours_extra.correspondencesRatio, theirs_extra.correspondencesRatio);
    EXPECT_EQ(ours_extra.sumSqrDist, theirs_extra.sumSqrDist);
    compared_pairs += static_cast<int>(ours.size());
  }
  EXPECT_GT(compared_pairs, 5000);  // the gates were wide enough to pair most points
}

TEST(IndexedPointsTest, MatchingRefusesWhatIcpNeverPasses) {
  // Another map that is not a point cloud, and a decimation that would skip every
  // point: both are programming errors, refused with the reason.
  std::mt19937 rng(3);
  const IndexedPoints indexed(SubmapLike(rng, 100));
  const CSimplePointsMap scan = SubmapLike(rng, 50);
  mrpt::tfest::TMatchingPairList pairs;
  mrpt::maps::TMatchingExtraResults extra;
  mrpt::maps::TMatchingParams params;
  const mrpt::maps::COccupancyGridMap2D grid;
  EXPECT_THROW(indexed.AsIcpReference().determineMatching2D(&grid, mrpt::poses::CPose2D(), pairs, params, extra),
               std::invalid_argument);
  for (const auto& [decimation, offset] : {std::pair{0u, 0u}, std::pair{2u, 2u}, std::pair{3u, 5u}}) {
    params.decimation_other_map_points = decimation;
    params.offset_other_map_points = offset;
    EXPECT_THROW(indexed.AsIcpReference().determineMatching2D(&scan, mrpt::poses::CPose2D(), pairs, params, extra),
                 std::invalid_argument)
        << decimation << ", " << offset;
  }
  params.decimation_other_map_points = 2;
  params.offset_other_map_points = 1;
  EXPECT_NO_THROW(indexed.AsIcpReference().determineMatching2D(&scan, mrpt::poses::CPose2D(), pairs, params, extra));
}

}  // namespace
}  // namespace specht::slam
