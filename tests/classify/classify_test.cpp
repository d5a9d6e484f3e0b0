// Trajectory preprocessing against hand-made trajectories with known answers (issue
// acceptance 3), scores, and the 1D ResNet: it learns a separable toy problem, saves
// and reloads to identical predictions, trains reproducibly, refuses mismatched
// models and inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "specht/classify/baseline.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/classify/map_features.h"
#include "specht/classify/metrics.h"
#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "test_support.h"

namespace specht::classify {
namespace {

Trajectory Line(const std::string& id, int n, double dt, double vx, double vy, double t0 = 0) {
  Trajectory t{id, "car", {}};
  for (int i = 0; i < n; ++i) t.points.push_back({t0 + i * dt, vx * i * dt, vy * i * dt});
  return t;
}

TEST(PreprocessTest, SplitsAtTimeGapsAndJumps) {
  PreprocessOptions o;
  o.max_gap_s = 1.0;
  o.max_jump_sq = 4.0;  // 2 m
  Trajectory t = Line("a", 10, 0.1, 1, 0);
  t.points[5].t_s += 5;  // a 5 s gap before sample 5 …
  for (size_t i = 6; i < t.points.size(); ++i) t.points[i].t_s += 5;
  t.points[8].x += 3;  // … and a 3 m jump before sample 8 (and back after it)
  const auto pieces = Split(t, o);
  ASSERT_EQ(pieces.size(), 4u);
  EXPECT_EQ(pieces[0].points.size(), 5u);
  EXPECT_EQ(pieces[1].points.size(), 3u);
  EXPECT_EQ(pieces[2].points.size(), 1u);
  EXPECT_EQ(pieces[3].points.size(), 1u);
}

TEST(PreprocessTest, ChunksWithTheEightyPercentRule) {
  PreprocessOptions o;
  o.length = 10;
  o.min_fill = 0.8;
  auto w = Chunk(Line("a", 28, 0.1, 1, 0), o);  // 10 + 10 + 8 (kept: 8 ≥ 8)
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[2].valid, 8);
  EXPECT_DOUBLE_EQ(w[1].t0_s, 1.0);
  w = Chunk(Line("a", 27, 0.1, 1, 0), o);  // leftover 7 < 8: dropped
  EXPECT_EQ(w.size(), 2u);
  // The padded window: zeros after the valid points in every feature.
  o.features = {"x", "speed"};
  const auto f = Features(Chunk(Line("a", 28, 0.1, 1, 0), o)[2], o, {});
  ASSERT_EQ(f.size(), 20u);
  EXPECT_GT(f[7], 0.9f);  // x at the last valid point: 1 after local min-max
  EXPECT_EQ(f[8], 0.0f);
  EXPECT_EQ(f[9], 0.0f);
  EXPECT_EQ(f[19], 0.0f);
}

TEST(PreprocessTest, StationaryFilterUsesMeanStepLength) {
  // 5 points 1 m apart: Σ|ΔP| = 4, n = 5 → α = 0.8.
  EXPECT_DOUBLE_EQ(MeanStepLength(Line("a", 5, 1, 1, 0).points), 0.8);
  PreprocessOptions o;
  o.length = 5;
  o.stationary_threshold = 0.5;
  std::map<std::string, std::map<std::string, long>> counts;
  auto parked = Line("p", 5, 1, 0.01, 0);
  parked.label = "parked";
  const auto w = MakeWindows({Line("a", 5, 1, 1, 0), parked}, o, &counts);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].object_id, "a");
  EXPECT_EQ(counts["chunked"]["parked"], 1);
  EXPECT_EQ(counts["moving"].count("parked"), 0u);
}

