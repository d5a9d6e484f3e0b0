// The stack's stages as DDS nodes (pipeline/nodes.h), each its own process on this
// machine's loopback: a dataset played as ROS 2 topics and mapped by the SLAM node
// gives what `specht slam` gives on the file — the same trajectory, map and graph,
// byte for byte — and the node publishes its map and TF as it goes; the recorder
// node's MCAP of it all maps to the same trajectory again. Each test has its
// own DDS domain (from the process id).
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "report.h"
#include "specht/io/trajectory_io.h"
#include "test_support.h"

namespace specht {
namespace {

std::string Domain() { return std::to_string(1 + getpid() % 200); }

// Whether `a` and `b` hold the same keys, strings and booleans, and numbers within
// `tolerance`; `where` names the first difference.
bool Close(const nlohmann::json& a, const nlohmann::json& b, double tolerance, std::string& where) {
  if (a.is_number() && b.is_number()) {
    if (std::abs(a.get<double>() - b.get<double>()) <= tolerance) return true;
  } else if (a.is_object() && b.is_object() && a.size() == b.size()) {
    for (const auto& [key, value] : a.items())
      if (!b.contains(key) || !Close(value, b[key], tolerance, where)) return where = key + "." + where, false;
    return true;
  } else if (a.is_array() && b.is_array() && a.size() == b.size()) {
    for (size_t i = 0; i < a.size(); ++i)
      if (!Close(a[i], b[i], tolerance, where)) return where = std::to_string(i) + "." + where, false;
    return true;
  } else if (a == b) {
    return true;
  }
  where = a.dump().substr(0, 80) + " != " + b.dump().substr(0, 80);
  return false;
}

TEST(NodeCliTest, SlamNodeOnAPlayedLogWritesWhatSlamWritesOnTheFile) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir("node_slam");
  const std::string domain = " --domain " + Domain();
  testing::BackgroundSpecht slam("node slam --idle-end 2 -q -o '" + dir + "/node'" + domain);
  testing::BackgroundSpecht record("node record --idle-end 3 -q -o '" + dir + "/record'" + domain);
  const auto play = testing::RunSpecht("node play --rate 0 --subscribers 2 -q -o '" + dir + "/play'" + domain);
  ASSERT_EQ(play.exit_code, 0) << play.err;
  const auto mapped = slam.Wait();
  ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
  const auto recorded = record.Wait();
  ASSERT_EQ(recorded.exit_code, 0) << recorded.err;
  ASSERT_EQ(testing::RunSpecht("slam -q --no-mcap -o '" + dir + "/file'").exit_code, 0);
  ASSERT_EQ(testing::RunSpecht("slam -q --no-mcap '" + dir + "/record/run.mcap' -o '" + dir + "/replayed'").exit_code,
            0);

  for (const char* f : {"trajectory.tum", "map.pgm", "graph.g2o"})  // compared as booleans: the files are long
    EXPECT_TRUE(testing::ReadFile(dir + "/node/" + f) == testing::ReadFile(dir + "/file/" + f)) << f;
  const auto played = Report(dir + "/play")["counts"]["published"];
  EXPECT_EQ(played["/clock"].get<int>(), played["/scan"].get<int>() + played["/odom"].get<int>());
  const auto node = Report(dir + "/node");
  EXPECT_EQ(node["inputs"]["format"], "ROS 2 topics (DDS)");
  EXPECT_EQ(node["counts"]["scans"], played["/scan"]);
  EXPECT_EQ(node["counts"]["odometry"], played["/odom"]);
  EXPECT_EQ(node["counts"]["scans"], Report(dir + "/file")["counts"]["scans"]);
  // What it published: map → odom at every scan, the map every second of data and at
  // the end (59 s of data), the trajectory once.
  const auto published = node["published"]["messages"];
  EXPECT_EQ(published["/tf"], node["counts"]["scans"]);
  EXPECT_GE(published["/map"].get<int>(), 50);
  EXPECT_EQ(published["/trajectory"], 1);
  // The recording holds the player's and the node's messages, and maps as the file did.
  const auto kept = Report(dir + "/record")["counts"]["recorded"];
  for (const char* topic : {"/scan", "/odom", "/tf_static"}) EXPECT_EQ(kept[topic], played[topic]) << topic;
  // The node's /map is latched (keep last 1) and /tf keeps the last 10, as ROS 2 publishes
  // them: played as fast as possible, a newer sample may replace one not yet delivered.
  EXPECT_GE(kept["/map"].get<int>(), 1);
  EXPECT_LE(kept["/map"].get<int>(), published["/map"].get<int>());
  EXPECT_GE(kept["/tf"].get<int>(), played["/tf"].get<int>());
  EXPECT_LE(kept["/tf"].get<int>(), played["/tf"].get<int>() + published["/tf"].get<int>());
  EXPECT_TRUE(testing::ReadFile(dir + "/replayed/trajectory.tum") == testing::ReadFile(dir + "/file/trajectory.tum"));
}

// A SLAM node runs until stopped: SIGINT writes everything it mapped (the trajectory
// of every scan placed) and exits 130.
TEST(NodeCliTest, SlamNodeStoppedBySigintKeepsWhatItMapped) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir("node_sigint");
  const std::string domain = " --domain " + Domain();
  testing::BackgroundSpecht slam("node slam -q --no-mcap -o '" + dir + "/node'" + domain);
  ASSERT_EQ(testing::RunSpecht("node play --rate 0 -q -o '" + dir + "/play'" + domain).exit_code, 0);
  slam.Signal(SIGINT);
  const auto r = slam.Wait();
  ASSERT_EQ(r.exit_code, 130) << r.err;
  const auto report = Report(dir + "/node");
  EXPECT_EQ(report["status"], "interrupted");
  const long scans = report["counts"]["scans"].get<long>();
  EXPECT_GT(scans, 0);
  EXPECT_EQ(static_cast<long>(io::ReadTum(dir + "/node/trajectory.tum").size()), scans);
}

