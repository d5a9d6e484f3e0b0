// Tracker, assignment, CLEAR MOT and the object-track CSV on hand-made cases with
// known answers; tracking quality on simulated scenes (acceptance 1).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "specht/core/assignment.h"
#include "specht/core/error.h"
#include "specht/eval/mot.h"
#include "specht/io/object_tracks.h"
#include "specht/track/tracker.h"
#include "test_support.h"

namespace specht {
namespace {

template <class F>
void ExpectInputError(F&& f, const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no InputError, expected: " << message;
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(message));
  }
}

TEST(AssignmentTest, SquareKnownOptimum) {
  // The greedy choice (row 0 → column 0, cost 1) forces 100 elsewhere; optimum is 2+3+4.
  const auto a = SolveAssignment({{1, 2, 100}, {3, 100, 100}, {100, 100, 4}});
  EXPECT_EQ(a.column_of_row, (std::vector<int>{1, 0, 2}));
  EXPECT_DOUBLE_EQ(a.total_cost, 9);
}

TEST(AssignmentTest, RectangularAndForbidden) {
  const double inf = std::numeric_limits<double>::infinity();
  auto a = SolveAssignment({{5, 1, 9, 7}, {inf, inf, inf, inf}, {2, 8, 9, 1}});
  EXPECT_EQ(a.column_of_row, (std::vector<int>{1, -1, 3}));
  a = SolveAssignment({{1}, {0.5}, {2}});  // more rows than columns
  EXPECT_EQ(a.column_of_row, (std::vector<int>{-1, 0, -1}));
  a = SolveAssignment({{1, 5}, {6, 2}}, 1.5);  // above max_cost: not assigned
  EXPECT_EQ(a.column_of_row, (std::vector<int>{0, -1}));
  EXPECT_TRUE(SolveAssignment({}).column_of_row.empty());
}

TEST(AssignmentTest, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 10);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<std::vector<double>> c(5, std::vector<double>(5));
    for (auto& r : c)
      for (auto& v : r) v = u(rng);
    std::vector<int> perm = {0, 1, 2, 3, 4};
    double best = 1e9;
    do {
      double s = 0;
      for (int i = 0; i < 5; ++i) s += c[i][perm[i]];
      best = std::min(best, s);
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(SolveAssignment(c).total_cost, best, 1e-9);
  }
}

types::Obstacle Det(double x, double y, const std::string& cls = "pedestrian", double sigma = 0.1) {
  types::Obstacle o;
  o.cls = cls;
  o.x_m = x, o.y_m = y;
  o.covariance_xy = cv::Matx22d::eye() * sigma * sigma;
  o.score = 0.9;
  return o;
}

Stamp At(double t) { return Stamp::FromSeconds(100 + t); }

TEST(TrackerTest, LifecycleTentativeConfirmedCoastingDeleted) {
  track::TrackerOptions o;
  track::Tracker tracker(o);
  tracker.Update({Det(0, 0)}, At(0));
  tracker.Update({Det(0.1, 0)}, At(0.1));
  EXPECT_TRUE(tracker.Tracks().empty());  // tentative: two hits
  EXPECT_EQ(tracker.tentative_count(), 1);
  tracker.Update({Det(0.2, 0)}, At(0.2));
  auto tracks = tracker.Tracks();
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].state, "confirmed");
  tracker.Update({}, At(0.3));
  tracks = tracker.Tracks();
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].state, "coasting");
  tracker.Update({}, At(0.3 + o.report_coasting_s + 0.1));  // kept, not reported
  EXPECT_TRUE(tracker.Tracks().empty());
  tracker.Update({Det(0.2 + (o.report_coasting_s + 0.2), 0)}, At(0.4 + o.report_coasting_s + 0.1));
  ASSERT_EQ(tracker.Tracks().size(), 1u);  // re-associated, same id
  EXPECT_EQ(tracker.Tracks()[0].id, tracks[0].id);
  tracker.Update({}, At(10));
  EXPECT_TRUE(tracker.Tracks().empty());
  EXPECT_EQ(tracker.tentative_count(), 0);
}

