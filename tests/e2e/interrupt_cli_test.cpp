// Long commands stopped by a signal part-way (core/interrupt.h): they stop at the
// next record or step, write everything computed so far as a truncated input does,
// say "interrupted" in the report and exit with 128 + the signal. And input with
// nothing to compute from is an error (exit 2 with the reason), not an empty result.
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "report.h"
#include "specht/io/g2o.h"
#include "specht/io/map_io.h"
#include "specht/io/trajectory_io.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The last line of a command's stderr: where an error's one-line reason goes.
std::string LastLine(std::string err) {
  while (!err.empty() && err.back() == '\n') err.pop_back();
  return err.substr(err.rfind('\n') + 1);
}

// Starts `args`, waits until its output directory is set up (params.yaml: the run has
// begun), lets it work `seconds` more, then sends `signal`.
testing::CommandResult InterruptAfter(const std::string& args, const std::string& out, double seconds, int signal) {
  testing::BackgroundSpecht run(args);
  EXPECT_TRUE(run.WaitForFile(out + "/params.yaml", 120)) << "the run did not start";
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  run.Signal(signal);
  return run.Wait();
}

// Intel's full-rate log (13,631 scans, about two minutes): SIGINT part-way keeps the
// map, trajectory and graph of every scan processed, each loadable.
TEST(InterruptCliTest, SlamStoppedBySigintWritesWhatItMapped) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/freiburg/intel.clf.bz2";
  if (!fs::exists(log)) SPECHT_SKIP() << log << " not here";
  const std::string out = testing::TempDir("slam_sigint") + "/out";
  const auto r = InterruptAfter("slam '" + log + "' -q -o '" + out + "'", out, 4.0, SIGINT);
  ASSERT_EQ(r.exit_code, 130) << r.err;
  const auto report = Report(out);
  EXPECT_EQ(report["status"], "interrupted");
  const long scans = report["counts"]["scans"].get<long>();
  EXPECT_GT(scans, 0);
  EXPECT_LT(scans, 13631);
  EXPECT_THAT(report["error"].get<std::string>(), HasSubstr("SIGINT after " + std::to_string(scans) + " scans"));
  // Every processed scan has its pose; the graph has a node per keyframe; the maps load.
  EXPECT_EQ(static_cast<long>(io::ReadTum(out + "/trajectory.tum").size()), scans);
  const io::G2oReadResult graph = io::ReadG2o(out + "/graph.g2o", io::OnBadRecord::kStop);
  EXPECT_EQ(static_cast<long>(graph.graph.nodes.size()), report["counts"]["keyframes"].get<long>());
  EXPECT_GT(graph.graph.nodes.size(), 10u);
  const auto grid = io::ReadRosMap(out + "/map.yaml");
  EXPECT_GT(grid.getSizeX() * grid.getSizeY(), 10000u);
  EXPECT_EQ(io::ReadMrptGridmap(out + "/map.gridmap").getSizeX(), grid.getSizeX());
}

// The closed loop under SIGTERM: the drive in progress is written and reported as
// interrupted; the seeds after it are not started.
TEST(InterruptCliTest, RunStoppedBySigtermWritesTheDrivesSoFar) {
  const std::string out = testing::TempDir("run_sigterm") + "/out";
  const auto r = InterruptAfter(
      "run '" + testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml' --seeds 1-40 -q -o '" + out + "'", out,
      1.5, SIGTERM);
  ASSERT_EQ(r.exit_code, 143) << r.err;
  const auto report = Report(out);
  EXPECT_EQ(report["status"], "interrupted");
  const auto& runs = report["runs"];
  ASSERT_GE(runs.size(), 1u);
  EXPECT_LT(runs.size(), 40u);
  EXPECT_EQ(report["metrics"]["runs"].get<size_t>(), runs.size());
  for (const auto& run : runs) {
    const std::string seed = std::to_string(run["seed"].get<int>());
    EXPECT_TRUE(fs::exists(out + "/steps-" + seed + ".jsonl")) << seed;
    EXPECT_TRUE(fs::exists(out + "/run-" + seed + ".png")) << seed;
  }
  EXPECT_FALSE(fs::exists(out + "/steps-40.jsonl"));
}

// metric = (p1 − 10)² / 100 + (p2 − 50)² / 10⁵ from the overlay, slowly; each
// worker's pid is kept.
const char* kSlowObjective = R"(#!/bin/sh
echo $$ >> "$3/pids"
sleep 0.4
p1=$(awk '/p1:/ {print $2}' "$1"); p2=$(awk '/p2:/ {print $2}' "$1")
if [ -z "$p1" ]; then m=1; else m=$(awk -v a="$p1" -v b="$p2" 'BEGIN {print (a-10)^2/100 + (b-50)^2/100000}'); fi
echo "{\"metrics\": {\"loss\": $m}}" > "$2/report.json"
)";

