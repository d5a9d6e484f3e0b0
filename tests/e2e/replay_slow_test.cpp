// Longer `specht replay` runs (label: slow).
#include <nlohmann/json.hpp>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

// MRPT's simulated rawlogs come with ground truth: the run reports ATE against it.
// The bounds sit above the measured figures by a margin run-to-run noise does not
// cross (the replay is deterministic) and a real regression would.
TEST(ReplayCliTest, ReportsTrajectoryErrorAgainstMrptGroundTruth) {
  SPECHT_REQUIRE_FILE(testing::MrptDemoDir());
  const std::string out = testing::TempDir() + "/out";
  const auto r = testing::RunSpecht("replay -q '" + testing::MrptDemoDir() + "/simul.rawlog' -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto ate = Report(out)["metrics"]["ate"];
  std::printf("simul.rawlog ATE: RMSE %.3f m, max %.3f m, %.2f deg\n", ate["rmse_m"].get<double>(),
              ate["max_m"].get<double>(), ate["rmse_deg"].get<double>());
  EXPECT_EQ(ate["pairs"], 1733);
  EXPECT_LT(ate["rmse_m"].get<double>(), 0.08);   // 0.050 m measured
  EXPECT_LT(ate["rmse_deg"].get<double>(), 0.5);  // 0.25° measured
}

}  // namespace
}  // namespace specht
