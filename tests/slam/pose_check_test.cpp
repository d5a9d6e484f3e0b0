// The pose check: a scan taken at the true pose agrees with the prior map, one read at
// a kidnapped pose does not, and relocalisation finds the true pose again.
#include "specht/slam/pose_check.h"

#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>

namespace specht::slam {
namespace {

using mrpt::maps::COccupancyGridMap2D;
using mrpt::maps::CSimplePointsMap;
using mrpt::poses::CPose2D;

// A 20 m × 12 m hall at 0.1 m: outer walls, an inner wall with a door, two pillars.
COccupancyGridMap2D Hall() {
  COccupancyGridMap2D grid(-1, 21, -1, 13, 0.1f);
  grid.fill(0.9f);  // p(free)
  const auto wall = [&](double x0, double y0, double x1, double y1) {
    const double n = std::ceil(std::hypot(x1 - x0, y1 - y0) / 0.05);
    for (int i = 0; i <= n; ++i)
      grid.setCell(grid.x2idx(x0 + (x1 - x0) * i / n), grid.y2idx(y0 + (y1 - y0) * i / n), 0);
  };
  wall(0, 0, 20, 0), wall(20, 0, 20, 12), wall(20, 12, 0, 12), wall(0, 12, 0, 0);
  wall(12, 0, 12, 5), wall(12, 7, 12, 12);  // the inner wall, a 2 m door
  wall(4, 4, 5, 4), wall(5, 4, 5, 5), wall(5, 5, 4, 5), wall(4, 5, 4, 4);
  wall(8, 8, 8.6, 8), wall(8.6, 8, 8.6, 8.6), wall(8.6, 8.6, 8, 8.6), wall(8, 8.6, 8, 8);
  return grid;
}

// What a 360° LiDAR at `pose` sees of the hall, in its own frame.
CSimplePointsMap ScanAt(const COccupancyGridMap2D& hall, const CPose2D& pose) {
  mrpt::obs::CObservation2DRangeScan scan;
  scan.aperture = static_cast<float>(2 * M_PI * 719 / 720);
  scan.maxRange = 30;
  hall.laserScanSimulator(scan, pose, 0.5f, 720);
  CSimplePointsMap points;
  points.insertionOptions.minDistBetweenLaserPoints = 0;
  points.loadFromRangeScan(scan);
  return points;
}

PoseCheckOptions Options() { return PoseCheckOptions{}; }

TEST(PoseCheckTest, AScanAtTheTruePoseAgreesAndOneAtAKidnappedPoseDoesNot) {
  const COccupancyGridMap2D hall = Hall();
  const PoseCheck check(hall, Options());
  const CPose2D truth(6.0, 3.0, mrpt::DEG2RAD(35));
  const CSimplePointsMap scan = ScanAt(hall, truth);
  const auto at_truth = check.Score(scan, truth);
  ASSERT_TRUE(at_truth.has_value());
  EXPECT_GT(*at_truth, 0.9);
  // The closed loop's kidnap: 2 m ahead and 20° off.
  const CPose2D kidnapped = truth + CPose2D(2.0, 0, mrpt::DEG2RAD(20));
  EXPECT_LT(*check.Score(scan, kidnapped), Options().lost_below);
  // A small error (the tracker's centimetres) is no loss.
  EXPECT_GT(*check.Score(scan, truth + CPose2D(0.05, 0.03, mrpt::DEG2RAD(0.5))), 0.8);
}

TEST(PoseCheckTest, RelocalisationFindsTheTruePoseFromTheKidnappedOne) {
  const COccupancyGridMap2D hall = Hall();
  const PoseCheck check(hall, Options());
  const CPose2D truth(15.0, 8.0, mrpt::DEG2RAD(-120));
  const CPose2D kidnapped = truth + CPose2D(2.0, 0, mrpt::DEG2RAD(20));
  const auto found = check.Relocalize(ScanAt(hall, truth), kidnapped);
  ASSERT_TRUE(found.has_value());
  // The search's lattice alone leaves a cell and an angle step (1.2° here); ICP refines.
  EXPECT_NEAR(found->pose.x(), truth.x(), 0.03);
  EXPECT_NEAR(found->pose.y(), truth.y(), 0.03);
  EXPECT_NEAR(mrpt::RAD2DEG(mrpt::math::wrapToPi(found->pose.phi() - truth.phi())), 0.0, 0.2);
  EXPECT_GE(found->score, Options().relocalized_above);
}

TEST(PoseCheckTest, TooFewPointsGiveNoVerdictAndNoSearch) {
  const COccupancyGridMap2D hall = Hall();
  const PoseCheck check(hall, Options());
  CSimplePointsMap few;
  for (int i = 0; i < Options().min_points - 1; ++i) few.insertPoint(1.0 + 0.01 * i, 0, 0);
  EXPECT_FALSE(check.Score(few, CPose2D(5, 5, 0)).has_value());
  EXPECT_FALSE(check.Relocalize(few, CPose2D(5, 5, 0)).has_value());
}

TEST(PoseCheckTest, ThePoseIsLostOnlyAfterEnoughDisagreeingScansInARow) {
  PoseCheckOptions o;
  o.lost_after_scans = 3, o.lost_below = 0.4;
  PoseMonitor m(o);
  EXPECT_FALSE(m.Add(0.1));
  EXPECT_FALSE(m.Add(0.2));
  EXPECT_FALSE(m.Add(0.9));  // one scan that agrees starts the count again
  EXPECT_FALSE(m.Add(0.1));
  EXPECT_FALSE(m.Add(std::nullopt));  // no verdict: the count stands
  EXPECT_FALSE(m.Add(0.3));
  EXPECT_TRUE(m.Add(0.39));
  EXPECT_EQ(m.scored(), 6);
  EXPECT_EQ(m.disagreeing_total(), 5);
  EXPECT_DOUBLE_EQ(m.lowest(), 0.1);
  m.Reset();
  EXPECT_FALSE(m.lost());
}

}  // namespace
}  // namespace specht::slam
