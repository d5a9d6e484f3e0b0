// ICP and scan-matching odometry: known offsets in a ray-cast room, and the built-in rawlog's
// second pass over its first corridor.
#include "specht/slam/scan_matching.h"

#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <vector>

#include "specht/eval/map_quality.h"
#include "specht/io/dataset.h"
#include "specht/slam/correlative_matcher.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/icp.h"
#include "synthetic_scans.h"
#include "test_support.h"

namespace specht::slam {
namespace {

using mrpt::poses::CPose2D;
using namespace synthetic;  // the ray-cast scanner of synthetic_scans.h

// A 10 m x 6 m room with a 1 m x 1 m pillar at (6.5, 2.5).
const std::vector<Box> kRoom = {{0, 10, 0, 6}, {6, 7, 2, 3}};

mrpt::obs::CObservation2DRangeScan::Ptr ScanAt(const CPose2D& pose, Stamp stamp,
                                               const std::vector<Box>& world = kRoom) {
  return Scan180(pose, stamp, [&](double a) { return RayCast(world, pose.x(), pose.y(), a); });
}

// Two scans of the room from poses 0.4 m and 7 degrees apart sample its walls at
// different places: point-to-point pairs then also pull along the walls, the
// point-to-line refinement only across them.
TEST(IcpTest, PointToLineRefinementRecoversTheMotionToAMillimetre) {
  const CPose2D a(2.0, 2.0, 0.1), b(2.3, 2.25, 0.22);
  const auto reference = ScanToPoints(*ScanAt(a, Stamp{1}));
  const auto scan = ScanToPoints(*ScanAt(b, Stamp{2}));
  const CPose2D truth = b - a;
  const CPose2D guess = truth + CPose2D(0.08, -0.05, mrpt::DEG2RAD(2.0));
  auto error = [&](int point_to_line_iterations) {
    IcpOptions options;
    options.point_to_line_iterations = point_to_line_iterations;
    IcpAligner icp(options);
    const CPose2D off = icp.Align(IndexedPoints(reference), scan, guess).pose - truth;
    return std::make_pair(off.norm(), std::abs(mrpt::RAD2DEG(off.phi())));
  };
  const auto [point_to_point_m, point_to_point_deg] = error(0);
  const auto [point_to_line_m, point_to_line_deg] = error(IcpOptions{}.point_to_line_iterations);
  EXPECT_LT(point_to_line_m, 0.001);
  EXPECT_LT(point_to_line_deg, 0.02);
  // What the refinement is for: point-to-point alone stops further off (7 mm here).
  EXPECT_GT(point_to_point_m, 3 * point_to_line_m) << point_to_point_m << " m, " << point_to_point_deg << " deg";
}

// Two walls 2 m apart along x, from x0 to x1, one point every `step` metres.
mrpt::maps::CSimplePointsMap Corridor(double x0, double x1, double step) {
  mrpt::maps::CSimplePointsMap points;
  for (double x = x0; x <= x1; x += step) {
    points.insertPoint(static_cast<float>(x), -1.0f, 0);
    points.insertPoint(static_cast<float>(x), 1.0f, 0);
  }
  return points;
}

// A filled disc of points 3 cm apart, radius 0.15 m: a person seen from above, a blob
// with no line through it.
void AddPerson(mrpt::maps::CSimplePointsMap& points, double cx, double cy) {
  for (double dx = -0.15; dx <= 0.15; dx += 0.03) {
    for (double dy = -0.15; dy <= 0.15; dy += 0.03) {
      if (std::hypot(dx, dy) <= 0.15) points.insertPoint(static_cast<float>(cx + dx), static_cast<float>(cy + dy), 0);
    }
  }
}

// A corridor scan taken where the guess says, with a person who has walked 0.4 m on
// since the map saw them: point-to-point ICP pairs the two and, with nothing along the
// walls to hold it, slides the scan back after them; the refinement from the guess
// fits the walls as well and the person no worse, so the guess stays.
TEST(IcpTest, CorridorScanIsNotDraggedAlongTheWallsByAPersonWalking) {
  auto map = Corridor(-8.0, 8.0, 0.05);
  auto scan = Corridor(-6.0, 6.0, 0.033);  // taken at the map's origin
  AddPerson(map, 2.0, 0.0);
  AddPerson(scan, 2.4, 0.0);
  auto align = [&](int point_to_line_iterations) {
    IcpOptions options;
    options.point_to_line_iterations = point_to_line_iterations;
    IcpAligner icp(options);
    return icp.Align(IndexedPoints(map), scan, CPose2D()).pose;
  };
  const CPose2D point_to_point = align(0), refined = align(IcpOptions{}.point_to_line_iterations);
  EXPECT_LT(point_to_point.x(), -0.1) << "point-to-point ICP is no longer dragged: the test lost its point";
  EXPECT_LT(std::abs(refined.x()), 0.01);
  EXPECT_LT(std::abs(refined.y()), 0.01);
  EXPECT_LT(std::abs(mrpt::RAD2DEG(refined.phi())), 0.1);
}

// Walls at y = ±3 m from x0 to x1, sampled every `step` metres with noise of
// `sigma_m` across them: `scans` copies, as a submap stacks the scans of many keyframes.
mrpt::maps::CSimplePointsMap NoisyCorridor(double x0, double x1, double step, double sigma_m, int scans,
                                           unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::uniform_real_distribution<double> jitter(0.0, step);
  mrpt::maps::CSimplePointsMap points;
  for (int s = 0; s < scans; ++s) {
    const double offset = jitter(rng);
    for (double x = x0 + offset; x <= x1; x += step) {
      points.insertPoint(static_cast<float>(x), static_cast<float>(-3.0 + noise(rng)), 0);
      points.insertPoint(static_cast<float>(x), static_cast<float>(3.0 + noise(rng)), 0);
    }
  }
  return points;
}

// A submap stacked from 40 noisy scans of a corridor is dense along its walls (a few
// millimetres) but noisy across them (1.5 cm): the five points nearest a scan point lie
// across the wall, and the "lines" fitted through them have normals along it, which
// tie the pose along the corridor to the noise. The odometry's prior holds it there;
// lines fitted to the submap's 5 cm cell means are lines again.
TEST(IcpTest, AStackedCorridorSubmapLeavesThePoseAlongTheWallsToTheOdometry) {
  const auto map = NoisyCorridor(-15.0, 15.0, 0.08, 0.015, 40, 7);
  const auto scan = NoisyCorridor(-12.0, 12.0, 0.08, 0.015, 1, 8);  // taken at the map's origin
  const CPose2D guess(0.03, 0.0, 0.0);                              // the odometry, 3 cm ahead
  const IndexedPoints reference(map), means(CellMeans(map, 0.05));
  IcpPrior prior{guess, Eigen::Vector3d(1 / (0.01 * 0.01), 1 / (0.01 * 0.01), 1 / (0.01 * 0.01)).asDiagonal(), 0.015};
  IcpAligner icp(IcpOptions{});
  const CPose2D alone = icp.Align(reference, scan, guess).pose;
  const CPose2D held = icp.Align(reference, scan, guess, &prior, &means).pose;
  // Without the prior nothing holds the pose along the corridor where the guess put it.
  EXPECT_GT(std::abs(alone.x() - guess.x()), 0.01) << "the scan alone pins x: the test lost its point";
  EXPECT_NEAR(held.x(), guess.x(), 0.005);
  EXPECT_NEAR(held.y(), 0.0, 0.003);
  EXPECT_NEAR(mrpt::RAD2DEG(held.phi()), 0.0, 0.05);
}

TEST(ScanMatchingTest, RecoversAKnownMotionWithinOneCentimetreDespiteOdometryError) {
  ScanMatchingOptions options;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  const CPose2D a(2.0, 2.0, 0.1), b(2.6, 2.3, 0.25);
  // Odometry says the car moved 15 cm less and turned 3 degrees less than it did.
  mapper.Add(Stamp{0}, OdometryAt(CPose2D(0, 0, 0)));
  mapper.Add(Stamp{1}, ScanAt(a, Stamp{1}));
  const CPose2D true_motion = b - a;
  const CPose2D odo_motion(true_motion.x() - 0.15, true_motion.y(), true_motion.phi() - mrpt::DEG2RAD(3.0));
  mapper.Add(Stamp{2}, OdometryAt(odo_motion));
  mapper.Add(Stamp{3}, ScanAt(b, Stamp{3}));
  const Trajectory trajectory = mapper.trajectory();
  ASSERT_EQ(trajectory.size(), 2u);
  const CPose2D estimated = CPose2D(trajectory[1].pose) - CPose2D(trajectory[0].pose);
  EXPECT_NEAR(estimated.x(), true_motion.x(), 0.01);
  EXPECT_NEAR(estimated.y(), true_motion.y(), 0.01);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), mrpt::RAD2DEG(true_motion.phi()), 0.2);
  EXPECT_EQ(mapper.stats().rejected_matches, 0);
}

