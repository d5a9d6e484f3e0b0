// The branch-and-bound correlative matcher finds poses far from the guess.
#include "specht/slam/correlative_matcher.h"

#include <mrpt/core/bits_math.h>

#include <cmath>
#include <stdexcept>

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

TEST(CorrelativeMatcherTest, LikelihoodFallsAsAGaussianOfTheDistanceToTheNearestMapPoint) {
  CSimplePointsMap map;
  map.insertPoint(0, 0, 0);
  const double res = 0.05, sigma_cells = 1.5;
  const CorrelativeMatcher matcher(map, res, 0.5, sigma_cells);
  CSimplePointsMap probe;
  probe.insertPoint(0, 0, 0);
  auto score_at = [&](double x, double y) { return matcher.Score(probe, CPose2D(x, y, 0)); };
  // The centre of the map point's cell: the one probe of a cell around it scoring 1.
  double hx = 0, hy = 0;
  for (double ox : {-0.5, 0.5}) {
    for (double oy : {-0.5, 0.5}) {
      if (score_at(ox * res, oy * res) == 1.0) hx = ox * res, hy = oy * res;
    }
  }
  ASSERT_EQ(score_at(hx, hy), 1.0);
  // L = round(255 exp(−d²/2σ²)) / 255, d in cells between cell centres; 0 from 3.53σ.
  for (const auto& [cx, cy] : {std::pair{1, 0}, {1, 1}, {0, -2}, {3, 1}, {-4, 2}, {5, 0}, {6, 0}, {0, 9}}) {
    const double d2 = cx * cx + cy * cy;
    const double expected = std::round(255.0 * std::exp(-d2 / (2 * sigma_cells * sigma_cells))) / 255.0;
    EXPECT_NEAR(score_at(hx + cx * res, hy + cy * res), expected, 1e-12) << "offset " << cx << ", " << cy;
  }
}

// The best score of the search lattice around `guess` (±window_cells, ±window_rad in
// the matcher's angle steps), by trying every pose of it.
double BestLatticeScore(const CorrelativeMatcher& m, const CSimplePointsMap& scan, const CPose2D& guess, double res,
                        int window_cells, double window_rad, const DrivePrior& prior = {}) {
  double max_range = 0;
  for (size_t i = 0; i < scan.size(); ++i) {
    float x, y, z;
    scan.getPoint(i, x, y, z);
    max_range = std::max<double>(max_range, std::hypot(x, y));
  }
  const double step = std::acos(1.0 - res * res / (2.0 * max_range * max_range));
  const int half_angles = static_cast<int>(std::ceil(window_rad / step));
  double best = -1e9;
  for (int a = -half_angles; a <= half_angles; ++a) {
    for (int dx = -window_cells; dx <= window_cells; ++dx) {
      for (int dy = -window_cells; dy <= window_cells; ++dy) {
        const CPose2D pose(guess.x() + dx * res, guess.y() + dy * res, guess.phi() + a * step);
        best = std::max(best, m.Score(scan, pose, prior));
      }
    }
  }
  return best;
}

TEST(CorrelativeMatcherTest, BranchAndBoundFindsTheBestScoreOfTheWholeLattice) {
  // The map holds the room up to x = 8 m: the scan's points on the far wall (x = 10 m)
  // lie outside the map's grid, so candidates take the bounds-checked path too.
  const CPose2D a(2.0, 2.0, 0.0), b(2.3, 1.8, 0.1);
  CSimplePointsMap corner;
  const CSimplePointsMap room = InWorld(RoomScan(a), a);
  for (size_t i = 0; i < room.size(); ++i) {
    float x, y, z;
    room.getPoint(i, x, y, z);
    if (x < 8) corner.insertPoint(x, y, 0);
  }
  const double res = 0.1;
  const CorrelativeMatcher matcher(corner, res, 0.5);
  const CSimplePointsMap scan = Decimate(RoomScan(b), res);
  const auto r = matcher.Match(scan, a, 0.5, mrpt::DEG2RAD(10), 0.1);
  ASSERT_TRUE(r.has_value());
  // Score() places points by the pose directly, Match() by integer cell offsets from
  // the guess: the two may differ on a point lying on a cell border, hence one point.
  EXPECT_NEAR(r->score, BestLatticeScore(matcher, scan, a, res, 5, mrpt::DEG2RAD(10)), 1.0 / scan.size());
  EXPECT_NEAR(r->score, matcher.Score(scan, r->pose), 1.0 / scan.size());
  EXPECT_NEAR(r->pose.x(), b.x(), 0.11);
  EXPECT_NEAR(r->pose.y(), b.y(), 0.11);
}