// Nothing to publish is an error, not an empty stream.
TEST(NodeCliTest, PlayingADatasetWithoutScansIsAnError) {
  const std::string dir = testing::TempDir("node_empty");
  testing::WriteFile(dir + "/odometry.log", "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 1 0 0 0 0 0 2.0 host 2.0\n");
  const auto r = testing::RunSpecht("node play --rate 0 -q --set node.wait_for_subscriber_s=0 -o '" + dir +
                                    "/play' --domain " + Domain() + " '" + dir + "/odometry.log'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("no laser scan to publish"), std::string::npos) << r.err;
}

// `specht launch` on the shipped one-computer file: the three nodes as child
// processes give what they give started by hand (the SLAM node's trajectory is
// `specht slam`'s on the file), each console kept in its folder.
TEST(NodeCliTest, LaunchFileStartsTheNodesAsTheyRunByHand) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir("launch");
  const auto r = testing::RunSpecht("launch '" + testing::SourceDir() + "/params/launch/slam-over-dds.yaml' --domain " +
                                    Domain() + " -o '" + dir + "/launch'");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("[slam] "), std::string::npos) << r.out;  // consoles shown, prefixed
  ASSERT_EQ(testing::RunSpecht("slam -q --no-mcap -o '" + dir + "/file'").exit_code, 0);
  EXPECT_TRUE(testing::ReadFile(dir + "/launch/slam/trajectory.tum") ==
              testing::ReadFile(dir + "/file/trajectory.tum"));
  const auto report = Report(dir + "/launch");
  EXPECT_EQ(report["status"], "complete");
  ASSERT_EQ(report["nodes"].size(), 3u);
  for (const auto& node : report["nodes"]) {
    EXPECT_EQ(node["exit_code"], 0) << node;
    EXPECT_EQ(node["status"], "complete") << node;
    EXPECT_FALSE(testing::ReadFile(dir + "/launch/" + node["console"].get<std::string>()).empty());
  }
  EXPECT_EQ(Report(dir + "/launch/record")["counts"]["recorded"]["/scan"],
            Report(dir + "/launch/play")["counts"]["published"]["/scan"]);
}

