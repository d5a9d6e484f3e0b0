// loop_bench <scenario.yaml>...: the closed loop's full stack (SLAM on the simulated
// LiDAR, perceived tracks, hybrid A* route, OMPL local planner) on each scenario's
// default mission, seed 101, at the defaults: the real-time factor (simulated over
// wall-clock seconds), wall-clock milliseconds per simulated second by stage, and the
// planners' latency. One JSON object per scenario.
#include "bench_support.h"
#include "specht/decide/mission.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/sim/scenario.h"

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const specht::sim::Scenario s = specht::sim::LoadScenario(argv[i]);
    specht::pipeline::ClosedLoopConfig config;
    config.car = specht::pipeline::ScenarioCar(s, config.car);
    config.loop.localization = "slam", config.loop.perception = "detections";
    const auto mission = specht::decide::DefaultMission(specht::pipeline::MissionSiteOf(s), config.car);
    const specht::pipeline::ClosedLoopResult r = specht::pipeline::RunClosedLoop(s, 101, mission, config);
    const nlohmann::json j = r.ToJson();
    specht::bench::Emit({{"name", "loop/" + s.name},
                         {"success", r.success},
                         {"sim_s", r.time_s},
                         {"wall_s", r.wall_s},
                         {"real_time_factor", j["timing"]["real_time_factor"]},
                         {"stage_ms_per_sim_s", j["timing"]["stage_ms_per_s"]},
                         {"global_planning_ms", j["planning_ms"]},
                         {"local_planning_ms", j["local_planner"]["ms"]},
                         {"local_planner_calls", j["local_planner"]["calls"]},
                         {"peak_rss_mib", specht::bench::PeakRssMib()},
                         {"machine", specht::bench::MachineNotes()}});
  }
}
