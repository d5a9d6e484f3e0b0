// The pose-graph back end and the g2o reader: reference χ² on the shared benchmark
// graphs, and every kind of bad record named by file and line.
#include <cmath>

#include "specht/io/g2o.h"
#include "specht/slam/pose_graph_optimizer.h"
#include "test_support.h"

namespace specht {
namespace {

using ::testing::HasSubstr;

struct Reference {
  const char* name;
  double chi2;  // shared/data/README.md: Ceres 2.1 from odometry, measured there
};

class ReferenceChi2Test : public ::testing::TestWithParam<Reference> {};

TEST_P(ReferenceChi2Test, OptimumIsWithinATenthOfAPercentOfTheReference) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  auto read = io::ReadG2o(data + "/slam/g2o/" + GetParam().name + ".g2o");
  const auto summary = slam::Optimize(read.graph, slam::PoseGraphOptions{});
  EXPECT_TRUE(summary.usable);
  EXPECT_NEAR(summary.final_chi2, GetParam().chi2, GetParam().chi2 * 1e-3) << summary.report;
}

INSTANTIATE_TEST_SUITE_P(SharedGraphs, ReferenceChi2Test,
                         ::testing::Values(Reference{"intel", 45.005}, Reference{"CSAIL", 40.555},
                                           Reference{"manhattan", 3549.04}, Reference{"city10000", 511.99}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(PoseGraphTest, RecoversASquareFromNoisyOdometryAndOneLoop) {
  // Four 1 m sides, turning 90° left; odometry says 1.1 m per side, the loop edge
  // says node 4 is node 0. Optimisation spreads the 0.4 m of error.
  PoseGraph2D g;
  for (int i = 0; i <= 4; ++i) g.nodes[i] = mrpt::poses::CPose2D(1.1 * i, 0, 0);
  for (int i = 0; i < 4; ++i) g.edges.push_back({i, i + 1, mrpt::poses::CPose2D(1.1, 0, M_PI / 2)});
  g.edges.push_back({0, 4, mrpt::poses::CPose2D(0, 0, 0), Eigen::Matrix3d::Identity() * 100, true});
  const auto summary = slam::Optimize(g, slam::PoseGraphOptions{});
  EXPECT_LT(summary.final_chi2, summary.initial_chi2);
  EXPECT_NEAR(g.nodes[4].distanceTo(g.nodes[0]), 0.0, 0.05);
  EXPECT_NEAR(g.nodes[2].distanceTo(g.nodes[0]), std::sqrt(2.0), 0.15);
}

TEST(PoseGraphTest, LoopResidualsSetAsideTheLoopThatDisagrees) {
  // A straight corridor of 11 nodes 1 m apart with exact odometry, two loops from
  // node 0: one to node 10 saying 10 m (true), one to node 5 saying 8 m (an alias
  // 3 m off). Both loops as information 100 (σ = 0.1 m); odometry 10⁴.
  PoseGraph2D g;
  for (int i = 0; i <= 10; ++i) g.nodes[i] = mrpt::poses::CPose2D(i, 0, 0);
  for (int i = 0; i < 10; ++i)
    g.edges.push_back({i, i + 1, mrpt::poses::CPose2D(1, 0, 0), Eigen::Matrix3d::Identity() * 1e4});
  g.edges.push_back({0, 10, mrpt::poses::CPose2D(10, 0, 0), Eigen::Matrix3d::Identity() * 100, true});
  g.edges.push_back({0, 5, mrpt::poses::CPose2D(8, 0, 0), Eigen::Matrix3d::Identity() * 100, true});
  slam::PoseGraphOptions o;
  slam::Optimize(g, o);
  auto loops = slam::LoopResiduals(g, o);
  ASSERT_EQ(loops.size(), 2u);  // the robust edges only, in edge order
  EXPECT_EQ(loops[0].to, 10);
  EXPECT_EQ(loops[1].to, 5);
  EXPECT_LT(loops[0].error_m, 0.05);
  EXPECT_GT(loops[0].weight, 0.5);
  EXPECT_NEAR(loops[1].error_m, 3.0, 0.05);
  // s = 100 · 3² = 900 whitened; Cauchy with c = 1 leaves 1 / (1 + 900).
  EXPECT_NEAR(loops[1].chi2, 900, 30);
  EXPECT_NEAR(loops[1].weight, 1.0 / (1.0 + loops[1].chi2), 1e-9);
  EXPECT_LT(loops[1].weight, 0.01);
  o.loop_loss = "huber";
  loops = slam::LoopResiduals(g, o);
  EXPECT_NEAR(loops[1].weight, 1.0 / std::sqrt(loops[1].chi2), 1e-9);
  EXPECT_DOUBLE_EQ(loops[0].weight, 1.0);  // inside Huber's quadratic part
  o.loop_loss = "none";
  EXPECT_DOUBLE_EQ(slam::LoopResiduals(g, o)[1].weight, 1.0);
}

std::string ReadError(const std::string& text, io::OnBadRecord on_bad = io::OnBadRecord::kStop) {
  const std::string path = testing::TempDir() + "/g.g2o";
  testing::WriteFile(path, text);
  try {
    io::ReadG2o(path, on_bad);
  } catch (const InputError& e) {
    return std::string(e.what()).substr(path.size());
  }
  return "";
}

TEST(G2oTest, BadRecordsAreNamedByLine) {
  EXPECT_EQ(ReadError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 2 1 0 0 1 0 0 1 0 1\n"),
            ":3: EDGE_SE2 0 -> 2 names a missing vertex 2");
  EXPECT_EQ(ReadError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n"),
            ":3: EDGE_SE2 0 -> 1: information matrix is not positive definite");
  EXPECT_EQ(ReadError("VERTEX_SE2 0 0 0\n"), ":1: VERTEX_SE2 needs 4 numbers, got 3");
  EXPECT_EQ(ReadError("VERTEX_SE2 0 0 nan 0\n"), ":1: VERTEX_SE2: 'nan' is not a finite number");
  EXPECT_EQ(ReadError("VERTEX_SE2 -1 0 0 0\n"), ":1: VERTEX_SE2: ids must be non-negative integers");
}

TEST(G2oTest, SkipModeKeepsTheGoodRecordsAndListsTheBadOnes) {
  const std::string path = testing::TempDir() + "/g.g2o";
  testing::WriteFile(path,
                     "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                     "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\nEDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\n");
  const auto r = io::ReadG2o(path, io::OnBadRecord::kSkip);
  EXPECT_EQ(r.graph.edges.size(), 1u);
  ASSERT_EQ(r.skipped.size(), 2u);
  EXPECT_THAT(r.skipped[0], HasSubstr(":4: "));
  EXPECT_THAT(r.skipped[1], HasSubstr(":5: "));
}

TEST(G2oTest, EdgesOnlyGraphsChainOdometryForTheInitialGuess) {
  const std::string path = testing::TempDir() + "/g.g2o";
  testing::WriteFile(path, "EDGE_SE2 0 1 1 0 1.5707963 1 0 0 1 0 1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n");
  const auto r = io::ReadG2o(path);
  ASSERT_EQ(r.graph.nodes.size(), 3u);
  EXPECT_NEAR(r.graph.nodes.at(2).x(), 1.0, 1e-6);
  EXPECT_NEAR(r.graph.nodes.at(2).y(), 1.0, 1e-6);
  testing::WriteFile(path, "EDGE_SE2 0 2 1 0 0 1 0 0 1 0 1\n");
  EXPECT_THROW(io::ReadG2o(path), InputError);
}

TEST(G2oTest, WriteReadRoundTrip) {
  PoseGraph2D g;
  g.nodes[0] = mrpt::poses::CPose2D(0, 0, 0);
  g.nodes[1] = mrpt::poses::CPose2D(1.25, -0.5, 0.3);
  PoseGraphEdge e{0, 1, mrpt::poses::CPose2D(1.25, -0.5, 0.3)};
  e.information << 10, 1, 0, 1, 20, 2, 0, 2, 30;
  g.edges.push_back(e);
  const std::string path = testing::TempDir() + "/g.g2o";
  io::WriteG2o(g, path);
  const auto r = io::ReadG2o(path);
  EXPECT_NEAR(r.graph.nodes.at(1).phi(), 0.3, 1e-9);
  EXPECT_EQ(r.graph.edges.at(0).information(1, 2), 2.0);
  EXPECT_NEAR(Chi2(r.graph), 0.0, 1e-12);
}

TEST(PoseGraphTest, NonPositiveDefiniteInformationIsAnInputError) {
  PoseGraph2D g;
  g.nodes[0] = {};
  g.nodes[1] = {};
  PoseGraphEdge e{0, 1, {}};
  e.information = -Eigen::Matrix3d::Identity();
  g.edges.push_back(e);
  EXPECT_THROW(slam::Optimize(g, slam::PoseGraphOptions{}), InputError);
  g.edges[0].information = Eigen::Matrix3d::Identity();
  g.edges[0].to = 5;
  EXPECT_THROW(slam::Optimize(g, slam::PoseGraphOptions{}), InputError);
}

}  // namespace
}  // namespace specht
