// The options mechanism: one declaration drives load, validation, dump and description.
#include "specht/core/params.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <set>

#include "options_registry.h"
#include "specht/ais/dataset.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/scan_matching.h"
#include "test_support.h"

namespace specht {
namespace {

using params::ParamTree;
using ::testing::HasSubstr;

std::string ErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string LoadText(const std::string& yaml) {
  return ErrorOf([&] {
    ParamTree tree;
    tree.MergeText(yaml, "test.yaml");
    app::AllOptions().Load(tree);
  });
}

TEST(ParamsTest, BuiltInDefaultsAreValid) {
  const params::Params p = app::AllOptions().Defaults();
  EXPECT_DOUBLE_EQ(p.Get<slam::GridOptions>("grid").resolution_m, 0.05);
  EXPECT_EQ(p.Get<FramesOptions>("frames").base_frame, "base_link");
}

TEST(ParamsTest, UnknownKeyNamesFileLineKeyAndNearestValidKey) {
  const std::string e = LoadText("grid:\n  resolution_m: 0.1\n  max_insert_rnage_m: 10\n");
  EXPECT_EQ(e, "test.yaml:3: unknown key 'grid.max_insert_rnage_m' (did you mean 'grid.max_insert_range_m'?)");
}

TEST(ParamsTest, UnknownKeysPastTwentyAreCountedNotListed) {
  std::string yaml = "grid:\n";
  for (int i = 0; i < 25; ++i) yaml += (i < 10 ? "  bogus_0" : "  bogus_") + std::to_string(i) + ": 1\n";
  const std::string e = LoadText(yaml);
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 20);  // twenty lines, then the count
  EXPECT_THAT(e, HasSubstr("test.yaml:21: unknown key 'grid.bogus_19'"));
  EXPECT_THAT(e, ::testing::Not(HasSubstr("bogus_20")));
  EXPECT_THAT(e, ::testing::EndsWith("... and 5 more unknown keys"));
}

TEST(ParamsTest, MisspelledSectionSuggestsTheSection) {
  const std::string e = LoadText("gird:\n  resolution_m: 0.1\n");
  EXPECT_THAT(e, HasSubstr("test.yaml:2: unknown key 'gird.resolution_m'"));
  EXPECT_THAT(e, HasSubstr("did you mean 'grid.resolution_m'"));
}

TEST(ParamsTest, WrongTypeNamesKeyAndExpectation) {
  EXPECT_EQ(LoadText("grid:\n  resolution_m: fine\n"),
            "test.yaml:2: key 'grid.resolution_m': expected a finite real number, got 'fine'");
  EXPECT_EQ(LoadText("scan_matching:\n  submap_keyframes: 2.5\n"),
            "test.yaml:2: key 'scan_matching.submap_keyframes': expected an integer, got '2.5'");
  EXPECT_EQ(LoadText("scan_matching:\n  use_odometry: [1, 2]\n"),
            "test.yaml:2: key 'scan_matching.use_odometry': expected a bool (true/false), got a list");
}

TEST(ParamsTest, OutOfRangeNamesKeyValueAndRange) {
  EXPECT_EQ(LoadText("grid:\n  resolution_m: -1\n"),
            "test.yaml:2: key 'grid.resolution_m': value -1.0 is outside [0.01, 1.0] log");
}

TEST(ParamsTest, NestedGroupKeysAreAddressedWithDots) {
  EXPECT_EQ(LoadText("scan_matching:\n  icp:\n    max_iterations: 0\n"),
            "test.yaml:3: key 'scan_matching.icp.max_iterations': value 0 is outside [5, 500]");
}

TEST(ParamsTest, GroupGivenAValueIsExplained) {
  EXPECT_THAT(LoadText("scan_matching:\n  icp: 3\n"),
              HasSubstr("'scan_matching.icp' is a group of parameters and needs a map"));
}

TEST(ParamsTest, BadChoiceListsTheChoices) {
  EXPECT_EQ(LoadText("replay:\n  on_bad_record: ignore\n"),
            "test.yaml:2: key 'replay.on_bad_record': 'ignore' is not one of: stop, skip");
}

TEST(ParamsTest, RelationsBetweenFieldsAreChecked) {
  EXPECT_THAT(LoadText("scan_matching:\n  min_range_m: 1.5\n  max_range_m: 1.2\n"),
              HasSubstr("min_range_m must be below max_range_m"));
}

TEST(ParamsTest, EveryProblemGetsItsOwnLine) {
  const std::string e = LoadText("grid:\n  resolution_m: x\n  bogus: 1\n");
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 1) << e;
}

TEST(ParamsTest, MissingFileNamesTheFile) {
  const std::string e = ErrorOf([] {
    ParamTree tree;
    tree.MergeFile("/nonexistent/specht.yaml");
  });
  EXPECT_EQ(e, "/nonexistent/specht.yaml: cannot read parameter file: No such file or directory");
}

