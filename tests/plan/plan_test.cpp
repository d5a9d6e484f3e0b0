// Hybrid A* on hand-made maps with known answers: a straight run, a U-turn, a
// perpendicular parking manoeuvre between parked cars; every returned pose is
// checked against the obstacle raster with the exact rectangular footprint (not
// the planner's disc cover), and every arc against the steering limit.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "specht/core/error.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/smoother.h"
#include "specht/plan/tracker.h"
#include "test_maps.h"

namespace specht::plan {
namespace {

struct Planner {
  CarOptions car;
  HybridAStarOptions options;
  cv::Mat obstacles;
  std::shared_ptr<DistanceMap> map;
  std::unique_ptr<HybridAStar> search;
  // The expansion budget alone, as in the closed loop: an answer that hung on the
  // machine's speed would differ in a sanitizer build.
  explicit Planner(cv::Mat m, HybridAStarOptions o = {}) : options(WithoutTimeBudget(o)), obstacles(std::move(m)) {
    map = std::make_shared<DistanceMap>(obstacles, 0.0, 0.0, kRes);
    search = std::make_unique<HybridAStar>(options, car, map);
  }
};

void ExpectFeasible(const Planner& p, const PlanResult& r, const Pose& goal) {
  ASSERT_TRUE(r.found) << r.failure;
  ASSERT_GE(r.path.points.size(), 2u);
  EXPECT_NEAR(r.path.points.back().pose.x, goal.x, 1e-3);
  EXPECT_NEAR(r.path.points.back().pose.y, goal.y, 1e-3);
  EXPECT_NEAR(std::remainder(r.path.points.back().pose.theta - goal.theta, 2 * M_PI), 0.0, 1e-3);
  EXPECT_LE(r.path.MaxCurvature(), 1.0 / p.car.MinTurningRadius() * 1.05);  // 5 %: chord vs arc at 0.1 m
  EXPECT_EQ(Overlaps(p.obstacles, p.car, r.path), 0);
  for (size_t i = 1; i < r.path.points.size(); ++i)  // no jumps
    EXPECT_LT(std::hypot(r.path.points[i].pose.x - r.path.points[i - 1].pose.x,
                         r.path.points[i].pose.y - r.path.points[i - 1].pose.y),
              0.2)
        << i;
}

// Where the disc cover says no, Free skips blocks of footprint samples the distance
// field proves clear; it must answer exactly as reading every sample (Clearance)
// does, including poses hanging over a map edge that has no wall.
TEST(DistanceMapTest, FreeAgreesWithTheFullFootprintCheck) {
  cv::Mat m(200, 300, CV_8U, cv::Scalar(0));  // 30 × 20 m, no outer wall
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-1, 31), y(-1, 21), heading(-M_PI, M_PI);
  for (int i = 0; i < 25; ++i)
    cv::circle(m, {static_cast<int>(x(rng) * 10), static_cast<int>(y(rng) * 10)}, 2 + i % 7, 1, -1);
  const DistanceMap map(m, 0.0, 0.0, kRes);
  const CarOptions car;
  int free = 0, blocked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Pose p{x(rng), y(rng), heading(rng)};
    const DiscCover discs = car.Discs();
    bool discs_free = true;  // the first stage, unchanged: every disc centre far enough
    for (const double d : discs.offsets)
      discs_free &=
          map.Distance(p.x + std::cos(p.theta) * d, p.y + std::sin(p.theta) * d) > discs.radius + discs.margin;
    const bool expected = discs_free || map.Clearance(car, p) > car.safety_margin_m;
    ASSERT_EQ(map.Free(car, p), expected) << p.x << " " << p.y << " " << p.theta;
    (expected ? free : blocked)++;
  }
  EXPECT_GT(free, 2000);  // both answers well represented
  EXPECT_GT(blocked, 2000);
}

TEST(HybridAStarTest, StraightRunIsStraight) {
  Planner p(Map(30, 30));
  const Pose goal{25, 15, 0};
  const PlanResult r = p.search->Plan({5, 15, 0}, goal);
  ExpectFeasible(p, r, goal);
  EXPECT_NEAR(r.path.Length(), 20.0, 0.05);
  EXPECT_EQ(r.path.GearChanges(), 0);
}

