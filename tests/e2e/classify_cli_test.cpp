// `specht classify` and `specht track --model` as a user runs them on the robot
// classes: tracks from the simulator, a dataset, a (one-epoch) model with its forest,
// evaluation, prediction and online classification; the network and the forest
// combined by default, the network alone on request.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

using ::testing::HasSubstr;

// `classify crossval` on the prepared windows (the forest alone, fast): every window
// tested once per deal, a track's windows all in one fold, and the forest well above
// chance (1/3) on tracks it has not seen.
void ExpectCrossValidationDisjointByTrack(const std::string& dir) {
  const auto r =
      testing::RunSpecht("classify crossval '" + dir + "/data' --folds 3 --networks '' -q -o '" + dir + "/cv'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("3-fold CV by track"));
  const auto cv = Report(dir + "/cv");
  EXPECT_GT(cv["models"]["forest"]["macro_f1"]["mean"].get<double>(), 0.82);  // 0.856 measured
  std::stringstream csv(testing::ReadFile(dir + "/cv/predictions.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("index,object_id,repeat,fold,model,truth,predicted,p_car", 0), 0u) << line;
  std::map<std::string, std::string> fold_of_track;
  size_t rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 7u) << line;
    const auto [it, inserted] = fold_of_track.emplace(f[1], f[3]);
    EXPECT_EQ(it->second, f[3]) << "track " << f[1] << " tested in two folds";
    ++rows;
  }
  EXPECT_EQ(rows, cv["windows"].get<size_t>());
  EXPECT_GT(fold_of_track.size(), 20u);

  // A learning curve: one run per share on the same folds; the run on every track
  // is the run above, the run on half of them trains on fewer windows.
  const auto curve = testing::RunSpecht("classify crossval '" + dir +
                                        "/data' --folds 3 --networks '' --train-fraction 1,0.5 -q -o '" + dir + "/lc'");
  ASSERT_EQ(curve.exit_code, 0) << curve.err;
  EXPECT_THAT(curve.out, HasSubstr("learning curve"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/lc/learning_curve.png"));
  const auto points = Report(dir + "/lc")["learning_curve"];
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0]["train_fraction"].get<double>(), 0.5);  // in share order
  EXPECT_LT(points[0]["trained_windows_per_fold"].get<double>(),
            0.7 * points[1]["trained_windows_per_fold"].get<double>());
  EXPECT_EQ(points[1]["models"]["forest"]["macro_f1"], cv["models"]["forest"]["macro_f1"]);
  // Every scoring level: its figures, its pairs and its picture, each the share's own.
  for (const char* level : {"per_object", "with_history"}) {
    EXPECT_EQ(points[1]["models"]["forest"].at(level).at("macro_f1"), cv["models"]["forest"][level]["macro_f1"])
        << level;
    EXPECT_TRUE(std::filesystem::exists(dir + "/lc/learning_curve_" + std::string(level) + ".png")) << level;
  }
  for (const char* paired : {"paired", "paired_per_object", "paired_with_history"})
    EXPECT_EQ(points[0].at(paired), Report(dir + "/lc/share-0.5").at(paired)) << paired;
  EXPECT_THAT(curve.out, HasSubstr("learning curve, tracks"));
  EXPECT_THAT(curve.out, HasSubstr("learning curve, so far"));
  const auto &objects_half = points[0]["trained_objects_per_fold"], objects_all = points[1]["trained_objects_per_fold"];
  ASSERT_EQ(objects_half.size(), objects_all.size());
  for (size_t c = 0; c < objects_half.size(); ++c) {  // ⌈n / 2⌉ of each class's n tracks
    EXPECT_GE(objects_half[c].get<double>(), objects_all[c].get<double>() / 2) << c;
    EXPECT_LE(objects_half[c].get<double>(), objects_all[c].get<double>() / 2 + 1) << c;
  }
  EXPECT_EQ(Report(dir + "/lc/share-1")["models"]["forest"]["folds"], cv["models"]["forest"]["folds"]);
  const auto half = Report(dir + "/lc/share-0.5");
  EXPECT_EQ(half["train_fraction"].get<double>(), 0.5);
  const auto zero =
      testing::RunSpecht("classify crossval '" + dir + "/data' --train-fraction 0,1 -q -o '" + dir + "/lc0'");
  EXPECT_NE(zero.exit_code, 0);
  EXPECT_THAT(zero.err, HasSubstr("--train-fraction: 0 is not in (0, 1]"));

  const auto bad =
      testing::RunSpecht("classify crossval '" + dir + "/data' --networks resnet50 -q -o '" + dir + "/cv2'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("unknown variant \"resnet50\""));
}