TEST(ScanMatchingTest, ImplausibleMatchFallsBackToOdometryWithoutRecovery) {
  ScanMatchingOptions options;
  options.max_correction_m = 0.05;  // any real correction is now "implausible"
  options.recovery_window_m = 0;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  mapper.Add(Stamp{0}, OdometryAt(CPose2D(0, 0, 0)));
  mapper.Add(Stamp{1}, ScanAt(CPose2D(2, 2, 0), Stamp{1}));
  mapper.Add(Stamp{2}, OdometryAt(CPose2D(0.3, 0, 0)));
  mapper.Add(Stamp{3}, ScanAt(CPose2D(2.5, 2, 0), Stamp{3}));  // truly moved 0.5 m
  EXPECT_EQ(mapper.stats().rejected_matches, 1);
  EXPECT_NEAR(mapper.trajectory()[1].pose.x(), 0.3, 1e-9);
  EXPECT_EQ(mapper.stats().recovered_matches, 0);
}

TEST(ScanMatchingTest, RecoveryFindsAMotionTheOdometryMissed) {
  // The car turned 40° and moved 1 m; odometry reports nothing (as across gaps in
  // the Seattle and Orebro logs). ICP from the guess fails; the correlative search
  // finds the motion.
  ScanMatchingMapper mapper(ScanMatchingOptions{}, nullptr, "base_link");
  const CPose2D a(2.0, 2.0, 0.0), b(2.9, 2.4, mrpt::DEG2RAD(40));
  mapper.Add(Stamp{0}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{1}, ScanAt(a, Stamp{1}));
  mapper.Add(Stamp{2}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{3}, ScanAt(b, Stamp{3}));
  const Trajectory t = mapper.trajectory();
  const CPose2D estimated = CPose2D(t[1].pose) - CPose2D(t[0].pose), truth = b - a;
  EXPECT_NEAR(estimated.x(), truth.x(), 0.02);
  EXPECT_NEAR(estimated.y(), truth.y(), 0.02);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), 40.0, 0.5);
  EXPECT_EQ(mapper.stats().recovered_matches, 1);
}

