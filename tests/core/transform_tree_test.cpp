#include "specht/core/transform_tree.h"

#include <gtest/gtest.h>

#include <cmath>

namespace specht {
namespace {

using mrpt::poses::CPose3D;

void ExpectNear(const CPose3D& a, const CPose3D& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(a.z(), b.z(), tol);
  EXPECT_NEAR(a.yaw(), b.yaw(), tol);
  EXPECT_NEAR(a.pitch(), b.pitch(), tol);
  EXPECT_NEAR(a.roll(), b.roll(), tol);
}

TEST(TransformTreeTest, ComposesAStaticChainAndItsInverse) {
  TransformTree tree;
  // A laser 1 m ahead of the car, turned left by 90 degrees.
  tree.SetStatic("base_link", "laser", CPose3D(1, 0, 0.5, M_PI / 2, 0, 0));
  // A point 2 m in front of the laser is at (1, 2, 0.5) in base_link.
  tree.SetStatic("laser", "target", CPose3D(2, 0, 0, 0, 0, 0));
  ExpectNear(tree.LookupStatic("base_link", "target"), CPose3D(1, 2, 0.5, M_PI / 2, 0, 0));
  ExpectNear(tree.LookupStatic("target", "base_link"), -CPose3D(1, 2, 0.5, M_PI / 2, 0, 0));
}

TEST(TransformTreeTest, LooksUpAcrossBranchesThroughTheCommonRoot) {
  TransformTree tree;
  tree.SetStatic("base_link", "left_camera", CPose3D(0.5, 0.25, 1, 0, 0, 0));
  tree.SetStatic("base_link", "right_camera", CPose3D(0.5, -0.25, 1, 0, 0, 0));
  ExpectNear(tree.LookupStatic("left_camera", "right_camera"), CPose3D(0, -0.5, 0, 0, 0, 0));
}

TEST(TransformTreeTest, InterpolatesDynamicTransformsInTime) {
  TransformTree tree;
  tree.Set("odom", "base_link", Stamp{1'000'000'000}, CPose3D(0, 0, 0, 0, 0, 0));
  tree.Set("odom", "base_link", Stamp{2'000'000'000}, CPose3D(2, 0, 0, 0, 0, 0));
  tree.SetStatic("base_link", "laser", CPose3D(0.5, 0, 0, 0, 0, 0));
  ExpectNear(tree.Lookup("odom", "laser", Stamp{1'500'000'000}), CPose3D(1.5, 0, 0, 0, 0, 0), 1e-6);
  EXPECT_THROW(tree.Lookup("odom", "laser", Stamp{9'000'000'000}), RuntimeError);
  EXPECT_THROW(tree.LookupStatic("odom", "laser"), RuntimeError);
}

TEST(TransformTreeTest, RejectsSecondParentsCyclesAndUnknownFrames) {
  TransformTree tree;
  tree.SetStatic("base_link", "laser", CPose3D());
  EXPECT_THROW(tree.SetStatic("odom", "laser", CPose3D()), InputError);
  EXPECT_THROW(tree.SetStatic("laser", "base_link", CPose3D()), InputError);
  EXPECT_THROW(tree.SetStatic("laser", "laser", CPose3D()), InputError);
  EXPECT_THROW(tree.LookupStatic("base_link", "camera"), RuntimeError);
  tree.SetStatic("island", "rock", CPose3D());
  EXPECT_THROW(tree.LookupStatic("base_link", "rock"), RuntimeError);
}

TEST(TransformTreeTest, BuildsFromFrameOptions) {
  FramesOptions options;
  options.static_transforms.push_back({"base_link", "LASER", {0.2, 0, 0.3}, {0, 0, 90}});
  const TransformTree tree(options);
  ExpectNear(tree.LookupStatic("base_link", "LASER"), CPose3D(0.2, 0, 0.3, M_PI / 2, 0, 0), 1e-12);
  options.static_transforms.push_back({"base_link", "LASER", {0, 0, 0}, {0, 0, 0}});
  options.static_transforms.push_back({"LASER", "odom", {0, 0, 0}, {0, 0, 0}});
  EXPECT_EQ(options.Relations().size(), 2u);
}

TEST(TransformTreeTest, CodecRejectsMalformedEntries) {
  std::vector<StaticTransform> out;
  std::string why;
  using Codec = params::Codec<std::vector<StaticTransform>>;
  EXPECT_FALSE(Codec::Decode(YAML::Load("[{parent: a}]"), out, &why));
  EXPECT_EQ(why, "entry 0: needs both 'parent' and 'child'");
  EXPECT_FALSE(Codec::Decode(YAML::Load("[{parent: a, child: b, xyz_m: [1, 2]}]"), out, &why));
  EXPECT_EQ(why, "entry 0: xyz_m and rpy_deg need exactly 3 numbers each");
  EXPECT_FALSE(Codec::Decode(YAML::Load("[{parent: a, child: b, xyz: [1, 2, 3]}]"), out, &why));
  EXPECT_EQ(why, "entry 0: unknown field 'xyz' (parent, child, xyz_m, rpy_deg)");
  EXPECT_TRUE(Codec::Decode(YAML::Load("[{parent: a, child: b, xyz_m: [1, 2, 3], rpy_deg: [0, 0, 0]}]"), out, &why));
}

}  // namespace
}  // namespace specht
