// specht/plan/hybrid_astar.h: the global search (Dolgov et al. 2008, "Path Planning
// for Autonomous Vehicles in Unknown Semi-structured Environments"): A* over
// (x, y, θ) cells whose nodes carry continuous poses, expanded by driving arcs of
// the bicycle model (steer_samples angles from −δmax to δmax, forward and reverse).
//
// Cost of an arc of length s: s · (reverse ? reverse_penalty : 1)
//   + steer_penalty · |δ|/δmax · s + steer_change_penalty · |δ − δ_parent|/δmax
//   + gear_change_penalty_m when the direction flips.
// Paths use steer_fraction of the car's steering limit (arcs and Reeds-Shepp
// radius): a path at full lock leaves a tracker no room to correct.
// Heuristic: max(Reeds-Shepp length ignoring obstacles (OMPL's ReedsSheppStateSpace
// at R_min), shortest 8-connected grid distance to the goal around obstacles
// ignoring heading) — both admissible for the arc lengths. The Reeds-Shepp term is
// used only within reeds_shepp_radius_m (grid distance) of the goal: farther away it
// costs much of the search time (OMPL solves 48 path families per call) and, pulling
// nodes towards the goal's heading long before it matters, makes the weighted search
// expand more without shortening the paths. The grid distances come
// from one Dijkstra from the goal; they are cached, so replanning to the same goal
// on the same map costs only the search.
// Nodes are ordered by g + w·h: with heuristic_weight w > 1 the search expands far
// fewer nodes and its path costs at most w times the optimum (weighted A*).
// Analytic expansion: from the start, from every node within two car lengths of the
// goal (a tight goal is often reached only by the right shot), and every
// analytic_every expansions within analytic_radius_m (grid distance), the Reeds-Shepp
// path from the node to the goal is checked for collisions; when free, and no
// stretch between its gear changes is shorter than min_stretch_m, it ends the
// search exactly at the goal (far from the goal such shots rarely survive and cost
// most of the time). A shot with a centimetre stretch is kept as the fallback, used
// should the search fail.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/plan/distance_map.h"
#include "specht/plan/path.h"

namespace specht::plan {

// Section "hybrid_astar".
struct HybridAStarOptions {
  double steer_fraction = 0.85;
  double xy_cell_m = 0.5;
  int heading_bins = 72;
  double step_m = 0.75;
  int steer_samples = 5;
  bool allow_reverse = true;
  double reverse_penalty = 2.0;
  double gear_change_penalty_m = 10.0;
  double steer_penalty = 0.05;
  double steer_change_penalty = 0.2;
  int analytic_every = 5;
  double analytic_radius_m = 15.0;
  double heuristic_weight = 2.5;
  double reeds_shepp_radius_m = 15.0;
  double min_stretch_m = 0.3;
  double collision_step_m = 0.15;
  double output_spacing_m = 0.1;
  int max_expansions = 40000;
  double time_budget_ms = 500;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("steer_fraction", steer_fraction,
            "plan with this share of the steering limit: the rest is the tracker's to correct errors",
            Range::Of(0.3, 1.0));
    v.Param("xy_cell_m", xy_cell_m, "search cell size (one node per cell and heading bin)", Range::Of(0.05, 5.0).Log());
    v.Param("heading_bins", heading_bins, "heading cells over 360°", Range::Of(8, 720));
    v.Param("step_m", step_m, "arc length of one expansion (more than a cell diagonal)", Range::Of(0.05, 10.0).Log());
    v.Param("steer_samples", steer_samples, "steering angles per direction (odd: includes straight)", Range::Of(3, 31));
    v.Param("allow_reverse", allow_reverse, "expand in reverse too");
    v.Param("reverse_penalty", reverse_penalty, "cost factor on reversing arcs", Range::Of(1.0, 100.0));
    v.Param("gear_change_penalty_m", gear_change_penalty_m, "cost of a change of direction, in metres",
            Range::Of(0.0, 1000.0));
    v.Param("steer_penalty", steer_penalty, "cost per metre at full steering lock", Range::Of(0.0, 10.0));
    v.Param("steer_change_penalty", steer_change_penalty, "cost of a steering change of δmax", Range::Of(0.0, 10.0));
    v.Param("analytic_every", analytic_every, "try the Reeds-Shepp shot to the goal every n expansions",
            Range::Of(1, 1000));
    v.Param("analytic_radius_m", analytic_radius_m,
            "try the shot only within this grid distance of the goal (and from the start)", Range::Of(0.0, 1000.0));
    v.Param("heuristic_weight", heuristic_weight, "weighted A*: f = g + w·h (w > 1: faster, cost ≤ w × optimal)",
            Range::Of(1.0, 10.0));
    v.Param("reeds_shepp_radius_m", reeds_shepp_radius_m,
            "heuristic: the Reeds-Shepp length counts only within this grid distance of the goal",
            Range::Of(0.0, 1000.0));
    v.Param("min_stretch_m", min_stretch_m,
            "a Reeds-Shepp shot with a shorter stretch between gear changes is kept only as the fallback",
            Range::Of(0.0, 10.0));
    v.Param("collision_step_m", collision_step_m, "spacing of collision checks along arcs", Range::Of(0.01, 1.0).Log());
    v.Param("output_spacing_m", output_spacing_m, "spacing of the returned path's points",
            Range::Of(0.01, 1.0).Fixed());
    v.Param("max_expansions", max_expansions,
            "give up after this many expansions (the budget that makes a search reproducible)",
            Range::Of(100, 100000000).Fixed());
    v.Param("time_budget_ms", time_budget_ms,
            "also give up after this long (specht run: only with closed_loop.planning_budget time)",
            Range::Of(1.0, 600000.0).Fixed());
  }
  std::vector<std::string> Relations() const;
};

