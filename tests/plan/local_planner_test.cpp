// The local planner over a receding horizon: from a moving car to the route a horizon
// ahead in the route's direction, around a road user standing on the route, the route
// spliced on behind; nothing planned near the route's end; the same seed gives the
// same path; a box's discs cover it.
#include "specht/plan/local_planner.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_maps.h"

namespace specht::plan {
namespace {

// A straight route along y = 5 from x = 2 to x = 2 + length, points 0.1 m apart,
// the car facing +x; in reverse it backs from x = 2 + length to x = 2.
Path StraightRoute(double length, int direction = 1) {
  Path route;
  for (double s = 0; s <= length + 1e-9; s += 0.1)
    route.points.push_back({{direction > 0 ? 2 + s : 2 + length - s, 5.0, 0.0}, direction});
  return route;
}

struct Street {
  cv::Mat obstacles = Map(60, 10);
  CarOptions car;
  std::shared_ptr<DistanceMap> map = std::make_shared<DistanceMap>(obstacles, 0.0, 0.0, kRes);
  LocalPlannerOptions options;
  LocalPlanner planner{options, KinodynamicOptions{}, car, map};
};

TEST(LocalPlannerTest, PlansFromTheMovingCarToTheRouteAHorizonAheadAndSplicesTheRestOn) {
  Street s;
  const Path route = StraightRoute(50);
  const Pose car{6.0, 5.2, 0.05};
  const LocalPlan p = s.planner.Plan(car, {3.0, 0.0}, route, 0, {}, 7);
  ASSERT_TRUE(p.found) << p.failure;
  EXPECT_FALSE(p.skipped);
  ASSERT_GT(p.local_points, 10u);
  EXPECT_NEAR(p.path.points[0].pose.x, car.x, 1e-9);
  EXPECT_NEAR(p.path.points[0].pose.y, car.y, 1e-9);
  // The local path ends within the goal tolerance of the route a horizon ahead.
  const Pose& end = p.path.points[p.local_points - 1].pose;
  EXPECT_NEAR(end.x, 6.0 + s.options.horizon_m, s.options.goal_tolerance_m + 0.15);
  EXPECT_NEAR(end.y, 5.0, s.options.goal_tolerance_m);
  // Forward only, then the route's tail exactly, from a point ahead of the end.
  for (const auto& q : p.path.points) EXPECT_EQ(q.direction, 1);
  ASSERT_LT(p.route_resume, route.points.size());
  EXPECT_GT(route.points[p.route_resume].pose.x, end.x);
  EXPECT_EQ(p.path.points.size(), p.local_points + route.points.size() - p.route_resume);
  EXPECT_EQ(p.path.points.back().pose.x, route.points.back().pose.x);
  EXPECT_EQ(Overlaps(s.obstacles, s.car, p.path), 0);
  EXPECT_LE(p.iterations, s.options.max_iterations);
}

TEST(LocalPlannerTest, GoesAroundARoadUserStandingOnTheRouteWithItsMargin) {
  Street s;
  const Path route = StraightRoute(50);
  // A parked car (4.4 m × 1.8 m) at x = 14 beside the route: its box reaches to
  // 1.1 m from the route's line, less than the car's half width and the 0.5 m margin.
  const std::vector<MovingObstacle> parked = BoxDiscs(14.0, 3.0, 0.0, 2.2, 0.9, 0, 0, 0.5);
  const LocalPlan p = s.planner.Plan({4.0, 5.0, 0.0}, {2.0, 0.0}, route, 0, parked, 3);
  ASSERT_TRUE(p.found) << p.failure;
  const DiscCover discs = s.car.Discs();
  for (size_t i = 0; i < p.local_points; ++i) {
    const Pose& q = p.path.points[i].pose;
    for (const MovingObstacle& o : parked)
      for (const double d : discs.offsets)
        ASSERT_GE(std::hypot(q.x + std::cos(q.theta) * d - o.x, q.y + std::sin(q.theta) * d - o.y),
                  o.radius_m + discs.radius)
            << "at point " << i;
  }
  // The local path passes the parked car: it ends beyond it.
  EXPECT_GT(p.path.points[p.local_points - 1].pose.x, 14.0 + 2.2);
}

TEST(LocalPlannerTest, LeavesTheFinalMetresToTheRouteAndPlansAReversingStretchInReverseOnRequest) {
  Street s;
  // 6 m left: less than twice min_horizon_m, the last metres into the goal.
  const LocalPlan near_end = s.planner.Plan({2.0, 5.0, 0.0}, {1.0, 0.0}, StraightRoute(6), 0, {}, 1);
  EXPECT_TRUE(near_end.skipped);
  EXPECT_FALSE(near_end.found);
  const Path back = StraightRoute(30, -1);
  EXPECT_TRUE(s.planner.Plan({32.0, 5.1, 0.0}, {-0.5, 0.0}, back, 0, {}, 1).skipped);  // reverse off by default
  LocalPlannerOptions o = s.options;
  o.reverse = true;
  const LocalPlanner backing(o, KinodynamicOptions{}, s.car, s.map);
  const LocalPlan reversing = backing.Plan({32.0, 5.1, 0.0}, {-0.5, 0.0}, back, 0, {}, 1);
  ASSERT_TRUE(reversing.found) << reversing.failure;
  for (const auto& q : reversing.path.points) EXPECT_EQ(q.direction, -1);
  const Pose& end = reversing.path.points[reversing.local_points - 1].pose;
  EXPECT_NEAR(end.x, 32.0 - s.options.horizon_m, s.options.goal_tolerance_m + 0.15);
  EXPECT_NEAR(std::remainder(end.theta, 2 * M_PI), 0.0, s.options.goal_heading_tolerance_deg * M_PI / 180);
  EXPECT_LT(back.points[reversing.route_resume].pose.x, end.x);
  EXPECT_EQ(Overlaps(s.obstacles, s.car, reversing.path), 0);
}

TEST(LocalPlannerTest, TheSameSeedGivesTheSamePathWhateverRanBefore) {
  Street s;
  const Path route = StraightRoute(50);
  const LocalPlan a = s.planner.Plan({6.0, 5.0, 0.0}, {2.0, 0.0}, route, 0, {}, 11);
  s.planner.Plan({8.0, 5.3, 0.1}, {1.0, 0.0}, route, 0, {}, 12);  // draws other numbers in between
  const LocalPlan b = s.planner.Plan({6.0, 5.0, 0.0}, {2.0, 0.0}, route, 0, {}, 11);
  ASSERT_TRUE(a.found && b.found);
  ASSERT_EQ(a.path.points.size(), b.path.points.size());
  for (size_t i = 0; i < a.path.points.size(); ++i) {
    EXPECT_EQ(a.path.points[i].pose.x, b.path.points[i].pose.x);
    EXPECT_EQ(a.path.points[i].pose.y, b.path.points[i].pose.y);
  }
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(LocalPlannerTest, ABoxsDiscsCoverItGrownByTheMargin) {
  const double x = 3, y = -2, yaw = 0.7, hl = 2.2, hw = 0.9, margin = 0.5;
  const auto discs = BoxDiscs(x, y, yaw, hl, hw, 0.4, -0.2, margin);
  ASSERT_EQ(discs.size(), 3u);
  for (const auto& d : discs) {
    EXPECT_EQ(d.vx, 0.4);
    EXPECT_EQ(d.vy, -0.2);
  }
  // Every point of the box grown by the margin lies in a disc.
  for (double u = -(hl + margin); u <= hl + margin + 1e-9; u += 0.1)
    for (double v = -(hw + margin); v <= hw + margin + 1e-9; v += 0.1) {
      if (std::abs(u) > hl && std::abs(v) > hw && std::hypot(std::abs(u) - hl, std::abs(v) - hw) > margin) continue;
      const double px = x + u * std::cos(yaw) - v * std::sin(yaw), py = y + u * std::sin(yaw) + v * std::cos(yaw);
      bool covered = false;
      for (const auto& d : discs) covered = covered || std::hypot(px - d.x, py - d.y) <= d.radius_m + 1e-9;
      EXPECT_TRUE(covered) << "box point " << u << ", " << v;
    }
}

}  // namespace
}  // namespace specht::plan
