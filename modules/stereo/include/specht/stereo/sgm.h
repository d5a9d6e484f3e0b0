// specht/stereo/sgm.h: semi-global matching on a rectified pair, optionally guided.
//
// Pipeline (Hirschmüller 2008, with the guidance of Poggi et al. 2019 and of the
// scene-adaptive paper, ../shared/papers/scene-adaptive-disparity-estimation.md):
//
//   1. centre-symmetric census transform (census_width × census_height window,
//      (w·h − 1)/2 ≤ 31 bits; Spangenberg et al. 2013);
//   2. matching cost C(p,d) = Hamming(census_L(x,y), census_R(x−d,y)), plus a guidance
//      penalty where a hint or prior disparity g_p with weight v_p exists:
//        gaussian: C += v_p · strength · (1 − exp(−(d − g_p)² / (2 width²)))
//        window:   C += v_p · strength   where |d − g_p| > window   (the paper's
//                  exclusion of costs far from the prior; strength 255 = hard)
//      and, with reject_px > 0, the guide is dropped where the data contradict it:
//      a first unguided pass has an estimate there that differs from g_p by more
//      than reject_px (grown by 2 px) — the paper's failure case, an object in front
//      of the modelled background, is then matched as if there were no prior;
//   3. aggregation along 4 or 8 paths (see internal/sgm_kernels.h for the recursion),
//      P2 adapted to intensity edges;
//   4. winner-take-all with uniqueness, parabola sub-pixel refinement, left-right
//      consistency check against the right image's winners from the same costs;
//   5. speckle filter (OpenCV filterSpeckles) and optional 3×3 median and row-wise
//      hole filling.
//
// Vectorised kernels (scalar, SSE4.1, AVX2, AVX-512) are chosen at run time and give
// identical results. Two threads run the forward and backward sweeps concurrently;
// each row is finalised by whichever sweep reaches it second. OpenCV's StereoSGBM is
// selectable as a baseline (matcher: opencv_sgbm).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::stereo {

// One kind of guidance (sparse hints or a dense prior); see the formula above.
struct GuidanceOptions {
  std::string mode = "gaussian";
  double strength = 48;
  double width_px = 1.0;
  double window_px = 3.0;
  double reject_px = 0;  // 0 = never drop

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice(
        "mode", mode, {"gaussian", "window"},
        "gaussian: soft cost modulation (Poggi 2019); window: penalise |d − g| > window_px (scene-adaptive paper)");
    v.Param("strength", strength, "largest cost added far from the guide (census bits; 255 = exclusion)",
            Range::Of(1.0, 255.0));
    v.Param("width_px", width_px, "gaussian: standard deviation of the modulation in pixels",
            Range::Of(0.2, 20.0).Log());
    v.Param("window_px", window_px, "window: half width of the kept disparity interval", Range::Of(0.5, 20.0));
    v.Param("reject_px", reject_px,
            "drop the guide where an unguided first pass disagrees by more than this (px; 0 = never, one pass)",
            Range::Of(0.0, 64.0));
  }
};

