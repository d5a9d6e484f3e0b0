// Detection scoring on hand-made frames with known answers.
#include "specht/eval/detection.h"

#include <gtest/gtest.h>

namespace specht::eval {
namespace {

TEST(DetectionScorerTest, MatchesByClassAndIouAndIgnoresDontCareBoxes) {
  DetectionScorer scorer(0.5);
  const std::vector<TruthBox> truth = {{"pedestrian", {100, 100, 40, 80}, true, 8},
                                       {"car", {300, 120, 120, 60}, true, 25},
                                       {"car", {600, 130, 20, 12}, false, 45}};  // too small: don't care
  const std::vector<DetectedBox> detections = {
      {"pedestrian", {104, 98, 40, 84}, 0.9},   // finds the pedestrian
      {"pedestrian", {102, 100, 38, 80}, 0.5},  // a second box on it: a false positive
      {"car", {600, 130, 22, 12}, 0.6},         // on the don't-care car: nothing
      {"cyclist", {300, 120, 120, 60}, 0.7},    // the car, wrong class: a false positive
      {"car", {900, 100, 50, 50}, 0.4}};        // nothing there
  const std::vector<int> found = scorer.AddFrame(truth, detections);
  EXPECT_EQ(found, (std::vector<int>{0, -1, -1, -1, -1}));
  EXPECT_EQ(scorer.all().truth, 2);
  EXPECT_EQ(scorer.all().found, 1);
  EXPECT_EQ(scorer.all().false_positives, 3);
  EXPECT_DOUBLE_EQ(scorer.all().Recall(), 0.5);
  EXPECT_DOUBLE_EQ(scorer.all().Precision(), 0.25);
  EXPECT_EQ(scorer.per_class().at("car").found, 0);
  EXPECT_EQ(scorer.per_class().at("cyclist").false_positives, 1);
  const auto j = scorer.ToJson();
  EXPECT_EQ(j["recall_by_range"]["0-10 m"]["recall"], 1.0);
  EXPECT_EQ(j["recall_by_range"]["20-30 m"]["recall"], 0.0);
  EXPECT_FALSE(j["recall_by_range"].contains("30+ m"));  // the don't-care car is not counted
  EXPECT_DOUBLE_EQ(scorer.FalsePositivesPerFrame(), 3.0);
}

TEST(DetectionScorerTest, BelowTheIouThresholdIsAMissAndAFalsePositive) {
  DetectionScorer scorer(0.5);
  // IoU of these two: 40·40 / (40·80 + 40·80 − 40·40) = 1/3.
  scorer.AddFrame({{"pedestrian", {0, 0, 40, 80}, true, 5}}, {{"pedestrian", {0, 40, 40, 80}, 0.9}});
  EXPECT_NEAR(IoU({0, 0, 40, 80}, {0, 40, 40, 80}), 1.0 / 3, 1e-12);
  EXPECT_EQ(scorer.all().found, 0);
  EXPECT_EQ(scorer.all().false_positives, 1);
}

}  // namespace
}  // namespace specht::eval
