#include "specht/core/progress.h"

#include <gtest/gtest.h>

namespace specht {
namespace {

TEST(ProgressLineTest, ShowsPercentRateAndEta) {
  // 50 scans in 2 s at 25 % done: 25 scans/s, 6 s to go.
  EXPECT_EQ(ProgressLine::Format("replay", 50, 0.25, "scans", 2.0, "data 10 s"),
            "replay: 25.0% 50 scans 25.0 scans/s ETA 6s data 10 s");
}

TEST(ProgressLineTest, UnknownTotalHasNoEta) {
  EXPECT_EQ(ProgressLine::Format("sim", 10, -1, "frames", 4.0, ""), "sim: 10 frames 2.5 frames/s");
}

TEST(ProgressLineTest, LongEtaIsInMinutesAndHours) {
  EXPECT_EQ(ProgressLine::Format("tune", 1, 0.001, "evals", 10.0, ""), "tune: 0.1% 1 evals 0.1 evals/s ETA 2h46m");
}

TEST(ProgressLineTest, EtaFromElapsedAndFractionDone) {
  EXPECT_EQ(FormatEta(30.0, 0.25), "1m30s");  // a quarter in 30 s: 90 s to go
  EXPECT_EQ(FormatEta(10.0, 1.0), "0s");
  EXPECT_EQ(FormatEta(10.0, 0.0), "?");  // nothing done yet: unknown
  EXPECT_EQ(ProgressLine::Format("run", 0, 0.0, "runs", 1.0, ""), "run: 0.0% 0 runs 0.0 runs/s ETA ?");
}

}  // namespace
}  // namespace specht
