// `specht ais` as a user runs it: decode a real NMEA log, prepare a slice of the
// Brest tracks, cross-validate and train on it, predict with the model; and the
// errors a user meets first.
#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

using ::testing::HasSubstr;

// The first `lines` lines of a shipped track file (grouped by MMSI) as <dir>/slice.csv.
void WriteSliceOfTracks(const std::string& file, int lines, const std::string& dir) {
  const std::string text = testing::ReadDecompressed(testing::DataDir() + "/ais/tracks/" + file + ".csv.gz");
  size_t cut = 0;
  for (int i = 0; i < lines; ++i) cut = text.find('\n', cut) + 1;
  testing::WriteFile(dir + "/slice.csv", text.substr(0, cut));
}

TEST(AisCliTest, DecodeWritesMessagesPositionsAndRejectionReasons) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string out = testing::TempDir("ais_decode");
  const auto r = testing::RunSpecht("ais decode '" + testing::DataDir() + "/ais/nmea/gpsd-sample.aivdm' '" +
                                    testing::DataDir() + "/ais/nmea/signalk-nais400-merrimac.log' -q -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = Report(out);
  EXPECT_EQ(j["inputs"][0]["stats"]["emitted"], 97);
  EXPECT_GT(j["summary"]["messages"].get<int>(), 500);
  // These logs carry no receive times for position reports: none is written, all counted.
  EXPECT_GT(j["summary"]["positions_without_time"].get<int>(), 500);
  EXPECT_THAT(testing::ReadFile(out + "/positions.csv"), HasSubstr("mmsi,time,lon,lat,sog,cog,heading,ship_type\n"));
  EXPECT_THAT(r.out, HasSubstr("type 24 part B without its part A"));
}

