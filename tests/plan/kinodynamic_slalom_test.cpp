// Every kinodynamic planner through a slalom (three walls from alternate sides) to
// its first solution: a drivable path (ExpectDrivable) at least as long as the
// straight line. Seconds per planner: slow label.
#include "kinodynamic_test_support.h"

namespace specht::plan {
namespace {

class KinodynamicSlalomTest : public ::testing::TestWithParam<std::string> {};

TEST_P(KinodynamicSlalomTest, GetsThroughWithADrivablePath) {
  const cv::Mat obstacles = Slalom();
  const CarOptions car;
  const KinodynamicOptions o = Options(GetParam());
  KinodynamicPlanner planner(o, car, std::make_shared<DistanceMap>(obstacles, 0.0, 0.0, kRes));
  const Pose goal{27, 8, 0};
  const KinodynamicResult r = planner.Plan({2, 2, 0}, goal);
  ExpectDrivable(obstacles, car, o, r, goal);
  EXPECT_GT(r.path.Length(), std::hypot(25.0, 6.0));  // at least the straight distance
  EXPECT_EQ(r.planner, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Planners, KinodynamicSlalomTest, ::testing::Values("sst", "rrt", "kpiece"));

}  // namespace
}  // namespace specht::plan