TEST(ScanMatchingTest, WithoutOdometryUnmatchedScansAreNeitherKeyframesNorCarriedOn) {
  // No odometry; the car moves 0.5 m, then ten scans come back empty (nothing to
  // match), then it has moved 0.6 m more and turned 20°. Carrying the last step on
  // through the empty scans would put the guess 5 m ahead, beyond the search window;
  // keeping them as keyframes would put their (guessed) poses into the graph.
  ScanMatchingMapper mapper(ScanMatchingOptions{}, nullptr, "base_link");
  const CPose2D a(2.0, 2.0, 0.0), b(2.5, 2.0, 0.0), c(3.0, 2.4, mrpt::DEG2RAD(20));
  mapper.Add(Stamp{0}, ScanAt(a, Stamp{0}));
  mapper.Add(Stamp{1}, ScanAt(b, Stamp{1}));
  for (int i = 0; i < 10; ++i) {
    const Stamp t{2 + i};
    mapper.Add(t, Scan180(b, t, [](double) { return -1.0; }));
  }
  mapper.Add(Stamp{20}, ScanAt(c, Stamp{20}));
  const Trajectory t = mapper.trajectory();
  ASSERT_EQ(t.size(), 13u);
  const CPose2D estimated = CPose2D(t.back().pose) - CPose2D(t[0].pose), truth = c - a;
  EXPECT_NEAR(estimated.x(), truth.x(), 0.02);
  EXPECT_NEAR(estimated.y(), truth.y(), 0.02);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), 20.0, 0.5);
  EXPECT_EQ(mapper.stats().keyframes, 3);
}