// `specht tune` under SIGTERM stops its workers with it, and the log resumes to the
// result of the search that was never interrupted.
TEST(InterruptCliTest, TuneStoppedBySigtermResumesToTheSameResult) {
  const std::string dir = testing::TempDir("tune_sigterm");
  testing::WriteFile(dir + "/objective.sh", kSlowObjective);
  const std::string file = dir + "/tune.yaml";
  testing::WriteFile(file, "run: sh {tune_dir}/objective.sh {params} {out} " + dir +
                               "\nmetric: metrics.loss\ntimeout_s: 20\nparameters:\n  stereo.p1: {min: 1, max: 20}\n"
                               "  stereo.p2: {min: 21, max: 190}\n"
                               "search: {method: ga, budget: 30, population: 6, seed: 5}\n");
  const auto whole = testing::RunSpecht("tune '" + file + "' -j 2 -q -o '" + dir + "/whole'");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const auto expected = Report(dir + "/whole");

  const std::string out = dir + "/cut";
  testing::BackgroundSpecht run("tune '" + file + "' -j 2 -q -o '" + out + "'");
  ASSERT_TRUE(run.WaitForFile(out + "/evaluations.csv", 60));
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  run.Signal(SIGTERM);
  const auto r = run.Wait();
  ASSERT_EQ(r.exit_code, 143) << r.err;
  EXPECT_EQ(Report(out)["status"], "interrupted");
  // No worker outlives its parent.
  std::ifstream pids(dir + "/pids");
  for (int pid; pids >> pid;) EXPECT_NE(kill(pid, 0), 0) << "worker " << pid << " still runs";

  const auto resumed = testing::RunSpecht("tune '" + file + "' -j 2 -q --resume -o '" + out + "'");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto report = Report(out);
  EXPECT_EQ(report["status"], "complete");
  EXPECT_GT(report["metrics"]["reused_from_log"].get<int>(), 0);
  EXPECT_EQ(report["metrics"]["evaluations"], expected["metrics"]["evaluations"]);
  EXPECT_EQ(report["metrics"]["best"], expected["metrics"]["best"]);
  EXPECT_EQ(report["metrics"]["best_parameters"], expected["metrics"]["best_parameters"]);
}

// ---- nothing to compute from ------------------------------------------------------

TEST(EmptyInputCliTest, AnEmptyRawlogIsAnErrorNotAnEmptyMap) {
  const std::string dir = testing::TempDir("empty_rawlog");
  testing::WriteFile(dir + "/empty.rawlog", "");
  const auto r = testing::RunSpecht("replay '" + dir + "/empty.rawlog' -q -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(LastLine(r.err), HasSubstr("empty.rawlog"));
  EXPECT_FALSE(fs::exists(dir + "/out/map.png"));
  EXPECT_FALSE(fs::exists(dir + "/out/report.json"));
}

TEST(EmptyInputCliTest, ACarmenLogWithoutScansIsAnError) {
  const std::string dir = testing::TempDir("no_scans");
  testing::WriteFile(dir + "/odometry.log",
                     "# odometry only\nPARAM robot_front_laser_max 50.0 nohost 0\n"
                     "ODOM 0.0 0.0 0.0 0 0 0 1.0 nohost 1.0\nODOM 0.1 0.0 0.0 0 0 0 1.1 nohost 1.1\n");
  const auto r = testing::RunSpecht("slam '" + dir + "/odometry.log' -q -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(LastLine(r.err), HasSubstr("odometry.log: no laser scan to map with (it holds 2 "));
  EXPECT_FALSE(fs::exists(dir + "/out/map.yaml"));
  EXPECT_FALSE(fs::exists(dir + "/out/trajectory.tum"));
}

TEST(EmptyInputCliTest, ATracksFileWithoutRowsIsAnError) {
  const std::string dir = testing::TempDir("no_rows");
  testing::WriteFile(dir + "/tracks.csv", "id,t_s,x_m,y_m,class\n");
  const auto r = testing::RunSpecht("classify prepare '" + dir + "/tracks.csv' -q -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(LastLine(r.err), HasSubstr("tracks.csv: no track rows"));
  const auto e = testing::RunSpecht("eval track --truth '" + dir + "/tracks.csv' --tracks '" + dir +
                                    "/tracks.csv' -o '" + dir + "/e'");
  EXPECT_EQ(e.exit_code, 2) << e.err;
  EXPECT_THAT(LastLine(e.err), HasSubstr("tracks.csv: no truth rows"));
}

}  // namespace
}  // namespace specht