// The fallback search for goals the default cannot reach (a parallel slot of 1.5
// car lengths): the full steering lock, 0.25 m cells, 0.4 m arcs and a budget of
// 100,000 expansions or 2 s —
// slower, and its paths leave a tracker no steering in reserve. Section
// "hybrid_astar_fine".
HybridAStarOptions FineSearchDefaults();

// `o` with time_budget_ms taken out: the search stops at max_expansions alone, so
// its answer does not depend on the machine's speed (replays, tests).
HybridAStarOptions WithoutTimeBudget(HybridAStarOptions o);

struct PlanResult {
  bool found = false;
  Path path;
  std::string failure;  // why not found
  long expansions = 0;
  double milliseconds = 0;            // search (and heuristic, when not cached)
  double heuristic_milliseconds = 0;  // 0 when the goal's grid distances were cached
};

class HybridAStar {
 public:
  HybridAStar(const HybridAStarOptions& options, const CarOptions& car, std::shared_ptr<const DistanceMap> map);
  ~HybridAStar();
  // Throws InputError when start or goal is outside the map or in collision. A
  // start within the safety margin that touches nothing is planned from: within a
  // car length of it the arcs need only miss the obstacles (a map that changed
  // under the car must not strand it).
  PlanResult Plan(const Pose& start, const Pose& goal);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The default search, and the fine one (built on first use) where it finds no path.
// The result is the fine search's when it ran, with both searches' times summed and,
// when neither found a path, both reasons.
class SearchWithFallback {
 public:
  SearchWithFallback(const HybridAStarOptions& search, const HybridAStarOptions& fine, const CarOptions& car,
                     std::shared_ptr<const DistanceMap> map);
  // Throws InputError when start or goal is outside the map or in collision.
  PlanResult Plan(const Pose& start, const Pose& goal);
  bool last_used_fine() const { return last_used_fine_; }

 private:
  HybridAStarOptions fine_options_;
  CarOptions car_;
  std::shared_ptr<const DistanceMap> map_;
  HybridAStar search_;
  std::unique_ptr<HybridAStar> fine_;
  bool last_used_fine_ = false;
};

}  // namespace specht::plan
