#include "specht/plan/tracker.h"

#include <algorithm>
#include <cmath>

namespace specht::plan {

constexpr double kCurvatureWindow = 0.5;  // m

PathTracker::PathTracker(const TrackerOptions& options, const CarOptions& car, Path path)
    : o_(options), car_(car), path_(std::move(path)) {
  const auto& p = path_.points;
  along_.assign(p.size(), 0.0);
  for (size_t i = 1; i < p.size(); ++i)
    along_[i] = along_[i - 1] + std::hypot(p[i].pose.x - p[i - 1].pose.x, p[i].pose.y - p[i - 1].pose.y);
  stretch_end_.assign(p.size(), p.empty() ? 0 : p.size() - 1);
  // A stretch ends at the last point before the direction flips (the cusp).
  for (size_t i = p.size(); i-- > 1;)
    stretch_end_[i - 1] = p[i].direction != p[i - 1].direction && i - 1 > 0 ? i - 1 : stretch_end_[i];
  finished_ = p.size() < 2;
}

Command PathTracker::Update(const Pose& pose, double speed, double steer_now) {
  const auto& p = path_.points;
  if (finished_) return {};
  const auto dist = [&](size_t i) { return std::hypot(p[i].pose.x - pose.x, p[i].pose.y - pose.y); };
  // Arc length of the car's projection on the current stretch.
  const auto along_car = [&](size_t end) {
    while (index_ < end && dist(index_ + 1) <= dist(index_)) ++index_;
    const size_t j = std::min(index_ + 1, end);
    const double ex = p[j].pose.x - p[index_].pose.x, ey = p[j].pose.y - p[index_].pose.y;
    const double len = std::hypot(ex, ey);
    const double u = len > 1e-9 ? ((pose.x - p[index_].pose.x) * ex + (pose.y - p[index_].pose.y) * ey) / len : 0.0;
    return along_[index_] + std::clamp(u, -0.5, len);
  };
  size_t end = stretch_end_[index_];
  double left = along_[end] - along_car(end);
  // At a stretch's end: stop there, then take the next stretch (a gear change) or finish.
  if (left <= o_.goal_tolerance_m) {
    if (std::abs(speed) > o_.stop_speed_mps) return {0.0, 0.0};
    if (end + 1 >= p.size()) {
      finished_ = true;
      return {};
    }
    index_ = end + 1;
    end = stretch_end_[index_];
    left = along_[end] - along_car(end);
  }
  remaining_ = along_.back() - along_[index_];
  const int direction = p[std::min(index_ + 1, end)].direction;
  const double lookahead = o_.min_lookahead_m + o_.lookahead_per_mps * std::abs(speed);
  const double max_steer = car_.max_steer_deg * M_PI / 180;
  const double steer = std::clamp(o_.steering == "pure_pursuit" ? PurePursuit(pose, lookahead, end, left, direction)
                                                                : RearWheelFeedback(pose, end, direction),
                                  -max_steer, max_steer);
  if (std::abs(speed) <= o_.stop_speed_mps && std::abs(steer - steer_now) > o_.steer_ready_deg * M_PI / 180)
    return {0.0, steer};
  // Speed: direction limit, curvature ahead, braking to the stretch's end.
  // Curvature κ and its change per metre dκ/ds over the next metres: the steering
  // angle follows dκ/dt = dκ/ds · v at a limited rate (κ = tan δ / L, so
  // dδ/dt ≈ L · dκ/ds · v near straight), which bounds v through S-bends.
  // Both over windows of kCurvatureWindow metres: a path's headings carry
  // millimetre noise that, differentiated twice point to point, reads as steering
  // rates no car needs and would hold the speed at a crawl.
  double kappa = 0, kappa_rate = 0, previous = NAN;
  size_t from = index_;
  for (size_t i = index_ + 1; i <= end && along_[i] - along_[index_] < 3.0 + lookahead; ++i) {
    const double ds = along_[i] - along_[from];
    if (ds < kCurvatureWindow && i < end) continue;
    if (ds < 1e-3) break;
    const double k = std::remainder(p[i].pose.theta - p[from].pose.theta, 2 * M_PI) / ds;
    kappa = std::max(kappa, std::abs(k));
    if (!std::isnan(previous)) kappa_rate = std::max(kappa_rate, std::abs(k - previous) / ds);
    previous = k, from = i;
  }
  const double steer_rate = car_.max_steer_rate_deg_s * M_PI / 180;
  const double v_max = direction > 0 ? car_.max_speed_mps : car_.max_reverse_mps;
  double v = std::min({v_max, kappa > 1e-6 ? std::sqrt(o_.max_lateral_accel_mps2 / kappa) : v_max,
                       kappa_rate > 1e-6 ? 0.5 * steer_rate / (car_.wheelbase_m * kappa_rate) : v_max,
                       std::sqrt(2.0 * 0.8 * car_.max_accel_mps2 * std::max(0.0, left))});
  if (remaining_ < o_.approach_distance_m) v = std::min(v, o_.approach_speed_mps);
  v = std::max(v, std::min(0.3, v_max));  // creep the last centimetres rather than stall short
  return {direction * v, steer};
}

double PathTracker::PurePursuit(const Pose& pose, double lookahead, size_t end, double left, int direction) const {
  const auto& p = path_.points;
  size_t g = index_;
  while (g < end && along_[g] - along_[index_] < lookahead) ++g;
  double gx = p[g].pose.x, gy = p[g].pose.y;
  if (g == end && left < lookahead) {  // past the end: on the end pose's heading line, so the car arrives aligned
    const double beyond = (lookahead - left) * direction;
    gx += beyond * std::cos(p[end].pose.theta), gy += beyond * std::sin(p[end].pose.theta);
  }
  const double heading = direction > 0 ? pose.theta : pose.theta + M_PI;
  const double alpha = std::atan2(gy - pose.y, gx - pose.x) - heading;
  const double d = std::max(0.3, std::hypot(gx - pose.x, gy - pose.y));
  const double steer = std::atan(2.0 * car_.wheelbase_m * std::sin(alpha) / d);
  return direction < 0 ? -steer : steer;
}

double PathTracker::RearWheelFeedback(const Pose& pose, size_t end, int direction) const {
  const auto& p = path_.points;
  // The reference: the car's projection on the segment from the nearest point on.
  const size_t i = std::min(index_, end > 0 ? end - 1 : 0), j = std::min(i + 1, p.size() - 1);
  const double ex = p[j].pose.x - p[i].pose.x, ey = p[j].pose.y - p[i].pose.y, len2 = ex * ex + ey * ey;
  const double u =
      len2 > 1e-12 ? std::clamp(((pose.x - p[i].pose.x) * ex + (pose.y - p[i].pose.y) * ey) / len2, 0.0, 1.0) : 0.0;
  const double dtheta = std::remainder(p[j].pose.theta - p[i].pose.theta, 2 * M_PI);
  const double theta_ref = p[i].pose.theta + u * dtheta;
  const double xr = p[i].pose.x + u * ex, yr = p[i].pose.y + u * ey;
  const double e = -std::sin(theta_ref) * (pose.x - xr) + std::cos(theta_ref) * (pose.y - yr);
  const double theta_e = std::remainder(pose.theta - theta_ref, 2 * M_PI);
  // κ = dθ/dσ over kCurvatureWindow ahead within the stretch (behind when at its end).
  size_t a = i, b = i;
  while (b < end && along_[b] - along_[i] < kCurvatureWindow) ++b;
  while (a > 0 && along_[b] - along_[a] < kCurvatureWindow && p[a - 1].direction == direction) --a;
  const double ds = along_[b] - along_[a];
  const double kappa = ds > 1e-6 ? std::remainder(p[b].pose.theta - p[a].pose.theta, 2 * M_PI) / (direction * ds) : 0.0;
  const double sinc = std::abs(theta_e) < 1e-6 ? 1.0 : std::sin(theta_e) / theta_e;
  const double feedforward = kappa * std::cos(theta_e) / std::max(0.1, 1.0 - kappa * e);
  return std::atan(car_.wheelbase_m * (feedforward - o_.k_heading * direction * theta_e - o_.k_lateral * e * sinc));
}

}  // namespace specht::plan
