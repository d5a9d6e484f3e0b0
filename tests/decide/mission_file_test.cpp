// Mission files: the goals a valid file lists, in order, at the bays' poses; every
// malformed file is an InputError naming the file, the line and what is wrong,
// including keys and bays YAML allows as maps or lists.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "specht/core/error.h"
#include "specht/decide/mission.h"
#include "test_support.h"

namespace specht::decide {
namespace {

const MissionSite kSite{"the lot", {{"A", 10, 5, 0.5, 5, 2.5}, {"B", -4, 2, 3.1, 6, 3}}};

std::vector<Goal> Load(const std::string& text) {
  const std::string path = testing::TempDir("mission_file") + "/m.yaml";
  testing::WriteFile(path, text);
  return LoadMission(path, kSite, plan::CarOptions{});
}

TEST(MissionFileTest, GoalsComeInTheFilesOrder) {
  const auto goals = Load("goals:\n  - waypoint: [1, 2, 90]\n  - park: B\n");
  ASSERT_EQ(goals.size(), 2u);
  EXPECT_EQ(goals[0].name, "waypoint 1");
  EXPECT_NEAR(goals[0].pose.x, 1, 1e-12);
  EXPECT_NEAR(goals[0].pose.theta, M_PI / 2, 1e-12);
  EXPECT_EQ(goals[1].name, "park B");
  EXPECT_TRUE(goals[1].park);
}

TEST(MissionFileTest, MalformedFilesNameFileLineAndWhatIsWrong) {
  const auto fails = [](const std::string& text, const std::string& expected) {
    try {
      Load(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(expected)) << text;
    }
  };
  fails("goals: []\n", "m.yaml: a mission is a map with a non-empty 'goals' list");
  fails("goals:\n  - park: A\ngaols: 1\n", "m.yaml:3: unknown field 'gaols' (goals)");
  fails("goals:\n  - park: C\n", "m.yaml:2: the lot has no bay 'C'");
  fails("goals:\n  - waypoint: [1, 2]\n", "m.yaml:2: a waypoint is [x, y, heading_deg]");
  fails("goals:\n  - drive: A\n", "m.yaml:2: unknown goal 'drive' (waypoint, park)");
  // A map or a list where a name belongs (found by reading the fuzzer's finding in
  // the tune file: the same yaml-cpp conversion escaped here).
  fails("goals:\n  - park: A\n{x: 1}: 2\n", "m.yaml:3: a field is a name, not a map or a list");
  fails("goals:\n  - {[1]: A}\n", "m.yaml:2: a goal's kind is a name, not a map or a list");
  fails("goals:\n  - park: [A]\n", "m.yaml:2: a bay is a name, not a map or a list");
}

}  // namespace
}  // namespace specht::decide