// A wide window shifts the scan's points off the grid's low edge at the coarse levels
// while the finer translations below bring them back onto the map: the coarse bound
// must still count them, or the search cuts the branch holding the best pose and
// its answer depends on the acceptance threshold.
TEST(CorrelativeMatcherTest, BranchAndBoundStaysExactWhenTheWindowReachesPastTheGridsEdge) {
  const CPose2D a(2.0, 2.0, 0.0), b(2.3, 1.8, 0.1);
  const double res = 0.1, window = 2.0;
  const CorrelativeMatcher matcher(InWorld(RoomScan(a), a), res, window);
  const CSimplePointsMap scan = Decimate(RoomScan(b), res);
  const CPose2D guess(b.x() - 1.0, b.y() - 1.1, b.phi());
  const double best = BestLatticeScore(matcher, scan, guess, res, 20, 0.0);
  for (const double min_score : {0.1, 0.4, best - 0.01}) {
    const auto r = matcher.Match(scan, guess, window, 0.0, min_score);
    ASSERT_TRUE(r.has_value()) << "min_score " << min_score;
    EXPECT_NEAR(r->score, best, 1.0 / scan.size()) << "min_score " << min_score;
    EXPECT_NEAR(r->pose.x(), b.x(), 0.11);
    EXPECT_NEAR(r->pose.y(), b.y(), 0.11);
  }
}

TEST(DrivePriorTest, ExcessIsTheMotionSidewaysOrBackwardsBeyondTheSlack) {
  DrivePrior prior{CPose2D(1.0, 2.0, M_PI / 2), 0.1, 0.2, false};  // facing +y
  EXPECT_DOUBLE_EQ(prior.ExcessM(1.0, 4.0, M_PI / 2), 0.0);        // 2 m straight ahead
  EXPECT_NEAR(prior.ExcessM(2.0, 2.0, M_PI / 2), 0.8, 1e-12);      // 1 m to the right
  EXPECT_NEAR(prior.ExcessM(1.0, 1.0, M_PI / 2), 0.8, 1e-12);      // 1 m back
  EXPECT_NEAR(prior.ExcessM(2.0, 1.0, M_PI / 2), 1.6, 1e-12);      // both
  EXPECT_DOUBLE_EQ(prior.ExcessM(1.1, 2.0, M_PI / 2), 0.0);        // within the slack
  // A quarter circle of radius 1 to the left: the chord points along the mean heading.
  EXPECT_NEAR(prior.ExcessM(0.0, 3.0, M_PI), 0.0, 1e-12);
  prior.reverse = true;
  EXPECT_DOUBLE_EQ(prior.ExcessM(1.0, 1.0, M_PI / 2), 0.0);
  // The least excess over a box is at most the excess anywhere in it.
  prior.reverse = false;
  for (double x = -1.0; x <= 3.0; x += 0.25) {
    for (double y = 0.0; y <= 4.0; y += 0.25) {
      EXPECT_LE(prior.MinExcessM(-1.0, 3.0, 0.0, 4.0, 2.0), prior.ExcessM(x, y, 2.0) + 1e-12);
      EXPECT_LE(prior.MinExcessM(x, x + 0.5, y, y + 0.5, 2.0), prior.ExcessM(x + 0.25, y + 0.5, 2.0) + 1e-12);
    }
  }
}