TEST(HybridAStarTest, UTurnInACorridorRespectsTheTurningRadius) {
  // 10 m wide corridor: a forward U-turn needs 2·R_min + width ≈ 7.2 m.
  Planner p(Map(40, 10));
  const Pose goal{10, 5, M_PI};
  const PlanResult r = p.search->Plan({10, 5, 0}, goal);
  ExpectFeasible(p, r, goal);
  EXPECT_GT(r.path.Length(), 0.99 * M_PI * p.car.MinTurningRadius());  // at least half a circle (chords)
}

TEST(HybridAStarTest, ParksPerpendicularlyBetweenParkedCars) {
  // A 3 m wide bay between two parked cars (2 m × 4.5 m) on the south side of a
  // 30 m × 14 m lot; the car starts in the aisle and must end inside the bay.
  Planner p(Map(30, 14, {{10.0, 0.0, 2.0, 4.5}, {15.0, 0.0, 2.0, 4.5}}));
  const Pose goal{13.5, 1.0, M_PI / 2};  // rear axle 1 m from the back wall, nose out
  const PlanResult r = p.search->Plan({4, 9, 0}, goal);
  ExpectFeasible(p, r, goal);
  EXPECT_GE(r.path.GearChanges(), 1);  // reversing into the bay
}

TEST(HybridAStarTest, ReplanningToTheSameGoalReusesTheHeuristic) {
  Planner p(Map(30, 30, {{12, 5, 2, 20}}));
  const Pose goal{25, 15, 0};
  const PlanResult first = p.search->Plan({5, 15, 0}, goal);
  ASSERT_TRUE(first.found) << first.failure;
  EXPECT_GT(first.heuristic_milliseconds, 0.0);
  const PlanResult second = p.search->Plan({5, 12, 0.3}, goal);
  ASSERT_TRUE(second.found) << second.failure;
  EXPECT_EQ(second.heuristic_milliseconds, 0.0);
}

TEST(HybridAStarTest, UnreachableGoalFailsWithAReason) {
  // The goal sits in a closed room.
  cv::Mat m = Map(30, 30);
  cv::rectangle(m, cv::Point(180, 100), cv::Point(280, 200), cv::Scalar(1), 2);
  Planner p(m);
  const PlanResult r = p.search->Plan({5, 5, 0}, {23, 15, 0});
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.failure.find("cannot be reached"), std::string::npos) << r.failure;
}

TEST(HybridAStarTest, StartInCollisionOrOutsideIsAnError) {
  Planner p(Map(30, 30, {{10, 10, 5, 5}}));
  EXPECT_THROW(p.search->Plan({12, 12, 0}, {25, 25, 0}), InputError);
  EXPECT_THROW(p.search->Plan({5, 5, 0}, {45, 25, 0}), InputError);
}

// A start inside the safety margin that touches nothing (a map that changed under
// the car) is planned from; the path leaves the margin within a car length.
TEST(HybridAStarTest, EscapesAStartInsideTheMarginThatTouchesNothing) {
  Planner p(Map(30, 30, {{10, 10, 5, 5}}));
  const Pose start{11, 9.3, 0};  // alongside the box, its left side 0.05 m below it (margin 0.1)
  ASSERT_FALSE(p.map->Free(p.car, start));
  ASSERT_GT(p.map->Clearance(p.car, start), 0.0);
  const Pose goal{25, 5, 0};
  const PlanResult r = p.search->Plan(start, goal);
  ASSERT_TRUE(r.found) << r.failure;
  EXPECT_EQ(Overlaps(p.obstacles, p.car, r.path), 0);
  double along = 0;
  for (size_t i = 1; i < r.path.points.size(); ++i) {
    along += std::hypot(r.path.points[i].pose.x - r.path.points[i - 1].pose.x,
                        r.path.points[i].pose.y - r.path.points[i - 1].pose.y);
    if (along > p.car.length_m + p.options.step_m) {
      EXPECT_TRUE(p.map->Free(p.car, r.path.points[i].pose)) << i;
    }
  }
}

