// Missions driven in closed loop over seeds (mission_runs.h): the closed
// loop — the mission state machine (decide/closed_loop.h) plans with hybrid A* and
// the smoother, follows the path with pure pursuit, and drives the simulated car,
// with ground-truth localisation, map and agents. Per seed: run-<seed>.png (the
// driven path with footprints), steps-<seed>.jsonl (state and pose at the control
// rate) and paths-<seed>.csv (every plan: plan,x_m,y_m,theta_rad,direction); report.json: each run (success,
// collisions, clearances, parking error, time, planning times, states visited and every transition) and the totals.
#include "specht/pipeline/mission_runs.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/decide/mission.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/pipeline/nodes.h"
#include "specht/pipeline/perception.h"
#include "specht/pipeline/run_directory.h"
#include "specht/plan/draw.h"
#include "specht/sim/world.h"

namespace specht::pipeline {
namespace {

// Over every run: the median mission time, the worst localisation errors,
// perception's recall and precision per class pooled over the frames, the local
// planner's success rate, latency and share of the driving time, and the real-time
// factor (simulated over wall-clock seconds, all runs together).
nlohmann::json LoopTotals(const nlohmann::json& runs) {
  std::vector<double> times;
  double ate_rmse = 0, ate_max = 0, heading_max = 0, sim_s = 0, wall_s = 0;
  double local_found = 0, local_tried = 0, on_local_s = 0, outside_s = 0, local_ms_max = 0;
  int over_budget = 0;
  std::map<std::string, std::array<long, 4>> pooled;  // found, in view, right, reported
  for (const auto& r : runs) {
    times.push_back(r["time_s"].get<double>());
    sim_s += r["time_s"].get<double>(), wall_s += r["timing"]["wall_s"].get<double>();
    const auto& k = r["local_planner"];
    local_found += k["found"].get<double>();
    local_tried += k["calls"].get<double>() - k["skipped"].get<double>();
    on_local_s += k["on_local_path_s"].get<double>();
    outside_s += k["driving_s"].get<double>() - k["on_manoeuvre_s"].get<double>();
    local_ms_max = std::max(local_ms_max, k["ms"]["max"].get<double>());
    over_budget += k["over_budget"].get<int>();
    const auto& l = r["localization"];
    ate_rmse = std::max(ate_rmse, l["ate_rmse_m"].get<double>());
    ate_max = std::max(ate_max, l["ate_max_m"].get<double>());
    heading_max = std::max(heading_max, l["heading_error_max_deg"].get<double>());
    for (const auto& [cls, c] : r["perception"]["by_class"].items()) {
      auto& p = pooled[cls];
      p[0] += c["found"].get<long>(), p[1] += c["in_view"].get<long>();
      p[2] += c["right"].get<long>(), p[3] += c["reported"].get<long>();
    }
  }
  std::sort(times.begin(), times.end());
  // --nodes: the slowest run's latencies between the car and the stack node.
  nlohmann::json nodes;
  for (const auto& r : runs)
    if (!r["nodes"].is_null())
      for (const char* key : {"acknowledged_ms", "answer_ms"})
        for (const char* q : {"p50", "p99", "max"}) {
          const double ms = r["nodes"][key][q].get<double>();
          nodes[key][q] = nodes[key].contains(q) ? std::max(nodes[key][q].get<double>(), ms) : ms;
        }
  nlohmann::json perception = nlohmann::json::object();
  const auto ratio = [](long a, long b) { return b ? nlohmann::json(static_cast<double>(a) / b) : nlohmann::json(); };
  for (const auto& [cls, p] : pooled)
    perception[cls] = {{"recall", ratio(p[0], p[1])}, {"precision", ratio(p[2], p[3])}};
  return {{"median_time_s", times.empty() ? 0.0 : times[times.size() / 2]},
          {"localization_ate_rmse_m_worst", ate_rmse},
          {"localization_ate_max_m", ate_max},
          {"localization_heading_error_max_deg", heading_max},
          {"perception", perception},
          {"local_planner",
           {{"success_rate", local_tried > 0 ? local_found / local_tried : 0.0},
            {"ms_max", local_ms_max},
            {"over_budget", over_budget},
            {"share_of_driving_outside_manoeuvres", outside_s > 0 ? on_local_s / outside_s : 0.0}}},
          {"real_time_factor", wall_s > 0 ? sim_s / wall_s : 0.0},
          {"nodes", nodes}};
}

// The map of `dir` (map_artefact.h), which must have been drawn in this scenario.
std::shared_ptr<const MapArtefact> SiteMap(const std::string& dir, const sim::Scenario& scenario) {
  auto map = std::make_shared<MapArtefact>(ReadMapArtefact(dir));
  if (map->site.empty())
    throw InputError(dir + ": a map without site.json, so not drawn by a mapping drive of `specht run` in " +
                     scenario.name + "; write one with `specht run " + scenario.name + ".yaml --stack full -o DIR`");
  if (map->site != scenario.name)
    throw InputError(dir + "/site.json: the map was drawn in scenario '" + map->site + "', this run is in '" +
                     scenario.name + "'");
  return map;
}

// `--nodes`: `specht node stack` on this run's parameters (the params.yaml its folder
// holds: the files and overrides resolved), its scenario, mission and map.
ClosedLoopConfig::StackNode StackNodeOf(const params::Params& params, const MissionRunInputs& a,
                                        const std::string& out) {
  const auto& loop = params.Get<ClosedLoopOptions>("closed_loop");
  if (loop.perception == "camera" || loop.localization == "truth" || loop.perception == "truth")
    throw InputError(
        "--nodes runs the full stack (closed_loop.localization slam or map, perception detections); "
        "this run has localization " +
        loop.localization + ", perception " + loop.perception);
  ClosedLoopConfig::StackNode node;
  node.command = {std::filesystem::read_symlink("/proc/self/exe").string(),
                  "node",
                  "stack",
                  a.scenario,
                  "-q",
                  "-p",
                  out + "/params.yaml"};
  if (!a.mission.empty()) node.command.insert(node.command.end(), {"--mission", a.mission});
  if (!a.map_dir.empty()) node.command.insert(node.command.end(), {"--map", a.map_dir});
  if (a.perception_node) {
    node.command.push_back("--perception-node");
    node.perception_command = {node.command[0],
                               "node",
                               "perception",
                               "-q",
                               "-p",
                               out + "/params.yaml",
                               "--set",
                               "dds.lease_s=" + std::to_string(params.Get<NodeOptions>("node").perception_lease_s)};
  }
  node.out_dir = out;
  node.dds = params.Get<net::Options>("dds");
  node.timeout_s = params.Get<NodeOptions>("node").command_timeout_s;
  return node;
}

}  // namespace

ClosedLoopConfig LoopConfigFrom(const params::Params& params, const sim::Scenario& scenario,
                                const std::string& map_dir) {
  ClosedLoopConfig config;
  config.car = ScenarioCar(scenario, params.Get<plan::CarOptions>("car"));
  config.search = params.Get<plan::HybridAStarOptions>("hybrid_astar");
  config.fine_search = params.Get<plan::HybridAStarOptions>("hybrid_astar_fine");
  config.smoother = params.Get<plan::SmootherOptions>("smoother");
  config.tracker = params.Get<plan::TrackerOptions>("tracker");
  config.kinodynamic = params.Get<plan::KinodynamicOptions>("kinodynamic");
  config.local = params.Get<plan::LocalPlannerOptions>("local_planner");
  config.loop = params.Get<ClosedLoopOptions>("closed_loop");
  config.slam = {params.Get<slam::SlamOptions>("slam"),
                 params.Get<slam::ScanMatchingOptions>("scan_matching"),
                 params.Get<slam::LoopClosureOptions>("loop_closure"),
                 params.Get<slam::PoseGraphOptions>("pose_graph"),
                 params.Get<slam::GridOptions>("grid"),
                 4.0,
                 nullptr};
  if (!map_dir.empty()) config.slam.site_map = SiteMap(map_dir, scenario);
  config.pose_check = params.Get<slam::PoseCheckOptions>("pose_check");
  config.detection = params.Get<sim::SyntheticDetectionOptions>("synthetic_detections");
  config.tracking = params.Get<track::TrackerOptions>("track");
  config.world = params.Get<world::WorldModelOptions>("world");
  return config;
}

std::vector<decide::Goal> MissionOf(const std::string& mission_file, const sim::Scenario& scenario,
                                    const plan::CarOptions& car) {
  return mission_file.empty() ? decide::DefaultMission(MissionSiteOf(scenario), car)
                              : decide::LoadMission(mission_file, MissionSiteOf(scenario), car);
}

int RunMissions(const params::Params& params, const MissionRunInputs& a, const std::string& out, bool quiet) {
  const sim::Scenario scenario = sim::LoadScenario(a.scenario);
  ClosedLoopConfig config = LoopConfigFrom(params, scenario, a.map_dir);
  std::optional<sim::SpriteLibrary> sprites;
  if (config.loop.perception == "camera") {
    if (a.data_dir.empty())
      throw InputError(
          "closed_loop.perception camera: no data directory (--data-dir or $SPECHT_DATA_DIR) for the detector's "
          "models and the sprites");
    sprites = sim::SpriteLibrary::Load(a.data_dir + "/sprites");
    config.camera = {params.Get<stereo::SgmOptions>("stereo"),
                     params.Get<detect::DetectorOptions>("detect"),
                     params.Get<detect::FusionOptions>("fusion"),
                     params.Get<PerceptionOptions>("perception").stereo_downsample,
                     a.data_dir,
                     &*sprites};
  }
  const std::vector<decide::Goal> mission = MissionOf(a.mission, scenario, config.car);
  if (a.perception_node && !a.nodes) throw InputError("--perception-node needs --nodes");
  if (a.nodes) config.stack_node = StackNodeOf(params, a, out);
  const auto [first, last] = a.seeds.value_or(std::pair<uint64_t, uint64_t>{scenario.seed, scenario.seed});
  PrepareRunDirectory(out, params);
  const auto map = plan::DistanceMap::FromGrid(sim::World(scenario).TrueGrid(0.1));

  io::RunReport report("run");
  nlohmann::json runs = nlohmann::json::array();
  int successes = 0, collisions = 0;
  double min_clearance = 1e9, min_pedestrian = 1e9, max_park_m = 0, max_park_deg = 0;
  ProgressLine progress("run", "runs", !quiet, 0.0);
  for (uint64_t seed = first; seed <= last; ++seed) {
    std::string steps;
    const auto chosen = [&](const std::string& which, const char* extension) {
      return which == "all" || (which == "first" && seed == first) ? out + "/run-" + std::to_string(seed) + extension
                                                                   : std::string();
    };
    // The video draws the stack's world model, which a stack node keeps in its process.
    config.video = a.nodes ? "" : chosen(config.loop.video, ".mp4");
    config.mcap = chosen(config.loop.mcap, ".mcap");
    const ClosedLoopResult r = RunClosedLoop(scenario, seed, mission, config, [&](const LoopStep& k) {
      char line[256];
      std::snprintf(line, sizeof(line),
                    "{\"t_s\":%.2f,\"state\":\"%s\",\"x_m\":%.3f,\"y_m\":%.3f,\"theta_rad\":%.4f,"
                    "\"believed\":[%.3f,%.3f,%.4f],\"tracks\":%d,\"path\":\"%s\"}\n",
                    k.t_s, k.state.c_str(), k.pose.x, k.pose.y, k.pose.theta, k.believed.x, k.believed.y,
                    k.believed.theta, k.tracks, k.on_local_path ? "local" : "route");
      steps += line;
    });
    io::WriteTextAtomically(out + "/steps-" + std::to_string(seed) + ".jsonl", steps);
    std::string paths;
    for (size_t k = 0; k < r.paths.size(); ++k) {
      const std::string csv = r.paths[k].ToCsv();
      paths += k == 0 ? "plan," + csv.substr(0, csv.find('\n') + 1) : "";
      for (size_t a = csv.find('\n') + 1, b; a < csv.size(); a = b + 1) {
        b = csv.find('\n', a);
        paths += std::to_string(k) + "," + csv.substr(a, b - a + 1);
      }
    }
    io::WriteTextAtomically(out + "/paths-" + std::to_string(seed) + ".csv", paths);
    if (r.drawn_map) {  // a mapping drive: what `--map` reads back
      const std::string dir = out + "/map-" + std::to_string(seed);
      std::filesystem::create_directories(dir);
      WriteMapArtefact(*r.drawn_map, dir);
      io::WriteMapPng(r.drawn_map->grid, {}, dir + "/map.png");
    }
    plan::Path driven;
    for (const auto& p : r.trajectory) driven.points.push_back({p, 1});
    const plan::Pose start = r.trajectory.empty() ? plan::Pose{} : r.trajectory.front();
    io::WritePng(plan::DrawPlan(map, config.car, driven, start, mission.back().pose, 3.0),
                 out + "/run-" + std::to_string(seed) + ".png");
    nlohmann::json j = r.ToJson();
    j["seed"] = seed;
    runs.push_back(j);
    successes += r.success, collisions += r.collisions;
    min_clearance = std::min(min_clearance, r.min_clearance_m);
    min_pedestrian = std::min(min_pedestrian, r.min_pedestrian_m);
    if (r.park_error_m >= 0)
      max_park_m = std::max(max_park_m, r.park_error_m), max_park_deg = std::max(max_park_deg, r.park_error_deg);
    progress.Update(static_cast<double>(seed - first + 1), static_cast<double>(seed - first + 1) / (last - first + 1),
                    r.success ? "ok" : "failed: " + r.failure);
    if (InterruptRequested()) break;  // this drive (cut short or not) is written; the next is not started
  }
  progress.Finish();
  const int n = static_cast<int>(runs.size());
  if (InterruptRequested())
    report.SetInterrupted(std::to_string(n) + " of " + std::to_string(last - first + 1) + " runs");
  auto& j = report.json();
  j["inputs"] = {{"scenario", a.scenario},
                 {"mission", a.mission.empty() ? "default" : a.mission},
                 {"seeds", {first, last}},
                 {"map", a.map_dir.empty() ? nlohmann::json() : nlohmann::json(a.map_dir)}};
  j["metrics"] = {
      {"runs", n},
      {"success_rate", static_cast<double>(successes) / n},
      {"collisions", collisions},
      {"min_clearance_m", min_clearance},
      {"min_pedestrian_distance_m", min_pedestrian > 1e8 ? nlohmann::json() : nlohmann::json(min_pedestrian)},
      {"pedestrian_margin_m", config.loop.pedestrian_margin_m},
      {"max_park_error_m", max_park_m},
      {"max_park_error_deg", max_park_deg},
      {"stack", config.loop.Stack()}};
  j["metrics"].update(LoopTotals(runs));
  j["runs"] = runs;
  report.Write(out);
  char closest[32] = "none near";
  if (min_pedestrian < 1e8) std::snprintf(closest, sizeof closest, "%.2f m", min_pedestrian);
  std::printf(
      "run %s (stack %s): %d/%d missions completed, %d collisions, min clearance %.2f m, closest pedestrian %s, "
      "worst parking %.3f m / %.1f°, median %.1f s, localisation error max %.3f m, on the local planner's paths "
      "%.0f %% of the driving outside manoeuvres, %.1f× real time\n",
      scenario.name.c_str(), config.loop.Stack().c_str(), successes, n, collisions, min_clearance, closest, max_park_m,
      max_park_deg, j["metrics"]["median_time_s"].get<double>(), j["metrics"]["localization_ate_max_m"].get<double>(),
      100 * j["metrics"]["local_planner"]["share_of_driving_outside_manoeuvres"].get<double>(),
      j["metrics"]["real_time_factor"].get<double>());
  for (const auto& run : runs)
    if (!run["success"].get<bool>())
      std::printf("  seed %llu: %s\n", static_cast<unsigned long long>(run["seed"].get<uint64_t>()),
                  run["failure"].get<std::string>().c_str());
  if (InterruptRequested()) return InterruptExitCode();
  return successes == n ? 0 : 1;
}

}  // namespace specht::pipeline