TEST(PreprocessTest, PositionTransforms) {
  std::vector<TrajectoryPoint> p = {{0, 10, 20}, {1, 11, 21}, {2, 12, 22}};
  RelativeToFirst(p);
  EXPECT_DOUBLE_EQ(p[0].x, 0);
  EXPECT_DOUBLE_EQ(p[2].x, 2);
  EXPECT_DOUBLE_EQ(p[2].y, 2);
  RotateToZero(p);  // the last point onto +x: (2√2, 0)
  EXPECT_NEAR(p[2].x, 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(p[2].y, 0, 1e-12);
  EXPECT_NEAR(p[1].x, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(p[1].y, 0, 1e-12);
  std::vector<TrajectoryPoint> loop = {{0, 0, 0}, {1, 1, 1}, {2, 0, 0}};  // round trip: unchanged
  RotateToZero(loop);
  EXPECT_DOUBLE_EQ(loop[1].x, 1);
}

TEST(PreprocessTest, NormalisationLocalGlobalAndFixedBounds) {
  PreprocessOptions o;
  o.length = 5;
  o.features = {"x", "y", "dt", "speed", "course", "dist_static"};
  o.max_gap_s = 2.0;
  o.max_speed = 4.0;
  o.static_cap = 10;
  const auto w = Chunk(Line("a", 5, 0.5, 2, 0), o)[0];  // x 0..4, speed 2 m/s, dt 0.5, course 0
  MapFeatures map;
  map.distance_to_static = [](double x, double) { return 5.0 + x; };
  auto f = Features(w, o, map);
  EXPECT_FLOAT_EQ(f[0 * 5 + 4], 1.0f);  // local: x max → 1
  EXPECT_FLOAT_EQ(f[0 * 5 + 2], 0.5f);
  EXPECT_FLOAT_EQ(f[1 * 5 + 3], 0.0f);   // y constant → 0
  EXPECT_FLOAT_EQ(f[2 * 5 + 1], 0.25f);  // dt 0.5 / 2
  EXPECT_FLOAT_EQ(f[3 * 5 + 2], 0.5f);   // speed 2 / 4
  EXPECT_FLOAT_EQ(f[4 * 5 + 2], 0.0f);   // course 0
  EXPECT_FLOAT_EQ(f[5 * 5 + 0], 0.5f);   // distance 5 / 10
  EXPECT_FLOAT_EQ(f[5 * 5 + 4], 0.9f);   // 9 / 10
  o.normalisation = "global";
  const PositionBounds b{0, 8, -1, 1};
  f = Features(w, o, map, b);
  EXPECT_FLOAT_EQ(f[4], 0.5f);      // 4 in [0, 8]
  EXPECT_FLOAT_EQ(f[5 + 4], 0.5f);  // 0 in [−1, 1]
  const auto fitted = FitPositionBounds({w}, o);
  EXPECT_DOUBLE_EQ(fitted.max_x, 4);
}

TEST(PreprocessTest, BadTrajectories) {
  PreprocessOptions o;
  Trajectory t = Line("obj-7", 5, 0.1, 1, 0);
  t.points[3].x = std::nan("");
  try {
    Split(t, o);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("obj-7: sample 3"), std::string::npos);
  }
  t = Line("obj-8", 5, 0.1, 1, 0);
  t.points[2].t_s = -1;
  EXPECT_THROW(Split(t, o), InputError);
  EXPECT_TRUE(MakeWindows({Trajectory{"empty", "car", {}}}, o).empty());
  o.features = {"x", "colour"};
  EXPECT_EQ(o.Relations().size(), 1u);
}

TEST(MapFeaturesTest, DistanceTransformOfGrid) {
  cv::Mat occupied = cv::Mat::zeros(100, 100, CV_8U);
  occupied.col(0).setTo(1);  // a wall along x = 0 (cells of 0.1 m from origin −0.05)
  const auto f = GridMapFeatures(occupied, -0.05, 0, 0.1, {{5, 5}});
  EXPECT_NEAR(f.distance_to_static(3.0, 5.0), 3.0, 0.11);
  EXPECT_NEAR(f.distance_to_poi(5, 8), 3.0, 1e-12);
}

TEST(MetricsTest, F1ByHand) {
  // truth   0 0 0 1 1 2
  // predict 0 0 1 1 1 0
  const auto s = Score({0, 0, 0, 1, 1, 2}, {0, 0, 1, 1, 1, 0}, 3);
  EXPECT_NEAR(s.f1[0], 2 * (2.0 / 3) * (2.0 / 3) / (4.0 / 3), 1e-12);  // P 2/3, R 2/3
  EXPECT_NEAR(s.f1[1], 0.8, 1e-12);                                    // P 2/3, R 1
  EXPECT_NEAR(s.f1[2], 0.0, 1e-12);
  EXPECT_NEAR(s.macro_f1, (2.0 / 3 + 0.8) / 3, 1e-12);
  EXPECT_NEAR(s.weighted_f1, (3 * 2.0 / 3 + 2 * 0.8) / 6, 1e-12);
  EXPECT_EQ(s.confusion[2][0], 1);
}

// Two classes that differ only in how they move (straight vs. weaving), with the
// same speed range: learnable from the sequence, not from one point.
Dataset ToyDataset(int per_class, int seed, std::vector<std::string>* ids = nullptr, int length = 32) {
  PreprocessOptions o;
  o.length = length;
  o.features = {"x", "y", "speed", "turn_rate"};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> speed(1, 3), phase(0, 6.28);
  Dataset d;
  d.features = 4, d.length = length;
  for (int i = 0; i < 2 * per_class; ++i) {
    const int cls = i % 2;
    const double v = speed(rng), ph = phase(rng);
    Trajectory t{"obj" + std::to_string(seed) + "_" + std::to_string(i), "", {}};
    double x = 0, y = 0, h = ph;
    for (int k = 0; k < length; ++k) {
      h += cls ? 0.5 * std::sin(k * 0.8) : 0.0;
      x += v * 0.1 * std::cos(h), y += v * 0.1 * std::sin(h);
      t.points.push_back({0.1 * k, x, y});
    }
    const auto w = Chunk(t, o);
    const auto f = Features(w[0], o, {});
    d.x.insert(d.x.end(), f.begin(), f.end());
    d.y.push_back(cls);
    d.object_ids.push_back(t.object_id);
  }
  return d;
}

ModelOptions Small() {
  ModelOptions o;
  o.variant = "tiny";
  o.epochs = 8;
  o.batch_size = 32;
  o.learning_rate = 3e-3;
  o.threads = 1;
  return o;
}

TEST(DatasetTest, SubsetThenAppendRestoresTheWindowsAndRefusesOtherShapes) {
  const Dataset d = ToyDataset(3, 1);  // 6 windows of 4 × 32
  Dataset back = d.Subset({0, 1, 2});
  back.Append(d.Subset({3, 4, 5}));
  EXPECT_EQ(back.x, d.x);
  EXPECT_EQ(back.y, d.y);
  EXPECT_EQ(back.object_ids, d.object_ids);
  Dataset shorter = d.Subset({0});
  shorter.length = 16, shorter.x.resize(4 * 16);
  EXPECT_THROW(back.Append(shorter), InputError);
  Dataset wider = d.Subset({0});
  wider.features = 8, wider.length = 16;  // the same floats a window, another shape
  EXPECT_THROW(back.Append(wider), InputError);
  EXPECT_EQ(back.size(), d.size());  // a refused append leaves the windows as they were
}

// A teacher's probabilities travel with their windows through Subset and Append,
// and an Append of windows without them drops them all (a part cannot be taught).
TEST(DatasetTest, TeacherProbabilitiesTravelWithTheirWindows) {
  Dataset d = ToyDataset(3, 1);  // 6 windows
  for (size_t i = 0; i < d.size(); ++i) d.teacher.insert(d.teacher.end(), {0.1f * i, 1 - 0.1f * i});
  const Dataset odd = d.Subset({1, 3, 5});
  EXPECT_EQ(odd.teacher, (std::vector<float>{0.1f, 0.9f, 0.3f, 0.7f, 0.5f, 0.5f}));
  Dataset back;
  back.features = 4, back.length = 32;
  back.Append(d.Subset({0, 1, 2}));  // into an empty dataset: kept
  back.Append(d.Subset({3, 4, 5}));
  EXPECT_EQ(back.teacher, d.teacher);
  Dataset untaught = ToyDataset(1, 2);
  back.Append(untaught);
  EXPECT_TRUE(back.teacher.empty());
  EXPECT_TRUE(untaught.Subset({0, 1}).teacher.empty());
}

TEST(ModelTest, LearnsAToyProblemAndReloadsIdentically) {
  const Dataset train = ToyDataset(100, 1), test = ToyDataset(50, 2);
  Classifier c(Small(), 4, 32, {"straight", "weaving"});
  EXPECT_GT(c.parameter_count(), 10000);
  const auto reports = c.Train(train, test);
  ASSERT_FALSE(reports.empty());
  const Scores s = Score(test.y, c.PredictClasses(test), 2);
  EXPECT_GT(s.macro_f1, 0.95);
  const std::string dir = testing::TempDir("model");
  c.Save(dir + "/m", {{"note", "toy"}});
  nlohmann::json extra;
  const Classifier back = Classifier::Load(dir + "/m", &extra);
  EXPECT_EQ(extra["note"], "toy");
  EXPECT_EQ(back.Predict(test), c.Predict(test));  // bit-identical
}

// With input_bins the rows are encoded piecewise-linearly over quantile bins fitted
// on the training data: the first convolution sees rows × bins channels, the bins
// travel with the weights (a reloaded model predicts bit-identically) and the model
// still learns the toy problem.
TEST(ModelTest, InputBinsAreFittedAndTravelWithTheModel) {
  const Dataset train = ToyDataset(100, 1), test = ToyDataset(50, 2);
  auto o = Small();
  o.input_bins = 4;
  Classifier plain(Small(), 4, 32, {"straight", "weaving"}), binned(o, 4, 32, {"straight", "weaving"});
  // Only the first block's two input convolutions widen: kernel 8 + the 1×1 shortcut.
  EXPECT_EQ(binned.parameter_count() - plain.parameter_count(), 32 * (4 * 4 - 4) * (8 + 1));
  // "split" keeps one path per input row, over the row's 4 bins.
  o.variant = "split";
  auto split = Small();
  split.variant = "split";
  EXPECT_EQ(Classifier(o, 4, 32, {"s", "w"}).parameter_count() - Classifier(split, 4, 32, {"s", "w"}).parameter_count(),
            4 * 32 * (4 - 1) * (8 + 1));
  binned.Train(train, test);
  EXPECT_GT(Score(test.y, binned.PredictClasses(test), 2).macro_f1, 0.95);
  const std::string dir = testing::TempDir("model_bins");
  binned.Save(dir + "/m");
  const Classifier back = Classifier::Load(dir + "/m");
  EXPECT_EQ(back.options().input_bins, 4);
  EXPECT_EQ(back.Predict(test), binned.Predict(test));  // bins left at their initial 0, 1 would differ
}

// With distillation α = 1 the loss is the teacher's alone: a teacher that swaps the
// two classes is learnt instead of the labels. Without its probabilities for every
// training window distillation is refused.
TEST(ModelTest, DistillationLearnsTheTeachersAnswers) {
  Dataset train = ToyDataset(100, 1);
  const Dataset test = ToyDataset(50, 2);
  for (int y : train.y) train.teacher.insert(train.teacher.end(), {y == 1 ? 1.0f : 0.0f, y == 0 ? 1.0f : 0.0f});
  ModelOptions o = Small();
  o.distillation = 1.0;
  o.validation_fraction = 0;
  Classifier c(o, 4, 32, {"straight", "weaving"});
  c.Train(train, {});
  std::vector<int> swapped;
  for (int y : test.y) swapped.push_back(1 - y);
  EXPECT_GT(Score(swapped, c.PredictClasses(test), 2).macro_f1, 0.95);

  Dataset untaught = ToyDataset(100, 1);
  Classifier refuses(o, 4, 32, {"straight", "weaving"});
  EXPECT_THROW(refuses.Train(untaught, {}), InputError);
  untaught.teacher.assign(2 * 99, 0.5f);  // one window short
  EXPECT_THROW(refuses.Train(untaught, {}), InputError);
}

// Fine-tuning continues a model of 32-point windows on 64-point ones: the model
// then takes (and saves) the new length, keeps its options' rate, and
// tells the classes apart at that length. An MLP (fixed input size), a zero rate
// and windows of other features are refused, leaving the model as it was.
TEST(ModelTest, FineTuningContinuesOnLongerWindows) {
  auto o = Small();
  o.input_bins = 4;
  Classifier c(o, 4, 32, {"straight", "weaving"});
  c.Train(ToyDataset(100, 1), ToyDataset(50, 2));
  const Dataset long_train = ToyDataset(100, 3, nullptr, 64), long_test = ToyDataset(50, 4, nullptr, 64);
  EXPECT_THROW(c.Predict(long_test), InputError);
  const auto reports = c.FineTune(long_train, long_test, 3e-4);
  EXPECT_FALSE(reports.empty());
  EXPECT_EQ(c.length(), 64);
  EXPECT_EQ(c.options().learning_rate, o.learning_rate);
  EXPECT_GT(Score(long_test.y, c.PredictClasses(long_test), 2).macro_f1, 0.95);
  const std::string dir = testing::TempDir("model_tuned");
  c.Save(dir + "/m");
  const Classifier back = Classifier::Load(dir + "/m");
  EXPECT_EQ(back.length(), 64);
  EXPECT_EQ(back.Predict(long_test), c.Predict(long_test));

  const auto before = c.Predict(long_test);
  Dataset wider = long_train;
  wider.features = 8, wider.length = 32;  // the same floats a window, another shape
  EXPECT_THROW(c.FineTune(wider, {}, 3e-4), InputError);
  EXPECT_THROW(c.FineTune(long_train, {}, 0), InputError);
  EXPECT_EQ(c.length(), 64);
  EXPECT_EQ(c.Predict(long_test), before);
  auto mlp = Small();
  mlp.variant = "mlp";
  Classifier fixed(mlp, 4, 32, {"straight", "weaving"});
  EXPECT_THROW(fixed.FineTune(long_train, {}, 3e-4), InputError);
}

TEST(ModelTest, SameSeedSameModel) {
  const Dataset train = ToyDataset(40, 3);
  auto o = Small();
  o.epochs = 2;
  Classifier a(o, 4, 32, {"s", "w"}), b(o, 4, 32, {"s", "w"});
  a.Train(train, {});
  b.Train(train, {});
  EXPECT_EQ(a.Predict(train), b.Predict(train));
}

// Stopped after 2 epochs and resumed to 4 from the checkpoint = 4 epochs at once,
// bit for bit (weights, Adam state, learning-rate schedule, per-epoch seeds).
TEST(ModelTest, ResumedTrainingEqualsUninterruptedTraining) {
  const Dataset train = ToyDataset(40, 3), validation = ToyDataset(10, 4);
  auto o = Small();
  o.epochs = 4;
  o.plateau_patience = 1;  // the rate changes during the run, so the schedule must resume too
  Classifier whole(o, 4, 32, {"s", "w"});
  const auto whole_reports = whole.Train(train, validation);

  const std::string ckpt = testing::TempDir("model_resume") + "/ckpt.pt";
  auto first = o;
  first.epochs = 2;
  Classifier part(first, 4, 32, {"s", "w"});
  part.Train(train, validation, nullptr, ckpt);
  Classifier resumed(o, 4, 32, {"s", "w"});  // a new process would start from fresh weights
  int seen = 0;
  const auto reports = resumed.Train(
      train, validation, [&](const EpochReport&) { ++seen; }, ckpt);
  EXPECT_EQ(seen, static_cast<int>(whole_reports.size()));
  ASSERT_EQ(reports.size(), whole_reports.size());
  for (size_t i = 0; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].train_loss, whole_reports[i].train_loss) << "epoch " << i + 1;
    EXPECT_EQ(reports[i].learning_rate, whole_reports[i].learning_rate) << "epoch " << i + 1;
  }
  EXPECT_EQ(resumed.Predict(validation), whole.Predict(validation));

  // A checkpoint of another run is refused, and so is a corrupt one.
  Classifier other(o, 4, 32, {"s", "w"});
  EXPECT_THROW(other.Train(ToyDataset(30, 3), validation, nullptr, ckpt), InputError);
  testing::WriteFile(ckpt, "garbage");
  EXPECT_THROW(other.Train(train, validation, nullptr, ckpt), InputError);
}

TEST(ModelTest, RefusesMismatchedModelsAndInputs) {
  const std::string dir = testing::TempDir("model_bad");
  Classifier c(Small(), 4, 32, {"s", "w"});
  c.Save(dir + "/m");
  const Dataset wrong = ToyDataset(2, 1);
  Dataset five = wrong;
  five.features = 5;
  EXPECT_THROW(c.Predict(five), InputError);
  const std::string good = testing::ReadFile(dir + "/m.json");
  auto refused = [&](const std::string& from, const std::string& to, const std::string& says) {
    std::string meta = good;
    meta.replace(meta.find(from), from.size(), to);
    testing::WriteFile(dir + "/m.json", meta);
    try {
      Classifier::Load(dir + "/m");
      ADD_FAILURE() << to << ": accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("m.json")) << e.what();
      EXPECT_THAT(e.what(), ::testing::HasSubstr(says)) << e.what();
    }
  };
  // The weights of a tiny model under a json that says shallow; options outside
  // their declaration are named by key, not reported as weights that do not fit.
  refused("\"tiny\"", "\"shallow\"", "weights do not fit");
  refused("\"tiny\"", "\"huge\"", "variant");
  refused("\"input_bins\": 0", "\"input_bins\": 65", "input_bins");
  refused("\"input_bins\": 0", "\"input_bins\": \"eight\"", "input_bins");
  refused("\"batch_norm\": true", "\"batch_norm\": 3", "batch_norm");
  refused("\"variant\"", "\"kind\"", "variant");
  refused("{", "{not json", "not JSON");
  EXPECT_THROW(Classifier::Load(dir + "/missing"), InputError);
  EXPECT_THROW(Classifier(Small(), 4, 32, {"only"}), InputError);
}

