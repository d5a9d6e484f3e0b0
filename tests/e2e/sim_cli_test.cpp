// `specht sim` as a user runs it: byte-identical outputs for a seed, another seed
// changes them, and a scenario naming what does not exist stops before anything is
// written.
#include <filesystem>

#include "test_support.h"

namespace specht::sim {
namespace {

std::string ScenarioPath(const std::string& name) {
  return testing::SourceDir() + "/datasets/scenarios/" + name + ".yaml";
}

TEST(SimulatorTest, SameSeedIsByteIdenticalAndAnotherSeedChangesNoiseAndAgents) {
  const std::string dir = testing::TempDir();
  const std::string scenario = ScenarioPath("course-loop");
  for (const char* run : {"a", "b"}) {
    ASSERT_EQ(testing::RunSpecht("sim -q --no-camera '" + scenario + "' --duration 15 -o '" + dir + "/" + run + "'")
                  .exit_code,
              0);
  }
  ASSERT_EQ(
      testing::RunSpecht("sim -q --no-camera '" + scenario + "' --duration 15 --seed 99 -o '" + dir + "/c'").exit_code,
      0);
  for (const char* f : {"sim.rawlog", "ground_truth.tum", "agents.csv", "true_map.pgm"}) {
    EXPECT_TRUE(testing::ReadFile(dir + "/a/" + f) == testing::ReadFile(dir + "/b/" + f)) << f;
  }
  EXPECT_NE(testing::ReadFile(dir + "/a/agents.csv"), testing::ReadFile(dir + "/c/agents.csv"));
  EXPECT_NE(testing::ReadFile(dir + "/a/sim.rawlog"), testing::ReadFile(dir + "/c/sim.rawlog"));
  for (const char* f : {"true_map.yaml", "true_map.gridmap", "world.png", "report.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/a/" + f)) << f;
  }
}

TEST(SimulatorTest, StereoOutputsAreReproducibleToo) {
  const std::string dir = testing::TempDir();
  const std::string scenario = ScenarioPath("urban-crossing");
  for (const char* run : {"a", "b"}) {
    ASSERT_EQ(testing::RunSpecht("sim -q '" + scenario + "' --duration 2 -o '" + dir + "/" + run + "'").exit_code, 0);
  }
  for (const char* f : {"sim_Images/left_000001.png", "sim_Images/right_000001.png", "stereo/disparity/000001.png",
                        "stereo/labels/000001.txt", "sim.rawlog"}) {
    ASSERT_TRUE(std::filesystem::exists(dir + "/a/" + f)) << f;
    EXPECT_TRUE(testing::ReadFile(dir + "/a/" + f) == testing::ReadFile(dir + "/b/" + f)) << f;
  }
}

// A scenario naming a sprite the library does not have, and a sprite set that does
// not exist, stop `specht sim` before it writes anything, naming file, key and reason.
TEST(SpriteTest, AnUnknownSpriteIsNamedBeforeAnythingIsWritten) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !std::filesystem::exists(data + "/sprites") ? std::string() : data);
  const std::string dir = testing::TempDir();
  std::string yaml = testing::ReadFile(ScenarioPath("urban-crossing"));
  const std::string agent = "{id: 1, class: pedestrian, route: [[33, 20], [47, 20]], start_s: 0}";
  ASSERT_NE(yaml.find(agent), std::string::npos);
  yaml.replace(yaml.find(agent), agent.size(),
               "{id: 1, class: pedestrian, route: [[33, 20], [47, 20]], start_s: 0, sprite: coco/1/2}");
  testing::WriteFile(dir + "/named.yaml", yaml);
  const auto r =
      testing::RunSpecht("sim -q '" + dir + "/named.yaml' --duration 1 --data-dir '" + data + "' -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, ::testing::HasSubstr("named.yaml: agents[0].sprite: no sprite named \"coco/1/2\""));
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
  const auto set =
      testing::RunSpecht("sim -q '" + ScenarioPath("urban-crossing") + "' --sprites best -o '" + dir + "/out'");
  EXPECT_EQ(set.exit_code, 2);
  EXPECT_THAT(set.err, ::testing::HasSubstr("--sprites: \"best\" is not a sprite set"));
}

}  // namespace
}  // namespace specht::sim
