// stereo_bench [data_dir]: the matchers side by side on the KITTI 2015 frames of
// <data_dir>/stereo/kitti2015 (1242×375, 128 disparities): OpenCV StereoSGBM
// (3-way, the data README's settings) and specht's SGM at 1 and 2 threads, each
// instruction set, unguided and guided by 5 % ground-truth hints; and the Middlebury
// Aloe pair (1282×1110, 256 disparities). Per case: ms per frame (median of 7 runs,
// the cases of a frame interleaved run by run so that machine noise hits all alike),
// D1-all with holes filled row-wise (as KITTI scores), bad-2, D1 and density of the
// raw output. One JSON object per case and frame.
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
  for (int threads : {1, 2})
    cases.push_back({"opencv_sgbm_3way/t" + std::to_string(threads), specht::stereo::OpenCvSgbmBaseline(threads)});
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

struct Frame {
  std::string name;
  cv::Mat left, right, truth;
};

std::vector<Frame> Frames(const std::string& data) {
  std::vector<Frame> frames;
  const std::string kitti = data + "/stereo/kitti2015";
  for (const char* f : {"000000_10", "000001_10"}) {
    if (!std::filesystem::is_directory(kitti)) break;
    frames.push_back({std::string("kitti2015/") + f, specht::stereo::ReadGray8(kitti + "/image_2/" + f + ".png"),
                      specht::stereo::ReadGray8(kitti + "/image_3/" + f + ".png"),
                      specht::stereo::ReadDisparityPng(kitti + "/disp_occ_0/" + f + ".png")});
  }
  const std::string aloe = data + "/stereo/middlebury_aloe";
  if (std::filesystem::is_directory(aloe))
    frames.push_back({"middlebury/aloe", specht::stereo::ReadGray8(aloe + "/aloeL.jpg"),
                      specht::stereo::ReadGray8(aloe + "/aloeR.jpg"),
                      specht::stereo::ReadDisparityPng(aloe + "/aloeGT.png")});
  return frames;
}

}  // namespace

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const std::string data = argc > 1 ? argv[1] : SPECHT_DATA_DIR;
  const std::vector<Frame> frames = Frames(data);
  if (frames.empty()) {
    std::cerr << "stereo_bench: no stereo data under " << data << "/stereo\n";
    return 2;
  }
  for (const Frame& frame : frames) {
    const bool middlebury = frame.name.rfind("middlebury", 0) == 0;
    std::vector<Case> cases = Cases();
    for (Case& c : cases) c.options.num_disparities = middlebury ? 256 : 128;
    const cv::Mat hints = specht::stereo::SampleHints(frame.truth, 0.05, 1);
    const specht::stereo::Guidance guidance = specht::stereo::HintsGuidance(hints);
    // Our matcher keeps its buffers from frame to frame, as on a camera stream.
    std::vector<std::unique_ptr<specht::stereo::SemiGlobalMatcher>> matchers;
    for (const Case& c : cases)
      matchers.push_back(c.options.matcher == "specht" ? std::make_unique<specht::stereo::SemiGlobalMatcher>(c.options)
                                                       : nullptr);
    std::vector<std::vector<double>> ms(cases.size());
    std::vector<cv::Mat> disparity(cases.size());
    for (int run = 0; run < 7; ++run) {
      for (size_t i = 0; i < cases.size(); ++i) {
        const specht::stereo::Guidance* g = cases[i].guided ? &guidance : nullptr;
        const auto t0 = Clock::now();
        disparity[i] = matchers[i] ? matchers[i]->Compute(frame.left, frame.right, g)
                                   : specht::stereo::ComputeDisparity(frame.left, frame.right, cases[i].options, g);
        ms[i].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      }
    }
    for (size_t i = 0; i < cases.size(); ++i) {
      const Case& c = cases[i];
      std::sort(ms[i].begin(), ms[i].end());
      cv::Mat filled = disparity[i].clone();
      specht::stereo::FillHolesRowwise(filled);
      const cv::Mat scored = c.guided ? cv::Mat(hints <= 0) : cv::Mat();
      const auto raw = specht::eval::CompareDisparity(disparity[i], frame.truth, scored);
      const auto full = specht::eval::CompareDisparity(filled, frame.truth, scored);
      specht::bench::Emit({{"name", "stereo/" + c.name},
                           {"frame", frame.name},
                           {"size", std::to_string(frame.left.cols) + "x" + std::to_string(frame.left.rows)},
                           {"disparities", c.options.num_disparities},
                           {"instruction_set", matchers[i] ? matchers[i]->instruction_set() : "-"},
                           {"threads", c.options.threads},
                           {"ms_per_frame_p50", ms[i][ms[i].size() / 2]},
                           {"ms_per_frame_min", ms[i].front()},
                           {"d1_all_filled", full.d1_all},
                           {"bad2_all_filled", full.bad2_all},
                           {"d1_all_raw", raw.d1_all},
                           {"d1_est", raw.d1_est},
                           {"density", raw.density},
                           {"peak_rss_mib", specht::bench::PeakRssMib()}});
    }
  }
  return 0;
}