// Section "stereo".
struct SgmOptions {
  std::string matcher = "specht";
  int num_disparities = 128;
  int census_width = 9;
  int census_height = 7;
  int paths = 8;
  int p1 = 6;
  int p2 = 50;
  double p2_gamma = 0;
  int uniqueness = 5;
  int lr_max_diff = 1;
  bool subpixel = true;
  int median = 0;
  int speckle_window = 200;
  double speckle_range_px = 2;
  bool fill_holes = false;
  std::string simd = "auto";
  int threads = 2;
  // The OpenCV baseline (matcher: opencv_sgbm), with the settings of the data README.
  int sgbm_block = 5;
  int sgbm_p1 = 200;
  int sgbm_p2 = 800;
  std::string sgbm_mode = "3way";
  GuidanceOptions hints{"gaussian", 200, 1.0, 3.0, 0};
  GuidanceOptions prior{"gaussian", 24, 1.5, 3.0, 3};

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("matcher", matcher, {"specht", "opencv_sgbm"}, "our semi-global matcher, or OpenCV's StereoSGBM baseline");
    v.Param("num_disparities", num_disparities,
            "disparities searched, 0..n−1 (a multiple of 16; of 32 for avx2, 64 for avx512)", Range::Of(16, 256));
    v.Param("census_width", census_width, "census window width (odd)", Range::Of(3, 9));
    v.Param("census_height", census_height, "census window height (odd; width × height ≤ 63)", Range::Of(3, 9));
    v.Param("paths", paths, "aggregation paths: 4 (horizontal, vertical) or 8 (and diagonals)", Range::Of(4, 8));
    v.Param("p1", p1, "penalty for a disparity change of 1 along a path (census bits)", Range::Of(1, 64));
    v.Param("p2", p2, "penalty for larger disparity changes (census bits)", Range::Of(2, 190).Log());
    v.Param("p2_gamma", p2_gamma, "P2 · γ/(γ + |ΔI|): lower P2 across intensity edges (0 = constant P2)",
            Range::Of(0.0, 255.0));
    v.Param("uniqueness", uniqueness, "reject when another disparity's cost is within this percent", Range::Of(0, 50));
    v.Param("lr_max_diff", lr_max_diff, "left-right check tolerance in pixels (−1 = no check)", Range::Of(-1, 8));
    v.Param("subpixel", subpixel, "parabola sub-pixel refinement");
    v.Param("median", median, "median filter size on the disparity (0 = none, 3 or 5)", Range::Of(0, 5));
    v.Param("speckle_window", speckle_window, "remove disparity blobs smaller than this many pixels (0 = off)",
            Range::Of(0, 10000));
    v.Param("speckle_range_px", speckle_range_px, "disparity step that separates blobs", Range::Of(0.25, 16.0));
    v.Param("fill_holes", fill_holes, "fill invalid pixels row-wise from the farther neighbour (as KITTI does)");
    v.Choice("simd", simd, {"auto", "avx512", "avx2", "sse4.1", "scalar"},
             "instruction set of the kernels (auto = the widest this CPU has)");
    v.Param("threads", threads, "worker threads (the two sweeps run concurrently at 2)", Range::Of(1, 64).Fixed());
    v.Param("sgbm_block", sgbm_block, "opencv_sgbm: block size", Range::Of(1, 11));
    v.Param("sgbm_p1", sgbm_p1, "opencv_sgbm: P1", Range::Of(0, 10000));
    v.Param("sgbm_p2", sgbm_p2, "opencv_sgbm: P2", Range::Of(0, 40000));
    v.Choice("sgbm_mode", sgbm_mode, {"3way", "sgbm", "hh", "hh4"}, "opencv_sgbm: StereoSGBM mode");
    v.Group("hints", hints);
    v.Group("prior", prior);
  }
  std::vector<std::string> Relations() const;
};

// OpenCV's StereoSGBM as the data README measures it, the one baseline the tests and
// bench/stereo_bench compare against: SGBM_3WAY, block 5, P1 200, P2 800, uniqueness
// 10, speckle window 100 and range 2 px (OpenCV's 32 in 1/16 px), disp12MaxDiff 1.
SgmOptions OpenCvSgbmBaseline(int threads = 2);

// Guidance for one frame: a disparity g_p per left pixel (CV_32F, 0 = none) and its
// weight v_p in [0, 1] (CV_32F; empty = 1 wherever g_p > 0).
struct Guidance {
  enum class Kind { kHints, kPrior };
  Kind kind = Kind::kHints;
  cv::Mat disparity;
  cv::Mat weight;
};

// The instruction set the kernels use for `options` on this CPU ("avx512", ...).
std::string SelectedInstructionSet(const SgmOptions& options);

// What the left-right check saw in the last frame: pixels with a winner (d ≤ x),
// those that passed the uniqueness test, and of those the ones the right image's
// winner confirmed (lr_consistency = lr_consistent / unique).
struct MatchStats {
  long winners = 0, unique = 0, lr_consistent = 0;
  double lr_consistency() const { return unique == 0 ? 0.0 : static_cast<double>(lr_consistent) / unique; }
};

// Our matcher, keeping its buffers between frames of one size (a camera stream).
class SemiGlobalMatcher {
 public:
  explicit SemiGlobalMatcher(const SgmOptions& options);  // InputError on inconsistent options
  ~SemiGlobalMatcher();
  SemiGlobalMatcher(const SemiGlobalMatcher&) = delete;
  SemiGlobalMatcher& operator=(const SemiGlobalMatcher&) = delete;

  // See ComputeDisparity.
  cv::Mat Compute(const cv::Mat& left, const cv::Mat& right, const Guidance* guidance = nullptr);
  const char* instruction_set() const;
  MatchStats last_stats() const;

 private:
  cv::Mat ComputeOnce(const cv::Mat& left, const cv::Mat& right, const Guidance* guidance);
  struct State;
  std::unique_ptr<State> state_;
};

// Disparity of the left image (CV_32F, pixels, 0 = no estimate). Images: CV_8UC1 of
// equal size (InputError otherwise); guidance, when given, of the same size.
cv::Mat ComputeDisparity(const cv::Mat& left, const cv::Mat& right, const SgmOptions& options,
                         const Guidance* guidance = nullptr);

// Fills invalid pixels (0) of each row from the nearer of the valid neighbours'
// smaller disparity, as the KITTI devkit's interpolateBackground does; rows with no
// valid pixel stay empty.
void FillHolesRowwise(cv::Mat& disparity);

}  // namespace specht::stereo
