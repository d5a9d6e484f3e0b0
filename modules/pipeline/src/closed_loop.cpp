#include "specht/pipeline/closed_loop.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "internal/loop_geometry.h"
#include "internal/loop_perception.h"
#include "internal/loop_stack.h"
#include "internal/loop_video.h"
#include "internal/sim_stereo.h"
#include "internal/stack_link.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/io/report.h"
#include "specht/pipeline/perception_eval.h"
#include "specht/sim/detections.h"
#include "specht/sim/simulator.h"
#include "specht/sim/world.h"

namespace specht::pipeline {

using decide::Goal;
using internal::Box;

namespace {

Box AgentBox(const sim::AgentTruth& a) { return {a.pose.x, a.pose.y, a.pose.yaw_rad, a.length_m / 2, a.width_m / 2}; }

}  // namespace

plan::Pose EgoRearAxle(const sim::Scenario& s, const sim::Pose2& centre) {
  const double back = s.ego.model.PivotAhead();
  return {centre.x - back * std::cos(centre.yaw_rad), centre.y - back * std::sin(centre.yaw_rad), centre.yaw_rad};
}

decide::MissionSite MissionSiteOf(const sim::Scenario& s) {
  decide::MissionSite site{"scenario " + s.name, {}};
  for (const auto& b : s.bays) site.bays.push_back({b.name, b.pose.x, b.pose.y, b.pose.yaw_rad, b.length_m, b.width_m});
  return site;
}

plan::CarOptions ScenarioCar(const sim::Scenario& s, plan::CarOptions car) {
  const sim::VehicleModel& v = s.ego.model;
  car.wheelbase_m = v.wheelbase_m, car.max_steer_deg = v.max_steer_rad * 180 / M_PI;
  car.length_m = v.length_m, car.width_m = v.width_m, car.rear_overhang_m = v.rear_overhang_m;
  car.max_speed_mps = std::min(car.max_speed_mps, v.max_speed_mps);
  car.max_accel_mps2 = v.max_accel_mps2;
  return car;
}

namespace {

// Scores one simulator step against the truth: contacts with the true static map or
// an agent while moving (counted once per contact), clearances.
class ContactScore {
 public:
  ContactScore(const sim::Scenario& s, const ClosedLoopConfig& c, const plan::DistanceMap& truth)
      : s_(s), c_(c), truth_(truth) {}

  void Step(const sim::Simulator& sim, ClosedLoopResult& r) {
    const auto& e = sim.ego();
    const Box car = internal::CarBox(c_.car, EgoRearAxle(s_, e.pose));
    const bool moving = std::abs(e.speed_mps) > 0.05;
    const double clearance = internal::OutlineClearance(truth_, car);
    r.min_clearance_m = std::min(r.min_clearance_m, clearance);
    std::string what = clearance <= 0 ? "static obstacle" : "";
    for (const auto& a : sim.agents()) {
      const double d = internal::BoxToBox(car, AgentBox(a));
      if (moving && a.cls == sim::AgentClass::kPedestrian && d < r.min_pedestrian_m) {
        r.min_pedestrian_m = d;
        char at[64];
        std::snprintf(at, sizeof(at), "%.2f s: pedestrian %d", sim.time_s(), a.id);
        r.closest_pedestrian = at;
      }
      if (moving && d <= 0) what = std::string(sim::Name(a.cls)) + " " + std::to_string(a.id);
    }
    const bool contact = !what.empty();
    if (contact && !touching_) {
      ++r.collisions;
      char buf[96];
      std::snprintf(buf, sizeof(buf), "%.2f s: %s", sim.time_s(), what.c_str());
      r.collision_events.push_back(buf);
    }
    touching_ = contact;
  }

