// Box depth fusion on the simulator's crossing, against the rendered truth (slow:
// renders KITTI-sized stereo frames).
#include <cstdio>
#include <sstream>

#include "specht/detect/fusion.h"
#include "specht/sim/simulator.h"
#include "specht/stereo/sgm.h"
#include "test_support.h"

namespace specht::detect {
namespace {

// Acceptance 2, synthetic: on the simulated crossing (KITTI-like camera), every agent
// box of the rendered KITTI labels fused with our SGM disparity, against the true
// rendered disparity inside the same box.
TEST(FusionTest, BoxDistanceAgreesWithSyntheticTruth) {
  sim::Scenario s = sim::LoadScenario(testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml");
  s.stereo->width = 1242;
  s.stereo->height = 375;
  s.stereo->focal_px = 721;
  s.stereo->baseline_m = 0.54;
  s.stereo->rate_hz = 1.0;
  sim::Simulator simulator(s, 2);
  const stereo::RectifiedCamera camera{cv::Size(1242, 375), 721, (1242 - 1) / 2.0, (375 - 1) / 2.0, 0.54};
  std::vector<double> errors[2];
  stereo::SemiGlobalMatcher matcher{stereo::SgmOptions()};
  for (int k = 0; k < 1500; ++k) {
    simulator.Step([](Stamp, const mrpt::obs::CObservation::Ptr&) {},
                   [&](Stamp, const sim::StereoFrame& f) {
                     const cv::Mat disparity = matcher.Compute(f.left, f.right);
                     for (const auto& line : f.kitti_labels) {
                       std::istringstream fields(line);
                       std::string type;
                       double truncated, occluded, alpha, l, t, r, b;
                       fields >> type >> truncated >> occluded >> alpha >> l >> t >> r >> b;
                       if (truncated > 0 || r - l < 12 || b - t < 20) continue;  // whole and big enough to detect
                       Detection d{cv::Rect2d(cv::Point2d(l, t), cv::Point2d(r, b)), "car", type, 1.0};
                       const double reference_d = BoxDisparity(d.box, f.disparity, FusionOptions());
                       if (!(reference_d > 0) || camera.DepthOf(reference_d) > 30) continue;
                       for (int m = 0; m < 2; ++m) {
                         FusionOptions options;
                         options.method = m == 0 ? "centre" : "nearest_mode";
                         const auto o = Fuse(d, disparity, camera, options);
                         const double reference_m = camera.DepthOf(reference_d);
                         errors[m].push_back(o ? std::abs(o->distance_m - reference_m) / reference_m : 1.0);
                       }
                     }
                   });
  }
  for (int m = 0; m < 2; ++m) {
    ASSERT_GE(errors[m].size(), 5u);
    std::nth_element(errors[m].begin(), errors[m].begin() + static_cast<long>(errors[m].size() / 2), errors[m].end());
    std::printf("%s vs synthetic truth: median relative distance error %.2f %% over %zu agent boxes\n",
                m == 0 ? "centre" : "nearest_mode", 100 * errors[m][errors[m].size() / 2], errors[m].size());
  }
  EXPECT_LE(errors[1][errors[1].size() / 2], 0.05);
}

}  // namespace
}  // namespace specht::detect
