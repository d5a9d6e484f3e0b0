// Graph SLAM on the Radish logs (label: slow). Started from raw odometry, scored by
// the relation error of Kümmerle et al. 2009 against the corrected poses.
//
// The target is a mean of 0.05 m and 1° over all relations with no relation
// above 0.5 m. The bounds below are what main achieves today plus a margin, so a
// regression fails; where a log meets the target the bound is the target. Freiburg-079
// meets the mean; its maximum cannot be held to 0.5 m: the reference itself jumps
// 0.15 m and 8° and back at scans 4088–4089, so even the reference with those two
// scans put on the odometry scores 0.43 m there. Orebro has no odometry at all (its
// ODOM lines only repeat the corrected poses): every scan is placed by the search
// around the last step repeated and around the stop, scored with the drive prior
// (no sideways or backward jumps), each searched step is searched again with the
// keyframes after it, and the last room is closed against the first scan by the search
// of old keyframes; its figure still moves with slightly different parameters
// (0.049–0.056 m over five point-to-line gates; bench/slam_spread.sh).
#include <mrpt/core/bits_math.h>

#include <algorithm>

#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/carmen.h"
#include "specht/io/dataset.h"
#include "specht/io/trajectory_io.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/localizer.h"
#include "test_support.h"

namespace specht::slam {
namespace {

struct Bound {
  const char* log;
  double mean_m, max_m, mean_deg;
};

std::unique_ptr<GraphSlam> RunSlam(const std::string& log, const SlamOptions& options = {},
                                   const ScanMatchingOptions& matching = {}, const LoopClosureOptions& loops = {}) {
  auto slam = std::make_unique<GraphSlam>(options, matching, loops, PoseGraphOptions{}, nullptr, "base_link");
  auto source = io::OpenDataset(log);
  while (auto obs = source->Next()) slam->Add(obs->stamp, obs->data);
  slam->Finish();
  return slam;
}

// The front end alone (no loop closure): its consecutive relations against the reference.
eval::RelationStats FrontEndSteps(const std::string& log, const ScanMatchingOptions& matching) {
  SlamOptions front_end;
  front_end.method = "scan_matching";
  return eval::ComputeRelationError(RunSlam(log, front_end, matching)->trajectory(), io::ReadCarmenReference(log))
      .consecutive;
}

// How far the step from scan i to scan i + 1 is off the reference's step (m).
double StepError(const Trajectory& estimate, const Trajectory& reference, size_t i) {
  const mrpt::poses::CPose2D truth(reference.at(i + 1).pose - reference.at(i).pose);
  const mrpt::poses::CPose2D step(estimate.at(i + 1).pose - estimate.at(i).pose);
  return (step - truth).norm();
}

void PrintTo(const Bound& b, std::ostream* os) { *os << b.log; }

class CarmenSlamTest : public ::testing::TestWithParam<Bound> {};

TEST_P(CarmenSlamTest, RelationErrorWithinBound) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/" + GetParam().log + "-corrected.log.gz";
  const auto slam = RunSlam(log);
  const auto rel = eval::ComputeRelationError(slam->trajectory(), io::ReadCarmenReference(log));
  std::printf("%s: %zu relations, %.4f ± %.4f m (max %.3f), %.3f ± %.3f deg; %ld loop closures\n", GetParam().log,
              rel.all.count, rel.all.mean_m, rel.all.std_m, rel.all.max_m, rel.all.mean_deg, rel.all.std_deg,
              slam->stats().loops_accepted);
  EXPECT_LE(rel.all.mean_m, GetParam().mean_m);
  EXPECT_LE(rel.all.max_m, GetParam().max_m);
  EXPECT_LE(rel.all.mean_deg, GetParam().mean_deg);
}

INSTANTIATE_TEST_SUITE_P(Radish, CarmenSlamTest,
                         ::testing::Values(Bound{"intel", 0.05, 0.5, 1.0}, Bound{"seattle", 0.05, 0.5, 1.0},
                                           Bound{"freiburg-101", 0.05, 0.5, 1.0}, Bound{"freiburg-079", 0.05, 0.5, 1.0},
                                           Bound{"orebro", 0.05, 0.5, 1.0}),
                         [](const auto& info) {
                           std::string n = info.param.log;
                           for (auto& ch : n) ch = ch == '-' ? '_' : ch;
                           return n;
                         });

// The Freiburg benchmark (Kümmerle et al. 2009): the raw full-rate logs, scored on
// their published relations, every relation matched by stamp. The bound is
// Cartographer's published mean (Hess et al. 2016, Table II) where specht is ahead of
// it, and on ACES, where it is not, the figure measured on main plus 1.5 mm.
struct FreiburgBound {
  const char* log;
  double mean_m, mean_deg;
};
void PrintTo(const FreiburgBound& b, std::ostream* os) { *os << b.log; }
class FreiburgSlamTest : public ::testing::TestWithParam<FreiburgBound> {};

TEST_P(FreiburgSlamTest, PublishedRelationErrorWithinBound) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/freiburg/" + GetParam().log + ".clf.bz2";
  SPECHT_REQUIRE_FILE(log);
  const auto slam = RunSlam(log);
  const auto rel =
      eval::ComputePublishedRelationError(slam->trajectory(), io::ReadRelations(io::DefaultRelationsPath(log)));
  std::printf("%s: %zu published relations, %.4f ± %.4f m (max %.3f), %.3f ± %.3f deg\n", GetParam().log, rel.relations,
              rel.absolute.mean_m, rel.absolute.std_m, rel.absolute.max_m, rel.absolute.mean_deg, rel.absolute.std_deg);
  EXPECT_LE(rel.absolute.mean_m, GetParam().mean_m);
  EXPECT_LE(rel.absolute.mean_deg, GetParam().mean_deg);
}