 private:
  const sim::Scenario& s_;
  const ClosedLoopConfig& c_;
  const plan::DistanceMap& truth_;
  bool touching_ = false;
};

// The parking error against the truth: the machine judged its goals on the pose it
// believed, so a mission it completed on a wrong belief fails here.
void ScoreParking(const ClosedLoopConfig& c, const std::vector<Goal>& mission, const plan::Pose& truth,
                  ClosedLoopResult& r) {
  if (r.believed_park_error_m < 0 || !mission.back().park) return;
  const plan::Pose& goal = mission.back().pose;
  r.park_error_m = std::hypot(truth.x - goal.x, truth.y - goal.y);
  r.park_error_deg = std::abs(std::remainder(truth.theta - goal.theta, 2 * M_PI)) * 180 / M_PI;
  if (!r.success || (r.park_error_m <= c.loop.park_tolerance_m && r.park_error_deg <= c.loop.park_tolerance_deg))
    return;
  r.success = false;
  char note[160];
  std::snprintf(note, sizeof(note), "parked %.3f m, %.1f° off by the truth (%.3f m, %.1f° as believed)", r.park_error_m,
                r.park_error_deg, r.believed_park_error_m, r.believed_park_error_deg);
  r.failure = note;
}

// The believed pose against the truth at every control step (never fed back):
// absolute trajectory error of the position (RMSE, p90, max) and of the heading (max).
class LocalizationScore {
 public:
  void Add(const sim::Pose2& believed, const sim::Pose2& truth) {
    position_error_m_.push_back(std::hypot(believed.x - truth.x, believed.y - truth.y));
    max_heading_error_deg_ = std::max(
        max_heading_error_deg_, std::abs(std::remainder(believed.yaw_rad - truth.yaw_rad, 2 * M_PI)) * 180 / M_PI);
  }
  nlohmann::json ToJson() const {
    std::vector<double> e = position_error_m_;
    std::sort(e.begin(), e.end());
    double sq = 0;
    for (double v : e) sq += v * v;
    return {{"ate_rmse_m", e.empty() ? 0.0 : std::sqrt(sq / e.size())},
            {"ate_p90_m", e.empty() ? 0.0 : e[std::min(e.size() - 1, static_cast<size_t>(0.9 * e.size()))]},
            {"ate_max_m", e.empty() ? 0.0 : e.back()},
            {"heading_error_max_deg", max_heading_error_deg_}};
  }

