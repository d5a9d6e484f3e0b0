#include <gtest/gtest.h>

#include <chrono>

#include "specht/io/replay.h"

namespace specht::io {
namespace {

TEST(ReplayClockTest, WindowIsRelativeToTheFirstStamp) {
  ReplayOptions o;
  o.from_s = 1.0;
  o.to_s = 3.0;
  ReplayClock clock(o);
  const int64_t t0 = 5'000'000'000;
  EXPECT_EQ(clock.Classify(Stamp{t0}), ReplayClock::Verdict::kBefore);
  EXPECT_EQ(clock.Classify(Stamp{t0 + 999'999'999}), ReplayClock::Verdict::kBefore);
  EXPECT_EQ(clock.Classify(Stamp{t0 + 1'000'000'000}), ReplayClock::Verdict::kInside);
  EXPECT_EQ(clock.Classify(Stamp{t0 + 3'000'000'000}), ReplayClock::Verdict::kInside);
  EXPECT_EQ(clock.Classify(Stamp{t0 + 3'000'000'001}), ReplayClock::Verdict::kAfter);
}

TEST(ReplayClockTest, RatePacesDataTimeAgainstTheWallClock) {
  ReplayOptions o;
  o.rate = 10.0;  // 1 s of data in 0.1 s
  ReplayClock clock(o);
  const auto start = std::chrono::steady_clock::now();
  clock.WaitFor(Stamp{0});
  clock.WaitFor(Stamp{1'000'000'000});
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(waited, 0.099);
}

TEST(ReplayClockTest, RelationsRejectAnEmptyWindow) {
  ReplayOptions o;
  o.from_s = 5;
  o.to_s = 2;
  EXPECT_EQ(o.Relations().size(), 1u);
}

}  // namespace
}  // namespace specht::io
