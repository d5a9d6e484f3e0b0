// sim_bench <scenario.yaml>...: simulation speed per scenario, default seed, whole
// duration: simulated seconds per wall second, ms per LiDAR scan (ray casting
// included), stereo frames rendered per second (scenarios with a camera), peak memory.
// One JSON object per scenario. With --sprites DIR (<data>/sprites) agents are drawn
// as photographs (sim/sprites.h), else as boxes.
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <chrono>
#include <optional>
#include <string>

#include "bench_support.h"
#include "specht/sim/simulator.h"

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  std::optional<specht::sim::SpriteLibrary> sprites;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--sprites" && i + 1 < argc) {
      sprites = specht::sim::SpriteLibrary::Load(argv[++i]);
      continue;
    }
    const specht::sim::Scenario s = specht::sim::LoadScenario(argv[i]);
    specht::sim::Simulator sim(s, s.seed, sprites ? &*sprites : nullptr);
    long scans = 0, observations = 0, stereo_frames = 0;
    const auto t0 = Clock::now();
    const long steps = std::lround(s.duration_s / specht::sim::Simulator::kStepS);
    for (long k = 0; k < steps; ++k) {
      sim.Step(
          [&](specht::Stamp, const mrpt::obs::CObservation::Ptr& obs) {
            ++observations;
            scans += std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs) != nullptr;
          },
          [&](specht::Stamp, const specht::sim::StereoFrame&) { ++stereo_frames; });
    }
    const double total = std::chrono::duration<double>(Clock::now() - t0).count();
    const double render = sim.render_seconds(), wall = total - render;
    specht::bench::Emit({{"name", "sim/" + s.name},
                         {"simulated_s", s.duration_s},
                         {"wall_s", wall},
                         {"simulated_s_per_wall_s", s.duration_s / wall},
                         {"scans", scans},
                         {"observations", observations},
                         {"ms_per_simulated_second", 1000.0 * wall / s.duration_s},
                         {"agents", s.agents.size()},
                         {"sprites", sprites ? sprites->size() : 0},
                         {"stereo_frames", stereo_frames},
                         {"stereo_frames_per_s", render > 0 ? stereo_frames / render : 0.0},
                         {"stereo_resolution",
                          s.stereo ? std::to_string(s.stereo->width) + "x" + std::to_string(s.stereo->height) : "-"},
                         {"peak_rss_mib", specht::bench::PeakRssMib()},
                         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
