#include "specht/sim/motion.h"

#include <algorithm>
#include <cmath>

#include "internal/geometry.h"

namespace specht::sim {
namespace {

// One step of motion with the speed and yaw rate set: the rear axle, `pivot_ahead`
// behind the pose point, moves along the heading and the body turns about it (a
// car's kinematics); with pivot_ahead 0 the pose point itself does.
void Advance(MoverState& s, double dt, double pivot_ahead) {
  const double rear_x = s.pose.x - pivot_ahead * std::cos(s.pose.yaw_rad) + s.speed_mps * std::cos(s.pose.yaw_rad) * dt;
  const double rear_y = s.pose.y - pivot_ahead * std::sin(s.pose.yaw_rad) + s.speed_mps * std::sin(s.pose.yaw_rad) * dt;
  s.pose.yaw_rad = internal::WrapAngle(s.pose.yaw_rad + s.yaw_rate * dt);
  s.pose.x = rear_x + pivot_ahead * std::cos(s.pose.yaw_rad);
  s.pose.y = rear_y + pivot_ahead * std::sin(s.pose.yaw_rad);
}

double Clip(double v, double lo, double hi) { return std::min(hi, std::max(lo, v)); }

}  // namespace

MotionParams SampleMotion(AgentClass cls, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  MotionParams p;
  switch (cls) {
    case AgentClass::kPedestrian:
      p.cruise_mps = Clip(1.4 + 0.3 * n01(rng), 0.5, 2.8);
      if (u01(rng) < 0.15) p.cruise_mps *= 1.9;  // a jogger
      p.accel_mps2 = 1.0, p.decel_mps2 = 1.5, p.max_turn_rate = 120 * internal::kDeg;
      p.heading_noise = 0.3, p.pause_probability = 0.6, p.reach_m = 0.4;
      p.length_m = 0.5, p.width_m = 0.5;
      break;
    case AgentClass::kCyclist:
      p.cruise_mps = Clip(4.5 + 1.2 * n01(rng), 1.8, 8.0);
      p.accel_mps2 = 1.2, p.decel_mps2 = 2.0, p.max_turn_rate = 35 * internal::kDeg;
      p.heading_noise = 0.05, p.reach_m = 1.0;
      p.length_m = 1.8, p.width_m = 0.6;
      break;
    case AgentClass::kCar:
      p.cruise_mps = Clip(7.0 + 2.0 * n01(rng), 3.0, 12.0);
      p.accel_mps2 = 2.5, p.decel_mps2 = 4.0, p.bicycle = true, p.wheelbase_m = 2.7,
      p.max_steer_rad = 35 * internal::kDeg;
      p.stop_s = 1.0 + 2.0 * u01(rng), p.reach_m = 2.0;
      p.length_m = 4.5, p.width_m = 1.8;
      break;
  }
  return p;
}

MotionParams EgoMotion(const Ego& ego) {
  MotionParams p;
  p.cruise_mps = ego.cruise_speed_mps;
  p.accel_mps2 = ego.model.max_accel_mps2, p.decel_mps2 = 2 * ego.model.max_accel_mps2;
  p.bicycle = true, p.wheelbase_m = ego.model.wheelbase_m, p.max_steer_rad = ego.model.max_steer_rad;
  p.pivot_ahead_m = ego.model.PivotAhead();
  p.stop_s = 2.0, p.reach_m = 1.5;
  p.length_m = ego.model.length_m, p.width_m = ego.model.width_m;
  return p;
}

RouteFollower::RouteFollower(std::vector<Waypoint> route, bool loop, MotionParams params, Pose2 start,
                             bool back_and_forth)
    : route_(std::move(route)), loop_(loop), params_(params) {
  // Back and forth: the route walked to its end and back, as one closed loop.
  if (back_and_forth && !loop_ && route_.size() >= 2) {
    for (size_t i = route_.size() - 1; i-- > 1;) route_.push_back(route_[i]);
    loop_ = true;
  }
  state_.pose = start;
  state_.finished = route_.empty();
}

double RouteFollower::PursuePath() {
  MoverState& s = state_;
  const MotionParams& p = params_;
  const size_t n = route_.size();
  // Advance the segment (target-1 -> target) while the mover is past its end.
  auto seg_start = [&](size_t t) { return route_[t == 0 ? n - 1 : t - 1].p; };
  for (int guard = 0; guard < static_cast<int>(n); ++guard) {
    const Vec2 a = seg_start(s.target), b = route_[s.target].p;
    const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
    const double u = len2 > 0 ? ((s.pose.x - a.x) * ex + (s.pose.y - a.y) * ey) / len2 : 1.0;
    const double to_end = std::hypot(b.x - s.pose.x, b.y - s.pose.y);
    if (u < 1.0 && to_end > p.reach_m * 0.5) break;
    if (route_[s.target].stop && p.stop_s > 0) {
      if (s.speed_mps >= 0.2) break;  // still braking for the stop
      s.wait_s = p.stop_s;
    }
    if (s.target + 1 < n)
      ++s.target;
    else if (loop_)
      s.target = 0;
    else {
      s.finished = true;
      return 0;
    }
    if (s.wait_s > 0) return 0;
  }
  // Lookahead point: walk along the route from the projection.
  const double lookahead = std::max(2.0, 0.8 * s.speed_mps + 1.5);
  Vec2 a = seg_start(s.target);
  size_t t = s.target;
  const double ex = route_[t].p.x - a.x, ey = route_[t].p.y - a.y, len2 = ex * ex + ey * ey;
  const double u = len2 > 0 ? Clip(((s.pose.x - a.x) * ex + (s.pose.y - a.y) * ey) / len2, 0, 1) : 1.0;
  Vec2 from{a.x + u * ex, a.y + u * ey};
  double left = lookahead, stop_distance = 1e9, along = 0;
  Vec2 goal = route_[t].p;
  for (size_t k = 0; k < n; ++k) {
    const double d = std::hypot(route_[t].p.x - from.x, route_[t].p.y - from.y);
    if (route_[t].stop && p.stop_s > 0) stop_distance = std::min(stop_distance, along + d);
    if (d >= left) {
      goal = {from.x + (route_[t].p.x - from.x) * left / d, from.y + (route_[t].p.y - from.y) * left / d};
      break;
    }
    left -= d, along += d, from = route_[t].p, goal = from;
    if (!loop_ && t + 1 == n) break;
    t = Next(t);
  }
  const double dx = goal.x - s.pose.x, dy = goal.y - s.pose.y, dist = std::max(std::hypot(dx, dy), 0.5);
  const double alpha = internal::WrapAngle(std::atan2(dy, dx) - s.pose.yaw_rad);
  const double delta = Clip(std::atan2(2 * p.wheelbase_m * std::sin(alpha), dist), -p.max_steer_rad, p.max_steer_rad);
  s.yaw_rate = s.speed_mps * std::tan(delta) / p.wheelbase_m;
  const double curvature = std::abs(2 * std::sin(alpha) / dist);
  double target = std::min(p.cruise_mps, curvature > 1e-6 ? std::sqrt(2.0 / curvature) : p.cruise_mps);
  if (stop_distance < 1e8) target = std::min(target, std::sqrt(2 * p.decel_mps2 * std::max(0.0, stop_distance - 0.3)));
  return target;
}

double RouteFollower::HeadForWaypoint(std::mt19937_64& rng) {
  MoverState& s = state_;
  const MotionParams& p = params_;
  const Waypoint& wp = route_[s.target];
  const double dx = wp.p.x - s.pose.x, dy = wp.p.y - s.pose.y, dist = std::hypot(dx, dy);
  if (dist < p.reach_m) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    if (p.pause_probability > 0 && u01(rng) < p.pause_probability) {
      s.wait_s = p.pause_min_s + (p.pause_max_s - p.pause_min_s) * u01(rng);
    }
    if (s.target + 1 < route_.size())
      ++s.target;
    else if (loop_)
      s.target = 0;
    else
      s.finished = true;
    return 0;
  }
  const double bearing = internal::WrapAngle(std::atan2(dy, dx) - s.pose.yaw_rad);
  std::normal_distribution<double> noise(0.0, p.heading_noise);
  s.yaw_rate = Clip(3.0 * bearing + (p.heading_noise > 0 ? noise(rng) : 0.0), -p.max_turn_rate, p.max_turn_rate);
  // Slow in turns and when arriving: full speed straight ahead, a quarter at 90° off.
  const double turn = std::max(0.25, std::pow(std::cos(std::min(std::abs(bearing), M_PI / 2)), 2));
  return std::min(p.cruise_mps * turn, std::sqrt(2 * p.decel_mps2 * dist) + 0.3);
}

