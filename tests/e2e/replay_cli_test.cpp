// `specht replay` as a user runs it: outputs, determinism, exit codes, bad input.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report.h"
#include "specht/io/mcap.h"
#include "specht/io/ros_messages.h"
#include "specht/io/trajectory_io.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const char* kOutputs[] = {"map.yaml",         "map.pgm",   "map.gridmap", "map.png",     "trajectory.tum", "graph.g2o",
                          "keyframes.rawlog", "loops.png", "params.yaml", "report.json", "report.md"};

TEST(ReplayCliTest, DefaultRunWritesEveryOutput) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string out = testing::TempDir() + "/run";
  const auto r = testing::RunSpecht("replay -q -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : kOutputs) EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto report = Report(out);
  EXPECT_EQ(report["status"], "complete");
  EXPECT_EQ(report["counts"]["scans"], 225);
  EXPECT_GT(report["timing"]["real_time_factor"].get<double>(), 1.0);
  // The log's one loop, closed by loops that all agree: none set aside, each kept
  // one within a few centimetres of the final graph.
  const auto& loops = report["metrics"]["loops"];
  EXPECT_GT(loops["kept"].get<int>(), 10);
  EXPECT_EQ(loops["set_aside"].get<int>(), 0);
  EXPECT_EQ(loops["edges"].get<int>(), loops["kept"].get<int>() + loops["weakened"].get<int>());
  EXPECT_LT(loops["kept_error_m"]["max"].get<double>(), 0.05);
  EXPECT_EQ(loops["worst"].size(), 5u);
  // 225 scans, one TUM line each after the header.
  const std::string tum = testing::ReadFile(out + "/trajectory.tum");
  EXPECT_EQ(std::count(tum.begin(), tum.end(), '\n'), 226);
}

TEST(ReplayCliTest, SameInputTwiceGivesByteIdenticalMapAndTrajectory) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string a = testing::TempDir() + "/a", b = testing::TempDir() + "/b";
  ASSERT_EQ(testing::RunSpecht("replay -q -o '" + a + "'").exit_code, 0);
  ASSERT_EQ(testing::RunSpecht("replay -q -o '" + b + "'").exit_code, 0);
  for (const char* f :
       {"map.pgm", "map.yaml", "map.gridmap", "map.png", "loops.png", "trajectory.tum", "params.yaml"}) {
    EXPECT_TRUE(testing::ReadFile(a + "/" + f) == testing::ReadFile(b + "/" + f)) << f << " differs";
  }
}

struct BadParams {
  const char* name;
  const char* yaml;      // written to bad.yaml (nullptr: no file at all)
  const char* expected;  // the one-line message, after the file name
};

void PrintTo(const BadParams& p, std::ostream* os) { *os << p.name; }

class ReplayParamErrorTest : public ::testing::TestWithParam<BadParams> {};