// Prepared windows of `trajectories` as `classify prepare` writes them (no map):
// features, hand-crafted rows, spans, and the preprocessing in dataset.json.
PreparedDataset Prepared(const std::vector<Trajectory>& trajectories, const PreprocessOptions& o,
                         const std::vector<std::string>& classes) {
  PreparedDataset d;
  d.classes = classes;
  d.windows.features = FeatureRows(o), d.windows.length = o.length;
  for (const auto& w : MakeWindows(trajectories, o)) {
    const auto f = Features(w, o, {});
    d.windows.x.insert(d.windows.x.end(), f.begin(), f.end());
    const auto h = HandcraftedFeatures(w, {}, o.features);
    d.handcrafted.insert(d.handcrafted.end(), h.begin(), h.end());
    d.AddWindow(w, static_cast<int>(std::find(classes.begin(), classes.end(), w.label) - classes.begin()));
  }
  d.info = {{"preprocessing", PreprocessingJson(o, {})}};
  return d;
}

// Straight and weaving tracks of 160 points; track 0 has a 1 s gap before point 100
// (a piece boundary), track 1 stands still over points 50–69 (stationary pieces).
std::vector<Trajectory> StraightAndWeavingTracks() {
  std::vector<Trajectory> tracks;
  for (int i = 0; i < 12; ++i) {
    const int cls = i % 2;
    Trajectory t{"t" + std::to_string(i), cls ? "weaving" : "straight", {}};
    double x = 0, y = 0, h = 0.3 * i;
    for (int k = 0; k < 160; ++k) {
      h += cls ? 0.5 * std::sin(k * 0.8) : 0.0;
      const double v = (i == 1 && k >= 50 && k < 70) ? 0.0 : 1 + 0.1 * i;
      x += v * 0.1 * std::cos(h), y += v * 0.1 * std::sin(h);
      t.points.push_back({0.1 * k + (i == 0 && k >= 100 ? 1.0 : 0.0), x, y});
    }
    tracks.push_back(std::move(t));
  }
  return tracks;
}

// A model of shorter windows (train --train-on) classifies a window as eval
// --train-on scores it: its network's and forest's probabilities averaged over the
// shorter windows of the same track within the window's span (WindowsWithin,
// MeanWithin), and with a network fine-tuned on the full windows, that network's own
// answer beside the forest's mean. The windows within are found by chunking each
// window's points at predict time and by time spans over independently cut datasets
// in eval: equal when the length divides, which Load and ShorterWindowsProblem demand.
TEST(TrajectoryClassifierTest, AModelOfShorterWindowsScoresAWindowAsEvalDoes) {
  PreprocessOptions short_o;
  short_o.length = 16;
  short_o.max_gap_s = 0.5;
  short_o.features = {"x", "y", "speed", "turn_rate"};
  PreprocessOptions long_o = short_o;
  long_o.length = 48;
  const std::vector<std::string> classes = {"straight", "weaving"};
  const auto tracks = StraightAndWeavingTracks();
  const PreparedDataset shorter = Prepared(tracks, short_o, classes), windows = Prepared(tracks, long_o, classes);
  EXPECT_EQ(ShorterWindowsProblem(windows, shorter), "");
  const auto within = WindowsWithin(windows, shorter);
  size_t fewer = 0;  // windows with stationary pieces left out
  for (const auto& rows : within) fewer += rows.size() < 3;
  EXPECT_GT(fewer, 0u);

  const std::string dir = testing::TempDir("shorter_windows");
  Classifier network(Small(), 4, 16, classes);
  network.Train(shorter.windows, {});
  ForestBaseline forest(21, 4, 1);
  forest.Train(shorter.handcrafted, shorter.windows.y);
  forest.Save(dir + "/forest.yml");
  const nlohmann::json extra = {{"preprocessing", PreprocessingJson(long_o, {})},
                                {"input_preprocessing", PreprocessingJson(short_o, {})}};
  network.Save(dir + "/m", extra);

  std::vector<size_t> all_short(shorter.windows.size()), all_long(windows.windows.size());
  std::iota(all_short.begin(), all_short.end(), 0);
  std::iota(all_long.begin(), all_long.end(), 0);
  const auto net_mean = MeanWithin(network.Predict(shorter.windows), all_short, within, all_long, 2);
  const auto forest_mean = MeanWithin(forest.Probabilities(shorter.handcrafted, 2), all_short, within, all_long, 2);
  const std::vector<Window> long_windows = MakeWindows(tracks, long_o);
  ASSERT_EQ(long_windows.size(), windows.windows.size());
  auto expect_equal = [](const std::vector<float>& got, const std::vector<float>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-5) << "entry " << i;
  };
  const TrajectoryClassifier alone = TrajectoryClassifier::Load(dir + "/m");
  EXPECT_EQ(alone.input_length(), 16);
  EXPECT_EQ(alone.Windows(tracks).size(), long_windows.size());
  expect_equal(alone.Classify(long_windows), net_mean);
  const TrajectoryClassifier both = TrajectoryClassifier::Load(dir + "/m", dir + "/forest.yml");
  expect_equal(both.Classify(long_windows), CombinedProbabilities(net_mean, forest_mean));

  // Fine-tuned on the full windows: the network answers for the window itself.
  network.FineTune(windows.windows, {}, 1e-4);
  network.Save(dir + "/tuned", extra);
  const TrajectoryClassifier tuned = TrajectoryClassifier::Load(dir + "/tuned", dir + "/forest.yml");
  expect_equal(tuned.Classify(long_windows), CombinedProbabilities(network.Predict(windows.windows), forest_mean));

  // Lengths that do not divide, other preprocessing, other classes: refused, named.
  PreprocessOptions odd = short_o;
  odd.length = 20;
  Classifier other(Small(), 4, 20, classes);
  other.Save(dir + "/odd",
             {{"preprocessing", PreprocessingJson(long_o, {})}, {"input_preprocessing", PreprocessingJson(odd, {})}});
  EXPECT_THROW(TrajectoryClassifier::Load(dir + "/odd"), InputError);
  EXPECT_NE(ShorterWindowsProblem(windows, Prepared(tracks, odd, classes)).find("divide"), std::string::npos);
  PreprocessOptions gap = short_o;
  gap.max_gap_s = 5;
  EXPECT_NE(ShorterWindowsProblem(windows, Prepared(tracks, gap, classes)).find("max_gap_s"), std::string::npos);
  PreparedDataset renamed = shorter;
  renamed.classes = {"straight", "zigzag"};
  EXPECT_NE(ShorterWindowsProblem(windows, renamed).find("classes"), std::string::npos);
  // A damaged input preprocessing, or a dataset without its preprocessing: an error naming what is missing.
  network.Save(dir + "/broken", {{"preprocessing", PreprocessingJson(long_o, {})},
                                 {"input_preprocessing", {{"options_yaml", "length: 16\n"}}}});
  try {
    TrajectoryClassifier::Load(dir + "/broken");
    ADD_FAILURE() << "a model without input position bounds loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("input_preprocessing"), std::string::npos) << e.what();
  }
  PreparedDataset bare = shorter;
  bare.info = nlohmann::json::object();
  try {
    ShorterWindowsProblem(windows, bare);
    ADD_FAILURE() << "a dataset without preprocessing was compared";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shorter dataset carries no preprocessing"), std::string::npos) << e.what();
  }
}