INSTANTIATE_TEST_SUITE_P(Benchmark, FreiburgSlamTest,
                         ::testing::Values(FreiburgBound{"intel", 0.0229, 0.453}, FreiburgBound{"fr079", 0.0452, 0.538},
                                           FreiburgBound{"aces", 0.0403, 0.373}),
                         [](const auto& info) { return std::string(info.param.log); });

TEST(CarmenFrontEndTest, WithoutOdometryTheDrivePriorKeepsOrebrosStepsFromJumpingAside) {
  // The front end alone (no loop closure) on the log without odometry. Without the
  // drive prior corridor aliases beside and behind the robot win the search: four
  // steps 2.4 m off. With it one step was left (scans 16 -> 17: the stop scores 0.763
  // against the true 2 m step's 0.732), mean 0.043 m; the recheck (below) finds that
  // one too: 0.0325 m (max 0.22), against 0.137 m (max 4.7) without the prior.
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/orebro-corrected.log.gz";
  const auto with_prior = FrontEndSteps(log, {});
  ScanMatchingOptions no_prior;
  no_prior.search_drive_penalty = 0;
  const auto without = FrontEndSteps(log, no_prior);
  std::printf("orebro front end, consecutive: %.4f m (max %.3f) with the drive prior, %.4f m (max %.3f) without\n",
              with_prior.mean_m, with_prior.max_m, without.mean_m, without.max_m);
  EXPECT_LE(with_prior.mean_m, 0.06);
  EXPECT_LE(with_prior.max_m, 2.1);
  EXPECT_LT(with_prior.mean_m, without.mean_m / 1.5);
}

TEST(CarmenFrontEndTest, WithoutOdometryARefinementThatLosesTheSearchsScoreIsRefused) {
  // Orebro turns on the spot about 40° a scan. There ICP, started from the searched
  // pose, slides into another minimum 4-6° off (scans 76, 80 and 84; at 76 the score
  // on the search grid halves, 0.50 -> 0.27). Keeping the searched pose whenever ICP
  // loses more than a tenth of its score leaves no step more than 3° off.
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/orebro-corrected.log.gz";
  ScanMatchingOptions refusing;
  refusing.recheck_keyframes = 0;  // the refinement alone
  const auto refused = FrontEndSteps(log, refusing);
  ScanMatchingOptions always_icp = refusing;
  always_icp.refine_max_loss = 1;
  const auto taken = FrontEndSteps(log, always_icp);
  std::printf("orebro front end, worst step: %.2f deg (%.3f m) refusing such refinements, %.2f deg taking them\n",
              refused.max_deg, refused.mean_m, taken.max_deg);
  EXPECT_LT(refused.max_deg, 3.0);
  EXPECT_GT(taken.max_deg, 4.0);
  EXPECT_LE(refused.mean_deg, taken.mean_deg);
}

