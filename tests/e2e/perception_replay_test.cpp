// `specht replay` with the perception stage: a simulated drive whose stereo frames at
// one time step are replaced by the real KITTI object pair, so the detector has cars
// to find; they land in the report, the world model and the map picture.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;

TEST(PerceptionReplayTest, StereoFramesBecomeObstaclesInTheWorldModel) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !fs::exists(data + "/models") ? std::string() : data);
  const std::string base = testing::TempDir(), sim = base + "/sim", out = base + "/replay";
  ASSERT_EQ(testing::RunSpecht("sim -q '" + testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml' --duration 6 -o '" +
                               sim + "'").exit_code, 0);
  for (const char* side : {"left", "right"})
    fs::copy_file(data + "/stereo/kitti_object/" + side + ".png", sim + "/sim_Images/" + side + "_000003.png",
                  fs::copy_options::overwrite_existing);
  const auto r = testing::RunSpecht("replay -q '" + sim + "/sim.rawlog' --data-dir '" + data + "' -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(testing::ReadFile(out + "/report.json"));
  ASSERT_TRUE(report.contains("perception")) << report.dump();
  EXPECT_EQ(report["perception"]["frames"], 6);
  EXPECT_GE(report["perception"]["detections"].get<int>(), 4);
  EXPECT_GE(report["perception"]["obstacles"].get<int>(), 4);
  EXPECT_TRUE(fs::exists(out + "/world.json"));
  const auto world = nlohmann::json::parse(testing::ReadFile(out + "/world.json"));
  EXPECT_TRUE(world.contains("static_map"));
  EXPECT_GT(world["cost"]["lethal"].get<int>(), 0);

  // perception: off leaves it out.
  const auto off = testing::RunSpecht("replay -q '" + sim + "/sim.rawlog' --data-dir '" + data +
                                      "' --set replay.perception=off -o '" + out + "-off'");
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_FALSE(nlohmann::json::parse(testing::ReadFile(out + "-off/report.json")).contains("perception"));
}

}  // namespace
}  // namespace specht