TEST(AisCliTest, PrepareEvalTrainPredictOnASliceOfBrest) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string dir = testing::TempDir("ais_pipeline");
  WriteSliceOfTracks("brest-dev", 40000, dir);
  const std::string data = " --data-dir '" + testing::DataDir() + "'";
  auto r = testing::RunSpecht("ais prepare '" + dir + "/slice.csv' -q -o '" + dir + "/data'" + data);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/data/counts.png"));
  EXPECT_THAT(r.out, HasSubstr("Pleasure Craft"));
  // Same inputs → the same dataset files, byte for byte.
  r = testing::RunSpecht("ais prepare '" + dir + "/slice.csv' -q -o '" + dir + "/data2'" + data);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"windows.npy", "handcrafted.npy", "windows.csv"})
    EXPECT_EQ(testing::ReadFile(dir + "/data/" + f), testing::ReadFile(dir + "/data2/" + f)) << f;
  const std::string quick = " --set ais_model.epochs=1 --set ais_model.variant=tiny";
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks tiny -q -o '" + dir + "/cv'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto cv = Report(dir + "/cv");
  EXPECT_EQ(cv["models"]["tiny"]["folds"].size(), 2u);
  EXPECT_TRUE(cv["models"].contains("forest"));
  EXPECT_EQ(cv["models"]["tiny+forest"]["folds"].size(), 2u);           // the network and the forest combined
  EXPECT_EQ(cv["models"]["tiny"]["with_history"]["folds"].size(), 2u);  // each window from its vessel's so far
  // Each pair of models fold by fold: the combination against each of its parts.
  const auto& paired = cv["paired"];
  EXPECT_EQ(paired.size(), 3u);
  const double tiny_minus_forest =
      cv["models"]["tiny"]["macro_f1"]["mean"].get<double>() - cv["models"]["forest"]["macro_f1"]["mean"].get<double>();
  EXPECT_NEAR(paired["tiny vs forest"]["macro_f1_difference"]["mean"].get<double>(), tiny_minus_forest, 1e-9);
  EXPECT_EQ(paired["tiny vs forest"]["folds"], 2);
  // The corrected t-test's interval is around the mean difference, its p a probability.
  const auto& test = paired["tiny vs forest"]["corrected_t_test"];
  EXPECT_LE(test["interval_95"][0].get<double>(), tiny_minus_forest + 1e-12);
  EXPECT_GE(test["interval_95"][1].get<double>(), tiny_minus_forest - 1e-12);
  EXPECT_GE(test["p_value"].get<double>(), 0.0);
  EXPECT_LE(test["p_value"].get<double>(), 1.0);
  EXPECT_THAT(r.out, HasSubstr("tiny vs tiny+forest"));
  // The same pairs per vessel (majority vote) and from each vessel's windows so far.
  const double per_vessel = cv["models"]["tiny"]["per_object"]["macro_f1"]["mean"].get<double>() -
                            cv["models"]["forest"]["per_object"]["macro_f1"]["mean"].get<double>();
  EXPECT_NEAR(cv["paired_per_object"]["tiny vs forest"]["macro_f1_difference"]["mean"].get<double>(), per_vessel, 1e-9);
  EXPECT_EQ(cv["paired_with_history"].size(), 3u);
  EXPECT_THAT(r.out, HasSubstr("paired, vessels"));
  // One row per window and model (tiny, forest, tiny+forest), with the header.
  const std::string predictions = testing::ReadFile(dir + "/cv/predictions.csv");
  EXPECT_THAT(predictions, ::testing::StartsWith("index,object_id,repeat,fold,model,truth,predicted,p_"));
  EXPECT_EQ(std::count(predictions.begin(), predictions.end(), '\n'), 1 + 3 * cv["windows"].get<long>());
  EXPECT_TRUE(std::filesystem::exists(dir + "/cv/confusion_forest.png"));
  // Two deals of the vessels to the folds: the second is the run with seed 2.
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --repeats 2 --networks '' -q -o '" + dir + "/cv2'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("2-fold CV × 2 by MMSI"));
  const auto twice = Report(dir + "/cv2");
  EXPECT_EQ(twice["models"]["forest"]["folds"].size(), 4u);
  // The same run again against the first: the forest is deterministic, so no difference.
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --repeats 2 --networks '' -q -o '" + dir +
                         "/cv2b' --compare-to '" + dir + "/cv2'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("forest vs forest (earlier)"));
  for (const char* level : {"paired", "paired_per_object", "paired_with_history"}) {
    const auto against = Report(dir + "/cv2b")["compared_to"][level]["forest vs forest (earlier)"];
    EXPECT_EQ(against["macro_f1_difference"]["mean"].get<double>(), 0.0) << level;
    EXPECT_EQ(against["corrected_t_test"]["p_value"].get<double>(), 1.0) << level;
  }
  // Other folds (one deal, not two) are refused before any training, naming the report.
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks '' -q -o '" + dir + "/cv2c' --compare-to '" +
                         dir + "/cv2'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("cv2/report.json: \"repeats\" is 2 there and 1 here"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/cv2c/report.json"));
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks '' -q -o '" + dir + "/cv2c' --compare-to '" +
                         dir + "/nowhere'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("nowhere/report.json"));
  // A report without the fold sizes (an older run's) is refused up front too.
  auto old_report = twice;
  old_report.erase("fold_windows");
  std::filesystem::create_directories(dir + "/old");
  testing::WriteFile(dir + "/old/report.json", old_report.dump());
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --repeats 2 --networks '' -q -o '" + dir +
                         "/cv2c' --compare-to '" + dir + "/old'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("old/report.json: no \"fold_windows\""));
  EXPECT_FALSE(std::filesystem::exists(dir + "/cv2c/report.json"));
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks '' --set ais_model.seed=2 -q -o '" + dir +
                         "/cv3'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_DOUBLE_EQ(twice["models"]["forest"]["repeats"][1]["macro_f1"].get<double>(),
                   Report(dir + "/cv3")["models"]["forest"]["macro_f1"]["mean"].get<double>());
  // Self-training needs vessels of unknown type in the dataset (ais.unlabelled).
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks '' --pseudo-labels 0.6 -q -o '" + dir +
                         "/cv4'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("no unlabelled windows (AIS: prepare with ais.unlabelled)"));
  r = testing::RunSpecht("ais train '" + dir + "/data' -q -o '" + dir + "/model'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Same dataset and seed → the same model.
  r = testing::RunSpecht("ais train '" + dir + "/data' -q -o '" + dir + "/model2'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing::ReadFile(dir + "/model/model.pt"), testing::ReadFile(dir + "/model2/model.pt"));
  r = testing::RunSpecht("ais predict '" + dir + "/model' '" + dir + "/slice.csv' -q -o '" + dir + "/pred'" + data);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(testing::ReadFile(dir + "/pred/objects.csv"), HasSubstr("mmsi,ship_type,label,windows,class"));
  // Per window: its own class and the class from the vessel's windows so far; the
  // vessel's class in objects.csv is the last of those.
  EXPECT_THAT(testing::ReadFile(dir + "/pred/windows.csv"),
              ::testing::StartsWith("mmsi,window,t0,class,class_so_far,p_"));
  EXPECT_EQ(Report(dir + "/pred")["combination"], "network+forest");
  r = testing::RunSpecht("ais predict '" + dir + "/model' '" + dir + "/slice.csv' --network-only -q -o '" + dir +
                         "/pred1'" + data);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Report(dir + "/pred1")["combination"], "network");
  EXPECT_NE(testing::ReadFile(dir + "/pred/objects.csv"), testing::ReadFile(dir + "/pred1/objects.csv"));
}