TEST(ScanMatchingTest, WithoutOdometryAStopIsSearchedWhereTheCarWas) {
  // Odometry reports a 3 m step, then nothing while the car stops and turns on the
  // spot, 40° a scan (as the Orebro log does). The constant-velocity guess runs 3 m
  // on, beyond the ±1 m search window; the car is found where it was. The next scan
  // is predicted from there, not from the unverified guess.
  ScanMatchingOptions options;
  options.recovery_window_m = 1.0;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  const CPose2D a(0.8, 1.0, 0.0), b(3.8, 1.0, 0.0), c(3.8, 1.0, mrpt::DEG2RAD(40)), d(3.8, 1.0, mrpt::DEG2RAD(80));
  mapper.Add(Stamp{0}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{1}, ScanAt(a, Stamp{1}));
  mapper.Add(Stamp{2}, OdometryAt(b - a));
  mapper.Add(Stamp{3}, ScanAt(b, Stamp{3}));
  mapper.Add(Stamp{4}, OdometryAt(b - a));
  mapper.Add(Stamp{5}, ScanAt(c, Stamp{5}));
  mapper.Add(Stamp{6}, ScanAt(d, Stamp{6}));
  const Trajectory t = mapper.trajectory();
  ASSERT_EQ(t.size(), 4u);
  for (size_t i : {2u, 3u}) {
    const CPose2D estimated = CPose2D(t[i].pose) - CPose2D(t[0].pose), truth = (i == 2 ? c : d) - a;
    EXPECT_NEAR(estimated.x(), truth.x(), 0.02) << "scan " << i;
    EXPECT_NEAR(estimated.y(), truth.y(), 0.02) << "scan " << i;
    EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), mrpt::RAD2DEG(truth.phi()), 0.5) << "scan " << i;
  }
  EXPECT_EQ(mapper.stats().rejected_matches, 0);
}

TEST(ScanMatchingTest, WithoutOdometryAStopOutscoresAnAliasAhead) {
  // A 24 m corridor with pillars every 3 m. Odometry reports a 3 m step, then nothing
  // while the car turns on the spot. The constant-velocity guess lands on the next
  // pillar pair, where the scan fits all but the corridor's end: that alias must lose
  // to the stop, which is searched as well and fits the end too.
  std::vector<Box> corridor = {{0, 24, 0, 3}};
  for (double x = 1.5; x < 24; x += 3) corridor.insert(corridor.end(), {{x, x + 0.4, 0, 0.4}, {x, x + 0.4, 2.6, 3}});
  ScanMatchingOptions options;
  options.recovery_window_m = 1.0;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  const CPose2D a(4.7, 1.5, 0.0), b(7.7, 1.5, 0.0), c(7.7, 1.5, mrpt::DEG2RAD(40));
  mapper.Add(Stamp{0}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{1}, ScanAt(a, Stamp{1}, corridor));
  mapper.Add(Stamp{2}, OdometryAt(b - a));
  mapper.Add(Stamp{3}, ScanAt(b, Stamp{3}, corridor));
  mapper.Add(Stamp{4}, OdometryAt(b - a));
  mapper.Add(Stamp{5}, ScanAt(c, Stamp{5}, corridor));
  const Trajectory t = mapper.trajectory();
  ASSERT_EQ(t.size(), 3u);
  const CPose2D estimated = CPose2D(t[2].pose) - CPose2D(t[0].pose), truth = c - a;
  EXPECT_NEAR(estimated.x(), truth.x(), 0.02);
  EXPECT_NEAR(estimated.y(), truth.y(), 0.02);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), 40.0, 0.5);
}

TEST(ScanMatchingTest, GyroYawRateSeedsTheRotationBetweenScans) {
  // Wheels report 0.5 m straight ahead; the car also turned 35°, which only the gyro
  // saw (10 samples over 1 s at 35°/s). Recovery is off: the seed must do it.
  ScanMatchingOptions options;
  options.recovery_window_m = 0;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  const CPose2D a(3.0, 3.0, 0.0), b(3.5, 3.0, mrpt::DEG2RAD(35));
  mapper.Add(Stamp{0}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{1}, ScanAt(a, Stamp{1}));
  for (int k = 0; k <= 10; ++k) {
    auto imu = mrpt::obs::CObservationIMU::Create();
    imu->set(mrpt::obs::IMU_WZ, mrpt::DEG2RAD(35.0));
    mapper.Add(Stamp{1 + k * 100'000'000LL}, imu);
  }
  mapper.Add(Stamp{1'000'000'002}, OdometryAt(CPose2D(0.5, 0, 0)));
  mapper.Add(Stamp{1'000'000'003}, ScanAt(b, Stamp{1'000'000'003}));
  const Trajectory t = mapper.trajectory();
  const CPose2D estimated = CPose2D(t[1].pose) - CPose2D(t[0].pose), truth = b - a;
  EXPECT_NEAR(estimated.x(), truth.x(), 0.01);
  EXPECT_NEAR(estimated.y(), truth.y(), 0.01);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), 35.0, 0.2);
  EXPECT_EQ(mapper.stats().imu, 11);
  EXPECT_EQ(mapper.stats().rejected_matches, 0);
}

