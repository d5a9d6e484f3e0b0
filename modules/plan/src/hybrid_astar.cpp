#include "specht/plan/hybrid_astar.h"

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

#include "specht/core/error.h"

namespace specht::plan {

std::vector<std::string> HybridAStarOptions::Relations() const {
  std::vector<std::string> p;
  if (step_m <= xy_cell_m * std::sqrt(2.0)) p.push_back("step_m must exceed the cell diagonal (xy_cell_m · √2)");
  return p;
}

HybridAStarOptions FineSearchDefaults() {
  HybridAStarOptions o;
  o.steer_fraction = 1.0, o.xy_cell_m = 0.25, o.step_m = 0.4, o.max_expansions = 100000, o.time_budget_ms = 2000;
  return o;
}

HybridAStarOptions WithoutTimeBudget(HybridAStarOptions o) {
  o.time_budget_ms = std::numeric_limits<double>::infinity();
  return o;
}

namespace {

using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a) { return std::chrono::duration<double, std::milli>(Clock::now() - a).count(); }

// Drives `s` metres (negative: reverse) with steering tan δ = `tan_steer` from `p`.
Pose Drive(const Pose& p, double s, double tan_steer, double wheelbase) {
  if (std::abs(tan_steer) < 1e-9) return {p.x + s * std::cos(p.theta), p.y + s * std::sin(p.theta), p.theta};
  const double radius = wheelbase / tan_steer, theta = p.theta + s / radius;
  return {p.x + radius * (std::sin(theta) - std::sin(p.theta)), p.y - radius * (std::cos(theta) - std::cos(p.theta)),
          std::remainder(theta, 2 * M_PI)};
}

// OMPL keeps interpolation along a computed Reeds-Shepp path protected; we need it
// to sample the path we already have instead of solving it again per sample.
struct ReedsSheppSpace : ompl::base::ReedsSheppStateSpace {
  using ompl::base::ReedsSheppStateSpace::interpolate;
  using ompl::base::ReedsSheppStateSpace::ReedsSheppStateSpace;
};

struct Node {
  Pose pose;
  double g = 0;
  int parent = -1;
  int direction = 0;     // of the arc that led here (0 at the start)
  double tan_steer = 0;  // of that arc
};

}  // namespace

struct HybridAStar::Impl {
  HybridAStarOptions o;
  CarOptions car;
  DiscCover discs;
  std::shared_ptr<const DistanceMap> map;
  std::shared_ptr<ReedsSheppSpace> rs;
  int cols = 0, rows = 0;
  // Grid distances to the cached goal cell (−1: unreachable).
  int cached_goal = -1;
  std::vector<float> to_goal;
  // Closed set: node index per (cell, heading), valid when stamp matches.
  std::vector<uint32_t> stamp, closed;  // = search when the key has a node / was expanded
  std::vector<int> slot;
  uint32_t search = 0;

  int CellOf(double x, double y) const {
    const int c = static_cast<int>(std::floor((x - map->origin_x()) / o.xy_cell_m));
    const int r = static_cast<int>(std::floor((y - map->origin_y()) / o.xy_cell_m));
    return c < 0 || r < 0 || c >= cols || r >= rows ? -1 : r * cols + c;
  }
  int KeyOf(const Pose& p) const {
    const int cell = CellOf(p.x, p.y);
    if (cell < 0) return -1;
    const double t = std::remainder(p.theta, 2 * M_PI) + M_PI;
    const int bin = std::min(o.heading_bins - 1, static_cast<int>(t / (2 * M_PI) * o.heading_bins));
    return cell * o.heading_bins + bin;
  }