// M of N: a missed frame does not end a tentative track (a detector at 0.7 would
// otherwise need three hits in a row); it ends once confirm_hits is out of reach.
TEST(TrackerTest, TentativeTrackSurvivesAMissAndEndsWhenItCanNoLongerConfirm) {
  track::TrackerOptions o;  // 3 hits within 5 cycles
  track::Tracker tracker(o);
  tracker.Update({Det(0, 0)}, At(0));
  tracker.Update({}, At(0.1));
  tracker.Update({Det(0.2, 0)}, At(0.2));
  EXPECT_TRUE(tracker.Tracks().empty());
  EXPECT_EQ(tracker.tentative_count(), 1);
  tracker.Update({Det(0.3, 0)}, At(0.3));
  ASSERT_EQ(tracker.Tracks().size(), 1u);
  EXPECT_EQ(tracker.Tracks()[0].state, "confirmed");

  track::Tracker lonely(o);
  lonely.Update({Det(5, 5)}, At(0));
  for (int k = 1; k <= 3; ++k) {
    lonely.Update({}, At(0.1 * k));
    EXPECT_EQ(lonely.tentative_count(), 1) << "cycle " << k << ": 1 hit + " << 5 - k << " to come can still make 3";
  }
  lonely.Update({}, At(0.4));
  EXPECT_EQ(lonely.tentative_count(), 0);
  EXPECT_TRUE(lonely.Tracks().empty());
}

TEST(TrackerTest, IsolatedFalseAlarmsNeverConfirm) {
  track::Tracker tracker({});
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-50, 50);
  for (int k = 0; k < 100; ++k) tracker.Update({Det(u(rng), u(rng))}, At(0.1 * k));
  EXPECT_TRUE(tracker.Tracks().empty());
}

TEST(TrackerTest, ConstantVelocityRecoveredWithCovariance) {
  track::Tracker tracker({});
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0, 0.1);
  for (int k = 0; k <= 50; ++k) tracker.Update({Det(1.5 * 0.1 * k + n(rng), -0.5 * 0.1 * k + n(rng))}, At(0.1 * k));
  const auto tracks = tracker.Tracks();
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_NEAR(tracks[0].vx_mps, 1.5, 0.15);
  EXPECT_NEAR(tracks[0].vy_mps, -0.5, 0.15);
  EXPECT_EQ(tracks[0].motion_model, "cv");
  EXPECT_EQ(tracks[0].history.size(), 51u);
  // The prediction: 3 s ahead at 0.5 s, along the velocity, covariance growing.
  ASSERT_EQ(tracks[0].prediction.size(), 6u);
  EXPECT_NEAR(tracks[0].prediction.back().x_m, 1.5 * 8, 0.6);
  EXPECT_NEAR(tracks[0].prediction.back().y_m, -0.5 * 8, 0.6);
  EXPECT_GT(tracks[0].prediction.back().covariance(0, 0), tracks[0].prediction.front().covariance(0, 0));
}

// A car on a circle of radius 10 m at 5 m/s: the turn model predicts where it will
// be far better than constant velocity.
TEST(TrackerTest, TurnModelFollowsCircle) {
  const double r = 10, v = 5, w = v / r;
  double error[2] = {0, 0};
  for (int m = 0; m < 2; ++m) {
    track::TrackerOptions o;
    o.motion_model = m == 0 ? "cv" : "ct";
    track::Tracker tracker(o);
    std::mt19937 rng(4);
    std::normal_distribution<double> n(0, 0.05);
    for (int k = 0; k <= 60; ++k) {
      const double a = w * 0.1 * k;
      tracker.Update({Det(r * std::sin(a) + n(rng), r - r * std::cos(a) + n(rng), "car", 0.05)}, At(0.1 * k));
    }
    const auto tracks = tracker.Tracks();
    ASSERT_EQ(tracks.size(), 1u);
    const auto& p = tracks[0].prediction[1];  // 1 s ahead
    const double a = w * (6.0 + p.dt_s);
    error[m] = std::hypot(p.x_m - r * std::sin(a), p.y_m - (r - r * std::cos(a)));
    EXPECT_EQ(tracks[0].motion_model, o.motion_model);
    EXPECT_NEAR(std::hypot(tracks[0].vx_mps, tracks[0].vy_mps), v, 0.3);
  }
  EXPECT_LT(error[1], 0.3);
  EXPECT_LT(error[1], error[0] / 3);
}

TEST(TrackerTest, CrossingTargetsKeepTheirIds) {
  track::Tracker tracker({});
  std::map<long, double> first_y;
  for (int k = 0; k <= 80; ++k) {
    const double t = 0.1 * k;
    tracker.Update({Det(-6 + 1.5 * t, 0.3), Det(6 - 1.5 * t, -0.3)}, At(t));
    for (const auto& tr : tracker.Tracks())
      if (!first_y.count(tr.id)) first_y[tr.id] = tr.y_m;
    for (const auto& tr : tracker.Tracks()) EXPECT_NEAR(tr.y_m, first_y[tr.id], 0.2) << "at t " << t;
  }
  EXPECT_EQ(first_y.size(), 2u);
}