 private:
  std::vector<double> position_error_m_;
  double max_heading_error_deg_ = 0;
};

}  // namespace

std::vector<std::string> ClosedLoopOptions::Relations() const {
  if (blind_stop_s <= blind_slow_s) return {"blind_stop_s must be above blind_slow_s"};
  return {};
}

std::string ClosedLoopOptions::Stack() const {
  if (localization == "truth" && perception == "truth") return "truth";
  if (localization != "truth" && perception != "truth") return "full";
  return "mixed";
}

ClosedLoopResult RunClosedLoop(const sim::Scenario& scenario, uint64_t seed, const std::vector<Goal>& mission,
                               const ClosedLoopConfig& config, const std::function<void(const LoopStep&)>& on_step) {
  if (mission.empty()) throw InputError("closed loop: the mission has no goals");
  const ClosedLoopOptions& loop = config.loop;
  ClosedLoopResult r;
  const bool camera = loop.perception == "camera";
  if (camera && !scenario.stereo)
    throw InputError("closed_loop.perception camera: scenario " + scenario.name + " has no stereo camera");
  if (config.slam.site_map && loop.localization != "map")
    throw InputError("a map of the site is given, but closed_loop.localization is " + loop.localization +
                     " (it is read by localization map)");
  // The car and its world: the simulator with its sensors, the detector among them.
  sim::Simulator sim(scenario, seed, camera ? config.camera.sprites : nullptr);
  std::optional<sim::SyntheticDetector> detector;
  if (loop.perception == "detections") detector.emplace(config.detection, seed);
  const internal::Blindness blind{loop.blind_at_s, loop.blind_for_s};
  const int substeps = std::max(1, static_cast<int>(std::lround(1.0 / (loop.control_hz * sim::Simulator::kStepS))));
  // The referee: the truth the run is scored against, never fed back.
  const mrpt::maps::COccupancyGridMap2D true_grid = sim::World(scenario).TrueGrid(kPlanningResolutionM);
  const plan::DistanceMap truth_map = plan::DistanceMap::FromGrid(true_grid);
  ContactScore contacts(scenario, config, truth_map);
  LocalizationScore localization_score;
  internal::PerceptionScore perception_score(loop.perception_match_m);
  // The truth of each detector frame until its tracks come back: in view, all agents.
  std::map<int64_t, std::pair<std::vector<sim::AgentTruth>, std::vector<sim::AgentTruth>>> unscored;
  const auto on_tracks = [&](Stamp stamp, const std::vector<types::Track>& tracks) {
    const auto it = unscored.find(stamp.ns);
    if (it == unscored.end()) return;
    perception_score.Frame(it->second.first, it->second.second, tracks);
    unscored.erase(it);
  };
  // The stack, fed by what the car delivers: here, or in a process of its own.
  const std::unique_ptr<internal::StackLink> link =
      config.stack_node ? internal::DdsStackLink(scenario, seed, config, r, on_tracks)
                        : internal::LocalStackLink(scenario, seed, mission, config, sim.stamp(), r, on_tracks);
  internal::LoopStack* const here = link->local();
  // The oracle's pose reaches the stack wherever it may read its pose (the truth
  // mode's localisation; the other modes ignore it).
  const auto oracle = [&] { link->OracleEgo(sim.ego().pose); };
  // A perception frame after every simulator step (and once before the first):
  // the truth mode's at the control rate, the detector's at its own.
  const auto perceive = [&] {
    if (camera || blind.Covers(sim.time_s())) return;
    if (!detector) {
      if (std::llround(sim.time_s() / sim::Simulator::kStepS) % substeps != 0) return;
      const std::vector<sim::AgentTruth> agents = sim.agents();
      unscored[sim.stamp().ns] = {agents, agents};
      return link->OracleAgents(agents, sim.stamp());
    }
    if (!detector->Due(sim)) return;
    std::vector<types::Obstacle> in_car = detector->Detect(sim);
    for (auto& o : in_car) o = internal::InCarFrame(o, sim.ego().pose);
    unscored[sim.stamp().ns] = {detector->visible(), sim.agents()};
    link->Detections(std::move(in_car), sim.stamp());
  };
  const auto on_observation = [&](Stamp t, const mrpt::obs::CObservation::Ptr& obs) {
    oracle();
    link->Observe(t, sim.time_s(), obs);
  };
  // Rendered stereo frames, only where perception reads them (rendering costs).
  sim::Simulator::StereoSink on_stereo;
  if (camera)
    on_stereo = [&](Stamp, const sim::StereoFrame& frame) {
      if (blind.Covers(sim.time_s())) return;
      oracle();
      const auto t0 = std::chrono::steady_clock::now();
      const auto tracks =
          here->Camera(*internal::SimStereoObservation(sim.stamp(), *scenario.stereo, frame), sim.stamp());
      r.stage_ms["camera_in_simulate"] +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const PerceptionEvalOptions counted;  // which agents in the image count as seeable
      std::vector<sim::AgentTruth> in_view;
      for (const auto& a : sim.agents())
        for (const auto& v : frame.agents)
          if (v.id == a.id && v.visible >= counted.min_visible && v.box.height >= counted.min_height_px)
            in_view.push_back(a);
      perception_score.Frame(in_view, sim.agents(), tracks);
    };
  oracle();
  perceive();
  // Wall-clock time per stage (the report's timing; never a pass/fail figure).
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  const auto run_start = Clock::now();
  std::optional<internal::LoopVideo> video;
  if (!config.video.empty()) video.emplace(config.video, true_grid, config.world, sim.stamp());
  bool finished = false;
  std::string time_limit;
  while (!finished) {
    const double t = sim.time_s();
    if (InterruptRequested()) {  // stop at this control step; what was driven is the result
      r.interrupted = true;
      r.failure = "interrupted by " + InterruptName() + " at " + std::to_string(t) + " s";
      break;
    }
    if (t > loop.time_limit_s) {
      r.failure = time_limit = "time limit of " + std::to_string(loop.time_limit_s) + " s";
      break;
    }
    oracle();
    const auto& ego = sim.ego();
    const internal::StackDecision decided = link->Control(t, sim.stamp(), ego.speed_mps, ego.steer_rad);
    finished = decided.finished;
    localization_score.Add(decided.believed, ego.pose);
    const plan::Command& cmd = decided.command;
    sim.CommandEgo({cmd.speed_mps, cmd.steer_rad, config.car.max_steer_rate_deg_s * M_PI / 180});
    const plan::Pose pose = EgoRearAxle(scenario, ego.pose);
    r.trajectory.push_back(pose);
    if (video) {
      const auto t0 = Clock::now();
      video->Step(sim, here->snapshot(), decided.believed, here->PathAhead());
      r.stage_ms["video"] += since(t0);
    }
    if (on_step)
      on_step({t, decided.state, pose, EgoRearAxle(scenario, decided.believed), decided.tracks, decided.on_local_path});
    for (int k = 0; k < substeps; ++k) {
      auto t0 = Clock::now();
      sim.Step(on_observation, on_stereo);  // localisation and camera perception run inside
      r.stage_ms["simulate"] += since(t0);
      oracle();
      perceive();
      contacts.Step(sim, r);
    }
  }
  r.time_s = sim.time_s();
  if (video) r.video = video->Close();
  link->Finish(sim.time_s(), sim.stamp(), time_limit, r);
  r.localization.update(localization_score.ToJson());
  r.perception.update(perception_score.ToJson());
  // What ran inside the simulator's step belongs to its own stage; rendering is its own.
  // A stack node localises in its own process: there the step only publishes.
  const double localized_inside = here ? r.stage_ms["localize"] : 0.0;
  r.stage_ms["simulate"] -= localized_inside + r.stage_ms["camera_in_simulate"] + 1e3 * sim.render_seconds();
  r.stage_ms.erase("camera_in_simulate");
  if (camera) r.stage_ms["render"] = 1e3 * sim.render_seconds();
  r.wall_s = since(run_start) / 1e3;
  ScoreParking(config, mission, EgoRearAxle(scenario, sim.ego().pose), r);
  return r;
}

namespace {

// Wall-clock milliseconds per stage per simulated second.
nlohmann::json PerSecond(const std::map<std::string, double>& stage_ms, double sim_s) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [stage, ms] : stage_ms) out[stage] = sim_s > 0 ? ms / sim_s : 0.0;
  return out;
}