  // Dijkstra from the goal cell over cells the rear axle can pass through: farther
  // than half the car's width (+ margin) from obstacles — the axle centre has the
  // car's sides on either hand — except within a car length of the goal, where the
  // car may stand with an obstacle just behind it (then only the rear overhang
  // separates the two; near the start Plan allows the same). Squeezing through gaps narrower than the car
  // is what made the search wander (with the overhang everywhere many of
  // bench/plan_bench's problems ran out of their budget).
  void GridDistances(int goal_cell, const Pose& goal) {
    to_goal.assign(static_cast<size_t>(cols) * rows, -1.f);
    const double need_far = car.width_m / 2 + car.safety_margin_m;
    const double need_near = std::min(car.width_m / 2, car.rear_overhang_m) + car.safety_margin_m;
    const double half_diagonal = o.xy_cell_m * std::sqrt(0.5);
    std::vector<uint8_t> passable(to_goal.size());
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const double x = map->origin_x() + (c + 0.5) * o.xy_cell_m, y = map->origin_y() + (r + 0.5) * o.xy_cell_m;
        const bool near_end = std::hypot(x - goal.x, y - goal.y) < car.length_m;
        passable[r * cols + c] = map->Distance(x, y) + half_diagonal > (near_end ? need_near : need_far);
      }
    using Item = std::pair<float, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    to_goal[goal_cell] = 0;
    open.push({0.f, goal_cell});
    const float diagonal = static_cast<float>(o.xy_cell_m * std::sqrt(2.0)), straight = static_cast<float>(o.xy_cell_m);
    while (!open.empty()) {
      const auto [d, cell] = open.top();
      open.pop();
      if (d > to_goal[cell]) continue;
      const int r = cell / cols, c = cell % cols;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int nr = r + dr, nc = c + dc;
          if ((dr == 0 && dc == 0) || nr < 0 || nc < 0 || nr >= rows || nc >= cols) continue;
          const int n = nr * cols + nc;
          if (!passable[n]) continue;
          const float nd = d + (dr && dc ? diagonal : straight);
          if (to_goal[n] < 0 || nd < to_goal[n]) to_goal[n] = nd, open.push({nd, n});
        }
    }
  }

  double ReedsShepp(const Pose& a, const Pose& b) const {
    ompl::base::ScopedState<ompl::base::SE2StateSpace> s1(rs), s2(rs);
    s1->setXY(a.x, a.y), s1->setYaw(a.theta);
    s2->setXY(b.x, b.y), s2->setYaw(b.theta);
    return rs->distance(s1.get(), s2.get());
  }

  // Poses of the Reeds-Shepp path a → b every `spacing`, with directions; empty when
  // any of them collides.
  std::vector<PathPoint> ReedsSheppShot(const Pose& a, const Pose& b, double spacing) const {
    ompl::base::ScopedState<ompl::base::SE2StateSpace> s1(rs), s2(rs), s(rs);
    s1->setXY(a.x, a.y), s1->setYaw(a.theta);
    s2->setXY(b.x, b.y), s2->setYaw(b.theta);
    const auto path = rs->reedsShepp(s1.get(), s2.get());
    const double rho = car.MinTurningRadius(), total = path.length() * rho;
    const int n = std::max(1, static_cast<int>(std::ceil(total / spacing)));
    std::vector<PathPoint> out;
    for (int i = 1; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      rs->interpolate(s1.get(), path, t, s.get());
      // Direction: the sign of the segment that contains arc length t · total.
      double along = t * path.length(), acc = 0;
      int direction = 1;
      for (int k = 0; k < 5; ++k) {
        acc += std::abs(path.length_[k]);
        if (path.length_[k] != 0 && along <= acc + 1e-9) {
          direction = path.length_[k] < 0 ? -1 : 1;
          break;
        }
      }
      const Pose p{s->getX(), s->getY(), s->getYaw()};
      if (!map->Free(discs, p)) return {};
      out.push_back({p, direction});
    }
    return out;
  }

  // The shortest stretch between gear changes on the Reeds-Shepp path a → b, in
  // metres; its first stretch counts only when it starts one (the car arrived at
  // `a` driving the other way, or not at all).
  double ShortestShotStretch(const Pose& a, const Pose& b, int arrival_direction) const {
    ompl::base::ScopedState<ompl::base::SE2StateSpace> s1(rs), s2(rs);
    s1->setXY(a.x, a.y), s1->setYaw(a.theta);
    s2->setXY(b.x, b.y), s2->setYaw(b.theta);
    const auto path = rs->reedsShepp(s1.get(), s2.get());
    double shortest = INFINITY, stretch = 0;
    int direction = 0;
    bool first = true;
    for (int k = 0; k < 5; ++k) {
      if (path.length_[k] == 0) continue;
      const int d = path.length_[k] < 0 ? -1 : 1;
      if (direction != 0 && d != direction) {
        if (!first || direction != arrival_direction) shortest = std::min(shortest, stretch);
        first = false, stretch = 0;
      }
      direction = d, stretch += std::abs(path.length_[k]) * car.MinTurningRadius();
    }
    if (!first || direction != arrival_direction) shortest = std::min(shortest, stretch);
    return shortest;
  }

  // The arc from a node's parent, sampled every `spacing` (excluding the parent).
  void AppendArc(const Node& from, const Node& to, double spacing, std::vector<PathPoint>& out) const {
    const int n = std::max(1, static_cast<int>(std::round(o.step_m / spacing)));
    for (int i = 1; i <= n; ++i)
      out.push_back({Drive(from.pose, to.direction * o.step_m * i / n, to.tan_steer, car.wheelbase_m), to.direction});
    out.back().pose = to.pose;
  }

  bool ArcFree(const Pose& p, double s, double tan_steer, const DiscCover& cover, Pose& end) const {
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(s) / o.collision_step_m)));
    for (int i = 1; i <= n; ++i) {
      end = Drive(p, s * i / n, tan_steer, car.wheelbase_m);
      if (!map->Free(cover, end)) return false;
    }
    return true;
  }
};