// The model carries its preprocessing: a model saved with non-default options
// cuts and normalises new trajectories exactly as its training set was.
TEST(TrajectoryClassifierTest, CarriesItsPreprocessingAndCutsTheLatestWindow) {
  PreprocessOptions o;
  o.length = 32;
  o.max_gap_s = 0.5;
  o.features = {"x", "y", "speed", "turn_rate"};
  o.transform = "rotate_to_zero";
  const std::string dir = testing::TempDir("trajectory_classifier");
  Classifier c(Small(), 4, 32, {"straight", "weaving"});
  c.Save(dir + "/m", {{"preprocessing", PreprocessingJson(o, {-5, 5, -2, 2})}});
  const TrajectoryClassifier t = TrajectoryClassifier::Load(dir + "/m");
  EXPECT_EQ(t.preprocessing().max_gap_s, 0.5);
  EXPECT_EQ(t.preprocessing().features, o.features);
  EXPECT_EQ(t.preprocessing().transform, "rotate_to_zero");

  // 100 points, a 1 s gap before point 70: the latest piece has 30 points (≥ 80 % of
  // 32, so one padded window of 30); after a gap at point 90 only 10 (none).
  Trajectory track = Line("a", 100, 0.1, 1, 0);
  for (size_t i = 70; i < track.points.size(); ++i) track.points[i].t_s += 1.0;
  const auto w = t.LatestWindow(track);
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(w->valid, 30);
  EXPECT_DOUBLE_EQ(w->points.front().t_s, track.points[70].t_s);
  EXPECT_DOUBLE_EQ(w->points.back().t_s, track.points.back().t_s);
  for (size_t i = 90; i < track.points.size(); ++i) track.points[i].t_s += 1.0;
  EXPECT_FALSE(t.LatestWindow(track).has_value());
  EXPECT_FALSE(t.LatestWindow(Line("still", 40, 0.1, 0, 0)).has_value());  // stationary
  const auto p = t.Classify({*w});
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0] + p[1], 1.0, 1e-5);

  // With the forest beside it: the mean of both, the forest fed the window's
  // hand-crafted features exactly as at training.
  std::vector<float> hx;
  std::vector<int> hy;
  for (int i = 0; i < 40; ++i) {
    const Trajectory line = Line("f" + std::to_string(i), 32, 0.1, 0.5 + 0.1 * i, 0);
    const auto h = HandcraftedFeatures(Chunk(line, o)[0], {}, o.features);
    hx.insert(hx.end(), h.begin(), h.end());
    hy.push_back(i % 2);
  }
  ForestBaseline forest(21, 4, 1);
  forest.Train(hx, hy);
  forest.Save(dir + "/forest.yml");
  const TrajectoryClassifier both = TrajectoryClassifier::Load(dir + "/m", dir + "/forest.yml");
  EXPECT_EQ(both.combination(), "network+forest");
  EXPECT_EQ(t.combination(), "network");
  const auto trees = forest.Probabilities(HandcraftedFeatures(*w, {}, o.features), 2);
  const auto pb = both.Classify({*w});
  ASSERT_EQ(pb.size(), 2u);
  for (int c = 0; c < 2; ++c) EXPECT_NEAR(pb[c], 0.5 * (p[c] + trees[c]), 1e-6);
  EXPECT_THROW(TrajectoryClassifier::Load(dir + "/m", dir + "/no-forest.yml"), InputError);
  // A truncated or corrupted forest file is an error naming it, not a crash.
  const std::string text = testing::ReadFile(dir + "/forest.yml");
  testing::WriteFile(dir + "/truncated.yml", text.substr(0, text.size() / 2));
  testing::WriteFile(dir + "/corrupt.yml", "%YAML:1.0\nopencv_ml_rtrees: [1, 2\n");
  for (const char* bad : {"/truncated.yml", "/corrupt.yml"}) {
    try {
      TrajectoryClassifier::Load(dir + "/m", dir + bad);
      ADD_FAILURE() << bad << " loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }

  // A model without preprocessing, or with preprocessing that does not fit it.
  c.Save(dir + "/bare");
  EXPECT_THROW(TrajectoryClassifier::Load(dir + "/bare"), InputError);
  o.length = 60;
  c.Save(dir + "/misfit", {{"preprocessing", PreprocessingJson(o, {})}});
  EXPECT_THROW(TrajectoryClassifier::Load(dir + "/misfit"), InputError);
  c.Save(dir + "/badkey", {{"preprocessing", {{"options_yaml", "lenght: 32\n"}, {"position_bounds", {0, 1, 0, 1}}}}});
  EXPECT_THROW(TrajectoryClassifier::Load(dir + "/badkey"), InputError);
}

// The forest's probabilities are its trees' vote fractions: rows sum to one and their
// most probable class is the forest's own prediction (an odd number of trees on two
// classes: no ties). The combination is the mean, and sizes must agree.
TEST(ForestBaselineTest, VoteFractionsAgreeWithPredictAndCombine) {
  const int f = HandcraftedFeatureCount();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> x;
  std::vector<int> y;
  for (int i = 0; i < 300; ++i) {
    for (int j = 0; j < f; ++j) x.push_back(u(rng));
    y.push_back(x[static_cast<size_t>(i) * f] + 0.3f * u(rng) > 0.65f ? 1 : 0);  // noisy: not every vote unanimous
  }
  ForestBaseline forest(51, 6, 1);
  forest.Train(x, y);
  const std::vector<float> p = forest.Probabilities(x, 2);
  ASSERT_EQ(p.size(), 600u);
  const std::vector<int> predicted = forest.Predict(x);
  EXPECT_EQ(MostProbable(p, 2), predicted);
  int split_votes = 0;
  for (size_t i = 0; i < 300; ++i) {
    EXPECT_NEAR(p[2 * i] + p[2 * i + 1], 1.0, 1e-6);
    split_votes += p[2 * i] > 0 && p[2 * i + 1] > 0;
  }
  EXPECT_GT(split_votes, 10);  // fractions, not one-hot labels

  const std::vector<float> network = {0.9f, 0.1f, 0.2f, 0.8f};
  const std::vector<float> trees = {0.3f, 0.7f, 0.4f, 0.6f};
  const std::vector<float> both = CombinedProbabilities(network, trees);
  EXPECT_NEAR(both[0], 0.6, 1e-6);
  EXPECT_NEAR(both[3], 0.7, 1e-6);
  EXPECT_EQ(MostProbable(both, 2), (std::vector<int>{0, 1}));
  EXPECT_THROW(CombinedProbabilities(network, {0.5f, 0.5f}), InputError);
}

// The motion features on a window whose values are known by hand: 11 samples along
// +x at 2 m/s, reported every 2 s except for every fifth step, 10 s (AIS class B
// reports every 30 s, class A every 2–10 s: the percentiles of the time between
// samples tell transponders apart).
TEST(ForestBaselineTest, MotionFeaturesMatchHandComputedValues) {
  Window w;
  double t = 0;
  for (int i = 0; i <= 10; ++i) {
    if (i > 0) t += i % 5 == 0 ? 10.0 : 2.0;
    w.points.push_back({t, 2.0 * t, 0.0});
  }
  const std::vector<float> h = HandcraftedFeatures(w, {}, {});
  ASSERT_EQ(h.size(), static_cast<size_t>(HandcraftedFeatureCount()));
  EXPECT_FLOAT_EQ(h[0], 2.0f);    // speed mean
  EXPECT_FLOAT_EQ(h[1], 0.0f);    // speed std
  EXPECT_FLOAT_EQ(h[6], 0.0f);    // |acceleration| mean
  EXPECT_FLOAT_EQ(h[11], 0.0f);   // no stops
  EXPECT_FLOAT_EQ(h[12], 1.0f);   // straight
  EXPECT_FLOAT_EQ(h[13], 36.0f);  // duration: 8 × 2 s + 2 × 10 s
  EXPECT_FLOAT_EQ(h[14], 2.0f);   // interval 10th percentile
  EXPECT_FLOAT_EQ(h[15], 2.0f);   // median
  EXPECT_FLOAT_EQ(h[16], 10.0f);  // 90th percentile
}

// The baseline gets only the geography and category the network's features name:
// the last six handcrafted features are static distance mean and min, harbour
// distance mean, the region (x, y) and the object's category.
TEST(ForestBaselineTest, HandcraftedFeaturesUseOnlyNamedGeography) {
  MapFeatures map;
  map.distance_to_static = [](double, double) { return 1.0; };
  map.distance_to_poi = [](double, double) { return 2.0; };
  map.region = [](double, double) { return std::array<double, 2>{0.1, 0.2}; };
  PreprocessOptions o;
  o.length = 16;
  Trajectory t = Line("a", 16, 1.0, 0.5, 0);
  t.category = 227;
  const Window w = Chunk(t, o).at(0);
  auto named = [&](const std::vector<std::string>& features) {
    const auto h = HandcraftedFeatures(w, map, features);
    return std::vector<float>(h.end() - 6, h.end());
  };
  EXPECT_EQ(named({"x", "y", "speed"}), (std::vector<float>{0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(named({"x", "dist_poi", "region_y"}), (std::vector<float>{0, 0, 2, 0.1f, 0.2f, 0}));
  EXPECT_EQ(named({"dist_static", "dist_poi", "region_x"}), (std::vector<float>{1, 1, 2, 0.1f, 0.2f, 0}));
  EXPECT_EQ(named({"speed", "category"}), (std::vector<float>{0, 0, 0, 0, 0, 227}));
  // The motion features do not depend on the geography or category at all.
  const auto all = HandcraftedFeatures(w, map, {"dist_static", "category"}), none = HandcraftedFeatures(w, {}, {});
  EXPECT_EQ(std::vector<float>(all.begin(), all.end() - 6), std::vector<float>(none.begin(), none.end() - 6));
}

// The object's category reaches every window of every piece, and the feature is
// u = category / category_cap at each valid point (0 in the padding), followed by
// ½ + ½ sin and cos of 2π u, 2π 2u, … (category_frequencies pairs).
TEST(PreprocessTest, CategoryIsCarriedToEveryWindowAndScaled) {
  PreprocessOptions o;
  o.length = 8;
  o.min_fill = 0.5;
  o.max_gap_s = 5;
  o.features = {"speed", "category"};
  o.category_cap = 1000;
  o.category_frequencies = 2;
  ASSERT_EQ(FeatureRows(o), 6);
  Trajectory t = Line("a", 20, 1.0, 0.5, 0);
  for (size_t i = 14; i < t.points.size(); ++i) t.points[i].t_s += 100;  // a gap: two pieces
  t.category = 316;
  const std::vector<Window> windows = MakeWindows({t}, o);
  ASSERT_EQ(windows.size(), 3u);  // 14 points → 8 + 6, then 6
  for (const auto& w : windows) {
    EXPECT_EQ(w.category, 316);
    const std::vector<float> f = Features(w, o, {});
    ASSERT_EQ(f.size(), 6u * o.length);
    const double u = 0.316;
    const std::vector<double> rows = {u, 0.5 + 0.5 * std::sin(2 * M_PI * u), 0.5 + 0.5 * std::cos(2 * M_PI * u),
                                      0.5 + 0.5 * std::sin(4 * M_PI * u), 0.5 + 0.5 * std::cos(4 * M_PI * u)};
    for (size_t r = 0; r < rows.size(); ++r)
      for (int i = 0; i < o.length; ++i)
        EXPECT_FLOAT_EQ(f[(1 + r) * o.length + i], i < w.valid ? static_cast<float>(rows[r]) : 0.0f) << r << " " << i;
  }
  // Codes outside [0, category_cap] are clamped to its ends: u = 1 or 0, and the
  // pairs are those of u (sin 2πu = 0 at both ends, cos 2πu = 1).
  for (int code : {1500, -3}) {
    Window w = windows[0];
    w.category = code;
    const std::vector<float> f = Features(w, o, {});
    const float u = code > 0 ? 1.0f : 0.0f;
    for (int r = 1; r <= 5; ++r) {
      const float expected = r == 1 ? u : r % 2 == 0 ? 0.5f : 1.0f;
      EXPECT_NEAR(f[static_cast<size_t>(r) * o.length], expected, 1e-6) << code << " row " << r;
    }
  }
}

// "heading" is the course as ½ + ½ sin and ½ + ½ cos (two rows). Steps at 350°,
// 350°, 10° (course from +x, counter-clockwise) cross the 0/360 seam: "course"
// jumps from 0.97 to 0.03 there, heading moves by 0.17 (the reason a network gets
// heading).
TEST(PreprocessTest, HeadingIsTheCourseOnTheCircle) {
  PreprocessOptions o;
  o.length = 4;
  o.features = {"course", "heading"};
  o.stationary_threshold = 0;
  ASSERT_EQ(FeatureRows(o), 3);
  const double course_deg[] = {350, 350, 10};
  Trajectory t;
  t.object_id = "seam";
  t.points.push_back({0, 0, 0});
  for (int i = 0; i < 3; ++i) {
    const double a = course_deg[i] * M_PI / 180;
    const auto& last = t.points.back();
    t.points.push_back({i + 1.0, last.x + std::cos(a), last.y + std::sin(a)});
  }
  const std::vector<Window> windows = MakeWindows({t}, o);
  ASSERT_EQ(windows.size(), 1u);
  const std::vector<float> f = Features(windows[0], o, {});
  ASSERT_EQ(f.size(), 3u * o.length);
  for (int i = 1; i < 4; ++i) {
    const double a = course_deg[i - 1] * M_PI / 180;
    EXPECT_NEAR(f[i], a / (2 * M_PI), 1e-5) << i;
    EXPECT_NEAR(f[o.length + i], 0.5 + 0.5 * std::sin(a), 1e-5) << i;
    EXPECT_NEAR(f[2 * o.length + i], 0.5 + 0.5 * std::cos(a), 1e-5) << i;
  }
  EXPECT_GT(f[2] - f[3], 0.9);            // course jumps across the seam
  EXPECT_LT(std::abs(f[6] - f[7]), 0.2);  // sin moves a little
  EXPECT_NEAR(f[10], f[11], 1e-5);        // cos(350°) = cos(10°)
}

// A prepared dataset reads back as written; a truncated or corrupted file, a
// handcrafted.npy of another width (an older version's 19 features) or row count,
// and a windows.csv with a row missing are refused with the file named.
TEST(DatasetIoTest, RoundTripsAndRefusesDamagedFiles) {
  PreparedDataset d;
  d.windows.features = 2, d.windows.length = 3;
  d.classes = {"a", "b"};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 6; ++j) d.windows.x.push_back(0.1f * (i * 6 + j));
    d.windows.y.push_back(i % 2);
    d.windows.object_ids.push_back("obj" + std::to_string(i / 2));
    d.labels.push_back(d.classes[i % 2]);
    d.t0_s.push_back(1444565687.25 + 600 * i), d.t1_s.push_back(d.t0_s.back() + 590.5);
    for (int j = 0; j < HandcraftedFeatureCount(); ++j) d.handcrafted.push_back(static_cast<float>(i * 100 + j));
  }
  const std::string dir = testing::TempDir("dataset_io");
  WritePrepared(d, dir);
  const PreparedDataset r = ReadPrepared(dir);
  EXPECT_EQ(r.windows.x, d.windows.x);
  EXPECT_EQ(r.windows.y, d.windows.y);
  EXPECT_EQ(r.windows.object_ids, d.windows.object_ids);
  EXPECT_EQ(r.handcrafted, d.handcrafted);
  EXPECT_EQ(r.t0_s, d.t0_s);  // to the millisecond, which these are
  EXPECT_EQ(r.t1_s, d.t1_s);
  EXPECT_TRUE(HasSpans(r));
  EXPECT_EQ(HandcraftedRows(r, {3}),
            std::vector<float>(d.handcrafted.end() - HandcraftedFeatureCount(), d.handcrafted.end()));

  auto refused = [&](const std::string& file, const std::string& bytes, const std::string& says) {
    const std::string good = testing::ReadFile(dir + "/" + file);
    testing::WriteFile(dir + "/" + file, bytes);
    try {
      ReadPrepared(dir);
      ADD_FAILURE() << file << ": accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(file)) << e.what();
      EXPECT_THAT(e.what(), ::testing::HasSubstr(says)) << e.what();
    }
    testing::WriteFile(dir + "/" + file, good);
  };
  const std::string windows = testing::ReadFile(dir + "/windows.npy");
  refused("windows.npy", windows.substr(0, windows.size() - 5), "windows.npy");
  refused("windows.npy", "not numpy at all", "windows.npy");
  std::vector<float> old_width(4 * 19, 0.0f);
  WriteNpy(dir + "/old.npy", old_width, {4, 19});
  refused("handcrafted.npy", testing::ReadFile(dir + "/old.npy"), "prepare it again");
  std::vector<float> fewer_rows(static_cast<size_t>(3) * HandcraftedFeatureCount(), 0.0f);
  WriteNpy(dir + "/fewer.npy", fewer_rows, {3, static_cast<size_t>(HandcraftedFeatureCount())});
  refused("handcrafted.npy", testing::ReadFile(dir + "/fewer.npy"), "expected 4 windows");
  const std::string csv = testing::ReadFile(dir + "/windows.csv");
  refused("windows.csv", csv.substr(0, csv.rfind('\n', csv.size() - 2) + 1), "3 rows");
  refused("windows.csv", "index,object_id,label\n0;obj0;a\n", "need index,object_id,label");
  refused("windows.csv", "idx,object,label\n", ":1: the header");
  const std::string header = "index,object_id,label,t0_s,t1_s\n";
  refused("windows.csv", header + "0,obj0,a,100.0\n", "windows.csv:2: 4 fields");
  refused("windows.csv", header + "0,obj0,a,100.0,9x\n", "windows.csv:2: t0_s, t1_s");
  refused("windows.csv", header + "0,obj0,a,100.0,99.0\n", "windows.csv:2: t0_s, t1_s");
  refused("dataset.json", "{\"classes\": ", "dataset.json");
  EXPECT_NO_THROW(ReadPrepared(dir));  // every damaged file was put back

  // A dataset of an older version (no spans) reads, without spans, and is written so.
  std::string old_csv = "index,object_id,label\n";
  for (int i = 0; i < 4; ++i)
    old_csv += std::to_string(i) + ",obj" + std::to_string(i / 2) + "," + d.classes[i % 2] + "\n";
  testing::WriteFile(dir + "/windows.csv", old_csv);
  const PreparedDataset old = ReadPrepared(dir);
  EXPECT_EQ(old.windows.object_ids, d.windows.object_ids);
  EXPECT_FALSE(HasSpans(old));
  WritePrepared(old, dir);
  EXPECT_EQ(testing::ReadFile(dir + "/windows.csv"), old_csv);
}

// WindowsWithin: the shorter windows of the same object inside a window's span;
// where the stationary filter left none inside, the overlapping ones; else none.
TEST(CrossValidationTest, WindowsWithinAreTheSameObjectsShorterWindowsInTheSpan) {
  PreparedDataset longer, shorter;
  auto add = [](PreparedDataset& d, const std::string& id, double t0, double t1) {
    d.windows.object_ids.push_back(id), d.windows.y.push_back(0), d.labels.push_back("a");
    d.t0_s.push_back(t0), d.t1_s.push_back(t1);
  };
  add(longer, "v1", 0, 100), add(longer, "v1", 110, 200), add(longer, "v2", 0, 100), add(longer, "v3", 0, 100);
  add(shorter, "v1", 0, 40), add(shorter, "v1", 50, 100), add(shorter, "v2", 0, 50);  // 0–2
  add(shorter, "v1", 90, 130);   // 3: overlaps both of v1's, within neither
  add(shorter, "v2", 80, 120);   // 4: overlaps v2's
  add(shorter, "v1", 300, 340);  // 5: within none
  add(shorter, "v4", 0, 40);     // 6: an object with no longer window
  const auto within = WindowsWithin(longer, shorter);
  ASSERT_EQ(within.size(), 4u);
  EXPECT_EQ(within[0], (std::vector<size_t>{0, 1}));
  EXPECT_EQ(within[1], (std::vector<size_t>{3}));  // none inside: the overlapping one
  EXPECT_EQ(within[2], (std::vector<size_t>{2}));  // the inside one only
  EXPECT_TRUE(within[3].empty());
  shorter.t0_s.pop_back();
  EXPECT_THROW(WindowsWithin(longer, shorter), InputError);
}

TEST(SplitTest, DisjointByObject) {
  std::vector<std::string> ids;
  for (int i = 0; i < 200; ++i) ids.push_back("obj" + std::to_string(i / 4));  // 4 windows per object
  std::vector<size_t> kept, held;
  SplitByObject(ids, 0.25, 1, kept, held);
  std::set<std::string> a, b;
  for (size_t i : kept) a.insert(ids[i]);
  for (size_t i : held) b.insert(ids[i]);
  for (const auto& id : b) EXPECT_EQ(a.count(id), 0u);
  EXPECT_NEAR(static_cast<double>(held.size()) / ids.size(), 0.25, 0.12);
}

// Two classes "a" and "b", 40 objects of 3 windows (1 feature × 2 points, all 0);
// every handcrafted feature is the class index plus N(0, 1) noise.
PreparedDataset TwoClassDataset() {
  PreparedDataset d;
  d.classes = {"a", "b"};
  d.windows.features = 1, d.windows.length = 2;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 1);
  for (int object = 0; object < 40; ++object) {
    const int label = object % 2;
    for (int w = 0; w < 3; ++w) {
      d.windows.x.insert(d.windows.x.end(), {0.0f, 0.0f});
      d.windows.y.push_back(label);
      d.windows.object_ids.push_back("o" + std::to_string(object));
      d.labels.push_back(d.classes[static_cast<size_t>(label)]);
      for (int j = 0; j < HandcraftedFeatureCount(); ++j) d.handcrafted.push_back(label + noise(rng));
    }
  }
  return d;
}

// The distillation teacher is out of fold: where each object's features are its own
// (a random value, unrelated to its class) a forest remembers its training objects
// but cannot tell an unseen one, so out of fold it is near chance; where the features
// carry the class it is right (features = class + N(0, 1): about 0.94, as the
// trees see the rows in another order). Rows come back in the order asked, summing to 1.
TEST(CrossValidationTest, OutOfFoldForestNeverSawTheRowsObject) {
  const PreparedDataset separable = TwoClassDataset();
  PreparedDataset memorised = separable;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> value(0, 1);
  const auto width = static_cast<size_t>(HandcraftedFeatureCount());
  for (size_t i = 0; i < memorised.windows.size(); i += 3) {
    const float v = value(rng);  // the object's own value, in all of its 3 windows
    std::fill_n(memorised.handcrafted.begin() + static_cast<long>(i * width), 3 * width, v);
  }
  std::vector<size_t> all(separable.windows.size());
  std::iota(all.begin(), all.end(), 0);
  auto accuracy = [](const std::vector<float>& p, const std::vector<int>& y) {
    double right = 0;
    for (size_t i = 0; i < y.size(); ++i) right += (p[2 * i + 1] > p[2 * i]) == (y[i] == 1);
    return right / static_cast<double>(y.size());
  };
  const std::vector<float> p = OutOfFoldForest(separable, all, 1);
  ASSERT_EQ(p.size(), 2 * all.size());
  for (size_t i = 0; i < all.size(); ++i) EXPECT_NEAR(p[2 * i] + p[2 * i + 1], 1.0f, 1e-5f);
  EXPECT_GT(accuracy(p, separable.windows.y), 0.85);

  ForestBaseline remembers(200, 12, 1);
  remembers.Train(memorised.handcrafted, memorised.windows.y);
  EXPECT_GT(accuracy(remembers.Probabilities(memorised.handcrafted, 2), memorised.windows.y), 0.95);
  EXPECT_LT(accuracy(OutOfFoldForest(memorised, all, 1), memorised.windows.y), 0.7);

  const std::vector<size_t> reversed(all.rbegin(), all.rend());
  const std::vector<float> back = OutOfFoldForest(separable, reversed, 1);
  std::vector<int> reversed_y(separable.windows.y.rbegin(), separable.windows.y.rend());
  EXPECT_GT(accuracy(back, reversed_y), 0.85);
}

// Training on shorter windows (train_on): a scored window is classified from the
// models' answers on the shorter windows within it. Where those carry the class
// (class + N(0, 1), as TwoClassDataset) the forest is right on most; where each
// object's short windows carry only a value of its own, a forest that saw a tested
// object's windows would recognise it, so a score near chance shows that none of a
// tested object's windows trained — not even the one outside its scored window.
// Objects with only short windows train in every fold; the folds are the scored
// dataset's (the same as a plain run's), and so is the t-test's ρ.
TEST(CrossValidationTest, TrainingOnShorterWindowsNeverSeesATestedObject) {
  PreparedDataset scored = TwoClassDataset();
  const PreparedDataset plain = scored;
  for (size_t i = 0; i < scored.windows.size(); ++i)
    scored.t0_s.push_back(1000.0 * i), scored.t1_s.push_back(1000.0 * i + 900);
  auto shorter = [&](bool memorised) {
    PreparedDataset d;
    d.classes = scored.classes;
    d.windows.features = 1, d.windows.length = 1;
    std::mt19937 rng(5);
    std::normal_distribution<float> noise(0, 1);
    std::uniform_real_distribution<float> value(0, 1);
    const auto width = static_cast<size_t>(HandcraftedFeatureCount());
    std::map<std::string, float> own;
    auto add = [&](const std::string& id, int y, double t0) {
      d.windows.x.push_back(0.0f), d.windows.y.push_back(y), d.windows.object_ids.push_back(id);
      d.labels.push_back(d.classes[static_cast<size_t>(y)]), d.t0_s.push_back(t0), d.t1_s.push_back(t0 + 100);
      if (!own.count(id)) own[id] = value(rng);
      for (size_t j = 0; j < width; ++j) d.handcrafted.push_back(memorised ? own[id] : y + noise(rng));
    };
    for (size_t i = 0; i < scored.windows.size(); ++i)
      for (int k = 0; k < 3; ++k) add(scored.windows.object_ids[i], scored.windows.y[i], scored.t0_s[i] + 300 * k);
    for (size_t i = 0; i < scored.windows.size(); i += 3)  // after the object's scored windows: within none
      add(scored.windows.object_ids[i], scored.windows.y[i], 1e7);
    for (int extra = 0; extra < 10; ++extra) add("short-only" + std::to_string(extra), extra % 2, 0);
    return d;
  };
  CrossValidationOptions o;
  o.folds = 4, o.seed = 2;
  const CrossValidationResult reference = CrossValidate(plain, o);
  const PreparedDataset separable = shorter(false), memorised = shorter(true);
  o.train_on = &separable;
  const CrossValidationResult learns = CrossValidate(scored, o);
  EXPECT_GT(learns.pooled.at("forest").macro_f1, 0.9);
  EXPECT_EQ(learns.fold_of, reference.fold_of);
  EXPECT_EQ(learns.FoldSizes(), reference.FoldSizes());
  o.train_on = &memorised;
  EXPECT_LT(CrossValidate(scored, o).pooled.at("forest").macro_f1, 0.7);

  PreparedDataset other_classes = separable;
  other_classes.classes = {"b", "a"};
  o.train_on = &other_classes;
  EXPECT_THROW(CrossValidate(scored, o), InputError);
  o.train_on = &separable, o.train_fraction = 0.5;
  EXPECT_THROW(CrossValidate(scored, o), InputError);
}

// Fine-tuning after training on shorter windows: where only the scored (longer)
// windows carry the class in their values and the shorter ones carry nothing, the
// network alone is at chance on the shorter windows' mean and right once tuned on
// the scored training windows; the forest (no tuning) stays as it was. Fine-tuning
// needs train_on and a rate in [0, 1).
TEST(CrossValidationTest, FineTunedNetworkScoresTheLongerWindowsItself) {
  PreparedDataset scored = TwoClassDataset();
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0, 0.3f);
  for (size_t i = 0; i < scored.windows.size(); ++i) {
    scored.t0_s.push_back(1000.0 * i), scored.t1_s.push_back(1000.0 * i + 900);
    for (int t = 0; t < 2; ++t) scored.windows.x[2 * i + t] = 2.0f * scored.windows.y[i] - 1 + noise(rng);
  }
  PreparedDataset shorter;
  shorter.classes = scored.classes;
  shorter.windows.features = 1, shorter.windows.length = 1;
  for (size_t i = 0; i < scored.windows.size(); ++i) {
    const int y = scored.windows.y[i];
    shorter.windows.x.push_back(noise(rng)), shorter.windows.y.push_back(y);
    shorter.windows.object_ids.push_back(scored.windows.object_ids[i]);
    shorter.labels.push_back(scored.labels[i]), shorter.t0_s.push_back(scored.t0_s[i] + 100);
    shorter.t1_s.push_back(scored.t0_s[i] + 200);
    shorter.handcrafted.insert(shorter.handcrafted.end(), scored.handcrafted.begin() + i * HandcraftedFeatureCount(),
                               scored.handcrafted.begin() + (i + 1) * HandcraftedFeatureCount());
  }
  CrossValidationOptions o;
  o.folds = 3, o.seed = 2;
  ModelOptions m = Small();
  m.epochs = 15, m.batch_size = 16, m.class_weights = false;
  o.networks = {{"tiny", m}};
  o.train_on = &shorter;
  const CrossValidationResult mean_within = CrossValidate(scored, o);
  o.fine_tune_learning_rate = 3e-3;
  const CrossValidationResult tuned = CrossValidate(scored, o);
  EXPECT_LT(mean_within.pooled.at("tiny").macro_f1, 0.7);
  EXPECT_GT(tuned.pooled.at("tiny").macro_f1, 0.9);
  EXPECT_EQ(tuned.pooled.at("forest").macro_f1, mean_within.pooled.at("forest").macro_f1);
  for (double rate : {1.0, -1e-4}) {  // out of [0, 1)
    o.fine_tune_learning_rate = rate;
    EXPECT_THROW(CrossValidate(scored, o), InputError);
  }
  o.fine_tune_learning_rate = 3e-3, o.train_on = nullptr;
  EXPECT_THROW(CrossValidate(scored, o), InputError);
}