// A required node that fails stops the others (SIGINT: they keep what they have):
// a SLAM node that would wait forever for scans ends with the launch.
TEST(NodeCliTest, LaunchStopsTheNodesWhenARequiredOneFails) {
  const std::string dir = testing::TempDir("launch_required");
  testing::WriteFile(dir + "/launch.yaml",
                     "nodes:\n"
                     "  - {name: slam, node: slam, args: [--no-mcap]}\n"
                     "  - {name: play, node: play, args: [" +
                         dir + "/missing.rawlog], required: true}\n");
  const auto r =
      testing::RunSpecht("launch '" + dir + "/launch.yaml' -q --domain " + Domain() + " -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const auto report = Report(dir + "/out");
  EXPECT_EQ(report["status"], "failed");
  EXPECT_EQ(report["error"], "required node play exited with 2");
  EXPECT_EQ(report["nodes"][0]["exit_code"], 130);
  EXPECT_EQ(report["nodes"][1]["exit_code"], 2);
  EXPECT_NE(testing::ReadFile(dir + "/out/play/console.log").find("missing.rawlog"), std::string::npos);
}

// Ctrl-C on the launch reaches every node once: each writes what it has and exits
// 130, and so does the launch.
TEST(NodeCliTest, LaunchPassesSigintToEveryNode) {
  const std::string dir = testing::TempDir("launch_sigint");
  testing::WriteFile(dir + "/launch.yaml",
                     "nodes:\n  - {name: slam, node: slam, args: [--no-mcap]}\n  - {name: record, node: record}\n");
  testing::BackgroundSpecht launch("launch '" + dir + "/launch.yaml' -q --domain " + Domain() + " -o '" + dir +
                                   "/out'");
  ASSERT_TRUE(launch.WaitForFile(dir + "/out/record/params.yaml", 30));
  ASSERT_TRUE(launch.WaitForFile(dir + "/out/slam/params.yaml", 30));
  launch.Signal(SIGINT);
  const auto r = launch.Wait();
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  const auto report = Report(dir + "/out");
  EXPECT_EQ(report["status"], "interrupted");
  for (const auto& node : report["nodes"]) EXPECT_EQ(node["exit_code"], 130) << node;
  EXPECT_EQ(Report(dir + "/out/slam")["status"], "interrupted");
}

// Expects the drive in `other` (a run of parking-lot seed 101) to be the one in
// `here`: the same success and collisions, every other report figure within 1e-9 but
// for the wall clock's, the video and the nodes' own, every control step's pose within
// 1 mm (the messages round the orientations through quaternions: the poses agree to
// ~1e-11 m) and its state the same.
void ExpectTheSameDrive(const std::string& here, const std::string& other) {
  auto a = Report(here)["runs"][0], b = Report(other)["runs"][0];
  EXPECT_EQ(a["success"], b["success"]);
  EXPECT_EQ(a["collisions"], b["collisions"]);
  EXPECT_GT(b["nodes"]["answer_ms"]["count"].get<int>(), 100);
  EXPECT_GT(b["nodes"]["published"]["/scan"].get<int>(), 100);
  for (auto* run : {&a, &b}) {
    for (const char* key : {"timing", "planning_ms", "video", "nodes"}) run->erase(key);
    (*run)["local_planner"].erase("ms");
    (*run)["perception"].erase("tracked_by_perception_node");
  }
  std::string where;
  EXPECT_TRUE(Close(a, b, 1e-9, where)) << where;
  std::istringstream steps_here(testing::ReadFile(here + "/steps-101.jsonl")),
      steps_other(testing::ReadFile(other + "/steps-101.jsonl"));
  int steps = 0;
  for (std::string x, y; std::getline(steps_here, x) && std::getline(steps_other, y); ++steps) {
    const auto p = nlohmann::json::parse(x), q = nlohmann::json::parse(y);
    ASSERT_LE(
        std::hypot(p["x_m"].get<double>() - q["x_m"].get<double>(), p["y_m"].get<double>() - q["y_m"].get<double>()),
        1e-3)
        << "step " << steps;
    ASSERT_EQ(p["state"], q["state"]) << "step " << steps;
  }
  EXPECT_GT(steps, 100);
  EXPECT_TRUE(steps_here.eof() || steps_here.peek() == EOF);
  EXPECT_TRUE(steps_other.peek() == EOF);
  EXPECT_EQ(Report(other + "/stack-101")["status"], "complete");
}

// `specht run --nodes`: the stack as `specht node stack`, its own process, hearing
// the simulated car over DDS in lockstep, drives the run the in-process loop drives;
// so it does with its tracker in a third process (--perception-node), which tracks
// every detector frame at the pose the stack sent it.
TEST(NodeCliTest, RunWithTheStackAsANodeDrivesAsTheInProcessLoop) {
  const std::string dir = testing::TempDir("run_nodes");
  const std::string run = "run '" + testing::SourceDir() +
                          "/datasets/scenarios/parking-lot.yaml' --seeds 101 -q --set closed_loop.mcap=off";
  const auto here = testing::RunSpecht(run + " --set closed_loop.video=off -o '" + dir + "/here'");
  const auto nodes = testing::RunSpecht(run + " --nodes --domain " + Domain() + " -o '" + dir + "/nodes'");
  const auto three =
      testing::RunSpecht(run + " --nodes --perception-node --domain " + Domain() + " -o '" + dir + "/three'");
  ASSERT_EQ(here.exit_code, 0) << here.out << here.err;
  ASSERT_EQ(nodes.exit_code, 0) << nodes.out << nodes.err;
  ASSERT_EQ(three.exit_code, 0) << three.out << three.err;
  ExpectTheSameDrive(dir + "/here", dir + "/nodes");
  ExpectTheSameDrive(dir + "/here", dir + "/three");
  const auto perception = Report(dir + "/three/perception-101");
  EXPECT_EQ(perception["status"], "complete");
  EXPECT_EQ(perception["counts"]["frames"], Report(dir + "/here")["runs"][0]["perception"]["frames"]);
  EXPECT_EQ(perception["counts"]["skipped"], 0);
  EXPECT_EQ(Report(dir + "/three/stack-101")["perception_node"]["missing"], 0);
}

// Faults: the perception node is killed mid-drive. The stack, without the frames'
// tracks, stops the car within 0.5 s of simulated time (closed_loop.blind_stop_s,
// 0.4 s after the last frame) and does not drive again until the restarted node's
// tracks come; then the car drives on and completes the mission. The car may already
// be stopped when the kill lands (an emergency stop, waiting for a crossing cyclist):
// it goes blind as it leaves that state, so what is checked is that it is not driving
// from 0.5 s after the node went until it is back. In the parking lot: on the course
// the stall shifts the drive against the traffic, and whether seed 101 then parks in
// bay-a depends on when the kill lands.
TEST(NodeCliTest, APerceptionNodeKilledMidDriveStopsTheCarUntilItIsBack) {
  const std::string dir = testing::TempDir("run_nodes_perception_killed");
  testing::BackgroundSpecht run("run '" + testing::SourceDir() +
                                "/datasets/scenarios/parking-lot.yaml' --seeds 101 -q --nodes --perception-node "
                                "--domain " +
                                Domain() + " --set closed_loop.mcap=off -o '" + dir + "/out'");
  ASSERT_TRUE(run.WaitForFile(dir + "/out/perception-101/params.yaml", 30));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // driving by now
  ASSERT_EQ(std::system(("pkill -KILL -f -- '[-]o " + dir + "/out/perception-101'").c_str()), 0);
  const auto r = run.Wait();
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr("the perception node ended with exit code 137"));
  const auto drive = Report(dir + "/out")["runs"][0];
  const auto& restarts = drive["nodes"]["perception_node"]["restarts"];
  ASSERT_EQ(restarts.size(), 1u);
  EXPECT_EQ(restarts[0]["exit_code"], 137);
  const double gone_at = restarts[0]["gone_at_s"].get<double>();
  double blind_at = -1, back_at = -1;
  for (const auto& t : drive["transitions"]) {
    const double at = t["t_s"].get<double>();
    if (t["to"] == "blind" && blind_at < 0 && at >= gone_at) blind_at = at;
    if (t["from"] == "blind" && blind_at >= 0 && back_at < 0) back_at = at;
  }
  ASSERT_GE(blind_at, gone_at) << drive["transitions"].dump();
  EXPECT_GT(back_at, blind_at) << "the car did not drive on when the restarted node's tracks came";
  std::string state_then = "plan";  // the state 0.5 s after the node went
  for (const auto& t : drive["transitions"]) {
    const double at = t["t_s"].get<double>();
    if (at <= gone_at + 0.5) state_then = t["to"];
    if (t["to"] == "drive" && at > gone_at + 0.5 && at < back_at)
      ADD_FAILURE() << "drove at " << at << " s without perception: " << drive["transitions"].dump();
  }
  EXPECT_NE(state_then, "drive") << drive["transitions"].dump();
  EXPECT_TRUE(drive["success"].get<bool>());
  EXPECT_EQ(drive["collisions"], 0);
  EXPECT_GT(Report(dir + "/out/stack-101")["perception_node"]["missing"].get<int>(), 0);
}