HybridAStar::HybridAStar(const HybridAStarOptions& options, const CarOptions& car,
                         std::shared_ptr<const DistanceMap> map)
    : impl_(std::make_unique<Impl>()) {
  impl_->o = options;
  impl_->car = car;
  impl_->car.max_steer_deg *= options.steer_fraction;
  impl_->discs = car.Discs();
  impl_->map = std::move(map);
  impl_->rs = std::make_shared<ReedsSheppSpace>(impl_->car.MinTurningRadius());
  impl_->cols = static_cast<int>(std::ceil(impl_->map->cols() * impl_->map->resolution() / options.xy_cell_m));
  impl_->rows = static_cast<int>(std::ceil(impl_->map->rows() * impl_->map->resolution() / options.xy_cell_m));
  const size_t keys = static_cast<size_t>(impl_->cols) * impl_->rows * options.heading_bins;
  impl_->stamp.assign(keys, 0);
  impl_->closed.assign(keys, 0);
  impl_->slot.assign(keys, -1);
}
HybridAStar::~HybridAStar() = default;

PlanResult HybridAStar::Plan(const Pose& start_in, const Pose& goal_in) {
  Impl& m = *impl_;
  const Pose start{start_in.x, start_in.y, std::remainder(start_in.theta, 2 * M_PI)};
  const Pose goal{goal_in.x, goal_in.y, std::remainder(goal_in.theta, 2 * M_PI)};
  const auto t0 = Clock::now();
  PlanResult result;
  // A start inside the safety margin but touching nothing (the map changed under a
  // car that was clear) is escaped from: within a car length of it arcs need only
  // miss the obstacles (margin 0).
  DiscCover escape = m.discs;
  escape.margin = 0;
  const bool escaping = m.map->Contains(start.x, start.y) && !m.map->Free(m.discs, start) && m.map->Free(escape, start);
  if (!escaping) CheckEndpoint(*m.map, m.car, start, "start");
  CheckEndpoint(*m.map, m.car, goal, "goal");
  const int goal_cell = m.CellOf(goal.x, goal.y);
  if (goal_cell != m.cached_goal) {
    const auto th = Clock::now();
    m.GridDistances(goal_cell, goal);
    m.cached_goal = goal_cell;
    result.heuristic_milliseconds = Ms(th);
  }
  // Grid distance of a pose's cell; within a car length of the start a cell the
  // grid calls impassable may still hold the car (see GridDistances): there only
  // the Reeds-Shepp term counts.
  const auto grid = [&](const Pose& p) -> double {
    const float d = m.to_goal[m.CellOf(p.x, p.y)];
    if (d >= 0) return d;
    return std::hypot(p.x - start.x, p.y - start.y) < m.car.length_m ? 0.0 : -1.0;
  };
  const auto heuristic = [&](const Pose& p) {
    const double to_go = grid(p);
    if (to_go > m.o.reeds_shepp_radius_m) return m.o.heuristic_weight * to_go;
    return m.o.heuristic_weight * std::max(to_go, m.ReedsShepp(p, goal));
  };
  bool connected = false;  // some cell within a car length of the start leads to the goal
  const int reach = static_cast<int>(std::ceil(m.car.length_m / m.o.xy_cell_m));
  for (int dr = -reach; dr <= reach && !connected; ++dr)
    for (int dc = -reach; dc <= reach && !connected; ++dc) {
      const int cell = m.CellOf(start.x + dc * m.o.xy_cell_m, start.y + dr * m.o.xy_cell_m);
      connected = cell >= 0 && m.to_goal[cell] >= 0;
    }
  if (!connected) {
    result.failure = "the goal cannot be reached from the start (no free corridor)";
    result.milliseconds = Ms(t0);
    return result;
  }

  ++m.search;
  std::vector<Node> nodes;
  using Item = std::pair<double, int>;  // f, node
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  nodes.push_back({start, 0.0, -1, 0, 0.0});
  open.push({heuristic(start), 0});
  std::vector<double> steers;
  for (int i = 0; i < m.o.steer_samples; ++i)
    steers.push_back(std::tan((-1.0 + 2.0 * i / (m.o.steer_samples - 1)) * m.car.max_steer_deg * M_PI / 180.0));
  std::vector<PathPoint> shot, fallback_shot;
  int reached = -1, fallback = -1;
  while (!open.empty()) {
    const auto [f, index] = open.top();
    open.pop();
    const Node node = nodes[index];
    const int key = m.KeyOf(node.pose);
    if (index != 0 && m.stamp[key] == m.search && m.slot[key] != index) continue;  // superseded
    if (m.closed[key] == m.search) continue;  // expanded already: a cell is expanded once
    m.closed[key] = m.search;
    if (++result.expansions > m.o.max_expansions) {
      result.failure = "no path within " + std::to_string(m.o.max_expansions) + " expansions";
      break;
    }
    if ((result.expansions & 63) == 0 && Ms(t0) > m.o.time_budget_ms) {
      result.failure = "no path within the time budget of " + std::to_string(m.o.time_budget_ms) + " ms";
      break;
    }
    const double to_go = grid(node.pose);
    const bool shoot = index == 0 || to_go <= m.car.length_m * 2 ||
                       (to_go <= m.o.analytic_radius_m && result.expansions % m.o.analytic_every == 0);
    if (shoot) {
      shot = m.ReedsSheppShot(node.pose, goal, m.o.collision_step_m);
      if (!shot.empty()) {
        // A stretch of a few centimetres between gear changes is a path no car
        // tracks (it ends within the tracker's tolerance, its heading fix undone):
        // keep such a shot only as the fallback and search on for a cleaner one.
        if (m.ShortestShotStretch(node.pose, goal, node.direction) >= m.o.min_stretch_m) {
          reached = index;
          break;
        }
        if (fallback < 0) fallback = index, fallback_shot = shot;
      }
    }
    for (const int direction : {1, -1}) {
      if (direction < 0 && !m.o.allow_reverse) continue;
      for (const double tan_steer : steers) {
        Pose end;
        const bool near_start = escaping && std::hypot(node.pose.x - start.x, node.pose.y - start.y) < m.car.length_m;
        if (!m.ArcFree(node.pose, direction * m.o.step_m, tan_steer, near_start ? escape : m.discs, end)) continue;
        const int next = m.KeyOf(end);
        if (next < 0 || m.closed[next] == m.search || grid(end) < 0) continue;
        const double steer = std::abs(std::atan(tan_steer)) / (m.car.max_steer_deg * M_PI / 180.0);
        double g =
            node.g + m.o.step_m * (direction < 0 ? m.o.reverse_penalty : 1.0) + m.o.steer_penalty * steer * m.o.step_m;
        if (node.direction != 0) {
          g += m.o.steer_change_penalty * std::abs(std::atan(tan_steer) - std::atan(node.tan_steer)) /
               (m.car.max_steer_deg * M_PI / 180.0);
          if (direction != node.direction) g += m.o.gear_change_penalty_m;
        }
        if (m.stamp[next] == m.search && nodes[m.slot[next]].g <= g) continue;
        m.stamp[next] = m.search;
        m.slot[next] = static_cast<int>(nodes.size());
        nodes.push_back({end, g, index, direction, tan_steer});
        open.push({g + heuristic(end), m.slot[next]});
      }
    }
  }
  if (reached < 0 && fallback >= 0) reached = fallback, shot = fallback_shot, result.failure.clear();
  result.milliseconds = Ms(t0);
  if (reached < 0) {
    if (result.failure.empty()) result.failure = "the search space was exhausted: no path";
    return result;
  }
  std::vector<int> chain;
  for (int i = reached; i >= 0; i = nodes[i].parent) chain.push_back(i);
  std::reverse(chain.begin(), chain.end());
  Path& path = result.path;
  path.points.push_back({start, 1});
  for (size_t k = 1; k < chain.size(); ++k)
    m.AppendArc(nodes[chain[k - 1]], nodes[chain[k]], m.o.output_spacing_m, path.points);
  // The shot was sampled at the collision spacing; resample at the output spacing.
  auto final_leg = m.ReedsSheppShot(nodes[reached].pose, goal, m.o.output_spacing_m);
  if (final_leg.empty()) final_leg = shot;  // a finer sample grazed an obstacle: keep the checked spacing
  path.points.insert(path.points.end(), final_leg.begin(), final_leg.end());
  if (path.points.size() > 1) path.points[0].direction = path.points[1].direction;
  result.found = true;
  result.milliseconds = Ms(t0);
  return result;
}

SearchWithFallback::SearchWithFallback(const HybridAStarOptions& search, const HybridAStarOptions& fine,
                                       const CarOptions& car, std::shared_ptr<const DistanceMap> map)
    : fine_options_(fine), car_(car), map_(map), search_(search, car, std::move(map)) {}

PlanResult SearchWithFallback::Plan(const Pose& start, const Pose& goal) {
  PlanResult first = search_.Plan(start, goal);
  last_used_fine_ = !first.found;
  if (first.found) return first;
  if (!fine_) fine_ = std::make_unique<HybridAStar>(fine_options_, car_, map_);
  PlanResult fine = fine_->Plan(start, goal);
  fine.milliseconds += first.milliseconds, fine.heuristic_milliseconds += first.heuristic_milliseconds;
  fine.expansions += first.expansions;
  if (!fine.found) fine.failure = first.failure + "; the fine search: " + fine.failure;
  return fine;
}

}  // namespace specht::plan
