#include "specht/plan/local_planner.h"

#include <algorithm>
#include <cmath>

#include "specht/core/error.h"

namespace specht::plan {

std::vector<std::string> LocalPlannerOptions::Relations() const {
  if (min_horizon_m >= horizon_m) return {"min_horizon_m must be below horizon_m"};
  return {};
}

std::vector<MovingObstacle> BoxDiscs(double x, double y, double yaw, double half_length, double half_width, double vx,
                                     double vy, double margin_m) {
  // n discs along the length, each covering a 2·hl/n × 2·hw slice of the box.
  const double hl = std::max(half_length, half_width), hw = std::min(half_length, half_width);
  const double along = half_length >= half_width ? yaw : yaw + M_PI / 2;
  const int n = std::max(1, static_cast<int>(std::ceil(hl / hw - 1e-9)));
  const double slice = hl / n, radius = std::hypot(slice, hw) + margin_m;
  std::vector<MovingObstacle> discs;
  for (int k = 0; k < n; ++k) {
    const double offset = -hl + slice * (2 * k + 1);
    discs.push_back({x + offset * std::cos(along), y + offset * std::sin(along), vx, vy, radius});
  }
  return discs;
}

namespace {

double Step(const Path& path, size_t i) {
  const Pose &a = path.points[i - 1].pose, &b = path.points[i].pose;
  return std::hypot(b.x - a.x, b.y - a.y);
}

// The route point nearest `pose` from `from` on, looking no further than 30 m along.
size_t Projection(const Path& route, size_t from, const Pose& pose) {
  size_t best = std::min(from, route.points.size() - 1);
  double best_d = INFINITY, along = 0;
  for (size_t i = best; i < route.points.size() && along < 30.0; ++i) {
    if (i > from) along += Step(route, i);
    const double d = std::hypot(route.points[i].pose.x - pose.x, route.points[i].pose.y - pose.y);
    if (d < best_d) best_d = d, best = i;
  }
  return best;
}

}  // namespace

LocalPlanner::LocalPlanner(const LocalPlannerOptions& options, const KinodynamicOptions& kinodynamic,
                           const CarOptions& car, std::shared_ptr<const DistanceMap> map)
    : o_(options), car_(car), map_(std::move(map)) {
  KinodynamicOptions k = kinodynamic;
  k.planner = o_.planner, k.max_iterations = o_.max_iterations, k.time_budget_ms = o_.time_budget_ms;
  k.stop_at_first_solution = o_.stop_at_first_solution;
  k.goal_tolerance_m = o_.goal_tolerance_m, k.goal_heading_tolerance_deg = o_.goal_heading_tolerance_deg;
  k.directions = "forward";
  forward_ = std::make_unique<KinodynamicPlanner>(k, car_, map_);
  k.directions = "reverse";
  reverse_ = std::make_unique<KinodynamicPlanner>(k, car_, map_);
}
LocalPlanner::~LocalPlanner() = default;

LocalPlan LocalPlanner::Plan(const Pose& pose, const StartMotion& motion, const Path& route, size_t from_index,
                             const std::vector<MovingObstacle>& obstacles, unsigned seed) const {
  LocalPlan out;
  if (route.points.size() < 2) {
    out.skipped = true;
    return out;
  }
  const size_t at = Projection(route, from_index, pose);
  out.route_index = at;
  const int direction = route.points[at].direction;
  if (direction < 0 && !o_.reverse) {
    out.skipped = true;
    return out;
  }
  // The stretch ahead: to the next cusp or the route's end.
  std::vector<double> along = {0.0};
  size_t end = at;
  while (end + 1 < route.points.size() && route.points[end + 1].direction == route.points[at].direction) {
    ++end;
    along.push_back(along.back() + Step(route, end));
  }
  const double reach = std::min(o_.horizon_m, along.back() - o_.min_horizon_m);
  if (reach < o_.min_horizon_m) {
    out.skipped = true;  // the final metres into the bay, or to a cusp
    return out;
  }
  // The local goal: `reach` along, moved on while a road user stands on it.
  const DiscCover discs = car_.Discs();
  size_t goal = at;
  while (goal < end && along[goal - at] < reach) ++goal;
  const double farthest = std::min(2 * reach, along.back() - o_.min_horizon_m);
  bool moved = false;
  while (goal < end && along[goal - at] < farthest &&
         !ClearOfMovingObstacles(discs, route.points[goal].pose, obstacles))
    ++goal, moved = true;
  // Past a road user the car needs room to come back onto the route: a car length.
  const double back_on = along[goal - at] + car_.length_m;
  while (moved && goal < end && along[goal - at] < std::min(back_on, farthest)) ++goal;
  if (!ClearOfMovingObstacles(discs, route.points[goal].pose, obstacles)) {
    out.failure = "a road user stands on the route ahead";
    return out;
  }
  Path guide;
  guide.points.assign(route.points.begin() + static_cast<long>(at), route.points.begin() + static_cast<long>(goal) + 1);
  KinodynamicPlanner::Reseed(seed);
  KinodynamicResult found;
  try {
    found = (direction > 0 ? forward_ : reverse_)->Plan(pose, route.points[goal].pose, obstacles, &guide, motion);
  } catch (const InputError& e) {
    found.failure = e.what();  // the car within a safety margin of a wall, say
  }
  out.milliseconds = found.milliseconds, out.iterations = found.expansions;
  if (!found.found) {
    out.failure = found.failure;
    return out;
  }
  // The route resumes at its first point ahead of the local path's end (in the
  // direction of travel).
  const Pose& last = found.path.points.back().pose;
  size_t resume = goal;
  while (resume < route.points.size() && direction * ((route.points[resume].pose.x - last.x) * std::cos(last.theta) +
                                                      (route.points[resume].pose.y - last.y) * std::sin(last.theta)) <=
                                             0)
    ++resume;
  out.found = true;
  out.path = found.path;
  for (auto& p : out.path.points) p.direction = direction;
  out.local_points = out.path.points.size();
  out.route_resume = resume;
  out.path.points.insert(out.path.points.end(), route.points.begin() + static_cast<long>(resume), route.points.end());
  return out;
}

}  // namespace specht::plan