// The stack node dies mid-drive: the run stops within the node timeout, naming the
// node's exit and its console, instead of waiting for an answer that cannot come.
TEST(NodeCliTest, RunNodesEndsWithAClearErrorWhenTheStackNodeDies) {
  const std::string dir = testing::TempDir("run_nodes_killed");
  testing::BackgroundSpecht run("run '" + testing::SourceDir() +
                                "/datasets/scenarios/course-loop.yaml' --seeds 101 -q --nodes --domain " + Domain() +
                                " --set node.command_timeout_s=5 -o '" + dir + "/out'");
  ASSERT_TRUE(run.WaitForFile(dir + "/out/stack-101/params.yaml", 30));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // driving by now
  // "[-]o": a pattern that does not match the shell running pkill itself.
  ASSERT_EQ(std::system(("pkill -KILL -f -- '[-]o " + dir + "/out/stack-101'").c_str()), 0);
  const auto r = run.Wait();
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, ::testing::HasSubstr("the stack node ended with exit code 137"));
  EXPECT_THAT(r.err, ::testing::HasSubstr(dir + "/out/stack-101/console.log"));
}

TEST(NodeCliTest, RunNodesRunsTheFullStackOnly) {
  const auto r = testing::RunSpecht("run '" + testing::SourceDir() +
                                    "/datasets/scenarios/parking-lot.yaml' --stack truth --nodes -q -o '" +
                                    testing::TempDir("run_nodes_truth") + "/out'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr("--nodes runs the full stack"));
}

}  // namespace
}  // namespace specht