// A long-window dataset scored by models trained on the short windows of the same
// tracks (--train-on): the folds are the long dataset's, so the run compares with a
// plain one fold by fold; every long window has short ones within it.
// A slice of the Brest tracks in <dir>/slice.csv prepared at 60 and 180 points
// (<dir>/data60, <dir>/data180).
void PrepareShortAndLongWindows(const std::string& dir) {
  WriteSliceOfTracks("brest-dev", 40000, dir);
  for (const char* length : {"60", "180"}) {
    const auto r =
        testing::RunSpecht("ais prepare '" + dir + "/slice.csv' --set ais_classify.length=" + length + " -q -o '" +
                           dir + "/data" + length + "' --data-dir '" + testing::DataDir() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
}

TEST(AisCliTest, EvalTrainsOnTheShortWindowsOfTheSameTracks) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string dir = testing::TempDir("ais_train_on");
  PrepareShortAndLongWindows(dir);
  EXPECT_THAT(testing::ReadFile(dir + "/data180/windows.csv"),
              ::testing::StartsWith("index,object_id,label,t0_s,t1_s\n"));
  const std::string eval = "ais eval '" + dir + "/data180' --folds 2 --networks tiny -q --set ais_model.epochs=1";
  auto r = testing::RunSpecht(eval + " -o '" + dir + "/plain'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::RunSpecht(eval + " --train-on '" + dir + "/data60' -o '" + dir + "/short' --compare-to '" + dir +
                         "/plain'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("training on " + dir + "/data60: "));
  EXPECT_THAT(r.err, HasSubstr(", 0 windows here with none"));
  const auto j = Report(dir + "/short");
  EXPECT_EQ(j["train_on"], dir + "/data60");
  EXPECT_EQ(j["fold_windows"], Report(dir + "/plain")["fold_windows"]);
  EXPECT_TRUE(j["compared_to"]["paired"].contains("forest vs forest (earlier)"));
  EXPECT_EQ(j["models"]["tiny+forest"]["folds"].size(), 2u);
  // Fine-tuned on the long windows: the run records its rate; the forest (never tuned) scores as without it.
  r = testing::RunSpecht(eval + " --train-on '" + dir + "/data60' --fine-tune 1e-4 -o '" + dir + "/tuned'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto tuned = Report(dir + "/tuned");
  EXPECT_EQ(tuned["fine_tune_learning_rate"], 1e-4);
  EXPECT_EQ(tuned["models"]["forest"]["folds"], j["models"]["forest"]["folds"]);
  r = testing::RunSpecht(eval + " --fine-tune 1e-4 -o '" + dir + "/bad'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("--fine-tune: goes with --train-on"));
  r = testing::RunSpecht(eval + " --train-on '" + dir + "/nowhere' -o '" + dir + "/bad'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("nowhere/dataset.json"));
}

// `ais train --train-on`: the model eval --train-on measures, for predict. Trained on
// the 60-point windows of every vessel (and fine-tuned on the 180-point ones, or not),
// it classifies 180-point windows — predict cuts the same windows as with a model of
// the 180-point windows alone — by the mean over the 60-point windows within
// (classify_test checks that mean against eval's). Bad combinations exit 2 with why.
TEST(AisCliTest, TrainOnTheShortWindowsOfTheSameTracks) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string dir = testing::TempDir("ais_train_short");
  PrepareShortAndLongWindows(dir);
  const std::string quick = " -q --set ais_model.epochs=2";
  const std::string train = "ais train '" + dir + "/data180' --train-on '" + dir + "/data60'" + quick;
  auto r = testing::RunSpecht(train + " --fine-tune 1e-4 -o '" + dir + "/tuned'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto tuned = Report(dir + "/tuned");
  EXPECT_EQ(tuned["train_on"]["length"], 60);
  EXPECT_GE(tuned["train_on"]["fine_tuning_epochs"].get<int>(), 1);
  EXPECT_GT(tuned["train_on"]["fine_tuning_windows"].get<int>(), 0);
  EXPECT_GT(tuned["validation"]["windows"].get<int>(), 0);
  EXPECT_THAT(testing::ReadFile(dir + "/tuned/fine_tuning.csv"), ::testing::StartsWith("epoch,train_loss,"));
  const auto model = nlohmann::json::parse(testing::ReadFile(dir + "/tuned/model.json"));
  ASSERT_TRUE(model["extra"].contains("input_preprocessing")) << model.dump();
  EXPECT_EQ(model["length"], 180);  // fine-tuned: the network takes the long windows
  r = testing::RunSpecht(train + " -o '" + dir + "/short'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::RunSpecht("ais train '" + dir + "/data180'" + quick + " -o '" + dir + "/long'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string data = " --data-dir '" + testing::DataDir() + "'";
  std::map<std::string, std::string> windows;
  for (const char* m : {"tuned", "short", "long"}) {
    r = testing::RunSpecht("ais predict '" + dir + "/" + m + "' '" + dir + "/slice.csv' -q -o '" + dir + "/pred-" + m +
                           "'" + data);
    ASSERT_EQ(r.exit_code, 0) << m << ": " << r.err;
    const std::string csv = testing::ReadFile(dir + "/pred-" + m + "/windows.csv");
    std::string keys;  // each window's vessel and start: which windows were cut
    for (size_t at = csv.find('\n') + 1; at < csv.size(); at = csv.find('\n', at) + 1) {
      const size_t third = csv.find(',', csv.find(',', csv.find(',', at) + 1) + 1);
      keys += csv.substr(at, third - at) + "\n";
    }
    windows[m] = keys;
    EXPECT_GT(Report(dir + "/pred-" + m)["vessels"].get<int>(), 0) << m;
  }
  EXPECT_EQ(windows["tuned"], windows["long"]);
  EXPECT_EQ(windows["short"], windows["long"]);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"ais train '" + dir + "/data180' --fine-tune 1e-4", "--fine-tune: goes with --train-on"},
      {"ais train '" + dir + "/data60' --train-on '" + dir + "/data180'", "must be shorter than 60"},
      {train + " --pseudo-labels 0.6", "--train-on: not with --pseudo-labels"},
      {train + " --set ais_model.variant=mlp --fine-tune 1e-4", "cannot be fine-tuned"}};
  for (const auto& [command, why] : bad) {
    r = testing::RunSpecht(command + quick + " -o '" + dir + "/bad'");
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_THAT(r.err, HasSubstr(why)) << command;
  }
}

// Self-training on a slice of the Canadian tracks, whose first vessels report no
// ship type: prepared with ais.unlabelled, their windows are pseudo-labelled by the
// forest for the network in `eval` (per fold) and `train`, and the forest's own
// figures are those of a run without them.
TEST(AisCliTest, PseudoLabelsFromVesselsOfUnknownType) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string dir = testing::TempDir("ais_pseudo");
  WriteSliceOfTracks("mpa-dev", 40000, dir);  // its first vessels report no ship type
  auto r = testing::RunSpecht("ais prepare '" + dir + "/slice.csv' -q -o '" + dir + "/data' --set ais.unlabelled=true" +
                              " --data-dir '" + testing::DataDir() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("unlabelled"));
  const long unlabelled = Report(dir + "/data")["counts"]["moving"]["unlabelled"].get<long>();
  ASSERT_GT(unlabelled, 20);
  const std::string quick = " --set ais_model.epochs=1";
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks tiny --pseudo-labels 0.6 -q -o '" + dir +
                         "/cv'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto cv = Report(dir + "/cv");
  EXPECT_EQ(cv["unlabelled_windows"].get<long>(), unlabelled);
  ASSERT_EQ(cv["pseudo_labels"]["per_fold"].size(), 2u);
  for (const auto& fold : cv["pseudo_labels"]["per_fold"]) {
    long sum = 0;
    for (long n : fold.get<std::vector<long>>()) sum += n;
    EXPECT_GT(sum, 0);
    EXPECT_LE(sum, unlabelled);
  }
  r = testing::RunSpecht("ais eval '" + dir + "/data' --folds 2 --networks '' -q -o '" + dir + "/cv0'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Report(dir + "/cv0")["models"]["forest"]["folds"], cv["models"]["forest"]["folds"]);
  EXPECT_EQ(Report(dir + "/cv0")["windows"], cv["windows"]);  // the labelled windows only
  r = testing::RunSpecht("ais train '" + dir + "/data' --pseudo-labels 0.6 -q -o '" + dir + "/model'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto trained = Report(dir + "/model");
  long pseudo = 0;
  for (long n : trained["pseudo_labels"]["per_class"].get<std::vector<long>>()) pseudo += n;
  EXPECT_GT(pseudo, 0);
  r = testing::RunSpecht("ais train '" + dir + "/data' -q -o '" + dir + "/model0'" + quick);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(trained["windows"]["train"].get<long>(), Report(dir + "/model0")["windows"]["train"].get<long>() + pseudo);
  EXPECT_EQ(testing::ReadFile(dir + "/model/forest.yml"), testing::ReadFile(dir + "/model0/forest.yml"));

  // Two rounds (noisy student): a checkpoint each; resuming a finished run gives the
  // same model.
  const std::string twice =
      "ais train '" + dir + "/data' --pseudo-labels 0.6 --pseudo-label-rounds 2 -q -o '" + dir + "/model2'" + quick;
  r = testing::RunSpecht(twice);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto second = Report(dir + "/model2");
  ASSERT_EQ(second["pseudo_labels"]["per_round"].size(), 2u);
  EXPECT_EQ(second["pseudo_labels"]["per_round"][0], trained["pseudo_labels"]["per_class"]);
  EXPECT_EQ(second["model"]["epochs"].get<int>(), 2);
  EXPECT_TRUE(std::filesystem::exists(dir + "/model2/checkpoint-round1.pt"));
  r = testing::RunSpecht(twice + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Report(dir + "/model2")["validation"], second["validation"]);
}

TEST(AisCliTest, BadInputIsAClearError) {
  const std::string dir = testing::TempDir("ais_bad");
  testing::WriteFile(dir + "/x.csv", "a,b\n1,2\n");
  auto r =
      testing::RunSpecht("ais prepare '" + dir + "/x.csv' -q -o '" + dir + "/o' --set ais.coastline=/nonexistent.shp");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("/nonexistent.shp"));
  r = testing::RunSpecht("ais eval '" + dir + "' --networks resnet50 -q -o '" + dir + "/o2'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("resnet50"));
  if (testing::DataDir().empty()) return;
  r = testing::RunSpecht("ais prepare '" + dir + "/x.csv' -q -o '" + dir + "/o3' --data-dir '" + testing::DataDir() +
                         "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("x.csv:1: header matches no known AIS layout"));
}

}  // namespace
}  // namespace specht
