// The kinodynamic planner (OMPL SST, RRT, KPIECE1 over the bicycle model) on
// hand-made maps, each path checked by ExpectDrivable (collision-free with the
// exact footprint, curvature within the planned steering limit, never faster than
// the car): an obstacle crossing the corridor that blocks it at the
// start but not when the car gets there (time-aware checks); guided sampling into
// a parking bay; bounded calls on an unreachable goal; errors for bad endpoints.
// The slalom for every planner is in kinodynamic_slalom_test.cpp (slow label).
#include "specht/plan/kinodynamic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kinodynamic_test_support.h"
#include "specht/core/error.h"

namespace specht::plan {
namespace {

TEST(KinodynamicTest, PassesBehindACrossingObstacle) {
  // A 2.5 m radius obstacle fills the 5 m wide corridor at x = 12 at the start and
  // leaves it southwards at 1 m/s. Checked only at its start position, the goal is
  // unreachable; checked where it will be, the car passes once it has gone.
  const cv::Mat obstacles = Map(24, 5);
  const CarOptions car;
  const auto map = std::make_shared<DistanceMap>(obstacles, 0.0, 0.0, kRes);
  const Pose start{2, 2.5, 0}, goal{21, 2.5, 0};
  const MovingObstacle crossing{12, 2.5, 0, -1.0, 2.5};
  KinodynamicOptions o = Options("rrt");
  KinodynamicPlanner planner(o, car, map);
  const KinodynamicResult r = planner.Plan(start, goal, {crossing});
  ExpectDrivable(obstacles, car, o, r, goal);
  const DiscCover discs = car.Discs();
  for (size_t i = 0; i < r.path.points.size(); ++i) {
    const Pose& p = r.path.points[i].pose;
    const double oy = crossing.y + crossing.vy * r.times_s[i];
    for (const double d : discs.offsets)
      ASSERT_GE(std::hypot(p.x + std::cos(p.theta) * d - crossing.x, p.y + std::sin(p.theta) * d - oy),
                crossing.radius_m + discs.radius)
          << "at t = " << r.times_s[i];
  }

  o.max_iterations = 20000;
  KinodynamicPlanner frozen_planner(o, car, map);
  const MovingObstacle frozen{12, 2.5, 0, 0, 2.5};
  EXPECT_FALSE(frozen_planner.Plan(start, goal, {frozen}).found);
}

TEST(KinodynamicTest, StartInsideAMovingObstacleFailsWithAReason) {
  KinodynamicPlanner planner(KinodynamicOptions{}, CarOptions{},
                             std::make_shared<DistanceMap>(Map(30, 30), 0.0, 0.0, kRes));
  const KinodynamicResult r = planner.Plan({5, 5, 0}, {25, 25, 0}, {{5.5, 5.0, 1.0, 0.0, 0.5}});
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.failure, "the start lies within a moving obstacle");
}

TEST(KinodynamicTest, UnreachableGoalEndsWithinTheBudget) {
  cv::Mat m = Map(30, 30);
  cv::rectangle(m, cv::Point(180, 100), cv::Point(280, 200), cv::Scalar(1), 2);  // a closed room
  KinodynamicOptions o;
  o.time_budget_ms = 200;
  KinodynamicPlanner planner(o, CarOptions{}, std::make_shared<DistanceMap>(m, 0.0, 0.0, kRes));
  const KinodynamicResult r = planner.Plan({5, 5, 0}, {23, 15, 0});
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.approximate);  // the closest it got, for a caller to show
  EXPECT_NE(r.failure.find("within the budget"), std::string::npos) << r.failure;
  EXPECT_LT(r.milliseconds, 5000.0);  // a hang check, not a timing: the budget is 200 ms
}

TEST(KinodynamicTest, StartOrGoalInCollisionOrOutsideIsAnError) {
  KinodynamicPlanner planner(KinodynamicOptions{}, CarOptions{},
                             std::make_shared<DistanceMap>(Map(30, 30, {{10, 10, 5, 5}}), 0.0, 0.0, kRes));
  EXPECT_THROW(planner.Plan({12, 12, 0}, {25, 25, 0}), InputError);
  EXPECT_THROW(planner.Plan({5, 5, 0}, {45, 25, 0}), InputError);
}

TEST(KinodynamicTest, GuidedSamplingReachesABayTheSearchFound) {
  // The parking bay of HybridAStarTest: rear axle 1 m from the back wall between
  // two parked cars. Guided by a path into the bay the trees grow along it.
  const cv::Mat obstacles = Map(30, 14, {{10.0, 0.0, 2.0, 4.5}, {15.0, 0.0, 2.0, 4.5}});
  const CarOptions car;
  KinodynamicOptions o = Options("rrt");
  o.max_iterations = 400000;
  KinodynamicPlanner planner(o, car, std::make_shared<DistanceMap>(obstacles, 0.0, 0.0, kRes));
  Path guide;  // a straight reverse line into the bay from the aisle
  for (double y = 9; y >= 1.0; y -= 0.2) guide.points.push_back({{13.5, y, M_PI / 2}, -1});
  const Pose goal{13.5, 1.0, M_PI / 2};
  const KinodynamicResult r = planner.Plan({4, 9, 0}, goal, {}, &guide);
  ExpectDrivable(obstacles, car, o, r, goal);
}

}  // namespace
}  // namespace specht::plan