// Repeated cross-validation: repeat r is exactly the single run with seed + r, and
// the report holds every repeat's folds and each repeat's mean.
TEST(CrossValidationTest, RepeatRIsTheRunWithSeedPlusR) {
  const PreparedDataset d = TwoClassDataset();
  CrossValidationOptions o;
  o.folds = 3, o.repeats = 2, o.seed = 4;
  // The log's fraction done (forest only: one unit a fold) after each of the six folds.
  std::vector<double> fractions;
  const CrossValidationResult both = CrossValidate(d, o, [&](const std::string&, double f) { fractions.push_back(f); });
  ASSERT_EQ(fractions.size(), 6u);
  for (size_t i = 0; i < fractions.size(); ++i) EXPECT_NEAR(fractions[i], (i + 1) / 6.0, 1e-12);
  // Every fold and repeat has its test and training window counts (the t-test's ρ).
  const auto sizes = both.FoldSizes();
  ASSERT_EQ(sizes.size(), 6u);
  for (size_t slot = 0; slot < sizes.size(); ++slot) {
    const auto first = both.fold_of.begin() + static_cast<long>((slot / 3) * d.windows.size());
    const long tested = std::count(first, first + static_cast<long>(d.windows.size()), static_cast<int>(slot % 3));
    EXPECT_EQ(sizes[slot].first, tested) << slot;
    EXPECT_EQ(sizes[slot].second, 120 - tested) << slot;
  }
  o.repeats = 1, o.seed = 5;
  const CrossValidationResult second = CrossValidate(d, o);
  ASSERT_EQ(both.per_fold.size(), 6u);
  ASSERT_EQ(both.fold_of.size(), 2 * d.windows.size());
  EXPECT_EQ(std::vector<int>(both.fold_of.begin() + static_cast<long>(d.windows.size()), both.fold_of.end()),
            second.fold_of);
  EXPECT_NE(std::vector<int>(both.fold_of.begin(), both.fold_of.begin() + static_cast<long>(d.windows.size())),
            second.fold_of);  // another deal
  const std::vector<float>& p = both.probabilities.at("forest");
  EXPECT_EQ(std::vector<float>(p.begin() + static_cast<long>(p.size() / 2), p.end()),
            second.probabilities.at("forest"));
  const nlohmann::json j = both.ToJson(d.classes), one = second.ToJson(d.classes);
  ASSERT_EQ(j["forest"]["folds"].size(), 6u);
  ASSERT_EQ(j["forest"]["repeats"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["forest"]["repeats"][1]["macro_f1"].get<double>(),
                   one["forest"]["macro_f1"]["mean"].get<double>());
  EXPECT_GT(one["forest"]["macro_f1"]["mean"].get<double>(), 0.9);  // the label is in every feature
  o.repeats = 0;
  EXPECT_THROW(CrossValidate(d, o), InputError);
}

// A learning curve's subsample: each class keeps ⌈fraction · n⌉ of its objects (at
// least one) with all their windows, smaller fractions keep subsets, and the seed
// decides which.
TEST(CrossValidationTest, SubsampleKeepsAShareOfEachClassNested) {
  std::vector<std::string> ids;
  std::vector<int> labels;
  std::vector<size_t> rows;
  for (int object = 0; object < 43; ++object)  // class 0: 40 objects, class 1: 3
    for (int w = 0; w < 3; ++w) {
      rows.push_back(ids.size());
      ids.push_back("o" + std::to_string(object));
      labels.push_back(object < 40 ? 0 : 1);
    }
  auto objects_per_class = [&](const std::vector<size_t>& kept) {
    std::set<std::string> per_class[2];
    for (size_t i : kept) per_class[labels[i]].insert(ids[i]);
    EXPECT_EQ(kept.size(), 3 * (per_class[0].size() + per_class[1].size()));  // whole objects
    return std::vector<std::set<std::string>>{per_class[0], per_class[1]};
  };
  const auto quarter = objects_per_class(SubsampleObjects(ids, labels, rows, 0.25, 1));
  const auto half = objects_per_class(SubsampleObjects(ids, labels, rows, 0.5, 1));
  EXPECT_EQ(quarter[0].size(), 10u);
  EXPECT_EQ(quarter[1].size(), 1u);  // ⌈0.75⌉
  EXPECT_EQ(half[0].size(), 20u);
  EXPECT_EQ(half[1].size(), 2u);  // ⌈1.5⌉
  for (int c = 0; c < 2; ++c)
    for (const auto& id : quarter[c]) EXPECT_EQ(half[c].count(id), 1u) << id;  // nested
  EXPECT_EQ(SubsampleObjects(ids, labels, rows, 1.0, 1), rows);
  EXPECT_EQ(objects_per_class(SubsampleObjects(ids, labels, rows, 0.01, 1))[1].size(), 1u);  // never empty
  EXPECT_NE(objects_per_class(SubsampleObjects(ids, labels, rows, 0.5, 2))[0], half[0]);
  EXPECT_THROW(SubsampleObjects(ids, labels, rows, 0.0, 1), InputError);
  EXPECT_THROW(SubsampleObjects(ids, labels, rows, 1.5, 1), InputError);
}

// A run on half of each fold's training objects tests the same windows as the run
// on all of them, records the smaller training sets (the t-test's ρ), and compares
// with the full run fold by fold.
TEST(CrossValidationTest, TrainFractionKeepsTheTestFolds) {
  const PreparedDataset d = TwoClassDataset();
  CrossValidationOptions o;
  o.folds = 4;
  const CrossValidationResult all = CrossValidate(d, o);
  o.train_fraction = 0.5;
  const CrossValidationResult half = CrossValidate(d, o);
  EXPECT_EQ(half.fold_of, all.fold_of);
  const auto sizes = half.FoldSizes(), full = all.FoldSizes();
  ASSERT_EQ(sizes.size(), 4u);
  for (size_t f = 0; f < sizes.size(); ++f) {
    EXPECT_EQ(sizes[f].first, full[f].first);
    // 30 training objects of 3 windows, 15 of each class: 8 of each kept.
    EXPECT_EQ(full[f].second, 90);
    EXPECT_EQ(sizes[f].second, 48);
    EXPECT_EQ(half.trained_objects[f], (std::vector<long>{8, 8}));
    EXPECT_EQ(all.trained_objects[f], (std::vector<long>{15, 15}));
  }
  EXPECT_GT(half.per_fold[0].at("forest").macro_f1, 0.8);  // the label is in every feature
  const nlohmann::json earlier = {{"fold_windows", full}, {"models", all.ToJson(d.classes)}};
  const auto compared = CompareWithEarlier(half, earlier, "full/report.json");
  ASSERT_EQ(compared.size(), 1u);
  EXPECT_EQ(compared[0].b, "forest (earlier)");
  EXPECT_EQ(compared[0].folds, 4);
  o.folds = 5;  // other folds test other windows: refused
  EXPECT_THROW(CompareWithEarlier(CrossValidate(d, o), earlier, "full/report.json"), InputError);
  o.train_fraction = 0;
  EXPECT_THROW(CrossValidate(d, o), InputError);
}

// Two models "a" and "b" scored on three folds (macro F1 0.8 / 0.6 / 0.7 and
// 0.7 / 0.7 / 0.5) of 25 windows: 10, 10 and 5 tested, so 15, 15 and 20 trained on.
CrossValidationResult ThreeFoldResult() {
  CrossValidationResult r;
  r.models = {"a", "b"};
  r.folds = 3;
  const double a[] = {0.8, 0.6, 0.7}, b[] = {0.7, 0.7, 0.5};
  for (int f = 0; f < 3; ++f) {
    r.per_fold.emplace_back();
    r.per_fold.back()["a"].macro_f1 = a[f];
    r.per_fold.back()["b"].macro_f1 = b[f];
  }
  r.fold_of.assign(10, 0);
  r.fold_of.resize(20, 1);
  r.fold_of.resize(25, 2);
  return r;
}

// Fold-by-fold differences, worked by hand: d = 0.1, −0.1, 0.2 → mean 1/15,
// sd √((1/30² + 5/30² + 4/30²)/2) = √(7/300), ahead in 2 folds, behind in 1.
TEST(CrossValidationTest, PairedComparisonIsFoldByFold) {
  CrossValidationResult r = ThreeFoldResult();
  const PairedComparison c = r.Compare("a", "b");
  EXPECT_NEAR(c.mean_difference, 1.0 / 15, 1e-12);
  EXPECT_NEAR(c.std_difference, std::sqrt(7.0 / 300), 1e-12);
  EXPECT_EQ(c.ahead, 2);
  EXPECT_EQ(c.behind, 1);
  EXPECT_EQ(c.folds, 3);
  const std::vector<PairedComparison> all = r.PairedComparisons();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].a, "a");
  EXPECT_EQ(all[0].b, "b");
  EXPECT_EQ(all[0].ahead, 2);
  const nlohmann::json j = PairedComparisonsJson(all);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j["a vs b"]["folds_ahead"], 2);
  EXPECT_NEAR(j["a vs b"]["macro_f1_difference"]["mean"].get<double>(), 1.0 / 15, 1e-12);
  EXPECT_NEAR(r.Compare("b", "a").mean_difference, -1.0 / 15, 1e-12);
}

