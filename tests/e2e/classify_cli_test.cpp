// `specht classify` and `specht track --model` as a user runs them on the robot
// classes: tracks from the simulator, a dataset, a (one-epoch) model with its forest,
// evaluation, prediction and online classification; the network and the forest
// combined by default, the network alone on request.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace specht {
namespace {

using ::testing::HasSubstr;

nlohmann::json Report(const std::string& dir) { return nlohmann::json::parse(testing::ReadFile(dir + "/report.json")); }

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
