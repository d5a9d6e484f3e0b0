// track_bench <scenario.yaml>...: the tracker's cost per detection frame on each
// scenario's synthetic detections (default options, seed 1, whole duration), with
// the number of tracks it carried. One JSON object per scenario. Then crowds the
// scenes do not have: N pedestrians walking straight at 1.4 m/s in a 100 m square,
// detected every 0.1 s with σ 0.15 m, for N = 10, 50, 200 (assignment grows as N³
// in the worst case; gating keeps it sparse).
#include <chrono>
#include <cmath>
#include <random>

#include "bench_support.h"
#include "specht/pipeline/synthetic_tracking.h"
#include "specht/sim/scenario.h"

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const specht::sim::Scenario s = specht::sim::LoadScenario(argv[i]);
    long track_frames = 0;
    const auto run = specht::pipeline::RunSyntheticTracking(
        s, 1, specht::track::TrackerOptions{}, specht::sim::SyntheticDetectionOptions{}, "", nullptr,
        [&](std::vector<specht::types::Track>& tracks, double) { track_frames += static_cast<long>(tracks.size()); });
    specht::bench::Emit({{"name", "track/" + s.name},
                         {"frames", run.frames},
                         {"detections_per_frame", run.frames ? static_cast<double>(run.detections) / run.frames : 0.0},
                         {"tracks_per_frame", run.frames ? static_cast<double>(track_frames) / run.frames : 0.0},
                         {"tracker_ms_per_frame", run.frames ? 1000.0 * run.tracker_seconds / run.frames : 0.0},
                         {"peak_rss_mib", specht::bench::PeakRssMib()},
                         {"machine", specht::bench::MachineNotes()}});
  }
  for (const int n : {10, 50, 200}) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> pos(0, 100), heading(-M_PI, M_PI);
    std::normal_distribution<double> noise(0, 0.15);
    std::vector<std::array<double, 4>> agents;  // x, y, vx, vy
    for (int i = 0; i < n; ++i) {
      const double h = heading(rng);
      agents.push_back({pos(rng), pos(rng), 1.4 * std::cos(h), 1.4 * std::sin(h)});
    }
    specht::track::Tracker tracker(specht::track::TrackerOptions{});
    const int frames = 300;
    double seconds = 0;
    for (int k = 0; k < frames; ++k) {
      const specht::Stamp now = specht::Stamp::FromSeconds(0.1 * k);
      std::vector<specht::types::Obstacle> detections;
      for (auto& a : agents) {
        a[0] += 0.1 * a[2], a[1] += 0.1 * a[3];
        specht::types::Obstacle o;
        o.cls = "pedestrian", o.stamp = now, o.score = 0.9;
        o.x_m = a[0] + noise(rng), o.y_m = a[1] + noise(rng);
        o.covariance_xy = cv::Matx22d::eye() * 0.0225;
        detections.push_back(o);
      }
      const auto t0 = std::chrono::steady_clock::now();
      tracker.Update(detections, now);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    specht::bench::Emit({{"name", "track/crowd-" + std::to_string(n)},
                         {"frames", frames},
                         {"detections_per_frame", n},
                         {"tracks_per_frame", tracker.Tracks().size()},
                         {"tracker_ms_per_frame", 1000.0 * seconds / frames},
                         {"peak_rss_mib", specht::bench::PeakRssMib()},
                         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
