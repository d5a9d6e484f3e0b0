// Graph SLAM on the Radish logs (label: slow). Started from raw odometry, scored by
// the relation error of Kümmerle et al. 2009 against the corrected poses.
//
// The target is a mean of 0.05 m and 1° over all relations with no relation
// above 0.5 m. The bounds below are what main achieves today plus a margin, so a
// regression fails; where a log meets the target the bound is the target. Orebro is
// left out: its ODOM lines only repeat the corrected poses (no odometry at all), and
// its long corridors leave a 30 m error that loop search does not yet recover.
#include <mrpt/core/bits_math.h>

#include "specht/eval/relation_error.h"
#include "specht/io/carmen.h"
#include "specht/io/dataset.h"
#include "specht/slam/graph_slam.h"
#include "test_support.h"

namespace specht::slam {
namespace {

struct Bound {
  const char* log;
  double mean_m, max_m, mean_deg;
};

std::unique_ptr<GraphSlam> RunSlam(const std::string& log) {
  auto slam = std::make_unique<GraphSlam>(SlamOptions{}, ScanMatchingOptions{}, LoopClosureOptions{},
                                          PoseGraphOptions{}, nullptr, "base_link");
  auto source = io::OpenDataset(log);
  while (auto obs = source->Next()) slam->Add(obs->stamp, obs->data);
  slam->Finish();
  return slam;
}

void PrintTo(const Bound& b, std::ostream* os) { *os << b.log; }

class CarmenSlamTest : public ::testing::TestWithParam<Bound> {};

TEST_P(CarmenSlamTest, RelationErrorWithinBound) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/" + GetParam().log + "-corrected.log.gz";
  const auto slam = RunSlam(log);
  const auto rel = eval::ComputeRelationError(slam->trajectory(), io::ReadCarmenReference(log));
  std::printf("%s: %zu relations, %.4f ± %.4f m (max %.3f), %.3f ± %.3f deg; %ld loop closures\n", GetParam().log,
              rel.all.count, rel.all.mean_m, rel.all.std_m, rel.all.max_m, rel.all.mean_deg, rel.all.std_deg,
              slam->stats().loops_accepted);
  EXPECT_LE(rel.all.mean_m, GetParam().mean_m);
  EXPECT_LE(rel.all.max_m, GetParam().max_m);
  EXPECT_LE(rel.all.mean_deg, GetParam().mean_deg);
}

INSTANTIATE_TEST_SUITE_P(Radish, CarmenSlamTest,
                         ::testing::Values(Bound{"intel", 0.06, 0.5, 1.0}, Bound{"seattle", 0.05, 0.5, 1.0},
                                           Bound{"freiburg-101", 0.085, 0.5, 1.15},
                                           Bound{"freiburg-079", 0.10, 1.05, 1.0}),
                         [](const auto& info) {
                           std::string n = info.param.log;
                           for (auto& ch : n) ch = ch == '-' ? '_' : ch;
                           return n;
                         });

TEST(CarmenSlamDeterminismTest, SameLogTwiceGivesIdenticalTrajectoryAndGraph) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/intel-corrected.log.gz";
  const auto a = RunSlam(log), b = RunSlam(log);
  const Trajectory ta = a->trajectory(), tb = b->trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (size_t i = 0; i < ta.size(); ++i) {
    ASSERT_EQ(ta[i].pose.x(), tb[i].pose.x()) << i;
    ASSERT_EQ(ta[i].pose.y(), tb[i].pose.y()) << i;
    ASSERT_EQ(ta[i].pose.yaw(), tb[i].pose.yaw()) << i;
  }
  EXPECT_EQ(a->graph().edges.size(), b->graph().edges.size());
}

}  // namespace
}  // namespace specht::slam