// A scan of a featureless corridor (walls at y = ±1.5 m) from `pose`.
mrpt::obs::CObservation2DRangeScan::Ptr CorridorScan(const CPose2D& pose) {
  return Scan180(pose, Stamp{0}, [&](double a) {
    const double dy = std::sin(a);
    return std::abs(dy) < 1e-9 ? -1.0 : ((dy > 0 ? 1.5 : -1.5) - pose.y()) / dy;
  });
}

TEST(ScanMatchingTest, InACorridorOdometryDecidesTheMotionAlongTheWalls) {
  // The scan cannot tell how far the car moved along the corridor; with fusion the
  // odometry's 0.6 m decides, while the lateral offset and heading still come from
  // the scan (odometry claims 0.2 m and 4° of drift there).
  ScanMatchingOptions options;
  options.fuse_odometry = true;
  options.recovery_window_m = 0;
  ScanMatchingMapper mapper(options, nullptr, "base_link");
  const CPose2D a(0, 0.2, 0.0), b(0.6, 0.0, mrpt::DEG2RAD(2));
  mapper.Add(Stamp{0}, OdometryAt(CPose2D()));
  mapper.Add(Stamp{1}, CorridorScan(a));
  mapper.Add(Stamp{2}, OdometryAt(CPose2D(0.6, 0.0, mrpt::DEG2RAD(6))));
  mapper.Add(Stamp{3}, CorridorScan(b));
  const Trajectory t = mapper.trajectory();
  const CPose2D estimated = CPose2D(t[1].pose) - CPose2D(t[0].pose), truth = b - a;
  EXPECT_NEAR(estimated.x(), truth.x(), 0.05);
  EXPECT_NEAR(estimated.y(), truth.y(), 0.02);
  EXPECT_NEAR(mrpt::RAD2DEG(estimated.phi()), 2.0, 0.3);
}

TEST(ScanMatchingTest, SensorMountFromFramesOverridesTheRecordedOne) {
  FramesOptions frames_options;
  frames_options.static_transforms.push_back({"base_link", "LASER", {0.5, 0, 0}, {0, 0, 0}});
  const TransformTree frames(frames_options);
  ScanMatchingMapper mapper(ScanMatchingOptions{}, &frames, "base_link");
  // The laser is 0.5 m ahead of base_link; its scan is taken from (2.5, 2).
  mapper.Add(Stamp{1}, ScanAt(CPose2D(2.5, 2, 0), Stamp{1}));
  const auto& kf = mapper.keyframes().at(0);
  EXPECT_NEAR(kf.scan->sensorPose.x(), 0.5, 1e-12);
}

struct Pass {
  std::vector<Keyframe> first, second;
};

// The built-in rawlog drives one loop, then its first corridor again. The second pass
// starts where the car, after 30 m of travel, comes closest to where it started.
Pass SplitAtReturn(const std::vector<Keyframe>& keyframes) {
  double travelled = 0, closest = 1e9;
  size_t split = keyframes.size();
  for (size_t i = 1; i < keyframes.size(); ++i) {
    travelled += keyframes[i].pose.distanceTo(keyframes[i - 1].pose);
    const double d = keyframes[i].pose.distanceTo(keyframes[0].pose);
    if (travelled > 30.0 && d < closest) closest = d, split = i;
  }
  Pass p;
  p.first.assign(keyframes.begin(), keyframes.begin() + split);
  p.second.assign(keyframes.begin() + split, keyframes.end());
  return p;
}

// The built-in rawlog mapped with default parameters, by scan matching alone or by
// graph SLAM.
class BuiltInRawlogTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    rawlog_ = testing::BuiltInRawlog();
    if (rawlog_.empty()) SPECHT_SKIP() << "mrpt-common's rawlog not installed";
    SlamOptions slam;
    slam.method = GetParam();
    slam_ = std::make_unique<GraphSlam>(slam, ScanMatchingOptions{}, LoopClosureOptions{}, PoseGraphOptions{}, nullptr,
                                        "base_link");
    auto source = io::OpenDataset(rawlog_);
    while (auto obs = source->Next()) slam_->Add(obs->stamp, obs->data);
    slam_->Finish();
  }
  std::string rawlog_;
  std::unique_ptr<GraphSlam> slam_;
};