// The corrected resampled t-test worked by hand on the folds above: ρ = (10/15 +
// 10/15 + 5/20) / 3 = 19/36, σ² = (1/3 + 19/36) · 7/300 = 217/10800, t = (1/15) / σ
// = 0.47032; with 2 degrees of freedom P(|T| > t) = 1 − t / √(2 + t²) = 0.68443,
// and t_0.975,2 = 4.30265 (tables) gives the interval 1/15 ± 4.30265 σ.
TEST(CrossValidationTest, CorrectedResampledTTestWorkedByHand) {
  CrossValidationResult r = ThreeFoldResult();
  const PairedComparison c = r.Compare("a", "b");
  const double sigma = std::sqrt(217.0 / 10800);
  EXPECT_NEAR(c.corrected_t, (1.0 / 15) / sigma, 1e-9);
  EXPECT_NEAR(c.corrected_t, 0.47032, 1e-5);
  EXPECT_NEAR(c.p_value, 1 - c.corrected_t / std::sqrt(2 + c.corrected_t * c.corrected_t), 1e-9);
  EXPECT_NEAR(c.p_value, 0.68443, 1e-5);
  EXPECT_NEAR(c.interval_low, 1.0 / 15 - 4.30265 * sigma, 1e-5);
  EXPECT_NEAR(c.interval_high, 1.0 / 15 + 4.30265 * sigma, 1e-5);
  // Symmetric: b against a has the same p and the mirrored interval.
  const PairedComparison m = r.Compare("b", "a");
  EXPECT_NEAR(m.p_value, c.p_value, 1e-12);
  EXPECT_NEAR(m.interval_low, -c.interval_high, 1e-12);
  const nlohmann::json j = PairedComparisonsJson({c});
  EXPECT_NEAR(j["a vs b"]["corrected_t_test"]["p_value"].get<double>(), c.p_value, 1e-12);
  EXPECT_NEAR(j["a vs b"]["corrected_t_test"]["interval_95"][1].get<double>(), c.interval_high, 1e-12);

  // The same difference in every fold: no spread, so the interval is the point and p is 0.
  for (auto& per : r.per_fold) per["b"].macro_f1 = per["a"].macro_f1 - 0.05;
  const PairedComparison same = r.Compare("a", "b");
  EXPECT_NEAR(same.interval_low, 0.05, 1e-12);
  EXPECT_NEAR(same.interval_high, 0.05, 1e-12);
  EXPECT_EQ(same.p_value, 0.0);
  // Identical models: no difference, p = 1.
  EXPECT_EQ(r.Compare("a", "a").p_value, 1.0);
  // No fold assignment, a fold without training windows, a fold that does not exist: refused.
  r.fold_of.clear();
  EXPECT_THROW(r.Compare("a", "b"), InputError);
  r.fold_of.assign(25, 0);  // one fold holds every window: nothing to train on
  EXPECT_THROW(r.Compare("a", "b"), InputError);
  r.fold_of[3] = 7;  // a fold that does not exist
  EXPECT_THROW(r.Compare("a", "b"), InputError);
}