TEST(CarmenFrontEndTest, WithoutOdometryARecheckWithTheLaterKeyframesFindsTheStepTheCorridorHid) {
  // At scan 17 orebro drives 2 m down a corridor; the scan alone fits the stop as well
  // as the step, and the search keeps the stop. The full turn on the spot that follows
  // looks back down the corridor: searched again as one rigid scan with the keyframes
  // after it, the step is found. Front end alone, and graph SLAM (whose graph must
  // follow the moved keyframes).
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/orebro-corrected.log.gz";
  const Trajectory reference = io::ReadCarmenReference(log);
  auto step_error = [&](const Trajectory& t, size_t i) { return StepError(t, reference, i); };
  SlamOptions front_end;
  front_end.method = "scan_matching";
  ScanMatchingOptions no_recheck;
  no_recheck.recheck_keyframes = 0;
  const auto rechecked = RunSlam(log, front_end, {});
  const auto kept = RunSlam(log, front_end, no_recheck);
  std::printf("orebro front end, step 16 -> 17: %.3f m off with the recheck (%ld steps moved), %.3f m without\n",
              step_error(rechecked->trajectory(), 16), rechecked->front_end_stats().rechecked_steps,
              step_error(kept->trajectory(), 16));
  EXPECT_LT(step_error(rechecked->trajectory(), 16), 0.3);
  EXPECT_GT(step_error(kept->trajectory(), 16), 1.5);

  const auto slam = RunSlam(log, {}, {});
  const auto all = eval::ComputeRelationError(slam->trajectory(), reference).all;
  std::printf("orebro graph SLAM: step 16 -> 17 %.3f m off; all relations %.4f m (max %.3f)\n",
              step_error(slam->trajectory(), 16), all.mean_m, all.max_m);
  EXPECT_LT(step_error(slam->trajectory(), 16), 0.3);
  EXPECT_LT(all.mean_m, 0.10);
}

TEST(CarmenFrontEndTest, WithoutOdometryARecheckMayCostTheKeyframesOwnScanALittle) {
  // At scan 41 orebro turns 76° on the spot; the scan alone fits a place 0.46 m aside
  // a little better (0.53 against 0.50 on the search grid), and scans 42-44 turn on
  // from there. Scans 41-43 as one rigid scan fit the right place 0.10 better. The
  // recheck moves them when the own scan loses at most recheck_own_max_loss (0.05);
  // at 0.02 it does not, and scan 45 jumps back instead (0.39 m off).
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/orebro-corrected.log.gz";
  const Trajectory reference = io::ReadCarmenReference(log);
  SlamOptions front_end;
  front_end.method = "scan_matching";
  ScanMatchingOptions strict;
  strict.recheck_own_max_loss = 0.02;
  const Trajectory moved = RunSlam(log, front_end, {})->trajectory();
  const Trajectory kept = RunSlam(log, front_end, strict)->trajectory();
  std::printf(
      "orebro front end, steps 40 -> 41 and 44 -> 45: %.3f and %.3f m off (own loss 0.05), %.3f and %.3f m "
      "(0.02)\n",
      StepError(moved, reference, 40), StepError(moved, reference, 44), StepError(kept, reference, 40),
      StepError(kept, reference, 44));
  EXPECT_LT(StepError(moved, reference, 40), 0.2);
  EXPECT_LT(StepError(moved, reference, 44), 0.2);
  EXPECT_GT(StepError(kept, reference, 40), 0.3);
}