// Scans of the second pass, registered (ICP) against the grid of the first pass: the
// mean correction stays within a margin of what both front ends reach.
TEST_P(BuiltInRawlogTest, SecondPassAgreesWithTheFirstPassGrid) {
  const Pass pass = SplitAtReturn(slam_->keyframes());
  ASSERT_GT(pass.first.size(), 50u);
  ASSERT_GT(pass.second.size(), 10u);
  const auto grid = BuildGrid(pass.first, GridOptions{});
  const auto corrections = eval::RegisterAgainstGrid(grid, pass.second, IcpOptions{});
  double mean_m = 0, mean_deg = 0;
  for (const auto& c : corrections) mean_m += c.translation_m, mean_deg += c.rotation_deg;
  mean_m /= corrections.size();
  mean_deg /= corrections.size();
  RecordProperty("second_pass_keyframes", static_cast<int>(pass.second.size()));
  RecordProperty("mean_correction_m", std::to_string(mean_m));
  RecordProperty("mean_correction_deg", std::to_string(mean_deg));
  std::printf("%s: second pass %zu keyframes, mean ICP correction %.3f m, %.2f deg\n", GetParam().c_str(),
              pass.second.size(), mean_m, mean_deg);
  const bool graph = GetParam() == "graph";
  EXPECT_LT(mean_m, 0.05);                  // measured 0.026 m (graph), 0.032 m (scan matching)
  EXPECT_LT(mean_deg, graph ? 0.5 : 0.25);  // measured 0.26°, 0.07°
}

