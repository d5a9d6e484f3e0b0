// plan_bench [--quick] [--hybrid-only] [--per-problem] [scenario.yaml]...: planning time on a 60 m × 60 m map at 0.1 m
// (600 × 600 cells): a seeded clutter field of 45 parked cars (2 m × 4.5 m, random headings) and 6 walls, 50 start/goal
// pairs drawn in free space at least 20 m apart (many goals sit in pockets: a hard set); then each scenario's marked
// bays from 25 random free poses each. Pairs not in one free component are left out. Per problem: hybrid A* (grid
// heuristic computed fresh, as for a new goal; the fine search where the default finds no path, `fine_search_share`) +
// the Ceres smoother, and plain OMPL RRT (geometric, Reeds-Shepp state space, same collision check, 1 s limit, first
// solution simplified by SimpleSetup::simplifySolution inside the timed region) on the same problems. JSON: each
// planner's success rate; p50/p90/max ms and mean path length over the problems both solve (`compared_on`).
//
// The kinodynamic planner (plan/kinodynamic.h, OMPL control SST / RRT / KPIECE1
// over the bicycle model):
//   slalom     a 30 m × 10 m corridor with three walls from alternate sides (4 m
//              gaps, 9 m apart), start to goal 25 m: 20 seeds per planner to the
//              first solution (budget 10 s), SST within 250 ms, hybrid A* +
//              smoothing for reference;
//   quality    the length of hybrid A* + smoothing against the best path SST finds
//              in 10 s: 3 seeds on the slalom; 5 clutter problems, SST guided by
//              hybrid A*'s path (unguided it rarely solves them): the ratio;
//   clutter    SST and RRT with the default 250 ms budget, guided by hybrid A*'s
//              path and unguided, on the clutter field's problems.
// --quick skips the 10 s quality runs; --hybrid-only runs hybrid A* + smoothing
// alone (no slalom, RRT or kinodynamic runs); --per-problem prints, per hybrid A*
// problem, the heuristic, search and smoothing times and the expansions to stderr.
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <random>

#include "bench_support.h"
#include "specht/decide/mission.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/kinodynamic.h"
#include "specht/plan/smoother.h"
#include "specht/sim/scenario.h"
#include "specht/sim/world.h"