TEST(CorrelativeMatcherTest, ADrivePriorPrefersTheStepAheadToABetterFittingAliasBeside) {
  // Two copies of a U-shaped bay: one 1.5 m ahead of where the car was, one 1.5 m to
  // its left. The car drove to the one ahead, but that copy lost a tenth of its points
  // (unseen so far), so the copy beside fits the scan better.
  auto bay = [](double cx, double cy, bool gap, CSimplePointsMap& out) {
    int i = 0;
    auto add = [&](double x, double y) {
      if (!(gap && i++ % 10 == 0)) out.insertPoint(static_cast<float>(cx + x), static_cast<float>(cy + y), 0);
    };
    for (double t = -1.0; t <= 1.0; t += 0.02) add(2.0, t);  // back wall
    for (double t = 0.5; t < 2.0; t += 0.02) add(t, -1.0), add(t, 1.0);
  };
  CSimplePointsMap map, scan;
  bay(1.5, 0.0, true, map);
  bay(0.0, 1.5, false, map);
  bay(0.0, 0.0, false, scan);  // the full bay as the car sees it, in its own frame
  const CPose2D from(0, 0, 0), ahead(1.5, 0, 0), beside(0, 1.5, 0);
  const CorrelativeMatcher matcher(map, 0.05, 2.0);
  const auto plain = matcher.Match(scan, from, 2.0, mrpt::DEG2RAD(10), 0.3);
  ASSERT_TRUE(plain.has_value());
  EXPECT_LT(plain->pose.distanceTo(beside), 0.06);
  const DrivePrior prior{from, 0.1, 0.2, false};
  const auto driven = matcher.Match(scan, from, 2.0, mrpt::DEG2RAD(10), 0.3, prior);
  ASSERT_TRUE(driven.has_value());
  EXPECT_LT(driven->pose.distanceTo(ahead), 0.06);
  // The score is the likelihood less the penalty: the alias beside pays 0.1 × 1.3 m.
  EXPECT_NEAR(driven->score, matcher.Score(scan, driven->pose, prior), 1.0 / scan.size());
  EXPECT_NEAR(matcher.Score(scan, beside) - matcher.Score(scan, beside, prior), 0.13, 1e-9);
}

TEST(CorrelativeMatcherTest, WithADrivePriorBranchAndBoundStillFindsTheBestOfTheWholeLattice) {
  // As BranchAndBoundFindsTheBestScoreOfTheWholeLattice, with a prior strong enough to
  // move the answer: the bound of a block must stay above every penalised leaf in it.
  // A window of ±1.2 m makes the top blocks 16 cells wide, so a bound that took the
  // penalty at one corner of a block instead of its least would cut the best leaf.
  const CPose2D a(2.0, 2.0, 0.0), b(2.3, 1.8, 0.1);
  const double res = 0.1, window = 1.2;
  const CorrelativeMatcher matcher(InWorld(RoomScan(a), a), res, window);
  const CSimplePointsMap scan = Decimate(RoomScan(b), res);
  const double plain = matcher.Match(scan, a, window, mrpt::DEG2RAD(10), 0.05)->score;
  for (const CPose2D& from : {CPose2D(2.0, 2.0, 0.3), CPose2D(2.9, 1.3, -0.5), CPose2D(1.4, 2.6, 1.2)}) {
    const DrivePrior prior{from, 0.3, 0.05, false};
    const auto r = matcher.Match(scan, a, window, mrpt::DEG2RAD(10), 0.05, prior);
    ASSERT_TRUE(r.has_value());
    // One point on a cell border, and the penalty rounded down to a sum unit per block.
    EXPECT_NEAR(r->score, BestLatticeScore(matcher, scan, a, res, 12, mrpt::DEG2RAD(10), prior), 2.0 / scan.size())
        << "from " << from;
    EXPECT_LT(r->score, plain - 0.01) << "from " << from;  // the prior bit
  }
}

TEST(CorrelativeMatcherTest, NothingAboveTheMinimumScoreIsNoMatch) {
  const CPose2D a(2.0, 2.0, 0.0);
  const CorrelativeMatcher matcher(InWorld(RoomScan(a), a), 0.05, 1.0);
  CSimplePointsMap far;  // a scan of a wall that is not in the map
  for (int i = 0; i < 100; ++i) far.insertPoint(20.0f, -5.0f + 0.1f * i, 0);
  EXPECT_FALSE(matcher.Match(far, a, 1.0, mrpt::DEG2RAD(10), 0.5).has_value());
}

TEST(CorrelativeMatcherTest, RefusesANonPositiveResolutionOrBlur) {
  CSimplePointsMap map;
  map.insertPoint(0, 0, 0);
  EXPECT_THROW(CorrelativeMatcher(map, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(CorrelativeMatcher(map, 0.05, 1.0, 0.0), std::invalid_argument);
}

TEST(CorrelativeMatcherTest, DecimateKeepsOnePointPerCell) {
  CSimplePointsMap p;
  for (int i = 0; i < 100; ++i) p.insertPoint(0.001f * i, 0, 0);  // 10 cm of points
  EXPECT_EQ(Decimate(p, 0.05).size(), 2u);
}

}  // namespace
}  // namespace specht::slam