// Walls are thin: on the centre line of every occupied band, 95 % of the band is at
// most 3 cells (0.15 m) thick. Misregistered passes smear a wall into a band of
// several cells (the 0.5 m tolerance above would allow up to 10).
TEST_P(BuiltInRawlogTest, OccupiedCellsFormThinWalls) {
  const auto grid = BuildGrid(slam_->keyframes(), GridOptions{});
  const auto walls = eval::MeasureWallThickness(grid);
  std::printf("wall thickness: p50 %.3f m, p95 %.3f m over %zu centre cells\n", walls.p50_m, walls.p95_m,
              walls.centre_cells);
  EXPECT_GT(walls.centre_cells, 1000u);
  EXPECT_LE(walls.p95_m, 0.15 + 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Methods, BuiltInRawlogTest, ::testing::Values("scan_matching", "graph"));

// The measure itself: a 1-cell wall is 1 cell thick, a smeared 7-cell band is 7.
TEST(WallThicknessTest, MeasuresBandWidthOnTheCentreLine) {
  mrpt::maps::COccupancyGridMap2D grid(0.0f, 10.0f, 0.0f, 10.0f, 0.1f);
  for (unsigned x = 10; x < 90; ++x) grid.setCell(x, 20, 0.0f);  // thin wall
  for (unsigned x = 10; x < 90; ++x)
    for (unsigned y = 60; y < 67; ++y) grid.setCell(x, y, 0.0f);  // band
  const auto walls = eval::MeasureWallThickness(grid);
  EXPECT_NEAR(walls.p50_m, 0.1, 0.001);
  EXPECT_NEAR(walls.p95_m, 0.7, 0.001);
}

// A grid taller than the bands the measure works in: a 1-cell wall running across
// every band boundary, and a 9-cell band lying across one, measure as on a small grid.
TEST(WallThicknessTest, BandsOfRowsMeasureAsTheWholeGrid) {
  mrpt::maps::COccupancyGridMap2D grid(0.0f, 10.0f, 0.0f, 150.0f, 0.1f);  // 1,500 rows
  for (unsigned y = 10; y < 1490; ++y) grid.setCell(20, y, 0.0f);         // thin wall, vertical
  for (unsigned x = 40; x < 90; ++x)
    for (unsigned y = 508; y < 517; ++y) grid.setCell(x, y, 0.0f);  // band over rows 508–516 (a band edge at 512)
  const auto walls = eval::MeasureWallThickness(grid);
  EXPECT_NEAR(walls.p50_m, 0.1, 0.001);
  EXPECT_NEAR(walls.p95_m, 0.1, 0.001);  // the band's centre line holds few cells beside the wall's
  mrpt::maps::COccupancyGridMap2D band_only(0.0f, 10.0f, 0.0f, 150.0f, 0.1f);
  for (unsigned x = 40; x < 90; ++x)
    for (unsigned y = 508; y < 517; ++y) band_only.setCell(x, y, 0.0f);
  EXPECT_NEAR(eval::MeasureWallThickness(band_only).p50_m, 0.9, 0.001);
}

// Mean map entropy: two scans of one straight wall, the second placed δ off it.
// Half the neighbourhood on each line gives σ⊥² = δ²/4, so h grows by ln 2 when δ
// doubles (det Σ ∝ δ²); placed together the scans are far sharper.
TEST(MapEntropyTest, GrowsByLnTwoWhenTheOffsetBetweenTwoPassesDoubles) {
  const auto wall = [](double a) { return std::sin(a) > 0.2 ? 2.0 / std::sin(a) : -1.0; };  // y = 2
  const Stamp t0 = Stamp::FromSeconds(1), t1 = Stamp::FromSeconds(2);
  auto entropy = [&](double offset) {
    const std::vector<Keyframe> kfs = {{0, t0, CPose2D(0, 0, 0), Scan180(CPose2D(0, 0, 0), t0, wall)},
                                       {1, t1, CPose2D(0, offset, 0), Scan180(CPose2D(0, 0, 0), t1, wall)}};
    return eval::MeanMapEntropy(kfs).mean_nats;
  };
  const double h0 = entropy(0.0), h5 = entropy(0.05), h10 = entropy(0.1);
  EXPECT_NEAR(h10 - h5, std::log(2.0), 0.1);
  EXPECT_GT(h5 - h0, 1.0);
}

TEST(MapEntropyTest, NoPointsGiveNoEntropy) {
  EXPECT_EQ(eval::MeanMapEntropy({}).points, 0u);
  // Only returns beyond max_range_m (a wall 12 m away), and a scan of nothing.
  const Stamp t0 = Stamp::FromSeconds(1), t1 = Stamp::FromSeconds(2);
  const auto far_wall = [](double a) { return std::sin(a) > 0.2 ? 12.0 / std::sin(a) : -1.0; };
  const std::vector<Keyframe> kfs = {
      {0, t0, CPose2D(0, 0, 0), Scan180(CPose2D(0, 0, 0), t0, far_wall)},
      {1, t1, CPose2D(1, 0, 0), Scan180(CPose2D(0, 0, 0), t1, [](double) { return -1.0; })}};
  const eval::MapEntropy h = eval::MeanMapEntropy(kfs);
  EXPECT_EQ(h.points, 0u);
  EXPECT_EQ(h.mean_nats, 0.0);
}

TEST(MapEntropyTest, ReferencePosesReplaceTheEstimateByTimeStamp) {
  const Stamp t0 = Stamp::FromSeconds(1), t1 = Stamp::FromSeconds(2), t2 = Stamp::FromSeconds(3);
  const auto scan = ScanAt(CPose2D(2, 2, 0), t0);
  const std::vector<Keyframe> kfs = {
      {0, t0, CPose2D(0, 0, 0), scan}, {1, t1, CPose2D(1, 0, 0), scan}, {2, t2, CPose2D(2, 0, 0), scan}};
  const Trajectory reference = {{t0, mrpt::poses::CPose3D(5, 5, 0, 0, 0, 0)},
                                {Stamp::FromSeconds(2.5), mrpt::poses::CPose3D(6, 5, 0, 0, 0, 0)},
                                {t2, mrpt::poses::CPose3D(7, 5, 0, 0, 0, 0)}};
  const auto [at_estimate, at_reference] = eval::KeyframesAtReference(kfs, reference, 0.05);
  ASSERT_EQ(at_estimate.size(), 2u);  // t1 has no reference pose within 50 ms
  EXPECT_EQ(at_estimate[1].stamp, t2);
  EXPECT_DOUBLE_EQ(at_estimate[1].pose.x(), 2.0);
  EXPECT_DOUBLE_EQ(at_reference[1].pose.x(), 7.0);
  EXPECT_DOUBLE_EQ(at_reference[0].pose.y(), 5.0);
}

}  // namespace
}  // namespace specht::slam
