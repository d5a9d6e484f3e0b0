// Tracking on the shipped synthetic scenes from noisy detections (issue acceptance 1):
// every scenario with seeds 1–10, scored with CLEAR MOT against the visible agents.
#include <gtest/gtest.h>

#include "specht/eval/mot.h"
#include "specht/pipeline/synthetic_tracking.h"
#include "specht/sim/scenario.h"
#include "test_support.h"

namespace specht {
namespace {

TEST(TrackingSimTest, ShippedScenesMeetClearMotTargets) {
  eval::MotResult total;
  for (const char* name : {"urban-crossing", "course-loop", "parking-lot"}) {
    const sim::Scenario scenario = sim::LoadScenario(testing::SourceDir() + "/datasets/scenarios/" + name + ".yaml");
    for (uint64_t seed = 1; seed <= 10; ++seed) {
      const auto run = pipeline::RunSyntheticTracking(scenario, seed, {}, {}, "s" + std::to_string(seed) + "/");
      total.Add(eval::EvaluateMot(run.truth, run.tracks, 1.0));
    }
  }
  std::printf("MOTA %.3f MOTP %.3f m IDSW %ld (%.2f per 100 s) over %.0f track-s\n", total.mota, total.motp_m,
              total.id_switches, total.id_switches_per_100s, total.track_seconds);
  EXPECT_GT(total.track_seconds, 3000);
  EXPECT_GE(total.mota, 0.9);
  EXPECT_LE(total.id_switches_per_100s, 1.0);
  EXPECT_LT(total.motp_m, 0.3);  // detections have σ 0.15 m + 1 % of range
}

}  // namespace
}  // namespace specht