namespace {

using Clock = std::chrono::steady_clock;
struct Flags {
  bool quick = false, hybrid_only = false, per_problem = false;
};
double Ms(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

cv::Mat Field(std::mt19937& rng) {
  cv::Mat m(600, 600, CV_8U, cv::Scalar(0));
  cv::rectangle(m, {0, 0}, {599, 599}, cv::Scalar(1), 1);
  std::uniform_real_distribution<double> pos(30, 570), angle(0, 180);
  for (int i = 0; i < 45; ++i) {
    cv::Point2f corners[4];
    cv::RotatedRect(cv::Point2f(pos(rng), pos(rng)), cv::Size2f(20, 45), angle(rng)).points(corners);
    std::vector<cv::Point> poly(corners, corners + 4);
    cv::fillConvexPoly(m, poly, cv::Scalar(1));
  }
  std::uniform_int_distribution<int> cell(60, 540);
  for (int i = 0; i < 6; ++i) {
    const int x = cell(rng), y = cell(rng);
    if (i % 2)
      cv::rectangle(m, {x - 80, y}, {x + 80, y + 2}, cv::Scalar(1), cv::FILLED);
    else
      cv::rectangle(m, {x, y - 80}, {x + 2, y + 80}, cv::Scalar(1), cv::FILLED);
  }
  return m;
}

struct Stats {
  std::vector<double> ms, length;  // of the solved problems
  double call_ms_max = 0;          // of every call, solved or not (the budget's check)
  int solved = 0, problems = 0;
  nlohmann::json Json(const std::string& name) const {
    std::vector<double> t = ms;
    std::sort(t.begin(), t.end());
    const auto q = [&](double p) {
      return t.empty() ? 0.0 : t[std::min(t.size() - 1, static_cast<size_t>(p * t.size()))];
    };
    double mean_length = 0;
    for (double l : length) mean_length += l / std::max<size_t>(1, length.size());
    return {{"name", name},
            {"problems", problems},
            {"success_rate", static_cast<double>(solved) / problems},
            {"ms_p50", q(0.5)},
            {"ms_p90", q(0.9)},
            {"ms_max", t.empty() ? 0.0 : t.back()},
            {"call_ms_max", call_ms_max},
            {"mean_length_m", mean_length},
            {"peak_rss_mib", specht::bench::PeakRssMib()},
            {"machine", specht::bench::MachineNotes()}};
  }
};

// Free space the car's centre line could pass (a necessary condition for any path),
// labelled by connected component: problems whose ends lie in different
// components (a start inside a closed infield) are left out of the sets.
cv::Mat Components(const specht::plan::DistanceMap& map, const specht::plan::CarOptions& car) {
  const double need = std::min(car.width_m / 2, car.rear_overhang_m) + car.safety_margin_m;
  cv::Mat passable = map.distances() > need, labels;
  cv::connectedComponents(passable, labels, 8, CV_32S);
  return labels;
}
bool Connected(const cv::Mat& labels, const specht::plan::DistanceMap& map, const specht::plan::Pose& a,
               const specht::plan::Pose& b) {
  const auto label = [&](const specht::plan::Pose& p) {
    const int c = static_cast<int>((p.x - map.origin_x()) / map.resolution());
    const int r = static_cast<int>((p.y - map.origin_y()) / map.resolution());
    return labels.at<int>(r, c);
  };
  return label(a) != 0 && label(a) == label(b);
}

// One planner's outcome on one problem.
struct Outcome {
  bool solved = false;
  double ms = 0, length = 0;
};

// Stats over the problems both planners solved (a percentile over each planner's own
// solved subset would reward the one that gives up on the hard problems), with each
// planner's own success rate.
Stats Common(const std::vector<Outcome>& mine, const std::vector<Outcome>& other) {
  Stats stats;
  stats.problems = static_cast<int>(mine.size());
  for (size_t i = 0; i < mine.size(); ++i) {
    stats.solved += mine[i].solved;
    if (mine[i].solved && other[i].solved) stats.ms.push_back(mine[i].ms), stats.length.push_back(mine[i].length);
  }
  return stats;
}

// Plain OMPL RRT as its users run it: geometric, Reeds-Shepp state space, the same
// collision check, 1 s to an exact solution, then SimpleSetup::simplifySolution()
// (shortcutting and smoothing) inside the timed region.
std::vector<Outcome> OmplRrt(const std::shared_ptr<specht::plan::DistanceMap>& map, const specht::plan::CarOptions& car,
                             const std::vector<std::pair<specht::plan::Pose, specht::plan::Pose>>& problems) {
  using namespace specht::plan;
  auto space = std::make_shared<ompl::base::ReedsSheppStateSpace>(car.MinTurningRadius());
  ompl::base::RealVectorBounds bounds(2);
  bounds.setLow(0, map->origin_x()), bounds.setHigh(0, map->origin_x() + map->cols() * map->resolution());
  bounds.setLow(1, map->origin_y()), bounds.setHigh(1, map->origin_y() + map->rows() * map->resolution());
  space->setBounds(bounds);
  const DiscCover discs = car.Discs();
  std::vector<Outcome> outcomes;
  for (const auto& [start, goal] : problems) {
    ompl::geometric::SimpleSetup ss(space);
    ss.setStateValidityChecker([&](const ompl::base::State* s) {
      const auto* se2 = s->as<ompl::base::SE2StateSpace::StateType>();
      return map->Free(discs, {se2->getX(), se2->getY(), se2->getYaw()});
    });
    ss.getSpaceInformation()->setStateValidityCheckingResolution(0.1 / space->getMaximumExtent());
    ss.setPlanner(std::make_shared<ompl::geometric::RRT>(ss.getSpaceInformation()));
    ompl::base::ScopedState<ompl::base::SE2StateSpace> s(space), g(space);
    s->setXY(start.x, start.y), s->setYaw(start.theta);
    g->setXY(goal.x, goal.y), g->setYaw(goal.theta);
    ss.setStartAndGoalStates(s, g, 0.05);
    const auto t0 = Clock::now();
    Outcome o;
    o.solved = ss.solve(1.0) == ompl::base::PlannerStatus::EXACT_SOLUTION;
    if (o.solved) ss.simplifySolution();
    o.ms = Ms(t0);
    if (o.solved) o.length = ss.getSolutionPath().length();
    outcomes.push_back(o);
  }
  return outcomes;
}

// Hybrid A* + smoothing and plain OMPL RRT on the same problems; two JSON lines, their
// times and lengths over the problems both solve.
void Compare(const std::string& name, const std::shared_ptr<specht::plan::DistanceMap>& map,
             const specht::plan::CarOptions& car,
             const std::vector<std::pair<specht::plan::Pose, specht::plan::Pose>>& problems, const Flags& flags) {
  using namespace specht::plan;
  const HybridAStarOptions search_options;
  const SmootherOptions smoother;
  std::vector<Outcome> astar;
  int fine = 0;
  for (const auto& [start, goal] : problems) {
    // Fresh: the heuristic is computed per problem. The fine search where the
    // default finds no path, as the closed loop does.
    SearchWithFallback search(search_options, FineSearchDefaults(), car, map);
    const auto t0 = Clock::now();
    const PlanResult r = search.Plan(start, goal);
    fine += search.last_used_fine();
    SmoothResult smoothed;
    if (r.found) smoothed = SmoothPath(r.path, *map, car, smoother);
    const double length = smoothed.path.Length();
    if (flags.per_problem)
      std::fprintf(stderr,
                   "%s #%zu: %s, heuristic %.1f ms, search %.1f ms, %ld expansions, smoothing %.1f ms, %.1f m\n",
                   name.c_str(), astar.size(), r.found ? "found" : r.failure.c_str(), r.heuristic_milliseconds,
                   r.milliseconds, r.expansions, smoothed.milliseconds, length);
    astar.push_back({r.found, Ms(t0), length});
  }
  const std::vector<Outcome> rrt = flags.hybrid_only ? astar : OmplRrt(map, car, problems);
  // Over the problems both solve, and each planner over its own solved ones (`own`).
  const auto both = [](const std::string& planner, const std::vector<Outcome>& mine,
                       const std::vector<Outcome>& other) {
    const Stats common = Common(mine, other);
    nlohmann::json j = common.Json(planner);
    j["compared_on"] = common.ms.size();
    const nlohmann::json own = Common(mine, mine).Json(planner);
    j["own"] = {{"ms_p50", own["ms_p50"]}, {"ms_p90", own["ms_p90"]}, {"mean_length_m", own["mean_length_m"]}};
    return j;
  };
  nlohmann::json j = both("plan/hybrid_astar+smoothing/" + name, astar, rrt);
  j["fine_search_share"] = static_cast<double>(fine) / problems.size();
  specht::bench::Emit(j);
  if (!flags.hybrid_only) specht::bench::Emit(both("plan/ompl_rrt_reeds_shepp_simplified/" + name, rrt, astar));
}

// The kinodynamic planner on `problems`, `runs` times each (each call draws new
// random numbers), optionally guided by hybrid A*'s path (its time included).
Stats Kinodynamic(const std::shared_ptr<specht::plan::DistanceMap>& map, const specht::plan::CarOptions& car,
                  const std::vector<std::pair<specht::plan::Pose, specht::plan::Pose>>& problems,
                  const specht::plan::KinodynamicOptions& options, bool guided, int runs = 1) {
  using namespace specht::plan;
  Stats stats;
  KinodynamicPlanner planner(options, car, map);
  HybridAStar search(HybridAStarOptions{}, car, map);
  for (const auto& [start, goal] : problems)
    for (int run = 0; run < runs; ++run) {
      const auto t0 = Clock::now();
      PlanResult guide;
      if (guided) guide = search.Plan(start, goal);
      const auto t1 = Clock::now();
      const KinodynamicResult r = planner.Plan(start, goal, {}, guide.found ? &guide.path : nullptr);
      stats.call_ms_max = std::max(stats.call_ms_max, Ms(t1));  // the kinodynamic call alone
      const double ms = Ms(t0);
      ++stats.problems;
      if (r.found) ++stats.solved, stats.ms.push_back(ms), stats.length.push_back(r.path.Length());
    }
  return stats;
}

specht::plan::KinodynamicOptions KinoOptions(const std::string& planner, double budget_ms, bool first) {
  specht::plan::KinodynamicOptions o;
  o.planner = planner, o.time_budget_ms = budget_ms, o.stop_at_first_solution = first;
  return o;
}

double HybridLength(const std::shared_ptr<specht::plan::DistanceMap>& map, const specht::plan::CarOptions& car,
                    const specht::plan::Pose& start, const specht::plan::Pose& goal) {
  using namespace specht::plan;
  const PlanResult r = HybridAStar(HybridAStarOptions{}, car, map).Plan(start, goal);
  return r.found ? SmoothPath(r.path, *map, car, SmootherOptions{}).path.Length() : NAN;
}

// Hybrid A* + smoothing's length over the best SST finds in 10 s, per problem.
void Quality(const std::string& name, const std::shared_ptr<specht::plan::DistanceMap>& map,
             const specht::plan::CarOptions& car,
             const std::vector<std::pair<specht::plan::Pose, specht::plan::Pose>>& problems, int seeds, bool guided) {
  using namespace specht::plan;
  KinodynamicPlanner sst(KinoOptions("sst", 10000, false), car, map);
  HybridAStar search(HybridAStarOptions{}, car, map);
  std::vector<double> ratios;
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [start, goal] : problems) {
    double best = INFINITY;
    const PlanResult guide = guided ? search.Plan(start, goal) : PlanResult{};
    for (int seed = 0; seed < seeds; ++seed) {
      const KinodynamicResult r = sst.Plan(start, goal, {}, guide.found ? &guide.path : nullptr);
      if (r.found) best = std::min(best, r.path.Length());
    }
    const double hybrid = HybridLength(map, car, start, goal);
    rows.push_back({{"hybrid_astar_smoothed_m", hybrid}, {"sst_10s_best_m", std::isfinite(best) ? best : -1.0}});
    if (std::isfinite(best) && std::isfinite(hybrid)) ratios.push_back(hybrid / best);
  }
  std::sort(ratios.begin(), ratios.end());
  specht::bench::Emit({{"name", "plan/quality/" + name + (guided ? "/sst-guided" : "/sst")},
                       {"problems", rows},
                       {"length_ratio_max", ratios.empty() ? -1.0 : ratios.back()},
                       {"length_ratio_median", ratios.empty() ? -1.0 : ratios[ratios.size() / 2]},
                       {"machine", specht::bench::MachineNotes()}});
}

void Slalom(bool quick) {
  using namespace specht::plan;
  cv::Mat m(100, 300, CV_8U, cv::Scalar(0));
  cv::rectangle(m, {0, 0}, {299, 99}, cv::Scalar(1), 1);
  for (const auto& [x, y] : {std::pair{60, 0}, {150, 40}, {240, 0}})
    cv::rectangle(m, cv::Point(x, y), cv::Point(x + 4, y + 59), cv::Scalar(1), cv::FILLED);
  auto map = std::make_shared<DistanceMap>(m, 0.0, 0.0, 0.1);
  const CarOptions car;
  const std::vector<std::pair<Pose, Pose>> problem = {{{2, 2, 0}, {27, 8, 0}}};
  for (const std::string planner : {"rrt", "kpiece", "sst"})
    specht::bench::Emit(Kinodynamic(map, car, problem, KinoOptions(planner, 10000, true), false, 20)
                            .Json("plan/kinodynamic/" + planner + "-first-solution/slalom-30x10m"));
  specht::bench::Emit(Kinodynamic(map, car, problem, KinoOptions("sst", 250, false), false, 20)
                          .Json("plan/kinodynamic/sst-250ms/slalom-30x10m"));
  Stats astar;
  for (int run = 0; run < 20; ++run) {
    const auto t0 = Clock::now();
    const double length = HybridLength(map, car, problem[0].first, problem[0].second);
    ++astar.problems;
    if (std::isfinite(length)) ++astar.solved, astar.ms.push_back(Ms(t0)), astar.length.push_back(length);
  }
  specht::bench::Emit(astar.Json("plan/hybrid_astar+smoothing/slalom-30x10m"));
  if (!quick) Quality("slalom-30x10m", map, car, problem, 3, false);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace specht::plan;
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  Flags flags;
  std::vector<std::string> scenarios;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick")
      flags.quick = true;
    else if (arg == "--hybrid-only")
      flags.hybrid_only = true;
    else if (arg == "--per-problem")
      flags.per_problem = true;
    else
      scenarios.push_back(arg);
  }
  if (!flags.hybrid_only) Slalom(flags.quick);
  std::mt19937 rng(11);
  {  // the clutter field
    const cv::Mat field = Field(rng);
    auto map = std::make_shared<DistanceMap>(field, 0.0, 0.0, 0.1);
    const CarOptions car;
    const cv::Mat labels = Components(*map, car);
    std::vector<std::pair<Pose, Pose>> problems;
    std::uniform_real_distribution<double> xy(2, 58), heading(-M_PI, M_PI);
    while (problems.size() < 50) {
      const Pose a{xy(rng), xy(rng), heading(rng)}, b{xy(rng), xy(rng), heading(rng)};
      if (map->Free(car, a) && map->Free(car, b) && std::hypot(a.x - b.x, a.y - b.y) >= 20 &&
          Connected(labels, *map, a, b))
        problems.push_back({a, b});
    }
    Compare("clutter-60m-0.1m", map, car, problems, flags);
    for (const std::string planner : {"sst", "rrt"}) {
      if (flags.hybrid_only) break;
      for (const bool guided : {false, true})
        specht::bench::Emit(
            Kinodynamic(map, car, problems, KinoOptions(planner, 250, false), guided)
                .Json("plan/kinodynamic/" + planner + "-250ms" + (guided ? "-guided" : "") + "/clutter-60m-0.1m"));
    }
    if (!flags.quick && !flags.hybrid_only)
      Quality("clutter-60m-0.1m", map, car, {problems.begin(), problems.begin() + 5}, 1, true);
  }
  // Scenario maps: from 25 random free poses to each marked bay (the car centred in
  // the bay, nose along it), with the scenario's own car.
  for (const std::string& path : scenarios) {
    const specht::sim::Scenario s = specht::sim::LoadScenario(path);
    if (s.bays.empty()) continue;
    auto map = std::make_shared<DistanceMap>(DistanceMap::FromGrid(specht::sim::World(s).TrueGrid(0.1)));
    const CarOptions car = specht::pipeline::ScenarioCar(s, CarOptions{});
    const cv::Mat labels = Components(*map, car);
    std::vector<std::pair<Pose, Pose>> problems;
    std::uniform_real_distribution<double> x(map->origin_x(), map->origin_x() + map->cols() * 0.1),
        y(map->origin_y(), map->origin_y() + map->rows() * 0.1), heading(-M_PI, M_PI);
    for (const auto& bay : specht::pipeline::MissionSiteOf(s).bays) {
      const Pose goal = specht::decide::BayPose(bay, car);
      if (!map->Free(car, goal)) continue;
      for (int k = 0; k < 25;) {
        const Pose a{x(rng), y(rng), heading(rng)};
        if (map->Free(car, a) && Connected(labels, *map, a, goal)) problems.push_back({a, goal}), ++k;
      }
    }
    const int w = static_cast<int>(std::lround(map->cols() * 0.1)),
              h = static_cast<int>(std::lround(map->rows() * 0.1));
    Compare(s.name + "-bays-" + std::to_string(w) + "x" + std::to_string(h) + "m-0.1m", map, car, problems, flags);
  }
  return 0;
}