TEST(TrackerTest, ClassIsTheVoteAndSetsTheModel) {
  track::TrackerOptions o;
  o.motion_model = "auto";  // ct for vehicles
  track::Tracker tracker(o);
  for (int k = 0; k < 10; ++k) tracker.Update({Det(0.5 * k, 0, k == 4 ? "pedestrian" : "car")}, At(0.1 * k));
  ASSERT_EQ(tracker.Tracks().size(), 1u);
  EXPECT_EQ(tracker.Tracks()[0].cls, "car");
  EXPECT_EQ(tracker.Tracks()[0].motion_model, "ct");
}

TEST(TrackerTest, BadInput) {
  track::Tracker tracker({});
  tracker.Update({Det(0, 0)}, At(1));
  EXPECT_THROW(tracker.Update({}, At(0.5)), InputError);  // time went back
  tracker.Update({Det(std::nan(""), 0), Det(0, std::numeric_limits<double>::infinity())}, At(1.1));
  EXPECT_EQ(tracker.skipped_detections(), 2);
  track::TrackerOptions o;
  o.acceleration_noise = {"car=2"};  // no "other"
  EXPECT_THROW(track::Tracker{o}, InputError);
  o.acceleration_noise = {"other=-1"};
  EXPECT_THROW(track::Tracker{o}, InputError);
  o = {};
  o.confirm_hits = 6;
  EXPECT_THROW(track::Tracker{o}, InputError);
}

io::ObjectSample S(const std::string& id, double t, double x, double y, bool ignore = false) {
  io::ObjectSample s;
  s.id = id, s.t_s = t, s.x_m = x, s.y_m = y, s.ignore = ignore;
  return s;
}

// Two truth objects over four frames with a miss, a false positive, an identity
// switch and a don't-care object, counted by hand.
TEST(MotTest, HandCountedExample) {
  const std::vector<io::ObjectSample> truth = {S("a", 0, 0, 0), S("a", 1, 1, 0), S("a", 2, 2, 0),
                                               S("a", 3, 3, 0), S("b", 0, 0, 5), S("b", 1, 1, 5),
                                               S("b", 2, 2, 5), S("b", 3, 3, 5), S("c", 3, 9, 9, true)};
  const std::vector<io::ObjectSample> hyps = {S("1", 0, 0.1, 0), S("1", 1, 1.2, 0), S("3", 2, 2.0, 0.3),
                                              S("3", 3, 3.0, 0),  // switch 1 → 3 at t 2
                                              S("2", 0, 0, 5.4), S("2", 2, 2, 5),   S("2", 3, 3, 5),  // miss at t 1
                                              S("9", 1, 20, 20),                                      // false positive
                                              S("8", 3, 9.2, 9)};  // on the don't-care
  const auto r = eval::EvaluateMot(truth, hyps, 1.0);
  EXPECT_EQ(r.truth_objects, 8);
  EXPECT_EQ(r.matches, 7);
  EXPECT_EQ(r.false_negatives, 1);
  EXPECT_EQ(r.false_positives, 1);
  EXPECT_EQ(r.id_switches, 1);
  EXPECT_EQ(r.fragmentations, 1);  // b: tracked, missed, tracked
  EXPECT_NEAR(r.mota, 1.0 - 3.0 / 8.0, 1e-12);
  EXPECT_NEAR(r.motp_m, (0.1 + 0.2 + 0.3 + 0 + 0.4 + 0 + 0) / 7, 1e-12);
  EXPECT_NEAR(r.track_seconds, 8.0, 1e-9);
  EXPECT_EQ(r.truth_of_hypothesis.at("3"), "a");
  EXPECT_EQ(r.mostly_tracked, 1);  // b at 3 of 4 frames is 75 %
}

TEST(MotTest, KeepsCorrespondenceOverACloserNewcomer) {
  // Hypothesis 1 follows a; at t 1 hypothesis 2 is closer but 1 is still within the
  // threshold: no switch (CLEAR MOT keeps the previous correspondence).
  const auto r = eval::EvaluateMot({S("a", 0, 0, 0), S("a", 1, 0, 0)},
                                   {S("1", 0, 0, 0), S("1", 1, 0.8, 0), S("2", 1, 0.1, 0)}, 1.0);
  EXPECT_EQ(r.id_switches, 0);
  EXPECT_EQ(r.false_positives, 1);
}