// A run against an earlier run on the same folds: each model with its earlier self.
TEST(CrossValidationTest, ComparedWithAnEarlierRunOnTheSameFolds) {
  const CrossValidationResult r = ThreeFoldResult();
  nlohmann::json earlier = {{"fold_windows", {{10, 15}, {10, 15}, {5, 20}}}};
  // The earlier "a" scored b's figures, and it had a model this run has not.
  for (double f1 : {0.7, 0.7, 0.5}) earlier["models"]["a"]["folds"].push_back({{"macro_f1", f1}});
  earlier["models"]["gone"]["folds"] = nlohmann::json::array();
  const auto c = CompareWithEarlier(r, earlier, "old/report.json");
  ASSERT_EQ(c.size(), 1u);  // "b" is not in the earlier run
  EXPECT_EQ(c[0].a, "a");
  EXPECT_EQ(c[0].b, "a (earlier)");
  const PairedComparison same_as = r.Compare("a", "b");
  EXPECT_NEAR(c[0].mean_difference, same_as.mean_difference, 1e-12);
  EXPECT_NEAR(c[0].p_value, same_as.p_value, 1e-12);

  // Other folds, a malformed report, nothing in common: refused, naming the report.
  auto refused = [&](const nlohmann::json& j, const std::string& says) {
    try {
      CompareWithEarlier(r, j, "old/report.json");
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("old/report.json")) << e.what();
      EXPECT_THAT(e.what(), ::testing::HasSubstr(says)) << e.what();
    }
  };
  nlohmann::json other = earlier;
  other["fold_windows"][2] = {6, 19};
  refused(other, "fold_windows");
  other.erase("fold_windows");
  refused(other, "fold_windows");
  other = earlier;
  other["models"]["a"]["folds"].push_back({{"macro_f1", 0.5}});  // four folds against three
  refused(other, "folds");
  other = earlier;
  other["models"]["a"]["folds"][1] = {{"f1", 0.7}};
  refused(other, "models.a.folds");
  other = earlier;
  other["models"].erase("a");
  refused(other, "none of this run's models");
}

// Per object the same folds are compared by the objects' macro F1, and the t-test's
// ρ counts objects: 4, 4 and 2 tested against 8 trained on each, ρ = (1/2 + 1/2 +
// 1/4) / 3 = 5/12 (the windows' ρ above is 19/36).
TEST(CrossValidationTest, ObjectLevelComparisonCountsObjects) {
  CrossValidationResult r = ThreeFoldResult();
  const double a[] = {0.9, 0.5, 0.6}, b[] = {0.6, 0.6, 0.6};
  const std::vector<long> support[] = {{2, 2}, {2, 2}, {1, 1}};
  for (int f = 0; f < 3; ++f) {
    r.per_fold_objects.emplace_back();
    r.per_fold_objects.back()["a"].macro_f1 = a[f];
    r.per_fold_objects.back()["a"].support = support[f];
    r.per_fold_objects.back()["b"].macro_f1 = b[f];
    r.trained_objects.push_back({4, 4});
  }
  const std::vector<std::pair<long, long>> objects = {{4, 8}, {4, 8}, {2, 8}};
  EXPECT_EQ(r.FoldSizes(ScoreLevel::kObject), objects);
  EXPECT_EQ(r.MacroF1PerFold("a", ScoreLevel::kObject), (std::vector<double>{0.9, 0.5, 0.6}));
  const PairedComparison c = r.Compare("a", "b", ScoreLevel::kObject);
  EXPECT_NEAR(c.mean_difference, 0.2 / 3, 1e-12);
  EXPECT_EQ(c.ahead, 1);
  EXPECT_EQ(c.behind, 1);
  const double sigma = std::sqrt((1.0 / 3 + 5.0 / 12) * c.std_difference * c.std_difference);
  EXPECT_NEAR(c.corrected_t, c.mean_difference / sigma, 1e-9);
  // The window level is untouched by the object scores.
  EXPECT_NEAR(r.Compare("a", "b").mean_difference, 1.0 / 15, 1e-12);
  EXPECT_EQ(PairedKey(ScoreLevel::kObject), "paired_per_object");
  EXPECT_EQ(PairedKey(ScoreLevel::kWindow), "paired");

  // Against an earlier run that trained on fewer objects in fold 1: that fold's
  // smaller training set counts (the larger ρ).
  nlohmann::json earlier = {{"fold_windows", {{10, 15}, {10, 15}, {5, 20}}},
                            {"fold_objects_trained", {{2, 2}, {4, 4}, {4, 4}}}};
  for (double f1 : b) earlier["models"]["a"]["per_object"]["folds"].push_back({{"macro_f1", f1}});
  const auto against = CompareWithEarlier(r, earlier, "old/report.json", ScoreLevel::kObject);
  ASSERT_EQ(against.size(), 1u);
  const PairedComparison expected =
      CompareFolds("a", "a (earlier)", {0.9, 0.5, 0.6}, {0.6, 0.6, 0.6}, {{4, 4}, {4, 8}, {2, 8}});
  EXPECT_NEAR(against[0].mean_difference, expected.mean_difference, 1e-12);
  EXPECT_NEAR(against[0].p_value, expected.p_value, 1e-12);
  EXPECT_GT(against[0].p_value, c.p_value);      // the wider interval
  earlier["fold_objects_trained"][1] = "eight";  // corrupted: not counts per class
  EXPECT_THROW(CompareWithEarlier(r, earlier, "old/report.json", ScoreLevel::kObject), InputError);
  earlier["fold_objects_trained"].erase(1);  // truncated: two folds of three
  EXPECT_THROW(CompareWithEarlier(r, earlier, "old/report.json", ScoreLevel::kObject), InputError);
  earlier.erase("fold_objects_trained");
  EXPECT_THROW(CompareWithEarlier(r, earlier, "old/report.json", ScoreLevel::kObject), InputError);
  // Without the objects trained on per fold there is no object-level ρ.
  r.trained_objects.clear();
  EXPECT_THROW(r.Compare("a", "b", ScoreLevel::kObject), InputError);
}