TEST(ParamsTest, SyntaxErrorNamesFileAndLine) {
  const std::string dir = testing::TempDir();
  testing::WriteFile(dir + "/bad.yaml", "grid:\n  resolution_m: [0.1\n");
  const std::string e = ErrorOf([&] {
    ParamTree tree;
    tree.MergeFile(dir + "/bad.yaml");
  });
  EXPECT_THAT(e, HasSubstr(dir + "/bad.yaml:"));
  EXPECT_THAT(e, HasSubstr("YAML syntax error"));
}

TEST(ParamsTest, SetOverridesFilesAndIsCheckedLikeThem) {
  ParamTree tree;
  tree.MergeText("grid:\n  resolution_m: 0.1\n", "a.yaml");
  tree.Set("grid.resolution_m=0.2");
  EXPECT_DOUBLE_EQ(app::AllOptions().Load(tree).Get<slam::GridOptions>("grid").resolution_m, 0.2);

  ParamTree typo;
  typo.Set("grid.resolutoin_m=0.2");
  EXPECT_THAT(ErrorOf([&] { app::AllOptions().Load(typo); }),
              HasSubstr("--set: unknown key 'grid.resolutoin_m' (did you mean 'grid.resolution_m'?)"));
  EXPECT_THAT(ErrorOf([] { ParamTree().Set("grid.resolution_m"); }), HasSubstr("expected key=value"));
}

TEST(ParamsTest, IncludedFilesAreMergedFirst) {
  const std::string dir = testing::TempDir();
  testing::WriteFile(dir + "/base.yaml", "grid:\n  resolution_m: 0.1\n  max_insert_range_m: 12\n");
  testing::WriteFile(dir + "/preset.yaml", "include: base.yaml\ngrid:\n  resolution_m: 0.2\n");
  ParamTree tree;
  tree.MergeFile(dir + "/preset.yaml");
  const auto grid = app::AllOptions().Load(tree).Get<slam::GridOptions>("grid");
  EXPECT_DOUBLE_EQ(grid.resolution_m, 0.2);
  EXPECT_DOUBLE_EQ(grid.max_insert_range_m, 12);
}

TEST(ParamsTest, EffectiveParametersRoundTrip) {
  ParamTree tree;
  tree.Set("grid.resolution_m=0.125");
  tree.Set("frames.static_transforms=[{parent: base_link, child: LASER, xyz_m: [0.2, 0, 0.3], rpy_deg: [0, 0, 90]}]");
  const params::Params p = app::AllOptions().Load(tree);
  const std::string dumped = p.ToYaml(true);
  ParamTree again;
  again.MergeText(dumped, "dump.yaml");
  EXPECT_EQ(app::AllOptions().Load(again).ToYaml(true), dumped);
  EXPECT_EQ(app::AllOptions().Load(again).Get<FramesOptions>("frames").static_transforms.at(0).xyz_m[2], 0.3);
}

TEST(ParamsTest, DescribeListsRangesForTheTuner) {
  const auto infos = app::AllOptions().Defaults().Describe();
  auto it = std::find_if(infos.begin(), infos.end(),
                         [](const params::ParamInfo& i) { return i.key == "scan_matching.icp.max_pair_distance_m"; });
  ASSERT_NE(it, infos.end());
  ASSERT_TRUE(it->range.has_value());
  EXPECT_TRUE(it->range->tunable);
  EXPECT_TRUE(it->range->log_scale);
  EXPECT_DOUBLE_EQ(it->range->min, 0.05);
  EXPECT_EQ(it->type, "real");
}

// params/<module>.yaml are the defaults as declared in code: regenerate them with
// `specht params --write-defaults params` when a declaration changes.
TEST(ParamsTest, ShippedDefaultFilesMatchTheDeclarations) {
  const params::Params defaults = app::AllOptions().Defaults();
  for (const auto& file : app::DefaultsFiles()) {
    const std::string path = testing::SourceDir() + "/params/" + file.file;
    const std::string shipped = testing::ReadFile(path);
    EXPECT_NE(shipped.find(defaults.ToYaml(file.sections, true)), std::string::npos)
        << path << " is out of date: run `specht params --write-defaults params`";
  }
  ParamTree tree;
  tree.MergeFile(testing::SourceDir() + "/params/default.yaml");
  EXPECT_EQ(app::AllOptions().Load(tree).ToYaml(true), defaults.ToYaml(true));
}