TEST(ObjectTracksTest, RoundTripAndErrors) {
  const std::string dir = testing::TempDir("object_tracks");
  std::vector<io::ObjectSample> samples = {S("s1/7#1", 0.1, 1.25, -2.5), S("t3", 0.2, 4, 5, true)};
  samples[0].cls = "car";
  samples[1].truth_cls = "cyclist";
  io::WriteObjectTracks(samples, dir + "/a.csv");
  const auto back = io::ReadObjectTracks(dir + "/a.csv");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].id, "s1/7#1");
  EXPECT_DOUBLE_EQ(back[0].x_m, 1.25);
  EXPECT_EQ(back[0].cls, "car");
  EXPECT_EQ(back[1].truth_cls, "cyclist");
  EXPECT_TRUE(back[1].ignore);
  EXPECT_THROW(io::ReadObjectTracks(dir + "/missing.csv"), InputError);
  ExpectInputError([] { io::ParseObjectTracks("id,t_s,x_m\n", "f.csv"); }, "f.csv:1: header: no column \"y_m\"");
  ExpectInputError([] { io::ParseObjectTracks("id,t_s,x_m,y_m\na,0,1\n", "f.csv"); }, "f.csv:2: row has 3");
  ExpectInputError([] { io::ParseObjectTracks("id,t_s,x_m,y_m\na,0,1,nan\n", "f.csv"); }, "f.csv:2: y_m");
  ExpectInputError([] { io::ParseObjectTracks("", "f.csv"); }, "empty file");
}

// A classifier's probabilities travel as p_<class> columns: every class any row has,
// an empty cell where a row has none (a track too young to classify).
TEST(ObjectTracksTest, ClassProbabilitiesRoundTripAsPColumns) {
  const std::string dir = testing::TempDir("object_tracks_p");
  std::vector<io::ObjectSample> samples = {S("t1", 0.1, 1, 2), S("t1", 0.2, 1, 2), S("t2", 0.2, 3, 4)};
  samples[1].class_probabilities = {{"pedestrian", 0.75}, {"car", 0.25}};
  samples[2].class_probabilities = {{"cyclist", 1.0}};
  io::WriteObjectTracks(samples, dir + "/p.csv");
  const std::string text = testing::ReadFile(dir + "/p.csv");
  EXPECT_THAT(text,
              ::testing::StartsWith("id,t_s,x_m,y_m,class,p_car,p_cyclist,p_pedestrian\nt1,0.100,1.000,2.000,,,,\n"));
  EXPECT_THAT(text, ::testing::HasSubstr("t1,0.200,1.000,2.000,,0.2500,,0.7500\n"));
  const auto back = io::ReadObjectTracks(dir + "/p.csv");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_TRUE(back[0].class_probabilities.empty());
  EXPECT_EQ(back[1].class_probabilities, samples[1].class_probabilities);
  EXPECT_EQ(back[2].class_probabilities, samples[2].class_probabilities);
  ExpectInputError([] { io::ParseObjectTracks("id,t_s,x_m,y_m,p_car\na,0,1,2,high\n", "f.csv"); },
                   "f.csv:2: p_car: \"high\" is not a finite number");
}

TEST(ObjectTracksTest, TruncatedAndCorruptedInputNeverCrashes) {
  std::string text = "id,t_s,x_m,y_m,class,truth_class,ignore,p_car,p_pedestrian\n";
  for (int i = 0; i < 40; ++i)
    text += "o" + std::to_string(i % 3) + "," + std::to_string(0.1 * i) + ",1.5,-2,car,car,0" +
            (i % 4 == 0 ? ",," : ",0.7500,0.2500") + "\n";
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    std::string t = text.substr(0, rng() % text.size());
    for (int k = 0; k < 3 && !t.empty(); ++k) t[rng() % t.size()] = static_cast<char>(rng() % 256);
    try {
      const auto rows = io::ParseObjectTracks(t, "fuzz.csv");
      for (const auto& r : rows) {
        EXPECT_TRUE(std::isfinite(r.x_m) && std::isfinite(r.t_s));
        for (const auto& [cls, p] : r.class_probabilities) EXPECT_TRUE(std::isfinite(p)) << cls;
      }
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.csv"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace specht
