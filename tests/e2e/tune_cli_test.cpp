// `specht tune` as a user runs it, with worker processes: a shell script stands in
// for a real run (cheap and exact), so the test checks the machinery — overlays,
// placeholders, reports, failures, timeouts, outputs — not a module's tuning.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// metric = (p1 − 10)² / 100 + (p2 − 50)² / 1000 from the overlay; p1 ≤ 3 crashes,
// p1 ≥ 19 hangs (killed by the timeout); the defaults (no overlay) give 5.
const char* kScript = R"(#!/bin/sh
p1=$(awk '/p1:/ {print $2}' "$1"); p2=$(awk '/p2:/ {print $2}' "$1")
[ -n "$p1" ] && [ "$p1" -le 3 ] && exit 1
[ -n "$p1" ] && [ "$p1" -ge 19 ] && sleep 30
if [ -z "$p1" ]; then m=5; else m=$(awk -v a="$p1" -v b="$p2" 'BEGIN {print (a-10)^2/100 + (b-50)^2/1000}'); fi
echo "{\"metrics\": {\"loss\": $m}}" > "$2/report.json"
)";

std::string TuneFile(const std::string& dir, const std::string& metric, const std::string& params) {
  testing::WriteFile(dir + "/objective.sh", kScript);
  const std::string path = dir + "/tune.yaml";
  testing::WriteFile(path, "run: sh {tune_dir}/objective.sh {params} {out}\nmetric: " + metric +
                               "\ntimeout_s: 2\nparameters:\n" + params +
                               "search: {method: ga, budget: 60, population: 10, seed: 3}\n");
  return path;
}

TEST(TuneCliTest, SearchesWritesTheBestOverlayAndRecordsFailures) {
  const std::string dir = testing::TempDir("tune_cli"), out = dir + "/out";
  const std::string file =
      TuneFile(dir, "metrics.loss", "  stereo.p1: {min: 1, max: 20}\n  stereo.p2: {min: 21, max: 150}\n");
  const auto r = testing::RunSpecht("tune '" + file + "' -j 2 -q -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"evaluations.csv", "best.yaml", "convergence.png", "report.json", "report.md"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto report = nlohmann::json::parse(testing::ReadFile(out + "/report.json"));
  EXPECT_EQ(report["metrics"]["defaults"].get<double>(), 5.0);
  EXPECT_LT(report["metrics"]["best"].get<double>(), 0.05);  // p1 within 2 of 10, p2 within 7 of 50
  EXPECT_EQ(report["metrics"]["evaluations"].get<int>(), 61);
  const std::string log = testing::ReadFile(out + "/evaluations.csv");
  EXPECT_THAT(log, HasSubstr("exited with 1"));  // p1 ≤ 3 was tried and logged as failed
  EXPECT_THAT(log, HasSubstr("timed out"));      // p1 ≥ 19 too
  // best.yaml is a parameter overlay specht itself accepts.
  const auto p = testing::RunSpecht("params -p '" + out + "/best.yaml'");
  EXPECT_EQ(p.exit_code, 0) << p.err;
  // Resuming a finished search evaluates nothing again and ends the same.
  const auto again = testing::RunSpecht("tune '" + file + "' --resume -q -o '" + out + "'");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const auto resumed = nlohmann::json::parse(testing::ReadFile(out + "/report.json"));
  EXPECT_EQ(resumed["metrics"]["reused_from_log"].get<int>(), 61);
  EXPECT_EQ(resumed["metrics"]["best"], report["metrics"]["best"]);
}

TEST(TuneCliTest, BadInputStopsBeforeTheSearch) {
  const std::string dir = testing::TempDir("tune_cli_bad");
  struct Case {
    std::string metric, params, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"metrics.loss", "  stereo.p9: {}\n", "'stereo.p9': not a declared parameter (did you mean 'stereo.p1'?)"},
           {"metrics.loss", "  stereo.threads: {}\n", "declared fixed (not tunable)"},
           {"metrics.loss", "  stereo.p1: {min: 0, max: 100}\n", "outside the declared range"},
           {"metrics.los", "  stereo.p1: {min: 1, max: 20}\n",
            "no number at 'metrics.los' (did you mean 'metrics.loss'?)"},
       }) {
    const std::string out = dir + "/out" + std::to_string(c.expected.size());
    const auto r = testing::RunSpecht("tune '" + TuneFile(dir, c.metric, c.params) + "' -q -o '" + out + "'");
    EXPECT_EQ(r.exit_code, 2) << c.expected;
    EXPECT_THAT(r.err, HasSubstr(c.expected));
    // At most the defaults ran (for the metric check), never a search candidate.
    EXPECT_FALSE(fs::exists(out + "/evals/00001")) << c.expected;
  }
}

// The shipped tune files name parameters that exist (guards against renames).
TEST(TuneCliTest, ShippedTuneFilesAreValid) {
  int files = 0;
  for (const auto& f : fs::directory_iterator(testing::SourceDir() + "/params/tune")) {
    const auto r = testing::RunSpecht("tune --check '" + f.path().string() + "'");
    EXPECT_EQ(r.exit_code, 0) << f.path() << ": " << r.err;
    ++files;
  }
  EXPECT_GE(files, 2);
}

}  // namespace
}  // namespace specht
