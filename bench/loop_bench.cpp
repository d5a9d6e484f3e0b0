// loop_bench [--data DIR] <scenario.yaml>...: the closed loop's full stack (SLAM on
// the simulated LiDAR, perceived tracks, hybrid A* route, OMPL local planner) on each
// scenario's default mission, seed 101, at the defaults: the real-time factor
// (simulated over wall-clock seconds), wall-clock milliseconds per simulated second by
// stage, and the planners' latency. One JSON object per scenario and perception:
// "detections" (the simulator's), and with --data (detector models and sprites/)
// "camera" — SGM and the CNN on the rendered 10 Hz stereo frames, SGM at full size
// and at half size (perception.stereo_downsample 2).
#include <optional>
#include <string>
#include <vector>

#include "bench_support.h"
#include "specht/decide/mission.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/sim/scenario.h"
#include "specht/sim/sprites.h"

namespace {

void Run(const specht::sim::Scenario& s, specht::pipeline::ClosedLoopConfig config, const std::string& name) {
  config.car = specht::pipeline::ScenarioCar(s, config.car);
  config.loop.localization = "slam";
  const auto mission = specht::decide::DefaultMission(specht::pipeline::MissionSiteOf(s), config.car);
  const specht::pipeline::ClosedLoopResult r = specht::pipeline::RunClosedLoop(s, 101, mission, config);
  const nlohmann::json j = r.ToJson();
  specht::bench::Emit({{"name", name},
                       {"success", r.success},
                       {"sim_s", r.time_s},
                       {"wall_s", r.wall_s},
                       {"real_time_factor", j["timing"]["real_time_factor"]},
                       {"stage_ms_per_sim_s", j["timing"]["stage_ms_per_s"]},
                       {"global_planning_ms", j["planning_ms"]},
                       {"local_planning_ms", j["local_planner"]["ms"]},
                       {"local_planner_calls", j["local_planner"]["calls"]},
                       {"perception_frames", r.perception["frames"]},
                       {"peak_rss_mib", specht::bench::PeakRssMib()},
                       {"machine", specht::bench::MachineNotes()}});
}

}  // namespace

int main(int argc, char** argv) {
  std::string data;
  std::vector<std::string> scenarios;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--data" && i + 1 < argc)
      data = argv[++i];
    else
      scenarios.push_back(argv[i]);
  }
  std::optional<specht::sim::SpriteLibrary> sprites;
  if (!data.empty()) sprites = specht::sim::SpriteLibrary::Load(data + "/sprites");
  for (const auto& path : scenarios) {
    const specht::sim::Scenario s = specht::sim::LoadScenario(path);
    specht::pipeline::ClosedLoopConfig config;
    config.loop.perception = "detections";
    Run(s, config, "loop/" + s.name);
    if (!sprites || !s.stereo) continue;
    config.loop.perception = "camera";
    config.camera.data_dir = data, config.camera.sprites = &*sprites;  // the sections' defaults otherwise
    for (int downsample : {1, 2}) {
      config.camera.downsample = downsample;
      Run(s, config, "loop-camera-sgm-1of" + std::to_string(downsample) + "/" + s.name);
    }
  }
}