TEST(ClassifyCliTest, PrepareTrainEvalPredictAndClassifyOnline) {
  const std::string dir = testing::TempDir("classify_pipeline");
  const std::string scenarios = testing::SourceDir() + "/datasets/scenarios";
  const std::string urban = scenarios + "/urban-crossing.yaml", parking = scenarios + "/parking-lot.yaml";
  const std::string maps = " --scenario '" + urban + "' --scenario '" + parking + "'";
  auto r = testing::RunSpecht("track '" + urban + "' '" + parking + "' --seeds 1-2 -q -o '" + dir + "/tracks'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::RunSpecht("classify prepare '" + dir + "/tracks/tracks.csv'" + maps + " -q -o '" + dir + "/data'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("pedestrian"));
  ExpectCrossValidationDisjointByTrack(dir);
  r = testing::RunSpecht("classify train '" + dir + "/data' --set classify_model.epochs=1 -q -o '" + dir + "/model'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(dir + "/model/forest.yml"));

  // On its own training windows the forest is all but exact (a broken feature
  // pipeline between training and evaluation would not be).
  r = testing::RunSpecht("classify eval '" + dir + "/model' '" + dir + "/data' -q -o '" + dir + "/eval'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto eval = Report(dir + "/eval")["metrics"];
  EXPECT_GT(eval["forest"]["macro_f1"].get<double>(), 0.9);
  EXPECT_TRUE(eval.contains("resnet"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/eval/confusion_combined.png"));

  // Prediction preprocesses the tracks as preparation did: on the same tracks it
  // scores exactly what eval scored for the combination.
  r = testing::RunSpecht("classify predict '" + dir + "/model' '" + dir + "/tracks/tracks.csv'" + maps + " -q -o '" +
                         dir + "/pred'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto pred = Report(dir + "/pred");
  EXPECT_EQ(pred["combination"], "network+forest");
  EXPECT_EQ(pred["windows"], Report(dir + "/eval")["inputs"]["windows"]);
  EXPECT_DOUBLE_EQ(pred["metrics"]["macro_f1"].get<double>(), eval["resnet+forest"]["macro_f1"].get<double>());
  EXPECT_THAT(testing::ReadFile(dir + "/pred/objects.csv"), HasSubstr("object_id,windows,class,p_car,p_cyclist"));
  r = testing::RunSpecht("classify predict '" + dir + "/model' '" + dir + "/tracks/tracks.csv'" + maps +
                         " --network-only -q -o '" + dir + "/pred1'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto pred1 = Report(dir + "/pred1");
  EXPECT_EQ(pred1["combination"], "network");
  EXPECT_DOUBLE_EQ(pred1["metrics"]["macro_f1"].get<double>(), eval["resnet"]["macro_f1"].get<double>());

  // Online: the classifier on every confirmed track's latest window, in the tracker.
  for (const bool network_only : {false, true}) {
    const std::string out = dir + (network_only ? "/online1" : "/online");
    r = testing::RunSpecht("track '" + parking + "' --seeds 3 --model '" + dir + "/model'" +
                           (network_only ? " --network-only" : "") + " -q -o '" + out + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto online = Report(out)["online_classification"];
    EXPECT_EQ(online["combination"], network_only ? "network" : "network+forest");
    EXPECT_GT(online["track_frames"].get<int>(), 100);
    EXPECT_EQ(online["classifier"]["classes"].size(), 3u);
  }
}

TEST(ClassifyCliTest, AModelDirectoryWithoutAModelIsAClearError) {
  const std::string dir = testing::TempDir("classify_bad");
  testing::WriteFile(dir + "/tracks.csv", "id,t_s,x_m,y_m,class\n");
  const auto r = testing::RunSpecht("classify predict '" + dir + "' '" + dir + "/tracks.csv' -q -o '" + dir + "/o'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr(dir + "/model.json: cannot open"));
}

}  // namespace
}  // namespace specht
