// stereo_bench [data_dir]: the matchers side by side on the KITTI 2015 frames of
// <data_dir>/stereo/kitti2015 (1242×375, 128 disparities): OpenCV StereoSGBM
// (3-way, the data README's settings) and specht's SGM at 1 and 2 threads, each
// instruction set, unguided and guided by 5 % ground-truth hints. Per case: ms per
// frame (median of 5 runs), D1-all with holes filled row-wise (as KITTI scores),
// D1 and density of the raw output. One JSON object per case and frame.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "bench_support.h"
#include "specht/eval/disparity_error.h"
#include "specht/stereo/guidance.h"
#include "specht/stereo/images.h"
#include "specht/stereo/sgm.h"

namespace {

using specht::stereo::SgmOptions;

struct Case {
  std::string name;
  SgmOptions options;
  bool guided = false;
};

std::vector<Case> Cases() {
  std::vector<Case> cases;
  SgmOptions sgbm;
  sgbm.matcher = "opencv_sgbm";
  sgbm.uniqueness = 10;
  sgbm.speckle_range_px = 2;
  for (int threads : {1, 2}) {
    sgbm.threads = threads;
    cases.push_back({"opencv_sgbm_3way/t" + std::to_string(threads), sgbm});
  }
  for (int threads : {1, 2}) {
    SgmOptions o;
    o.threads = threads;
    cases.push_back({"specht_sgm/t" + std::to_string(threads), o});
    cases.push_back({"specht_sgm_guided/t" + std::to_string(threads), o, true});
  }
  for (const char* isa : {"scalar", "sse4.1", "avx2", "avx512"}) {
    SgmOptions o;
    o.simd = isa;
    cases.push_back({std::string("specht_sgm/") + isa + "/t2", o});
  }
  return cases;
}

}  // namespace

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const std::string data = argc > 1 ? argv[1] : SPECHT_DATA_DIR;
  const std::string kitti = data + "/stereo/kitti2015";
  if (!std::filesystem::is_directory(kitti)) {
    std::cerr << "stereo_bench: " << kitti << " not found\n";
    return 2;
  }
  for (const char* frame : {"000000_10", "000001_10"}) {
    const cv::Mat left = specht::stereo::ReadGray8(kitti + "/image_2/" + frame + ".png");
    const cv::Mat right = specht::stereo::ReadGray8(kitti + "/image_3/" + frame + ".png");
    const cv::Mat truth = specht::stereo::ReadDisparityPng(kitti + "/disp_occ_0/" + frame + ".png");
    const cv::Mat hints = specht::stereo::SampleHints(truth, 0.05, 1);
    const cv::Mat not_hint = hints <= 0;
    const specht::stereo::Guidance guidance = specht::stereo::HintsGuidance(hints);
    for (const Case& c : Cases()) {
      std::vector<double> ms;
      cv::Mat disparity;
      // Our matcher keeps its buffers from frame to frame, as on a camera stream.
      std::unique_ptr<specht::stereo::SemiGlobalMatcher> matcher;
      if (c.options.matcher == "specht") matcher = std::make_unique<specht::stereo::SemiGlobalMatcher>(c.options);
      for (int run = 0; run < 5; ++run) {
        const auto t0 = Clock::now();
        const specht::stereo::Guidance* g = c.guided ? &guidance : nullptr;
        disparity = matcher ? matcher->Compute(left, right, g) : specht::stereo::ComputeDisparity(left, right, c.options, g);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      cv::Mat filled = disparity.clone();
      specht::stereo::FillHolesRowwise(filled);
      const cv::Mat scored = c.guided ? not_hint : cv::Mat();
      const auto raw = specht::eval::CompareDisparity(disparity, truth, scored);
      const auto full = specht::eval::CompareDisparity(filled, truth, scored);
      specht::bench::Emit({{"name", "stereo/" + c.name},
                           {"frame", frame},
                           {"size", std::to_string(left.cols) + "x" + std::to_string(left.rows)},
                           {"disparities", c.options.num_disparities},
                           {"instruction_set", c.options.matcher == "specht"
                                                   ? specht::stereo::SelectedInstructionSet(c.options) : "-"},
                           {"threads", c.options.threads},
                           {"ms_per_frame_p50", ms[ms.size() / 2]},
                           {"ms_per_frame_min", ms.front()},
                           {"d1_all_filled", full.d1_all},
                           {"d1_all_raw", raw.d1_all},
                           {"d1_est", raw.d1_est},
                           {"density", raw.density},
                           {"peak_rss_mib", specht::bench::PeakRssMib()}});
    }
  }
  return 0;
}
