// Stereo on the simulator's urban crossing, where the truth is known exactly: the
// scene prior (acceptance 3) and the OctoMap built from stereo points (acceptance 4).
#include <cstdio>
#include <set>
#include <tuple>

#include "specht/eval/disparity_error.h"
#include "specht/sim/camera.h"
#include "specht/sim/simulator.h"
#include "specht/stereo/guidance.h"
#include "specht/stereo/point_cloud.h"
#include "specht/stereo/sgm.h"
#include "test_support.h"

namespace specht::stereo {
namespace {

// A frame of the urban crossing with agents in view, its static-world rendering
// from the same pose (the prior), and the pixels where agents are in front.
struct SceneWithAgents {
  sim::StereoFrame frame, static_world;
  cv::Mat agent_mask, static_mask;
  RectifiedCamera camera;
};

SceneWithAgents RenderCrossing(double seconds) {
  sim::Scenario s = sim::LoadScenario(testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml");
  // A camera like KITTI's (1242×375, f = 721 px, B = 0.54 m) on the scenario's mount.
  s.stereo->width = 1242;
  s.stereo->height = 375;
  s.stereo->focal_px = 721;
  s.stereo->baseline_m = 0.54;
  sim::Simulator simulator(s, 2);
  for (int k = 0; k < static_cast<int>(seconds / sim::Simulator::kStepS); ++k)
    simulator.Step([](Stamp, const mrpt::obs::CObservation::Ptr&) {});
  const sim::StereoRenderer renderer(s, simulator.world(), *s.stereo);
  SceneWithAgents scene;
  scene.frame = renderer.Render(simulator.ego().pose, simulator.AgentBoxes());
  scene.static_world = renderer.Render(simulator.ego().pose, {});
  // Agents: pixels whose surface is nearer than the static world's by > 0.2 m.
  const cv::Mat nearer = scene.static_world.depth - scene.frame.depth;
  scene.agent_mask = (nearer > 0.2) & (scene.frame.depth > 0);
  scene.static_mask = (scene.frame.disparity > 0) & ~scene.agent_mask;
  scene.camera = RectifiedCamera{scene.frame.left.size(), s.stereo->focal_px, (s.stereo->width - 1) / 2.0,
                                 (s.stereo->height - 1) / 2.0, s.stereo->baseline_m};
  return scene;
}

double D1(const cv::Mat& disparity, const cv::Mat& truth, const cv::Mat& mask) {
  cv::Mat filled = disparity.clone();
  FillHolesRowwise(filled);
  return eval::CompareDisparity(filled, truth, mask).d1_all;
}

// Acceptance 3: with the static world as a dense prior, static structure improves and
// the agents (not in the prior) are no worse than unguided; the paper's hard window
// without the consistency check is the failure case: agents forced onto the background.
TEST(ScenePriorTest, StaticStructureImprovesAndAgentsAreKept) {
  const SceneWithAgents scene = RenderCrossing(8.0);
  const long agent_pixels = cv::countNonZero(scene.agent_mask);
  ASSERT_GT(agent_pixels, 500) << "no agent in view";
  SgmOptions options;
  const Guidance prior = PriorGuidance(scene.static_world.disparity, 1.0);
  const cv::Mat unguided = ComputeDisparity(scene.frame.left, scene.frame.right, options);
  const cv::Mat guided = ComputeDisparity(scene.frame.left, scene.frame.right, options, &prior);
  SgmOptions hard = options;
  hard.prior = GuidanceOptions{"window", 255, 1.0, 3.0, 0};
  const cv::Mat forced = ComputeDisparity(scene.frame.left, scene.frame.right, hard, &prior);

  const cv::Mat& truth = scene.frame.disparity;
  const double static_unguided = D1(unguided, truth, scene.static_mask),
               static_guided = D1(guided, truth, scene.static_mask);
  const double agents_unguided = D1(unguided, truth, scene.agent_mask),
               agents_guided = D1(guided, truth, scene.agent_mask);
  const double agents_forced = D1(forced, truth, scene.agent_mask),
               static_forced = D1(forced, truth, scene.static_mask);
  std::printf("static D1: unguided %.2f %%, prior %.2f %%, hard window %.2f %%\n", 100 * static_unguided,
              100 * static_guided, 100 * static_forced);
  std::printf("agents D1 (%ld px): unguided %.2f %%, prior %.2f %%, hard window %.2f %%\n", agent_pixels,
              100 * agents_unguided, 100 * agents_guided, 100 * agents_forced);
  EXPECT_LT(static_guided, 0.8 * static_unguided);
  EXPECT_LE(agents_guided, agents_unguided + 0.005);
  EXPECT_GT(agents_forced, agents_guided + 0.05) << "the failure case should show without the consistency check";
}

// The ground-plane prior (camera height and pitch) is the rendered ground's disparity.
TEST(ScenePriorTest, GroundPlanePriorMatchesTheRenderedGround) {
  const SceneWithAgents scene = RenderCrossing(2.0);
  const sim::Scenario s = sim::LoadScenario(testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml");
  GroundPlane plane{scene.camera.focal_px, scene.camera.cy_px, scene.camera.baseline_m, s.stereo->z_m,
                    s.stereo->pitch_rad};
  const cv::Mat prior = GroundPlaneDisparity(plane, scene.frame.left.size(), 256);
  // The bottom rows see mostly ground (objects standing there differ, of course).
  const int rows = scene.frame.left.rows;
  long pixels = 0, agree = 0;
  for (int v = rows - 40; v < rows; ++v)
    for (int u = 0; u < scene.frame.left.cols; ++u) {
      ++pixels;
      agree += std::abs(prior.at<float>(v, u) - scene.static_world.disparity.at<float>(v, u)) < 0.05f;
    }
  std::printf("ground-plane prior vs rendered ground, bottom 40 rows: %.1f %% within 0.05 px\n",
              100.0 * agree / pixels);
  EXPECT_GT(agree, 0.8 * pixels);
}

using VoxelKey = std::tuple<int, int, int>;
VoxelKey KeyOf(const octomap::OcTree& tree, double x, double y, double z) {
  const octomap::OcTreeKey k = tree.coordToKey(x, y, z);
  return {k[0], k[1], k[2]};
}
bool NearAny(const std::set<VoxelKey>& keys, const VoxelKey& k) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (keys.count({std::get<0>(k) + dx, std::get<1>(k) + dy, std::get<2>(k) + dz})) return true;
  return false;
}

// Acceptance 4: an OcTree (0.2 m) from the synthetic stereo agrees with the true
// geometry within 20 m: precision (occupied voxels with a true surface in their
// neighbourhood) and recall (true surface voxels with an occupied neighbour) ≥ 0.9.
TEST(StereoOctomapTest, OccupiedVoxelsMatchTheTrueGeometry) {
  const SceneWithAgents scene = RenderCrossing(8.0);
  CloudOptions options;
  options.max_depth_m = 20;
  const cv::Mat disparity = ComputeDisparity(scene.frame.left, scene.frame.right, SgmOptions());
  octomap::OcTree tree(options.octree_resolution_m);
  InsertIntoOctree(tree, DisparityToPoints(disparity, scene.camera, scene.frame.left, options), {0, 0, 0}, options);

  // The true surface: every pixel's true depth, back-projected.
  std::set<VoxelKey> truth;
  const cv::Mat true_points_disparity = scene.frame.disparity;
  for (const auto& p : DisparityToPoints(true_points_disparity, scene.camera, cv::Mat(), options))
    if (cv::norm(p.xyz) <= 20) truth.insert(KeyOf(tree, p.xyz.x, p.xyz.y, p.xyz.z));
  long occupied = 0, correct = 0;
  std::set<VoxelKey> occupied_keys;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it) || it.getCoordinate().norm() > 20) continue;
    const VoxelKey k = KeyOf(tree, it.getX(), it.getY(), it.getZ());
    occupied_keys.insert(k);
    ++occupied;
    correct += NearAny(truth, k);
  }
  long found = 0;
  for (const auto& k : truth) found += NearAny(occupied_keys, k);
  const double precision = static_cast<double>(correct) / occupied, recall = static_cast<double>(found) / truth.size();
  std::printf("OctoMap 0.2 m within 20 m: %ld occupied voxels, %zu true; precision %.3f, recall %.3f\n", occupied,
              truth.size(), precision, recall);
  EXPECT_GE(precision, 0.9);
  EXPECT_GE(recall, 0.9);
}

}  // namespace
}  // namespace specht::stereo