nlohmann::json LocalToJson(const ClosedLoopResult::LocalPlanning& l) {
  const double outside = l.driving_s - l.on_manoeuvre_s;
  return {{"calls", l.calls},
          {"found", l.found},
          {"skipped", l.skipped},
          {"failed", l.failed},
          {"failures", l.failures},
          {"success_rate", l.calls - l.skipped > 0 ? static_cast<double>(l.found) / (l.calls - l.skipped) : 0.0},
          {"ms", io::Quantiles(l.ms, {0.5, 0.9})},
          {"max_iterations", l.max_iterations},
          {"over_budget", l.over_budget},
          {"driving_s", l.driving_s},
          {"on_local_path_s", l.on_local_s},
          {"on_manoeuvre_s", l.on_manoeuvre_s},
          {"share_outside_manoeuvres", outside > 0 ? l.on_local_s / outside : 0.0}};
}

}  // namespace

nlohmann::json ClosedLoopResult::ToJson() const {
  nlohmann::json states = nlohmann::json::array(), visited = nlohmann::json::array();
  for (const auto& tr : transitions) {
    states.push_back({{"t_s", tr.t_s}, {"from", tr.from}, {"to", tr.to}, {"reason", tr.reason}});
    if (std::find(visited.begin(), visited.end(), tr.to) == visited.end()) visited.push_back(tr.to);
  }
  return {{"success", success},
          {"failure", failure},
          {"stack", stack},
          {"static_layer", static_layer},
          {"video", video},
          {"mcap", mcap},
          {"localization", localization},
          {"perception", perception},
          {"nodes", nodes},
          {"interrupted", interrupted},
          {"collisions", collisions},
          {"collision_events", collision_events},
          {"min_clearance_m", min_clearance_m},
          {"min_pedestrian_distance_m", min_pedestrian_m > 1e8 ? nlohmann::json() : nlohmann::json(min_pedestrian_m)},
          {"closest_pedestrian", closest_pedestrian},
          {"time_s", time_s},
          {"park_error_m", park_error_m},
          {"park_error_deg", park_error_deg},
          {"believed_park_error_m", believed_park_error_m},
          {"believed_park_error_deg", believed_park_error_deg},
          {"planning_ms", io::Quantiles(plan_ms, {0.5, 0.9})},
          {"speed_limited_s", limited_s},
          {"map_replans", map_replans},
          {"local_planner", LocalToJson(local)},
          {"timing",
           {{"wall_s", wall_s},
            {"real_time_factor", wall_s > 0 ? time_s / wall_s : 0.0},
            {"stage_ms_per_s", PerSecond(stage_ms, time_s)}}},
          {"states_visited", visited},
          {"transitions", states}};
}

}  // namespace specht::pipeline
