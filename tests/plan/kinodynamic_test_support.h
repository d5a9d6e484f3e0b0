// Shared by the kinodynamic planner tests: iteration-bounded options (with a long
// time budget, so a slow machine changes only the wall time) and the check every
// returned path must pass.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "specht/plan/kinodynamic.h"
#include "test_maps.h"

namespace specht::plan {

// 30 m × 10 m with three 6 m walls from alternate sides, 9 m apart: 4 m gaps.
inline cv::Mat Slalom() { return Map(30, 10, {{6, 0, 0.5, 6}, {15, 4, 0.5, 6}, {24, 0, 0.5, 6}}); }

inline KinodynamicOptions Options(const std::string& planner) {
  KinodynamicOptions o;
  o.planner = planner;
  o.time_budget_ms = 60000;
  o.max_iterations = 200000;
  o.stop_at_first_solution = true;
  return o;
}

inline void ExpectDrivable(const cv::Mat& obstacles, const CarOptions& car, const KinodynamicOptions& o,
                           const KinodynamicResult& r, const Pose& goal) {
  ASSERT_TRUE(r.found) << r.failure;
  ASSERT_GE(r.path.points.size(), 2u);
  const Pose end = r.path.points.back().pose;
  EXPECT_LE(std::hypot(end.x - goal.x, end.y - goal.y), o.goal_tolerance_m + 1e-9);
  EXPECT_LE(std::abs(std::remainder(end.theta - goal.theta, 2 * M_PI)),
            o.goal_heading_tolerance_deg * M_PI / 180 + 1e-9);
  EXPECT_EQ(Overlaps(obstacles, car, r.path), 0);
  const double limit = std::tan(car.max_steer_deg * M_PI / 180 * o.steer_fraction) / car.wheelbase_m;
  EXPECT_LE(r.path.MaxCurvature(), limit * 1.05);  // chords of arcs sampled every control step
  ASSERT_EQ(r.times_s.size(), r.path.points.size());
  for (size_t i = 1; i < r.times_s.size(); ++i) {
    const double dt = r.times_s[i] - r.times_s[i - 1];
    const double ds = std::hypot(r.path.points[i].pose.x - r.path.points[i - 1].pose.x,
                                 r.path.points[i].pose.y - r.path.points[i - 1].pose.y);
    ASSERT_GT(dt, 0.0) << i;
    EXPECT_LE(ds, car.max_speed_mps * dt + 1e-6) << i;  // never faster than the car
  }
  EXPECT_NEAR(r.duration_s, r.times_s.back(), 1e-6);
}

}  // namespace specht::plan