// Discrete bending energy Σ κ_i² Δs_i from consecutive chords (κ as Path::MaxCurvature).
double Bending(const Path& path) {
  double e = 0;
  const auto& p = path.points;
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const double ux = p[i].pose.x - p[i - 1].pose.x, uy = p[i].pose.y - p[i - 1].pose.y;
    const double vx = p[i + 1].pose.x - p[i].pose.x, vy = p[i + 1].pose.y - p[i].pose.y;
    const double mean = 0.5 * (std::hypot(ux, uy) + std::hypot(vx, vy));
    const double k = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy) / mean;
    e += k * k * mean;
  }
  return e;
}

// Around a wall the searched path (full-lock arcs, then the Reeds-Shepp shot)
// grazes the corner; the smoothed one keeps more clearance without bending more
// (within 5 %), stays within the steering limit and keeps its ends.
TEST(SmootherTest, SmoothsWithoutLosingFeasibility) {
  // The Reeds-Shepp heuristic everywhere: that search grazes the wall's end (the
  // default, grid-led far from the goal, happens to keep clear of it here).
  HybridAStarOptions search;
  search.reeds_shepp_radius_m = 1000;
  Planner p(Map(40, 20, {{15, 0, 2, 12}}), search);
  const Pose goal{32, 4, -M_PI / 2};
  const PlanResult r = p.search->Plan({4, 4, M_PI / 2}, goal);
  ASSERT_TRUE(r.found) << r.failure;
  const SmoothResult s = SmoothPath(r.path, *p.map, p.car, SmootherOptions{});
  ASSERT_TRUE(s.accepted) << s.note << " max curvature " << s.path.MaxCurvature() << " gears " << r.path.GearChanges();
  EXPECT_LE(Bending(s.path), 1.05 * Bending(r.path)) << Bending(s.path) << " vs " << Bending(r.path);
  EXPECT_EQ(s.path.GearChanges(), r.path.GearChanges());
  EXPECT_EQ(Overlaps(p.obstacles, p.car, s.path), 0);
  EXPECT_LE(s.path.MaxCurvature(), 1.05 / p.car.MinTurningRadius());
  EXPECT_NEAR(s.path.points.front().pose.x, 4, 1e-9);
  EXPECT_NEAR(s.path.points.back().pose.x, goal.x, 1e-9);
  EXPECT_NEAR(s.path.points.back().pose.y, goal.y, 1e-9);
  // Clearance: how far the path falls short of margin + buffer (what the smoother
  // seeks), summed over points, per metre; the ends and cusps cannot move, so the
  // sum, not the minimum, shows the gain (measured: −25 %).
  const auto shortfall = [&](const Path& path) {
    const SmootherOptions o;
    double sum = 0;
    for (const auto& q : path.points)
      sum += std::max(0.0, p.car.safety_margin_m + o.clearance_buffer_m - p.map->Clearance(p.car, q.pose));
    return sum / path.points.size();
  };
  ASSERT_GT(shortfall(r.path), 0.01) << "the searched path must graze the wall for this test to mean something";
  EXPECT_LT(shortfall(s.path), 0.85 * shortfall(r.path)) << shortfall(r.path) << " → " << shortfall(s.path);
}

// Drives the car from `pose` along the tracker's commands until it finishes: a
// kinematic bicycle with speed, acceleration and steering-rate limits, 20 Hz
// control, 100 Hz motion. Returns the smallest footprint clearance on the way.
double Drive(PathTracker& tracker, const CarOptions& car, const DistanceMap& map, Pose& pose, double max_s = 600) {
  double v = 0, steer = 0, worst = INFINITY;
  const double dt = 0.01, max_steer = car.max_steer_deg * M_PI / 180, rate = car.max_steer_rate_deg_s * M_PI / 180;
  Command held;
  for (int steps = 0; steps * dt < max_s && !tracker.finished(); ++steps) {
    if (steps % 5 == 0) held = tracker.Update(pose, v, steer);
    v += std::clamp(held.speed_mps - v, -car.max_accel_mps2 * dt, car.max_accel_mps2 * dt);
    steer += std::clamp(std::clamp(held.steer_rad, -max_steer, max_steer) - steer, -rate * dt, rate * dt);
    pose.x += v * std::cos(pose.theta) * dt, pose.y += v * std::sin(pose.theta) * dt;
    pose.theta += v * std::tan(steer) / car.wheelbase_m * dt;
    worst = std::min(worst, map.Clearance(car, pose));
  }
  return worst;
}

