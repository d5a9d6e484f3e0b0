// The branch-and-bound correlative matcher finds poses far from the guess.
#include "specht/slam/correlative_matcher.h"

#include <cmath>

#include <mrpt/core/bits_math.h>

#include "specht/slam/icp.h"
#include "test_support.h"

namespace specht::slam {
namespace {

using mrpt::maps::CSimplePointsMap;
using mrpt::poses::CPose2D;

// Points on the walls of a 10 m x 6 m room with a 1 m pillar at (6.5, 2.5), as a
// 180° laser with 361 beams at `pose` sees them (in the laser's frame).
CSimplePointsMap RoomScan(const CPose2D& pose) {
  CSimplePointsMap points;
  for (int i = 0; i < 361; ++i) {
    const double a = -M_PI / 2 + M_PI * i / 360.0, th = pose.phi() + a;
    const double dx = std::cos(th), dy = std::sin(th);
    double best = 1e9;
    auto box = [&](double x0, double x1, double y0, double y1) {
      for (double wx : {x0, x1}) {
        if (std::abs(dx) < 1e-12) continue;
        const double t = (wx - pose.x()) / dx, hy = pose.y() + t * dy;
        if (t > 1e-9 && hy >= y0 && hy <= y1) best = std::min(best, t);
      }
      for (double wy : {y0, y1}) {
        if (std::abs(dy) < 1e-12) continue;
        const double t = (wy - pose.y()) / dy, hx = pose.x() + t * dx;
        if (t > 1e-9 && hx >= x0 && hx <= x1) best = std::min(best, t);
      }
    };
    box(0, 10, 0, 6);
    box(6, 7, 2, 3);
    points.insertPoint(best * std::cos(a), best * std::sin(a), 0);
  }
  return points;
}

CSimplePointsMap InWorld(const CSimplePointsMap& scan, const CPose2D& pose) {
  CSimplePointsMap world;
  world.insertAnotherMap(&scan, mrpt::poses::CPose3D(pose));
  return world;
}

TEST(CorrelativeMatcherTest, FindsAPoseOneAndAHalfMetresAndThirtyDegreesFromTheGuess) {
  const CPose2D a(2.0, 2.0, 0.2), b(3.2, 2.9, 0.2 + mrpt::DEG2RAD(30));
  const CorrelativeMatcher matcher(InWorld(RoomScan(a), a), 0.05, 2.0);
  const auto r = matcher.Match(RoomScan(b), a, 2.0, mrpt::DEG2RAD(45), 0.5);
  ASSERT_TRUE(r.has_value());
  // 30° is not on the angle lattice (steps of about 0.36° here), so the best lattice
  // pose may sit one cell and half a step away from the truth.
  EXPECT_NEAR(r->pose.x(), b.x(), 0.051);
  EXPECT_NEAR(r->pose.y(), b.y(), 0.051);
  EXPECT_NEAR(mrpt::RAD2DEG(r->pose.phi()), mrpt::RAD2DEG(b.phi()), 0.4);
  EXPECT_GT(r->score, 0.7);
  // Branch and bound returns the best pose of the lattice: no lattice pose around
  // it scores higher.
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      const CPose2D other(r->pose.x() + 0.05 * dx, r->pose.y() + 0.05 * dy, r->pose.phi());
      EXPECT_LE(matcher.Score(RoomScan(b), other), r->score + 1e-9);
    }
  }
}

TEST(CorrelativeMatcherTest, NothingAboveTheMinimumScoreIsNoMatch) {
  const CPose2D a(2.0, 2.0, 0.0);
  const CorrelativeMatcher matcher(InWorld(RoomScan(a), a), 0.05, 1.0);
  CSimplePointsMap far;  // a scan of a wall that is not in the map
  for (int i = 0; i < 100; ++i) far.insertPoint(20.0f, -5.0f + 0.1f * i, 0);
  EXPECT_FALSE(matcher.Match(far, a, 1.0, mrpt::DEG2RAD(10), 0.5).has_value());
}

TEST(CorrelativeMatcherTest, DecimateKeepsOnePointPerCell) {
  CSimplePointsMap p;
  for (int i = 0; i < 100; ++i) p.insertPoint(0.001f * i, 0, 0);  // 10 cm of points
  EXPECT_EQ(Decimate(p, 0.05).size(), 2u);
}

}  // namespace
}  // namespace specht::slam
