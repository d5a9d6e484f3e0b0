#include "specht/core/time.h"

#include <gtest/gtest.h>
#include <mrpt/system/datetime.h>

namespace specht {
namespace {

TEST(StampTest, ConvertsExactlyToAndFromMrptTime) {
  // 2006-01-21 09:03:45.9737599 UTC, the first stamp of the built-in rawlog.
  const Stamp s{1137834225973759900};
  EXPECT_EQ(FromMrpt(ToMrpt(s)), s);
  EXPECT_NEAR(mrpt::Clock::toDouble(ToMrpt(s)), 1137834225.9737599, 1e-6);
  EXPECT_EQ(Stamp::FromSeconds(1.5).ns, 1'500'000'000);
  EXPECT_DOUBLE_EQ(SecondsBetween(Stamp{0}, Stamp{2'500'000'000}), 2.5);
}

}  // namespace
}  // namespace specht