TEST(CarmenLoopClosureTest, OrebrosLastRoomIsClosedByTheFirstScanOnceItsSubmapIsFinished) {
  // Orebro starts in a room it sees only in part (scan 0 faces east, scans 1-4 look
  // out through the door) and ends in it. The last room's keyframes never match the
  // first submap well enough; the other way round, the first scan sits inside the
  // finished last submap. Those loops exist only through the search of old keyframes
  // against a finished submap, and they agree with the reference. They also need the
  // front end to reach the last room whole: at scan 213, after the loops before it
  // moved the map, ICP slides 1.2 m and 15° off a right searched pose, and the search
  // must keep its own pose rather than fall back to the constant-velocity guess.
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/orebro-corrected.log.gz";
  const Trajectory reference = io::ReadCarmenReference(log);
  auto last_room_loops = [&](const LoopClosureOptions& loops) {
    const auto slam = RunSlam(log, {}, {}, loops);
    const auto& kfs = slam->keyframes();
    std::vector<double> errors;  // of each loop from a submap after scan 200 to scans 0-4, against the reference
    for (const auto& e : slam->graph().edges) {
      const size_t from = kfs.at(e.from).scan_index, to = kfs.at(e.to).scan_index;
      if (!e.robust || from < 200 || to > 4) continue;
      const mrpt::poses::CPose2D truth(reference.at(to).pose - reference.at(from).pose);
      errors.push_back((e.measurement - truth).norm());
    }
    const double step_error = StepError(slam->trajectory(), reference, 212);
    std::printf("orebro: step 212 -> 213 %.3f m off the reference\n", step_error);
    EXPECT_LT(step_error, 0.3);
    return errors;
  };
  LoopClosureOptions without_old;
  without_old.old_keyframes_per_submap = 0;
  EXPECT_TRUE(last_room_loops(without_old).empty());
  const auto errors = last_room_loops({});
  ASSERT_FALSE(errors.empty());
  for (double e : errors) {
    std::printf("orebro: a loop from the last room to the first scans, %.3f m off the reference\n", e);
    EXPECT_LT(e, 0.25);
  }
}

TEST(CarmenSlamDeterminismTest, SameLogTwiceGivesIdenticalTrajectoryAndGraph) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/intel-corrected.log.gz";
  const auto a = RunSlam(log), b = RunSlam(log);
  const Trajectory ta = a->trajectory(), tb = b->trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (size_t i = 0; i < ta.size(); ++i) {
    ASSERT_EQ(ta[i].pose.x(), tb[i].pose.x()) << i;
    ASSERT_EQ(ta[i].pose.y(), tb[i].pose.y()) << i;
    ASSERT_EQ(ta[i].pose.yaw(), tb[i].pose.yaw()) << i;
  }
  EXPECT_EQ(a->graph().edges.size(), b->graph().edges.size());
}

}  // namespace
}  // namespace specht::slam

namespace specht::slam {
namespace {

// Localization on a saved map of the intel log: started 0.5 m and 10° off, it must
// converge within 20 scans and then track the reference with a mean error ≤ 0.1 m.
// The reference is brought into the map frame by the SE(2) alignment of the SLAM run
// that made the map.
TEST(LocalizationTest, ConvergesFromAPerturbedPoseAndTracksTheReference) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/intel-corrected.log.gz";
  const Trajectory reference = io::ReadCarmenReference(log);
  const auto mapping = RunSlam(log);
  const auto alignment = eval::AbsoluteTrajectoryError2D(mapping->trajectory(), reference, 0.001).alignment;
  const Trajectory reference_in_map = eval::Transform(reference, -alignment);

  LocalizationOptions options;
  const mrpt::poses::CPose2D start(reference_in_map.front().pose);
  const mrpt::poses::CPose2D perturbed = start + mrpt::poses::CPose2D(0.4, 0.3, mrpt::DEG2RAD(10));  // 0.5 m, 10°
  options.initial_pose = {perturbed.x(), perturbed.y(), mrpt::RAD2DEG(perturbed.phi())};
  Localizer localizer(mapping->keyframes(), options, ScanMatchingOptions{}, nullptr, "base_link");
  auto source = io::OpenDataset(log);
  while (auto obs = source->Next()) localizer.Add(obs->stamp, obs->data);

  const Trajectory& t = localizer.trajectory();
  ASSERT_EQ(t.size(), reference_in_map.size());
  std::vector<double> error;
  for (size_t i = 0; i < t.size(); ++i) error.push_back(t[i].pose.distanceTo(reference_in_map[i].pose));
  // Converged: the first scan from which ten in a row are within 0.15 m.
  size_t converged = error.size();
  for (size_t i = 0; i + 10 <= error.size(); ++i) {
    if (std::all_of(error.begin() + i, error.begin() + i + 10, [](double e) { return e < 0.15; })) {
      converged = i;
      break;
    }
  }
  double mean = 0;
  for (size_t i = converged; i < error.size(); ++i) mean += error[i];
  mean /= std::max<size_t>(1, error.size() - converged);
  std::printf("localization: converged at scan %zu, then mean error %.4f m over %zu scans\n", converged, mean,
              error.size() - converged);
  EXPECT_LE(converged, 20u);
  EXPECT_LE(mean, 0.1);
}

}  // namespace
}  // namespace specht::slam