TEST(CrossValidationTest, HistoryIsTheMeanOfTheObjectsWindowsSoFar) {
  // Two objects interleaved, two classes: each row is the mean of its object's rows up to it.
  const std::vector<std::string> ids = {"a", "b", "a", "a", "b"};
  const std::vector<float> p = {1.0f, 0.0f, 0.2f, 0.8f, 0.0f, 1.0f, 0.5f, 0.5f, 0.4f, 0.6f};
  const std::vector<float> mean = RunningMeanByObject(ids, p, 2);
  const std::vector<float> expected = {1.0f, 0.0f, 0.2f, 0.8f, 0.5f, 0.5f, 0.5f, 0.5f, 0.3f, 0.7f};
  ASSERT_EQ(mean.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(mean[i], expected[i], 1e-6) << i;
  // Row 2 alone says class 1; with its object's history it is a tie, which goes to class 0.
  EXPECT_EQ(MostProbable(mean, 2)[2], 0);
  EXPECT_THROW(RunningMeanByObject(ids, std::vector<float>(9), 2), InputError);
}

// Self-training: windows without a class are split off the dataset in order, the
// fold's forest labels those it is sure of, they join the network's training
// windows, and nothing about the forest or the folds changes.
TEST(CrossValidationTest, PseudoLabelsComeFromTheFoldsForestAndAreNeverScored) {
  const PreparedDataset labelled = TwoClassDataset();
  // Interleave 12 unlabelled windows of 4 objects: 6 clearly "b" (features 5), 6 of
  // a third kind the forest cannot be sure of (features 0.5, between "a" and "b").
  PreparedDataset mixed = labelled;
  mixed.windows = Dataset{1, 2, {}, {}, {}, {}}, mixed.handcrafted.clear(), mixed.labels.clear();
  const int width = HandcraftedFeatureCount();
  for (size_t i = 0; i < labelled.windows.size(); ++i) {
    if (i % 10 == 0) {
      const size_t u = i / 10;
      mixed.windows.Append(Dataset{1, 2, {0.0f, 0.0f}, {-1}, {"u" + std::to_string(u % 4)}, {}});
      mixed.labels.push_back("unlabelled");
      mixed.handcrafted.insert(mixed.handcrafted.end(), width, u % 2 ? 0.5f : 5.0f);
    }
    mixed.windows.Append(labelled.windows.Subset({i}));
    mixed.labels.push_back(labelled.labels[i]);
    mixed.handcrafted.insert(mixed.handcrafted.end(), labelled.handcrafted.begin() + static_cast<long>(i * width),
                             labelled.handcrafted.begin() + static_cast<long>((i + 1) * width));
  }
  const PreparedDataset unlabelled = SplitOffUnlabelled(mixed);
  ASSERT_EQ(unlabelled.windows.size(), 12u);
  EXPECT_EQ(unlabelled.windows.y, std::vector<int>(12, -1));
  EXPECT_EQ(unlabelled.windows.object_ids[1], "u1");
  EXPECT_EQ(unlabelled.handcrafted[0], 5.0f);
  EXPECT_EQ(unlabelled.handcrafted[static_cast<size_t>(width)], 0.5f);
  EXPECT_EQ(mixed.windows.x, labelled.windows.x);
  EXPECT_EQ(mixed.windows.y, labelled.windows.y);
  EXPECT_EQ(mixed.windows.object_ids, labelled.windows.object_ids);
  EXPECT_EQ(mixed.handcrafted, labelled.handcrafted);
  EXPECT_EQ(mixed.labels, labelled.labels);

  CrossValidationOptions o;
  o.folds = 3, o.seed = 4;
  const CrossValidationResult plain = CrossValidate(mixed, o);
  EXPECT_TRUE(plain.pseudo_labelled.empty());
  o.pseudo_labels.votes = 0.9;
  ModelOptions m;
  m.variant = "mlp", m.epochs = 1, m.threads = 1;
  o.networks = {{"mlp", m}};
  std::vector<std::string> lines;
  const CrossValidationResult self = CrossValidate(
      mixed, o, [&](const std::string& l, double) { lines.push_back(l); }, unlabelled);
  ASSERT_EQ(self.pseudo_labelled.size(), 3u);
  for (const auto& per_class : self.pseudo_labelled) EXPECT_EQ(per_class, (std::vector<long>{0, 6})) << "fold";
  EXPECT_NE(lines[0].find("+ 6 pseudo-labelled"), std::string::npos) << lines[0];
  // The forest learns from labelled windows only, on the same folds.
  EXPECT_EQ(self.fold_of, plain.fold_of);
  EXPECT_EQ(self.probabilities.at("forest"), plain.probabilities.at("forest"));
  EXPECT_EQ(self.probabilities.at("mlp").size(), labelled.windows.size() * 2);
  EXPECT_TRUE(self.pseudo_labelled_by_round[0].empty());  // one round: the forest's counts say it all

  // Two rounds: each fold's network and round counted, the forest still untouched.
  o.pseudo_labels.rounds = 2;
  lines.clear();
  const CrossValidationResult twice = CrossValidate(
      mixed, o, [&](const std::string& l, double) { lines.push_back(l); }, unlabelled);
  ASSERT_EQ(twice.pseudo_labelled_by_round.size(), 3u);
  for (size_t f = 0; f < 3; ++f) {
    const auto& rounds = twice.pseudo_labelled_by_round[f].at("mlp");
    ASSERT_EQ(rounds.size(), 2u);
    EXPECT_EQ(rounds[0], self.pseudo_labelled[f]);
  }
  EXPECT_NE(lines[0].find("in round 2"), std::string::npos) << lines[0];
  EXPECT_EQ(twice.probabilities.at("forest"), plain.probabilities.at("forest"));
  o.pseudo_labels.rounds = 1;

  o.forest = false;  // the teacher
  EXPECT_THROW(CrossValidate(mixed, o, {}, unlabelled), InputError);
  o.forest = true;
  EXPECT_THROW(CrossValidate(mixed, o), InputError);  // nothing to label
  o.pseudo_labels.votes = 1.5;
  EXPECT_THROW(CrossValidate(mixed, o, {}, unlabelled), InputError);
  o.pseudo_labels.votes = 0;
  PreparedDataset unsplit = mixed;
  unsplit.windows.Append(unlabelled.windows);
  EXPECT_THROW(CrossValidate(unsplit, o), InputError);  // unlabelled windows left among the scored ones
}

// Noisy student's rounds: round 1 learns the forest's sure windows; round 2 a fresh
// network learns those that round 1's network combined with the forest is sure of.
TEST(CrossValidationTest, SelfTrainingRoundsAreTaughtByTheLastNetworkWithTheForest) {
  const Dataset labelled = ToyDataset(30, 1);
  PreparedDataset unlabelled;
  unlabelled.windows = ToyDataset(10, 7);
  unlabelled.windows.y.assign(unlabelled.windows.size(), -1);
  // The forest: sure of class 0 for the first 8 windows, undecided on the other 12.
  std::vector<float> forest;
  for (size_t i = 0; i < unlabelled.windows.size(); ++i) {
    forest.push_back(i < 8 ? 0.9f : 0.5f);
    forest.push_back(i < 8 ? 0.1f : 0.5f);
  }
  PseudoLabelOptions o;
  o.votes = 0.6, o.rounds = 2;
  auto m = Small();
  m.epochs = 3;
  std::vector<int> rounds_seen;
  std::vector<size_t> sizes;
  Dataset expected_round_2;
  const TrainNetwork train = [&](const Dataset& windows, int round) {
    rounds_seen.push_back(round), sizes.push_back(windows.size());
    Classifier c(m, 4, 32, {"straight", "weaving"});
    c.Train(windows, {});
    std::vector<long> counts;
    if (round == 1)
      expected_round_2 =
          PseudoLabelled(CombinedProbabilities(c.Predict(unlabelled.windows), forest), unlabelled, o.votes, 2, counts);
    else
      EXPECT_EQ(std::vector<int>(windows.y.begin() + static_cast<long>(labelled.size()), windows.y.end()),
                expected_round_2.y);
    return c;
  };
  std::vector<std::vector<long>> per_round;
  SelfTrain(train, labelled, unlabelled, forest, o, 2, per_round);
  EXPECT_EQ(rounds_seen, (std::vector<int>{1, 2}));
  ASSERT_EQ(per_round.size(), 2u);
  EXPECT_EQ(per_round[0], (std::vector<long>{8, 0}));
  EXPECT_EQ(sizes[0], labelled.size() + 8);
  EXPECT_EQ(sizes[1], labelled.size() + expected_round_2.size());
  EXPECT_EQ(per_round[1][0] + per_round[1][1], static_cast<long>(expected_round_2.size()));
  // The 12 windows the forest cannot decide are learnable: a trained network is
  // sure enough of some of them to tip the combination.
  EXPECT_GT(expected_round_2.size(), 8u);

  for (int bad : {0, 6}) {
    o.rounds = bad;
    EXPECT_THROW(SelfTrain(train, labelled, unlabelled, forest, o, 2, per_round), InputError) << bad;
  }
  o.rounds = 1, o.votes = 0;
  EXPECT_THROW(SelfTrain(train, labelled, unlabelled, forest, o, 2, per_round), InputError);
  o.votes = 0.6;
  forest.pop_back();  // not one row per window
  EXPECT_THROW(SelfTrain(train, labelled, unlabelled, forest, o, 2, per_round), InputError);
}

}  // namespace
}  // namespace specht::classify
