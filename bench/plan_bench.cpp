// plan_bench [scenario.yaml]...: planning time on a 60 m × 60 m map at 0.1 m (600 ×
// 600 cells): a seeded clutter field of 45 parked cars (2 m × 4.5 m, random
// headings) and 6 walls, 50 start/goal pairs drawn in free space at least 20 m
// apart (many goals sit in pockets: a hard set); then each scenario's marked bays
// from 25 random free poses each. Pairs not in one free component are left out. Per problem: hybrid A*
// (grid heuristic computed fresh, as for a new goal) + the Ceres smoother, and
// plain OMPL RRT (geometric, Reeds-Shepp state space, same collision check, 1 s
// limit, first solution simplified by OMPL's default shortcutting) on the same
// problems. JSON: p50/p90/max ms, success rate, mean path length.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/util/Console.h>
#include <opencv2/imgproc.hpp>

#include "bench_support.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/smoother.h"
#include "specht/sim/scenario.h"
#include "specht/sim/world.h"

namespace {

using Clock = std::chrono::steady_clock;
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
    if (i % 2) cv::rectangle(m, {x - 80, y}, {x + 80, y + 2}, cv::Scalar(1), cv::FILLED);
    else cv::rectangle(m, {x, y - 80}, {x + 2, y + 80}, cv::Scalar(1), cv::FILLED);
  }
  return m;
}

struct Stats {
  std::vector<double> ms, length;
  int solved = 0, problems = 0;
  nlohmann::json Json(const std::string& name) const {
    std::vector<double> t = ms;
    std::sort(t.begin(), t.end());
    const auto q = [&](double p) { return t.empty() ? 0.0 : t[std::min(t.size() - 1, static_cast<size_t>(p * t.size()))]; };
    double mean_length = 0;
    for (double l : length) mean_length += l / std::max<size_t>(1, length.size());
    return {{"name", name},
            {"problems", problems},
            {"success_rate", static_cast<double>(solved) / problems},
            {"ms_p50", q(0.5)},
            {"ms_p90", q(0.9)},
            {"ms_max", t.empty() ? 0.0 : t.back()},
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

// Hybrid A* + smoothing and plain OMPL RRT on the same problems; two JSON lines.
void Compare(const std::string& name, const std::shared_ptr<specht::plan::DistanceMap>& map,
             const specht::plan::CarOptions& car, const std::vector<std::pair<specht::plan::Pose, specht::plan::Pose>>& problems) {
  using namespace specht::plan;
  const HybridAStarOptions search_options;
  const SmootherOptions smoother;
  Stats astar, rrt;
  for (const auto& [start, goal] : problems) {
    HybridAStar search(search_options, car, map);  // fresh: the heuristic is computed per problem
    const auto t0 = Clock::now();
    const PlanResult r = search.Plan(start, goal);
    double length = 0;
    if (r.found) length = SmoothPath(r.path, *map, car, smoother).path.Length();
    ++astar.problems;
    if (r.found) astar.ms.push_back(Ms(t0)), astar.length.push_back(length), ++astar.solved;
  }
  specht::bench::Emit(astar.Json("plan/hybrid_astar+smoothing/" + name));

  auto space = std::make_shared<ompl::base::ReedsSheppStateSpace>(car.MinTurningRadius());
  ompl::base::RealVectorBounds bounds(2);
  bounds.setLow(0, map->origin_x()), bounds.setHigh(0, map->origin_x() + map->cols() * map->resolution());
  bounds.setLow(1, map->origin_y()), bounds.setHigh(1, map->origin_y() + map->rows() * map->resolution());
  space->setBounds(bounds);
  const DiscCover discs = car.Discs();
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
    const auto solved = ss.solve(1.0);
    const double ms = Ms(t0);
    ++rrt.problems;
    if (solved == ompl::base::PlannerStatus::EXACT_SOLUTION) {
      ++rrt.solved, rrt.ms.push_back(ms);
      rrt.length.push_back(ss.getSolutionPath().length());
    }
  }
  specht::bench::Emit(rrt.Json("plan/ompl_rrt_reeds_shepp/" + name));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace specht::plan;
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
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
    Compare("clutter-60m-0.1m", map, car, problems);
  }
  // Scenario maps: from 25 random free poses to each marked bay (the car centred in
  // the bay, nose along it), with the scenario's own car.
  for (int i = 1; i < argc; ++i) {
    const specht::sim::Scenario s = specht::sim::LoadScenario(argv[i]);
    if (s.bays.empty()) continue;
    auto map = std::make_shared<DistanceMap>(DistanceMap::FromGrid(specht::sim::World(s).TrueGrid(0.1)));
    CarOptions car;
    car.wheelbase_m = s.ego.model.wheelbase_m, car.max_steer_deg = s.ego.model.max_steer_rad * 180 / M_PI;
    car.length_m = s.ego.model.length_m, car.width_m = s.ego.model.width_m;
    const cv::Mat labels = Components(*map, car);
    std::vector<std::pair<Pose, Pose>> problems;
    std::uniform_real_distribution<double> x(map->origin_x(), map->origin_x() + map->cols() * 0.1),
        y(map->origin_y(), map->origin_y() + map->rows() * 0.1), heading(-M_PI, M_PI);
    for (const auto& bay : s.bays) {
      const double back = car.length_m / 2 - car.rear_overhang_m;
      const Pose goal{bay.pose.x - back * std::cos(bay.pose.yaw_rad), bay.pose.y - back * std::sin(bay.pose.yaw_rad),
                      std::remainder(bay.pose.yaw_rad, 2 * M_PI)};
      if (!map->Free(car, goal)) continue;
      for (int k = 0; k < 25;) {
        const Pose a{x(rng), y(rng), heading(rng)};
        if (map->Free(car, a) && Connected(labels, *map, a, goal)) problems.push_back({a, goal}), ++k;
      }
    }
    const int w = static_cast<int>(std::lround(map->cols() * 0.1)), h = static_cast<int>(std::lround(map->rows() * 0.1));
    Compare(s.name + "-bays-" + std::to_string(w) + "x" + std::to_string(h) + "m-0.1m", map, car, problems);
  }
  return 0;
}
