// The tuner on known functions (sphere, Rastrigin: optimum 0 at the origin), its
// search space against the declared parameters, the grid, and resume: a search
// stopped part-way and resumed from its log ends exactly where an uninterrupted one
// does (issue acceptance 3 and 4; bad input, 5).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <set>

#include "specht/core/error.h"
#include "specht/tune/runner.h"
#include "test_support.h"

namespace specht::tune {
namespace {

// n real parameters "f.x0".."f.x<n-1>" declared on [-5.12, 5.12].
std::vector<params::ParamInfo> Declared(int n) {
  std::vector<params::ParamInfo> out;
  for (int i = 0; i < n; ++i) {
    params::ParamInfo p;
    p.key = "f.x" + std::to_string(i);
    p.type = "real";
    p.range = params::Range::Of(-5.12, 5.12);
    out.push_back(p);
  }
  params::ParamInfo fixed;
  fixed.key = "f.seed", fixed.type = "int", fixed.range = params::Range::Of(0, 100).Fixed();
  params::ParamInfo mode;
  mode.key = "f.mode", mode.type = "choice", mode.choices = {"a", "b", "c"};
  out.push_back(fixed), out.push_back(mode);
  return out;
}

SearchSpace Space(int n) {
  std::string yaml;
  for (int i = 0; i < n; ++i) yaml += "f.x" + std::to_string(i) + ": {}\n";
  return SearchSpace::FromTuneFile(Declared(n), YAML::Load(yaml), "t.yaml");
}

double Sphere(const std::vector<std::string>& v) {
  double s = 0;
  for (const auto& x : v) s += std::pow(std::stod(x), 2);
  return s;
}
double Rastrigin(const std::vector<std::string>& v) {
  double s = 10.0 * v.size();
  for (const auto& x : v) s += std::pow(std::stod(x), 2) - 10 * std::cos(2 * M_PI * std::stod(x));
  return s;
}

Evaluator Of(double (*f)(const std::vector<std::string>&)) {
  return [f](int, int, const std::vector<std::string>& v) {
    return Outcome{true, v.empty() ? 1e9 : f(v), ""};  // the "defaults" are far off
  };
}

RunOptions Options(const std::string& method, int budget, int population, const std::string& log) {
  RunOptions o;
  o.search.method = method, o.search.budget = budget, o.search.population = population, o.search.seed = 7;
  o.log_path = log;
  return o;
}

TEST(TuneSearchTest, GeneticAlgorithmFindsTheSphereOptimum) {
  const std::string dir = testing::TempDir("tune_sphere");
  // 4-D sphere on [−5.12, 5.12]⁴, 1,500 evaluations (30 × 50 generations).
  const RunResult ga = RunTuning(Space(4), Options("ga", 1500, 30, dir + "/ga.csv"), Of(Sphere));
  ASSERT_GE(ga.best, 1);
  EXPECT_LT(ga.evaluations[ga.best].value, 0.05);  // ≈ 0.1 from the optimum per coordinate at worst
  const RunResult random = RunTuning(Space(4), Options("random", 1500, 30, dir + "/random.csv"), Of(Sphere));
  EXPECT_LT(random.evaluations[random.best].value, 5.0);
  EXPECT_LT(ga.evaluations[ga.best].value, random.evaluations[random.best].value);  // selection pays off
}

TEST(TuneSearchTest, GeneticAlgorithmFindsTheRastriginBasin) {
  const std::string dir = testing::TempDir("tune_rastrigin");
  // 2-D Rastrigin: local minima at every integer point (value ≥ 1 away from the
  // origin); < 0.5 means the global basin was found. 2,000 evaluations.
  const RunResult ga = RunTuning(Space(2), Options("ga", 2000, 40, dir + "/ga.csv"), Of(Rastrigin));
  EXPECT_LT(ga.evaluations[ga.best].value, 0.5);
}

TEST(TuneSearchTest, GridEnumeratesTheProductOnce) {
  const auto space =
      SearchSpace::FromTuneFile(Declared(1), YAML::Load("f.x0: {min: 0, max: 4}\nf.mode: {}\n"), "t.yaml");
  auto o = Options("grid", 1000, 4, testing::TempDir("tune_grid") + "/grid.csv");
  o.search.levels = 4;
  std::set<std::vector<std::string>> seen;
  const RunResult r = RunTuning(space, o, [&](int i, int, const std::vector<std::string>& v) {
    if (i > 0) {
      EXPECT_TRUE(seen.insert(v).second);
    }
    return Outcome{true, 0.0, ""};
  });
  EXPECT_EQ(seen.size(), 12u);  // 4 levels (cell centres 0.5, 1.5, 2.5, 3.5) × 3 choices
  EXPECT_TRUE(seen.count({"0.5", "a"}));
  EXPECT_TRUE(seen.count({"3.5", "c"}));
  EXPECT_TRUE(r.complete);
}

TEST(TuneSpaceTest, DecodesScalesAndWritesAnOverlay) {
  params::ParamInfo p2;
  p2.key = "stereo.p2", p2.type = "int", p2.range = params::Range::Of(2, 200).Log();
  params::ParamInfo flag;
  flag.key = "stereo.subpixel", flag.type = "bool", flag.range = std::nullopt;
  const auto space = SearchSpace::FromTuneFile({p2, flag}, YAML::Load("stereo.p2: {}\nstereo.subpixel: {}\n"), "t");
  EXPECT_EQ(space.Decode({0.0, 0.2}), (std::vector<std::string>{"2", "false"}));
  EXPECT_EQ(space.Decode({0.5, 0.7}), (std::vector<std::string>{"20", "true"}));  // √(2·200) on a log scale
  EXPECT_EQ(space.Decode({1.0, 1.0}), (std::vector<std::string>{"200", "true"}));
  const YAML::Node overlay = YAML::Load(space.OverlayYaml({"20", "true"}));
  EXPECT_EQ(overlay["stereo"]["p2"].as<int>(), 20);
  EXPECT_EQ(overlay["stereo"]["subpixel"].as<bool>(), true);
}

TEST(TuneSpaceTest, RejectsBadParametersBeforeAnyEvaluation) {
  const auto declared = Declared(2);
  auto fails = [&](const std::string& yaml, const std::string& expected) {
    try {
      SearchSpace::FromTuneFile(declared, YAML::Load(yaml), "t.yaml");
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails("f.x9: {}", "'f.x9': not a declared parameter (did you mean 'f.x0'?)");
  fails("f.seed: {}", "declared fixed (not tunable)");
  fails("f.x0: {min: -10, max: 1}", "outside the declared range");
  fails("f.x0: {min: 1, max: 1}", "min must be below max");
  fails("f.x0: {min: -1, max: 1, scale: log}", "log scale needs a positive range");
  fails("f.mode: {choices: [a, z]}", "choice 'z' is not a valid value");
  fails("f.x0: {mni: 1}", "unknown field 'mni'");
  fails("{}", "at least one");
  // Found by fuzz_params (2026-12-08, after 3.0 M executions): a flow map as a key.
  fails("f.x0: {}\n{f.x1: , max: 16}: {}\n", "t.yaml:2: a parameter key must be a name such as stereo.p2");
}

// A GA over one three-way choice asks the same values again and again: each is run
// once, the repeats take its outcome (logged with 0 s) and the best is unchanged.
TEST(TuneRunTest, RepeatedValuesAreNotEvaluatedAgain) {
  const auto space = SearchSpace::FromTuneFile(Declared(0), YAML::Load("f.mode: {}\n"), "t.yaml");
  const std::string log = testing::TempDir("tune_repeats") + "/log.csv";
  std::atomic<int> calls{0};
  auto o = Options("ga", 40, 8, log);
  o.jobs = 2;
  const RunResult r = RunTuning(space, o, [&](int, int, const std::vector<std::string>& v) {
    ++calls;
    return Outcome{true, v.empty() ? 9.0 : static_cast<double>(v[0][0] - 'a'), ""};  // a 0, b 1, c 2
  });
  ASSERT_TRUE(r.complete);
  EXPECT_LE(calls.load(), 4);  // the defaults and at most the three choices
  EXPECT_EQ(r.duplicates, 40 - (calls.load() - 1));
  ASSERT_EQ(r.evaluations.size(), 41u);
  for (const auto& e : r.evaluations) {
    ASSERT_TRUE(e.ok);
    if (e.index > 0) {
      EXPECT_EQ(e.value, static_cast<double>(e.values[0][0] - 'a')) << e.index;
    }
  }
  EXPECT_EQ(r.evaluations[r.best].values, std::vector<std::string>{"a"});
  // The repeats are in the log: a resume takes all 41 from it.
  o.resume = true;
  const RunResult again = RunTuning(space, o, [&](int, int, const std::vector<std::string>&) -> Outcome {
    ADD_FAILURE() << "evaluated although logged";
    return {};
  });
  EXPECT_EQ(again.reused, 41);
}

// Acceptance 3: stopped after 23 evaluations (mid-generation, with two workers),
// resumed from the log: the same evaluations and the same best as one run.
TEST(TuneResumeTest, ResumedSearchEqualsUninterruptedSearch) {
  const std::string dir = testing::TempDir("tune_resume");
  auto o = Options("ga", 60, 10, dir + "/whole.csv");
  o.jobs = 2;
  const RunResult whole = RunTuning(Space(3), o, Of(Rastrigin));
  ASSERT_TRUE(whole.complete);

  o.log_path = dir + "/part.csv";
  o.stop_after = 23;
  const RunResult part = RunTuning(Space(3), o, Of(Rastrigin));
  EXPECT_FALSE(part.complete);
  // A kill mid-write leaves half a line: it is dropped and evaluated again.
  std::ofstream(o.log_path, std::ios::app) << "24,3,ok,1.5";
  o.stop_after = 0;
  o.resume = true;
  std::atomic<int> calls{0};  // the evaluator runs on 2 worker threads
  const RunResult resumed = RunTuning(Space(3), o, [&](int i, int r, const std::vector<std::string>& v) {
    ++calls;
    return Of(Rastrigin)(i, r, v);
  });
  EXPECT_TRUE(resumed.complete);
  EXPECT_GE(resumed.reused, 23);  // the 23 run before the stop, and the repeats logged among them
  // The GA asks its elites again: each value is run once.
  EXPECT_EQ(calls.load(), 61 - resumed.reused - resumed.duplicates);
  EXPECT_GT(resumed.duplicates, 0);
  ASSERT_EQ(resumed.evaluations.size(), whole.evaluations.size());
  for (size_t i = 0; i < whole.evaluations.size(); ++i)
    EXPECT_EQ(resumed.evaluations[i].values, whole.evaluations[i].values) << "evaluation " << i;
  EXPECT_EQ(resumed.best, whole.best);
  EXPECT_NEAR(resumed.evaluations[resumed.best].value, whole.evaluations[whole.best].value, 1e-9);

  // A log of another search is refused rather than mixed in.
  auto other = o;
  other.search.seed = 8;
  EXPECT_THROW(RunTuning(Space(3), other, Of(Rastrigin)), InputError);
  EXPECT_THROW(RunTuning(Space(2), o, Of(Rastrigin)), InputError);  // other columns
}

TEST(TuneRunTest, FailedEvaluationsAreRecordedAndTheSearchGoesOn) {
  const std::string dir = testing::TempDir("tune_failures");
  auto o = Options("random", 20, 5, dir + "/log.csv");
  const RunResult r = RunTuning(Space(1), o, [](int i, int, const std::vector<std::string>& v) -> Outcome {
    if (i % 3 == 0 && i > 0) throw std::runtime_error("worker crashed");
    if (i % 4 == 0 && i > 0) return {false, 0, "timed out after 5 s"};
    return {true, v.empty() ? 100.0 : Sphere(v), ""};
  });
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.evaluations.size(), 21u);
  EXPECT_FALSE(r.evaluations[3].ok);
  EXPECT_EQ(r.evaluations[3].error, "worker crashed");
  EXPECT_FALSE(r.evaluations[4].ok);
  EXPECT_TRUE(r.evaluations[r.best].ok);
  // The defaults' evaluation may stop everything (e.g. the metric is not in the report).
  EXPECT_THROW(RunTuning(Space(1), o,
                         [](int, int, const std::vector<std::string>&) -> Outcome {
                           throw InputError("report.json has no metric 'd1_al' (did you mean 'd1_all'?)");
                         }),
               InputError);
}

}  // namespace
}  // namespace specht::tune
