// classify_bench: the trajectory classifier's speed on 2 threads, per variant
// (tiny, shallow, deep, split, mlp) and window length (360 × 9 as in the vessel paper,
// 60 × 9 as the robot tracks use): batched inference in windows per second
// (Predict's cache-sized batches, best of 3 passes over 1,024 random windows) and training throughput in
// windows per second (one epoch of 512 windows, batch 64, Adam, input noise), and
// the latency of one window alone (what online use of a few tracks costs).
// Random weights and inputs: speed does not depend on the values.
//
// Why the shallow network cannot reach 1,000 windows/s at 360 points on 2 cores:
// its convolutions cost ≈ 505 k multiply-adds per time step (block 1: 9·64·8 +
// 64·64·(5+3) + 9·64; block 2: 64·128·8 + 128·128·(5+3) + 64·128; block 3:
// 128·128·16), i.e. 182 M per window, so 1,000 windows/s needs ≈ 364 GFLOP/s —
// above the peak of two AVX2 cores. The JSON gives `gflops` so the reader can see
// how close to the hardware each variant runs.
#include <algorithm>
#include <chrono>
#include <random>

#include "bench_support.h"
#include "specht/classify/model.h"

namespace {

using Clock = std::chrono::steady_clock;

specht::classify::Dataset RandomWindows(int n, int features, int length, int classes) {
  specht::classify::Dataset d;
  d.features = features, d.length = length;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  d.x.resize(static_cast<size_t>(n) * features * length);
  for (float& v : d.x) v = u(rng);
  for (int i = 0; i < n; ++i) {
    d.y.push_back(i % classes);
    d.object_ids.push_back("o" + std::to_string(i));
  }
  return d;
}

}  // namespace

int main() {
  const std::vector<std::string> classes = {"a", "b", "c", "d", "e"};
  for (const int length : {360, 60}) {
    for (const std::string& variant : specht::classify::ModelVariants()) {
      specht::classify::ModelOptions o;
      o.variant = variant;
      o.threads = 2;
      o.epochs = 1;
      specht::classify::Classifier model(o, 9, length, classes);
      const auto windows = RandomWindows(1024, 9, length, static_cast<int>(classes.size()));
      double best_s = 1e9;
      for (int pass = 0; pass < 3; ++pass) {
        const auto t0 = Clock::now();
        model.Predict(windows);
        best_s = std::min(best_s, std::chrono::duration<double>(Clock::now() - t0).count());
      }
      const double rate = windows.size() / best_s;
      // Online use classifies a few tracks at a time: latency of one window alone.
      const auto one = RandomWindows(1, 9, length, static_cast<int>(classes.size()));
      std::vector<double> single_ms;
      for (int i = 0; i < 50; ++i) {
        const auto t1 = Clock::now();
        model.Predict(one);
        single_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t1).count());
      }
      std::sort(single_ms.begin(), single_ms.end());
      const auto train = RandomWindows(512, 9, length, static_cast<int>(classes.size()));
      const auto t0 = Clock::now();
      model.Train(train, {});
      const double train_s = std::chrono::duration<double>(Clock::now() - t0).count();
      specht::bench::Emit({{"name", "classify/" + variant + "/" + std::to_string(length)},
                           {"window", "9x" + std::to_string(length)},
                           {"parameters", model.parameter_count()},
                           {"threads", o.threads},
                           {"inference_windows_per_s", rate},
                           {"inference_ms_per_window", 1000.0 / rate},
                           {"single_window_ms_p50", single_ms[single_ms.size() / 2]},
                           {"gflops", 2.0 * model.multiply_adds_per_window() * rate / 1e9},
                           {"training_windows_per_s", train.size() / train_s},
                           {"peak_rss_mib", specht::bench::PeakRssMib()},
                           {"machine", specht::bench::MachineNotes()}});
    }
  }
  return 0;
}
