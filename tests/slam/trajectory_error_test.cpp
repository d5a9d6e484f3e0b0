#include "specht/eval/trajectory_error.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "specht/core/error.h"
#include "specht/eval/relation_error.h"

namespace specht::eval {
namespace {

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

Trajectory Circle(int n) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    t.push_back({Stamp{int64_t(i) * 100'000'000}, CPose3D(5 * std::cos(a), 5 * std::sin(a), 0, a + M_PI / 2, 0, 0)});
  }
  return t;
}

TEST(TrajectoryErrorTest, ARigidlyMovedCopyHasZeroErrorAndTheAlignmentIsRecovered) {
  const Trajectory reference = Circle(100);
  const CPose2D offset(3, -2, 0.7);
  const Trajectory estimate = Transform(reference, offset);
  const AteResult r = AbsoluteTrajectoryError2D(estimate, reference, 0.01);
  EXPECT_EQ(r.pairs, 100u);
  EXPECT_NEAR(r.rmse_m, 0, 1e-9);
  EXPECT_NEAR(r.rmse_deg, 0, 1e-7);
  const CPose2D back = r.alignment + offset;  // alignment undoes the offset
  EXPECT_NEAR(back.norm(), 0, 1e-9);
  EXPECT_NEAR(back.phi(), 0, 1e-9);
}

TEST(TrajectoryErrorTest, IsotropicNoiseGivesItsExpectedRmse) {
  const Trajectory reference = Circle(2000);
  Trajectory estimate = reference;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.1);
  for (auto& p : estimate) p.pose.x_incr(noise(rng)), p.pose.y_incr(noise(rng));
  // E|e| for 2D Gaussian noise with sigma 0.1: RMSE = 0.1 * sqrt(2).
  EXPECT_NEAR(AbsoluteTrajectoryError2D(estimate, reference, 0.01).rmse_m, 0.1 * std::sqrt(2.0), 0.005);
}

TEST(TrajectoryErrorTest, PairsByNearestStampWithinTolerance) {
  Trajectory a = {{Stamp{0}, CPose3D()}, {Stamp{1'000'000'000}, CPose3D()}, {Stamp{5'000'000'000}, CPose3D()}};
  Trajectory b = {{Stamp{20'000'000}, CPose3D()}, {Stamp{990'000'000}, CPose3D()}};
  const auto pairs = AssociateByTime(a, b, 0.05);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0], std::make_pair(size_t(0), size_t(0)));
  EXPECT_EQ(pairs[1], std::make_pair(size_t(1), size_t(1)));
  EXPECT_THROW(AbsoluteTrajectoryError2D(a, {}, 0.05), InputError);
}

TEST(RelationErrorTest, AGlitchAtOneScanShowsInItsTwoConsecutiveRelationsAndHeadsTheWorstList) {
  // 300 poses on a circle of radius 5 m (10.5 cm apart); the estimate is the reference
  // with scan 150 pushed 0.3 m sideways. Loop relations (within 3 m, more than 100
  // scans apart) join the circle's start and end and carry no error.
  const Trajectory reference = Circle(300);
  Trajectory estimate = reference;
  estimate[150].pose.x_incr(0.3);
  RelationOptions options;
  options.worst_count = 3;
  const RelationError e = ComputeRelationError(estimate, reference, options);
  EXPECT_EQ(e.paired_poses, 300u);
  EXPECT_EQ(e.consecutive.count, 299u);
  EXPECT_GT(e.loop.count, 0u);
  EXPECT_NEAR(e.loop.max_m, 0, 1e-9);
  EXPECT_NEAR(e.consecutive.max_m, 0.3, 0.01);
  EXPECT_NEAR(e.all.max_m, e.consecutive.max_m, 1e-12);
  ASSERT_EQ(e.worst.size(), 3u);
  std::vector<std::pair<size_t, size_t>> broken = {{e.worst[0].i, e.worst[0].j}, {e.worst[1].i, e.worst[1].j}};
  std::sort(broken.begin(), broken.end());
  EXPECT_EQ(broken, (std::vector<std::pair<size_t, size_t>>{{149, 150}, {150, 151}}));
  EXPECT_GE(e.worst[0].m, e.worst[1].m);
  EXPECT_NEAR(e.worst[1].m, 0.3, 0.01);
  EXPECT_FALSE(e.worst[0].loop);
  EXPECT_EQ(e.worst[0].stamp_j.ns - e.worst[0].stamp_i.ns, 100'000'000);
  EXPECT_NEAR(e.worst[2].m, 0, 1e-9);  // then the first error-free relation
  EXPECT_EQ(e.worst[2].i, 0u);
  EXPECT_NEAR(e.consecutive.mean_m, (e.worst[0].m + e.worst[1].m) / 299, 1e-12);

  options.worst_count = 0;
  EXPECT_TRUE(ComputeRelationError(estimate, reference, options).worst.empty());
}

// Published relations: the estimate's motion between the two named scans against the
// relation's; a scan pushed 0.3 m aside shows in the relations that name it, stamps
// going backwards in the estimate do not matter, and a relation whose scan is not in
// the estimate is an error naming its line.
TEST(PublishedRelationErrorTest, ScoresEveryRelationByStampAndNamesOneThatDoesNotMatch) {
  Trajectory estimate = Circle(300);
  std::swap(estimate[10], estimate[11]);  // stamps out of order, as Intel's
  io::RelationsFile file{"test.relations", {}};
  for (size_t i = 0; i + 1 < 300; i += 3) {
    const CPose2D a(estimate[i].pose), b(estimate[i + 1].pose);
    file.relations.push_back({estimate[i].stamp, estimate[i + 1].stamp, b - a, static_cast<int64_t>(i / 3 + 1)});
  }
  estimate[150].pose.x_incr(0.3);  // relation 150 → 151 (i = 150 is a multiple of 3)
  PublishedRelationOptions options;
  options.worst_count = 2;
  const PublishedRelationError e = ComputePublishedRelationError(estimate, file, options);
  EXPECT_EQ(e.relations, 100u);
  EXPECT_EQ(e.absolute.count, 100u);
  EXPECT_NEAR(e.absolute.max_m, 0.3, 0.01);
  EXPECT_NEAR(e.absolute.mean_m, e.absolute.max_m / 100, 1e-12);
  EXPECT_NEAR(e.squared.mean_m, e.absolute.max_m * e.absolute.max_m / 100, 1e-12);
  ASSERT_EQ(e.worst.size(), 2u);
  EXPECT_EQ(e.worst[0].i, 150u);
  EXPECT_EQ(e.worst[0].j, 151u);
  EXPECT_EQ(RelationSegments(estimate, e.worst).size(), 4u);

  file.relations[7].t2 = Stamp{file.relations[7].t2.ns + 5'000'000};  // 5 ms off: no scan there
  try {
    ComputePublishedRelationError(estimate, file, options);
    FAIL() << "a relation without its scan was scored";
  } catch (const InputError& err) {
    EXPECT_THAT(err.what(), ::testing::HasSubstr("test.relations:8: the relation's stamp"));
    EXPECT_THAT(err.what(), ::testing::HasSubstr("1 of 100 relations do not match"));
  }
}

}  // namespace
}  // namespace specht::eval
