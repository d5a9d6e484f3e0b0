// `specht plan` as a user runs it: parking in a marked bay of a shipped scenario,
// and the errors a user meets first.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(PlanCliTest, ParksInAScenarioBay) {
  const std::string out = testing::TempDir("plan_cli") + "/out";
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml";
  const auto r = testing::RunSpecht("plan '" + scenario + "' --goal bay:south-13 -q -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"path.csv", "plan.png", "params.yaml", "report.json", "report.md"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto report = Report(out);
  EXPECT_TRUE(report["metrics"]["found"].get<bool>());
  EXPECT_GT(report["metrics"]["min_clearance_m"].get<double>(), 0.1);  // the safety margin
  EXPECT_LE(report["metrics"]["max_curvature_per_m"].get<double>(),
            1.05 * report["metrics"]["curvature_limit_per_m"].get<double>());
  // The last row of path.csv is the goal: the footprint centred in the bay (13.5,
  // 3.75, heading 90°): the scenario's car turns about its box centre (no
  // ego.rear_overhang_m), so its reference point is the bay centre itself.
  const std::string csv = testing::ReadFile(out + "/path.csv");
  const std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  double x = 0, y = 0, theta = 0;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%lf,%lf", &x, &y, &theta), 3) << last;
  EXPECT_NEAR(x, 13.5, 0.01);
  EXPECT_NEAR(y, 3.75, 0.01);
  EXPECT_NEAR(theta, M_PI / 2, 0.01);
}

TEST(PlanCliTest, KinodynamicPlannerReachesTheGoalWithinTolerance) {
  // OMPL RRT guided by hybrid A*, bounded by iterations (reproducible), to the
  // middle bay of the parking lot; the path ends within the goal tolerances, and
  // runs twice alike.
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml";
  std::string csv[2];
  for (int run = 0; run < 2; ++run) {
    const std::string out = testing::TempDir("plan_cli_kino") + "/out" + std::to_string(run);
    const auto r = testing::RunSpecht(
        "plan '" + scenario + "' --goal bay:middle-14 --planner rrt --guided -q " +
        "--set kinodynamic.time_budget_ms=60000 --set kinodynamic.max_iterations=100000 " + "-o '" + out + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const auto report = Report(out);
    EXPECT_TRUE(report["metrics"]["found"].get<bool>());
    EXPECT_EQ(report["inputs"]["planner"], "rrt");
    EXPECT_LE(report["metrics"]["goal_distance_m"].get<double>(), 0.3);
    EXPECT_LE(report["metrics"]["max_curvature_per_m"].get<double>(),
              1.05 * report["metrics"]["curvature_limit_per_m"].get<double>());
    csv[run] = testing::ReadFile(out + "/path.csv");
  }
  EXPECT_EQ(csv[0], csv[1]);  // a replay is deterministic
}

TEST(PlanCliTest, BadInputNamesTheProblem) {
  const std::string out = testing::TempDir("plan_cli_bad") + "/out";
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml";
  auto r = testing::RunSpecht("plan '" + scenario + "' --goal bay:nowhere -q -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("no bay \"nowhere\""));
  r = testing::RunSpecht("plan '" + scenario + "' --goal 13.5,3.75 -q -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("is not x,y,heading_deg"));
  r = testing::RunSpecht("plan '" + scenario + "' --start 0.5,0.5,0 --goal bay:south-13 -q -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("collides at the start"));
  // An empty map (a 0 × 0 image): named, before any planning.
  const std::string dir = testing::TempDir("plan_cli_empty");
  testing::WriteFile(dir + "/empty.pgm", "P5\n0 0\n255\n");
  testing::WriteFile(dir + "/empty.yaml",
                     "image: empty.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                     "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  r = testing::RunSpecht("plan '" + dir + "/empty.yaml' --start 1,1,0 --goal 2,2,0 -q -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("empty.pgm"));
  r = testing::RunSpecht("plan '" + scenario + "' --goal bay:south-13 --planner prm -q -o '" + out + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("prm"));
  r = testing::RunSpecht("plan '" + scenario + "' --start 90,5,0 --goal bay:south-13 --planner sst -q -o '" + out +
                         "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("start is outside the map"));
}

}  // namespace
}  // namespace specht
