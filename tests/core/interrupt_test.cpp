#include "specht/core/interrupt.h"

#include <gtest/gtest.h>
#include <signal.h>

namespace specht {
namespace {

class InterruptTest : public ::testing::Test {
 protected:
  void SetUp() override { ClearInterruptForTesting(); }
  void TearDown() override { ClearInterruptForTesting(); }
};

TEST_F(InterruptTest, TheFirstSignalOnlyAsksToStop) {
  InstallInterruptHandlers();
  EXPECT_FALSE(InterruptRequested());
  EXPECT_EQ(InterruptExitCode(), 0);
  EXPECT_NO_THROW(ThrowIfInterrupted("work"));
  raise(SIGTERM);  // handled: the process goes on
  EXPECT_TRUE(InterruptRequested());
  EXPECT_EQ(InterruptSignal(), SIGTERM);
  EXPECT_EQ(InterruptName(), "SIGTERM");
  EXPECT_EQ(InterruptExitCode(), 143);
  try {
    ThrowIfInterrupted("cross-validation");
    FAIL() << "no Interrupted thrown";
  } catch (const Interrupted& e) {
    EXPECT_STREQ(e.what(), "cross-validation: interrupted by SIGTERM");
    EXPECT_EQ(ExitCodeFor(e), 143);
  }
}

TEST_F(InterruptTest, TheFirstSignalIsKept) {
  RequestInterrupt(SIGINT);
  RequestInterrupt(SIGTERM);
  EXPECT_EQ(InterruptName(), "SIGINT");
  EXPECT_EQ(InterruptExitCode(), 130);
}

TEST(InterruptDeathTest, ASecondSignalEndsTheProcessAtOnce) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        InstallInterruptHandlers();
        raise(SIGINT);
        raise(SIGINT);
        std::exit(0);  // not reached
      },
      ::testing::KilledBySignal(SIGINT), "");
}

}  // namespace
}  // namespace specht