void RouteFollower::Step(double dt, std::mt19937_64& rng) {
  MoverState& s = state_;
  const MotionParams& p = params_;
  double target_speed = 0;
  if (s.wait_s > 0) {
    s.wait_s -= dt;
    s.yaw_rate = 0;
  } else if (!s.finished) {
    target_speed = p.bicycle ? PursuePath() : HeadForWaypoint(rng);
  }
  if (s.wait_s > 0 || s.finished) target_speed = 0;
  const double dv = Clip(target_speed - s.speed_mps, -p.decel_mps2 * dt, p.accel_mps2 * dt);
  s.accel_mps2 = dv / dt;
  s.speed_mps += dv;
  if (p.bicycle) s.yaw_rate = std::abs(s.speed_mps) < 1e-6 ? 0.0 : s.yaw_rate;
  Advance(s, dt, p.bicycle ? p.pivot_ahead_m : 0.0);
}

void RouteFollower::StepCommanded(double dt, double speed_mps, double steer_rad, double steer_rate_rad_s) {
  MoverState& s = state_;
  const MotionParams& p = params_;
  const double limit = p.bicycle ? p.max_steer_rad : 0.0;
  const double steer = Clip(steer_rad, -limit, limit);
  s.steer_rad += Clip(steer - s.steer_rad, -steer_rate_rad_s * dt, steer_rate_rad_s * dt);
  // Braking (towards zero) uses the deceleration limit, speeding up the acceleration one.
  const bool braking = std::abs(speed_mps) < std::abs(s.speed_mps) || speed_mps * s.speed_mps < 0;
  const double rate = braking ? p.decel_mps2 : p.accel_mps2;
  const double dv = Clip(speed_mps - s.speed_mps, -rate * dt, rate * dt);
  s.accel_mps2 = dv / dt;
  s.speed_mps += dv;
  s.yaw_rate = s.speed_mps * std::tan(s.steer_rad) / p.wheelbase_m;
  Advance(s, dt, p.bicycle ? p.pivot_ahead_m : 0.0);
}

}  // namespace specht::sim