// Each steering law on a parking path with gear changes: it ends on the goal.
class PathTrackerLawTest : public ::testing::TestWithParam<std::string> {};

TEST_P(PathTrackerLawTest, FollowsAParkingManoeuvreToTheGoal) {
  Planner p(Map(30, 14, {{10.0, 0.0, 2.0, 4.5}, {15.0, 0.0, 2.0, 4.5}}));
  const Pose goal{13.5, 1.0, M_PI / 2};
  const PlanResult r = p.search->Plan({4, 9, 0}, goal);
  ASSERT_TRUE(r.found) << r.failure;
  const SmoothResult s = SmoothPath(r.path, *p.map, p.car, SmootherOptions{});
  TrackerOptions o;
  o.steering = GetParam();
  PathTracker tracker(o, p.car, s.path);
  Pose pose{4, 9, 0};
  const double worst = Drive(tracker, p.car, *p.map, pose);
  ASSERT_TRUE(tracker.finished()) << "not finished within 600 s";
  EXPECT_NEAR(pose.x, goal.x, 0.1);
  EXPECT_NEAR(pose.y, goal.y, 0.1);
  EXPECT_NEAR(std::remainder(pose.theta - goal.theta, 2 * M_PI), 0.0, 5 * M_PI / 180);  // the parking tolerance
  EXPECT_GT(worst, 0.0);  // never touched an obstacle (disc cover, conservative)
}

INSTANTIATE_TEST_SUITE_P(Laws, PathTrackerLawTest, ::testing::Values("rear_wheel_feedback", "pure_pursuit"));

// The feedback's signs in reverse: backing 20 m down a straight from 0.3 m to its
// side and 8° off its heading, the car settles on it (e'' + k_h e' + k_l e = 0 over
// distance: a metre-scale decay) and ends within centimetres.
TEST(PathTrackerTest, RearWheelFeedbackSettlesOnAStraightInReverse) {
  Path path;
  for (int i = 0; i <= 200; ++i) path.points.push_back({{25.0 - 0.1 * i, 5.0, 0.0}, -1});
  const CarOptions car;
  const DistanceMap map(Map(30, 10), 0.0, 0.0, kRes);
  PathTracker tracker(TrackerOptions{}, car, path);
  Pose pose{25.0, 5.3, 8 * M_PI / 180};
  Drive(tracker, car, map, pose);
  ASSERT_TRUE(tracker.finished());
  EXPECT_NEAR(pose.y, 5.0, 0.03);
  EXPECT_NEAR(std::remainder(pose.theta, 2 * M_PI), 0.0, 1.0 * M_PI / 180);
  EXPECT_NEAR(pose.x, 5.0, 0.1);
}

TEST(PathTrackerTest, HeadingNoiseOnAStraightDoesNotHoldTheSpeedDown) {
  // A 40 m straight at 0.1 m spacing whose headings jitter by ±2 mrad (what a
  // smoother leaves): mid-path the car may drive at full speed; differentiated
  // point to point the jitter reads as a curvature rate that would cap it at a
  // crawl.
  Path path;
  for (int i = 0; i <= 400; ++i) path.points.push_back({{0.1 * i, 0.0, (i % 2 ? 0.002 : -0.002)}, 1});
  const CarOptions car;
  PathTracker tracker(TrackerOptions{}, car, path);
  const Command c = tracker.Update({10.0, 0.0, 0.0}, car.max_speed_mps, 0.0);
  EXPECT_NEAR(c.speed_mps, car.max_speed_mps, 1e-9);
  EXPECT_NEAR(c.steer_rad, 0.0, 0.01);
}

}  // namespace
}  // namespace specht::plan