// The presets beside the defaults (params/*.yaml that are not module defaults) load
// without an unknown key or a value out of range, and change what they say.
TEST(ParamsTest, ShippedPresetsLoad) {
  std::set<std::string> defaults_files = {"default.yaml"};
  for (const auto& file : app::DefaultsFiles()) defaults_files.insert(file.file);
  int presets = 0;
  for (const auto& entry : std::filesystem::directory_iterator(testing::SourceDir() + "/params")) {
    if (entry.path().extension() != ".yaml" || defaults_files.count(entry.path().filename().string()) > 0) continue;
    ParamTree tree;
    EXPECT_NO_THROW({
      tree.MergeFile(entry.path().string());
      app::AllOptions().Load(tree);
    }) << entry.path();
    ++presets;
  }
  EXPECT_GE(presets, 2);
  ParamTree noisy;
  noisy.MergeFile(testing::SourceDir() + "/params/noisy-laser.yaml");
  const auto matching = app::AllOptions().Load(noisy).Get<slam::ScanMatchingOptions>("scan_matching");
  EXPECT_TRUE(matching.fuse_odometry);
  EXPECT_DOUBLE_EQ(matching.point_sigma_m, 0.3);
  // good-odometry.yaml is slam::GoodOdometry, which the closed loop uses, over the defaults.
  ParamTree good;
  good.MergeFile(testing::SourceDir() + "/params/good-odometry.yaml");
  EXPECT_EQ(params::ToYaml(app::AllOptions().Load(good).Get<slam::ScanMatchingOptions>("scan_matching")),
            params::ToYaml(slam::GoodOdometry(slam::ScanMatchingOptions{})));
  EXPECT_NE(params::ToYaml(slam::GoodOdometry(slam::ScanMatchingOptions{})),
            params::ToYaml(slam::ScanMatchingOptions{}));
  // ais-360 is ais.yaml (the AIS defaults) with two values changed.
  ParamTree ais360;
  ais360.MergeFile(testing::SourceDir() + "/params/ais-360.yaml");
  const auto loaded = app::AllOptions().Load(ais360);
  const auto preprocess = loaded.Get<ais::AisPreprocessOptions>("ais_classify");
  EXPECT_EQ(preprocess.length, 360);
  EXPECT_DOUBLE_EQ(preprocess.max_gap_s, 7200.0);  // AIS's, not the classify default
  const auto model = loaded.Get<ais::AisModelOptions>("ais_model");
  EXPECT_DOUBLE_EQ(model.distillation, 0.5);
  EXPECT_EQ(model.input_bins, 4);
}

TEST(ParamsTest, EditDistance) {
  EXPECT_EQ(params::EditDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(params::EditDistance("", "abc"), 3u);
  // Bounded: past the cap the count stops at cap + 1, whichever way it got there.
  EXPECT_EQ(params::EditDistance("kitten", "sitting", 3), 3u);
  EXPECT_EQ(params::EditDistance("kitten", "sitting", 2), 3u);
  EXPECT_EQ(params::EditDistance("a", std::string(5000, 'b'), 10), 11u);
  EXPECT_EQ(params::EditDistance("abcdefgh", "hgfedcba", 1), 2u);
}

// The banded count against the whole table, on random short strings and every cap.
TEST(ParamsTest, EditDistanceWithACapAgreesWithTheFullTable) {
  std::mt19937 rng(7);
  auto random_word = [&] {
    std::string w(rng() % 12, 'a');
    for (char& c : w) c = static_cast<char>('a' + rng() % 3);
    return w;
  };
  for (int trial = 0; trial < 2000; ++trial) {
    const std::string a = random_word(), b = random_word();
    const size_t full = params::EditDistance(a, b);
    for (size_t cap = 0; cap <= 13; ++cap) {
      ASSERT_EQ(params::EditDistance(a, b, cap), std::min(full, cap + 1)) << a << " / " << b << " cap " << cap;
    }
  }
}

TEST(ParamsTest, NearestKeySuggestsOnlyWithinAThirdOfTheKey) {
  const std::vector<std::string> keys = {"slam.max_range", "slam.min_range", "grid.resolution"};
  EXPECT_EQ(params::NearestKey("slam.max_rnage", keys), "slam.max_range");
  EXPECT_EQ(params::NearestKey("grid.resolutoin", keys), "grid.resolution");
  EXPECT_EQ(params::NearestKey("stereo.disparities", keys), "");
  EXPECT_EQ(params::NearestKey(std::string(4096, 'x'), keys), "");
  EXPECT_EQ(params::NearestKey("stereo", keys, SIZE_MAX - 1), "slam.max_range");  // nearest at any distance
}

}  // namespace
}  // namespace specht

namespace specht::params {
namespace {

TEST(ParseNumberAssignmentsTest, KeepsValidEntriesInOrderAndNamesTheBadOnes) {
  std::vector<std::string> problems;
  const auto parsed = ParseNumberAssignments(
      {"car=0.5", "bus=x", "cyclist=-2", "oops", "other=3"}, "margins", [](double v) { return v >= 0; },
      "a distance ≥ 0", &problems);
  ASSERT_EQ(parsed.size(), 2u);
  EXPECT_EQ(parsed[0], (std::pair<std::string, double>{"car", 0.5}));
  EXPECT_EQ(parsed[1], (std::pair<std::string, double>{"other", 3.0}));
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0], "margins: 'oops' is not of the form name=value");
  EXPECT_EQ(problems[1], "margins: 'x' for 'bus' is not a distance ≥ 0");
  EXPECT_EQ(problems[2], "margins: '-2' for 'cyclist' is not a distance ≥ 0");
}

}  // namespace
}  // namespace specht::params