TEST_P(ReplayParamErrorTest, ExitsWithTwoOneLineNamingFileAndKeyAndWritesNothing) {
  const BadParams& p = GetParam();
  const std::string dir = testing::TempDir();
  const std::string file = dir + "/bad.yaml", out = dir + "/out";
  if (p.yaml != nullptr) testing::WriteFile(file, p.yaml);
  const auto r = testing::RunSpecht("replay -q -p '" + file + "' -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "specht: " + file + p.expected + "\n");
  EXPECT_FALSE(fs::exists(out)) << "nothing may be written on a parameter error";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ReplayParamErrorTest,
    ::testing::Values(BadParams{"unknown_key", "grid:\n  resolution: 0.1\n",
                                ":2: unknown key 'grid.resolution' (did you mean 'grid.resolution_m'?)"},
                      BadParams{"wrong_type", "scan_matching:\n  use_odometry: maybe\n",
                                ":2: key 'scan_matching.use_odometry': expected a bool (true/false), got 'maybe'"},
                      BadParams{"out_of_range", "scan_matching:\n  icp:\n    threshold_decay: 1.5\n",
                                ":3: key 'scan_matching.icp.threshold_decay': value 1.5 is outside [0.1, 0.95]"},
                      BadParams{"missing_file", nullptr, ": cannot read parameter file: No such file or directory"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(ReplayCliTest, BadSetOverrideAndMissingDatasetExitTwo) {
  const std::string out = testing::TempDir() + "/out";
  auto r = testing::RunSpecht("replay -q --set grid.resolution_m=0 -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "specht: --set: key 'grid.resolution_m': value 0.0 is outside [0.01, 1.0] log\n");
  r = testing::RunSpecht("replay -q /nonexistent.rawlog -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "specht: /nonexistent.rawlog: no such dataset file\n");
  EXPECT_FALSE(fs::exists(out));
}

TEST(ReplayCliTest, TruncatedRawlogKeepsEverythingComputedAndMarksTheReport) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir();
  const std::string bytes = testing::ReadDecompressed(testing::BuiltInRawlog());
  testing::WriteFile(dir + "/cut.rawlog", bytes.substr(0, bytes.size() * 3 / 5));
  const auto r = testing::RunSpecht("replay -q '" + dir + "/cut.rawlog' -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("cut.rawlog: record "));
  EXPECT_THAT(r.err, HasSubstr("(byte "));
  for (const char* f : kOutputs) EXPECT_TRUE(fs::exists(dir + "/out/" + f)) << f;
  const auto report = Report(dir + "/out");
  EXPECT_EQ(report["status"], "incomplete");
  EXPECT_THAT(report["error"].get<std::string>(), HasSubstr("truncated rawlog"));
  EXPECT_GT(report["counts"]["scans"].get<int>(), 100);
}

TEST(ReplayCliTest, TimeWindowCutsTheReplay) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string out = testing::TempDir() + "/out";
  ASSERT_EQ(testing::RunSpecht("replay -q --from 10 --to 20 -o '" + out + "'").exit_code, 0);
  const auto report = Report(out);
  EXPECT_NEAR(report["timing"]["data_s"].get<double>(), 10.0, 0.5);
  EXPECT_THAT(testing::ReadFile(out + "/params.yaml"), HasSubstr("from_s: 10.0"));
}

TEST(SlamCliTest, MapArtefactReloadsForLocalization) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir();
  ASSERT_EQ(testing::RunSpecht("slam -q -o '" + dir + "/map'").exit_code, 0);
  for (const char* f : {"graph.g2o", "keyframes.rawlog", "map.gridmap", "map.yaml", "trajectory.tum"}) {
    EXPECT_TRUE(fs::exists(dir + "/map/" + f)) << f;
  }
  // Localize the same log on it, from a whole-map search (no initial pose).
  const auto r = testing::RunSpecht("slam -q --map '" + dir + "/map' -o '" + dir + "/loc'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(dir + "/loc");
  EXPECT_GT(report["metrics"]["global_search_score"].get<double>(), 0.7);
  EXPECT_EQ(report["counts"]["scans"], 225);
  // A map directory without its keyframes is refused before anything is written.
  fs::remove(dir + "/map/keyframes.rawlog");
  const auto bad = testing::RunSpecht("slam -q --map '" + dir + "/map' -o '" + dir + "/loc2'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir + "/loc2"));
}

// Continuing a map: the built-in log mapped to 30 s, then continued from 30 s on

// The MCAP every replay records (run.mcap) read by the MCAP project's own reader and
// its ROS 2 messages decoded by Foxglove's (tests/npm/read_mcap.mjs; `npm ci` in
// tests/npm, which scripts/setup.sh runs): every channel with its schema and the
// count written, the first scan, map and mount as our decoders read them. Replaying
// the MCAP maps the same map and trajectory as the source did.
TEST(SlamCliTest, WritesAnMcapFoxglovesReadersOpenAndThatReplaysToTheSameMap) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string verifier = testing::SourceDir() + "/tests/npm";
  if (std::system("node --version > /dev/null 2>&1") != 0 ||
      !std::filesystem::is_directory(verifier + "/node_modules/@mcap/core"))
    SPECHT_SKIP() << "node or tests/npm/node_modules missing (scripts/setup.sh installs them)";
  const std::string dir = testing::TempDir("slam_mcap");
  ASSERT_EQ(testing::RunSpecht("slam -q -o '" + dir + "/source'").exit_code, 0);
  const auto source = Report(dir + "/source");
  const std::string mcap = dir + "/source/run.mcap";
  const std::string json_path = dir + "/read.json";
  ASSERT_EQ(std::system(("node '" + verifier + "/read_mcap.mjs' '" + mcap + "' > '" + json_path + "'").c_str()), 0);
  const auto read = nlohmann::json::parse(testing::ReadFile(json_path));
  EXPECT_EQ(read["profile"], "ros2");
  const auto& written = source["mcap"]["messages"];
  const std::map<std::string, std::string> schemas = {
      {"/scan", "sensor_msgs/msg/LaserScan"}, {"/odom", "nav_msgs/msg/Odometry"},
      {"/tf", "tf2_msgs/msg/TFMessage"},      {"/tf_static", "tf2_msgs/msg/TFMessage"},
      {"/map", "nav_msgs/msg/OccupancyGrid"}, {"/trajectory", "nav_msgs/msg/Path"}};
  for (const auto& [topic, schema] : schemas) {
    const auto& c = read["channels"][topic];
    EXPECT_EQ(c["schema"], schema) << topic;
    EXPECT_EQ(c["messageEncoding"], "cdr") << topic;
    EXPECT_EQ(c["statistics"], written[topic]) << topic;
    EXPECT_EQ(c["read"], written[topic]) << topic;
  }
  EXPECT_EQ(written["/scan"], source["counts"]["scans"]);
  EXPECT_EQ(written["/odom"], source["counts"]["odometry"]);
  EXPECT_GE(written["/map"].get<int>(), 2);  // every 10 s of data and at the end

  // The first scan, map and mount as our own reader decodes them.
  io::McapReader ours(mcap);
  std::map<std::string, bool> seen;
  while (auto m = ours.Next()) {
    if (seen[m->topic]) continue;
    seen[m->topic] = true;
    const auto& theirs = read["first"][m->topic];
    if (m->topic == "/scan") {
      const auto scan = io::ros::DecodeLaserScan(m->data);
      EXPECT_EQ(theirs["header"]["frame_id"], scan.header.frame_id);
      EXPECT_EQ(theirs["header"]["stamp"]["sec"].get<int64_t>() * 1000000000 +
                    theirs["header"]["stamp"]["nsec"].get<int64_t>(),
                scan.header.stamp.ns);
      EXPECT_FLOAT_EQ(theirs["angle_min"].get<float>(), scan.angle_min);
      EXPECT_FLOAT_EQ(theirs["range_max"].get<float>(), scan.range_max);
      double sum = 0;
      int non_finite = 0;
      for (float r : scan.ranges) std::isfinite(r) ? sum += r : ++non_finite;
      EXPECT_EQ(theirs["ranges"]["length"].get<size_t>(), scan.ranges.size());
      EXPECT_NEAR(theirs["ranges"]["finite_sum"].get<double>(), sum, 1e-6 * sum);
      EXPECT_EQ(theirs["ranges"]["non_finite"].get<int>(), non_finite);
    } else if (m->topic == "/map") {
      EXPECT_EQ(theirs["info"]["width"].get<uint32_t>() * theirs["info"]["height"].get<uint32_t>(),
                theirs["data"]["length"].get<uint32_t>());
      EXPECT_GT(theirs["data"]["minus_one"].get<int>(), 0);  // unknown cells
      EXPECT_NEAR(theirs["info"]["resolution"].get<double>(), 0.05, 1e-6);
    } else if (m->topic == "/tf_static") {
      const auto tf = io::ros::DecodeTfMessage(m->data);
      ASSERT_EQ(theirs["transforms"].size(), tf.size());
      EXPECT_EQ(theirs["transforms"][0]["child_frame_id"], tf[0].child_frame_id);
      EXPECT_DOUBLE_EQ(theirs["transforms"][0]["transform"]["translation"]["x"].get<double>(), tf[0].transform.x);
    }
  }
  EXPECT_TRUE(seen["/scan"] && seen["/map"] && seen["/tf_static"]);

  // Replaying the MCAP: the same map and trajectory.
  ASSERT_EQ(testing::RunSpecht("slam -q --no-mcap '" + mcap + "' -o '" + dir + "/again'").exit_code, 0);
  EXPECT_EQ(Report(dir + "/again")["inputs"]["format"], "MCAP (ros2)");
  EXPECT_EQ(testing::ReadFile(dir + "/again/map.pgm"), testing::ReadFile(dir + "/source/map.pgm"));
  EXPECT_EQ(testing::ReadFile(dir + "/again/trajectory.tum"), testing::ReadFile(dir + "/source/trajectory.tum"));

  // The same file as a ROS 2 bag folder of MCAP storage (ROS 2 Iron's default).
  std::filesystem::create_directories(dir + "/bag");
  std::filesystem::copy_file(mcap, dir + "/bag/bag_0.mcap");
  testing::WriteFile(dir + "/bag/metadata.yaml",
                     "rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n"
                     "  relative_file_paths:\n    - bag_0.mcap\n");
  const auto list = testing::RunSpecht("replay '" + dir + "/bag' --list");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_THAT(list.out, ::testing::ContainsRegex("/scan +sensor_msgs/msg/LaserScan +" +
                                                 std::to_string(written["/scan"].get<int>())));
}

// A ROS 1 bag with scans only (CCNY's scan_tools demo, read through Debian's
// rosbag_storage): mapped without odometry (walls measured 0.05 m thick at p95). A
// bag cut short has no index: an input error that says so.
TEST(SlamCliTest, MapsARos1BagOfScansAloneAndNamesACutOne) {
  const std::string bag = testing::DataDir() + "/ros/ccny-scan-tools/demo.bag";
  if (testing::DataDir().empty() || !std::filesystem::exists(bag)) SPECHT_SKIP() << bag;
  const std::string dir = testing::TempDir("slam_ros1_bag");
  const auto r = testing::RunSpecht("slam -q --no-mcap '" + bag + "' -o '" + dir + "/out'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(dir + "/out");
  EXPECT_EQ(report["inputs"]["format"], "ROS 1 bag");
  EXPECT_EQ(report["counts"]["scans"].get<int>(), 360);
  EXPECT_EQ(report["counts"]["odometry"].get<int>(), 0);
  EXPECT_LE(report["metrics"]["wall_thickness_p95_m"].get<double>(), 0.1);
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/map.yaml"));

  testing::WriteFile(dir + "/cut.bag", testing::ReadFile(bag).substr(0, 500000));
  const auto cut = testing::RunSpecht("slam -q '" + dir + "/cut.bag' -o '" + dir + "/cut'");
  EXPECT_EQ(cut.exit_code, 2);
  EXPECT_THAT(cut.err, ::testing::HasSubstr("cut.bag: "));
  EXPECT_THAT(cut.err, ::testing::HasSubstr("rosbag reindex"));
}

// A team's ROS 2 bag (rosbag2 SQLite, CDR): `specht slam` maps the floor from its
// scans, odometry and /tf_static mount, and scores the map against the team's own
// map in the bag's folder (measured: 72.1 % of our wall cells within 0.1 m of
// theirs, 78.9 % of their walls where we looked within 0.1 m of ours).
TEST(SlamCliTest, MapsATeamsRos2BagAndScoresItAgainstTheirMap) {
  const std::string bag = testing::DataDir() + "/ros/turtlebot4-mac-first-floor";
  if (testing::DataDir().empty() || !std::filesystem::is_directory(bag)) SPECHT_SKIP() << bag;
  const auto list = testing::RunSpecht("replay '" + bag + "' --list");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_THAT(list.out, ::testing::ContainsRegex("/scan +sensor_msgs/msg/LaserScan +357"));
  const std::string dir = testing::TempDir("slam_ros2_bag");
  const auto r = testing::RunSpecht("slam -q '" + bag + "' -o '" + dir + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(dir);
  EXPECT_EQ(report["inputs"]["format"], "ROS 2 bag (sqlite3)");
  EXPECT_EQ(report["counts"]["scans"].get<int>(), 357);
  EXPECT_EQ(report["counts"]["odometry"].get<int>(), 920);
  const auto& m = report["metrics"]["reference_map"];
  EXPECT_GT(m["ours_within_tolerance"].get<double>(), 0.68);
  EXPECT_GT(m["reference_seen_within_tolerance"].get<double>(), 0.75);
  EXPECT_TRUE(std::filesystem::exists(dir + "/map_vs_reference.png"));
}
// the saved map. The continuation is placed by a whole-map search and stays in the
// saved map's frame: scan for scan it lies on the uninterrupted run of the whole
// log (the same frame: both start at the first scan), and the extended graph
// holds the saved nodes and the new ones.
TEST(SlamCliTest, ContinuesASavedMapInItsFrame) {
  SPECHT_REQUIRE_FILE(testing::BuiltInRawlog());
  const std::string dir = testing::TempDir("slam_continue");
  ASSERT_EQ(testing::RunSpecht("slam -q -o '" + dir + "/full'").exit_code, 0);
  ASSERT_EQ(testing::RunSpecht("slam -q --to 30 -o '" + dir + "/first'").exit_code, 0);
  const auto r = testing::RunSpecht("slam -q --from 30 --continue '" + dir + "/first' -o '" + dir + "/rest'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(Report(dir + "/rest")["metrics"]["continue_global_search_score"].get<double>(), 0.7);

  const Trajectory full = io::ReadTum(dir + "/full/trajectory.tum");
  const Trajectory first = io::ReadTum(dir + "/first/trajectory.tum");
  const Trajectory rest = io::ReadTum(dir + "/rest/trajectory.tum");
  ASSERT_EQ(first.size() + rest.size(), full.size());
  double sum = 0, worst = 0;
  for (size_t i = 0; i < rest.size(); ++i) {
    const auto& a = rest[i].pose;
    const auto& b = full[first.size() + i].pose;
    const double d = std::hypot(a.x() - b.x(), a.y() - b.y());
    sum += d, worst = std::max(worst, d);
  }
  EXPECT_LT(sum / rest.size(), 0.1);  // measured 0.026 m
  EXPECT_LT(worst, 0.3);              // measured 0.09 m

  const auto vertices = [](const std::string& g2o) {
    std::istringstream in(testing::ReadFile(g2o));
    int n = 0;
    for (std::string line; std::getline(in, line);) n += line.rfind("VERTEX_SE2", 0) == 0;
    return n;
  };
  EXPECT_EQ(vertices(dir + "/rest/graph.g2o"),
            vertices(dir + "/first/graph.g2o") + Report(dir + "/rest")["counts"]["keyframes"].get<int>());
  // --continue and --map exclude each other.
  EXPECT_NE(testing::RunSpecht("slam -q --map '" + dir + "/first' --continue '" + dir + "/first' -o '" + dir + "/both'")
                .exit_code,
            0);
}

// The simulated course loop (featureless corridors, seed 1) mapped at the defaults,
// against the simulator's ground truth. Its corridors let a recovery search after a
// rejected ICP match find an alias turned 77°; a failed refinement of that must not
// be taken for the searched pose (it was, for one build: ATE 17.5 m).
TEST(SlamCliTest, SimulatedCourseLoopLiesOnItsGroundTruth) {
  const std::string dir = testing::TempDir("slam_sim");
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/course-loop.yaml";
  ASSERT_EQ(testing::RunSpecht("sim -q --no-camera '" + scenario + "' -o '" + dir + "/sim'").exit_code, 0);
  const auto r = testing::RunSpecht("slam -q '" + dir + "/sim/sim.rawlog' --ground-truth '" + dir +
                                    "/sim/ground_truth.tum' -o '" + dir + "/slam'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto metrics = Report(dir + "/slam")["metrics"];
  std::printf("simulated course loop: ATE RMSE %.3f m, relation error %.4f m (max %.3f)\n",
              metrics["ate"]["rmse_m"].get<double>(), metrics["relation"]["all"]["mean_m"].get<double>(),
              metrics["relation"]["all"]["max_m"].get<double>());
  EXPECT_LT(metrics["ate"]["rmse_m"].get<double>(), 0.1);  // measured 0.036 m
  EXPECT_LT(metrics["relation"]["all"]["max_m"].get<double>(), 0.5);
}

// A raw Freiburg log, as the benchmark ships it: its poses are odometry (no reference
// error is reported), its published relations beside it are scored, and a window that
// leaves relations out says so instead of scoring part of them; `eval slam
// --relations` scores the trajectory on the relations it holds and names the first
// relation it does not.
TEST(SlamCliTest, RawFreiburgLogIsScoredOnItsPublishedRelations) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/freiburg/fr079.clf.bz2", relations = data + "/slam/freiburg/fr079.relations";
  SPECHT_REQUIRE_FILE(log);
  const std::string dir = testing::TempDir();
  ASSERT_EQ(testing::RunSpecht("slam -q '" + log + "' --to 120 -o '" + dir + "/run'").exit_code, 0);
  const auto report = Report(dir + "/run");
  EXPECT_THAT(report["input_notes"][0].get<std::string>(), HasSubstr("a raw log"));
  EXPECT_FALSE(report["metrics"].contains("relation"));
  EXPECT_THAT(report["metrics"]["published_relations"]["error"].get<std::string>(), HasSubstr("do not match"));

  const std::string estimate = dir + "/run/trajectory.tum";
  auto r = testing::RunSpecht("eval slam --estimate '" + estimate + "' --relations '" + relations + "' -o '" + dir +
                              "/eval-all'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("fr079.relations:"));
  EXPECT_THAT(r.err, HasSubstr("is not in the trajectory"));
  r = testing::RunSpecht("eval slam --estimate '" + estimate + "' --reference '" + log + "' -o '" + dir + "/eval-ref'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("a raw CARMEN log"));

  // The relations whose two scans lie in the window: all matched, a sub-decimetre error.
  const Trajectory scans = io::ReadTum(estimate);
  const Stamp end = scans.back().stamp;
  std::istringstream all(testing::ReadFile(relations));
  std::string inside;
  int kept = 0;
  for (std::string line; std::getline(all, line);) {
    std::istringstream f(line);
    double t1 = 0, t2 = 0;
    if (f >> t1 >> t2 && std::max(t1, t2) <= end.Seconds()) inside += line + "\n", ++kept;
  }
  ASSERT_GT(kept, 50);
  testing::WriteFile(dir + "/inside.relations", inside);
  r = testing::RunSpecht("eval slam --estimate '" + estimate + "' --relations '" + dir + "/inside.relations' -o '" +
                         dir + "/eval'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("published relations " + std::to_string(kept) + " (all matched)"));
  const auto eval = Report(dir + "/eval");
  EXPECT_LT(eval["metrics"]["published_relations"]["absolute"]["mean_m"].get<double>(), 0.1);
  EXPECT_TRUE(fs::exists(dir + "/eval/relations.png"));
}

TEST(ReplayCliTest, HelpListsEveryOption) {
  const auto r = testing::RunSpecht("replay --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--params", "--set", "--out", "--data-dir", "--rate", "--from", "--to", "--ground-truth"}) {
    EXPECT_THAT(r.out, HasSubstr(opt));
  }
  EXPECT_THAT(testing::RunSpecht("--help").out, HasSubstr("replay"));
}

}  // namespace
}  // namespace specht
