#include "specht/stereo/sgm.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "internal/parallel.h"
#include "internal/sgm_kernels.h"
#include "specht/core/error.h"

namespace specht::stereo {

using internal::Kernels;
using internal::PathStride;

namespace {
int ByteLanes(const std::string& isa);
}  // namespace

std::vector<std::string> SgmOptions::Relations() const {
  std::vector<std::string> problems;
  if (num_disparities % 16 != 0) problems.push_back("num_disparities must be a multiple of 16");
  if (census_width % 2 == 0 || census_height % 2 == 0) problems.push_back("census_width and census_height must be odd");
  if (census_width * census_height > 63) problems.push_back("census window must have at most 63 pixels (31 bits)");
  if (paths != 4 && paths != 8) problems.push_back("paths must be 4 or 8");
  if (p2 <= p1) problems.push_back("p2 must be larger than p1");
  if (median != 0 && median != 3 && median != 5) problems.push_back("median must be 0, 3 or 5");
  if (simd != "auto" && num_disparities % ByteLanes(simd) != 0)
    problems.push_back("simd " + simd + " needs num_disparities to be a multiple of " +
                       std::to_string(ByteLanes(simd)));
  if (sgbm_block % 2 == 0) problems.push_back("sgbm_block must be odd");
  return problems;
}

namespace {

bool CpuHas(const char* feature) {
  __builtin_cpu_init();
  if (std::strcmp(feature, "avx512") == 0)
    return __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") &&
           __builtin_cpu_supports("avx512vpopcntdq") && __builtin_cpu_supports("bmi2");
  if (std::strcmp(feature, "avx2") == 0) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2");
  if (std::strcmp(feature, "sse4.1") == 0) return __builtin_cpu_supports("sse4.1") && __builtin_cpu_supports("popcnt");
  return true;
}

// Disparities per byte vector: the kernels need a multiple of it.
int ByteLanes(const std::string& isa) { return isa == "avx512" ? 64 : isa == "avx2" ? 32 : isa == "sse4.1" ? 16 : 1; }

const Kernels& KernelsFor(const SgmOptions& options) {
  std::string isa = options.simd;
  if (isa == "auto") {
    isa = "scalar";
    for (const char* candidate : {"avx512", "avx2", "sse4.1"}) {
      if (CpuHas(candidate) && options.num_disparities % ByteLanes(candidate) == 0) {
        isa = candidate;
        break;
      }
    }
  }
  if (!CpuHas(isa.c_str())) throw InputError("stereo.simd: this CPU does not support " + isa);
  if (isa == "avx512") return internal::Avx512Kernels();
  if (isa == "avx2") return internal::Avx2Kernels();
  if (isa == "sse4.1") return internal::Sse41Kernels();
  return internal::ScalarKernels();
}

void CheckPair(const cv::Mat& left, const cv::Mat& right, const SgmOptions& options, const Guidance* guidance) {
  auto describe = [](const cv::Mat& m) {
    return std::to_string(m.cols) + "×" + std::to_string(m.rows) + " " + cv::typeToString(m.type());
  };
  if (left.empty() || right.empty()) throw InputError("stereo: empty image");
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1)
    throw InputError("stereo: images must be 8-bit grayscale, got left " + describe(left) + ", right " +
                     describe(right));
  if (left.size() != right.size())
    throw InputError("stereo: left " + describe(left) + " and right " + describe(right) + " differ in size");
  if (left.cols < options.census_width || left.rows < options.census_height)
    throw InputError("stereo: image " + describe(left) + " smaller than the census window");
  if (guidance != nullptr) {
    if (guidance->disparity.size() != left.size() || guidance->disparity.type() != CV_32FC1)
      throw InputError("stereo: guidance disparity " + describe(guidance->disparity) +
                       " must be CV_32FC1 of the image size " + describe(left));
    if (!guidance->weight.empty() && (guidance->weight.size() != left.size() || guidance->weight.type() != CV_32FC1))
      throw InputError("stereo: guidance weight " + describe(guidance->weight) + " must be CV_32FC1 of the image size");
  }
}

int CensusBits(const SgmOptions& o) { return (o.census_width * o.census_height - 1) / 2; }

// P2 as a function of the intensity step |ΔI| (see internal/sgm_kernels.h).
std::array<uint8_t, 256> AdaptedP2Table(const SgmOptions& o) {
  std::array<uint8_t, 256> table{};
  for (int step = 0; step < 256; ++step) {
    const double p2 = o.p2_gamma > 0 ? o.p2 * o.p2_gamma / (o.p2_gamma + step) : o.p2;
    table[step] = static_cast<uint8_t>(std::lround(std::max<double>(o.p1 + 1, p2)));
  }
  return table;
}

// Census transform of a whole image, rows in parallel.
cv::Mat Census(const cv::Mat& image, const SgmOptions& o, const Kernels& k) {
  cv::Mat out(image.rows, image.cols, CV_32SC1);  // census words (bits, read as uint32)
  internal::ParallelRows(image.rows, o.threads, [&](int y) {
    const uint8_t* rows[9];
    for (int dy = 0; dy < o.census_height; ++dy)
      rows[dy] = image.ptr<uint8_t>(std::clamp(y + dy - o.census_height / 2, 0, image.rows - 1));
    k.census_row(rows, image.cols, o.census_width, o.census_height, out.ptr<uint32_t>(y));
  });
  return out;
}

// The guidance penalty of one row, added to the costs (see sgm.h).
class GuidancePenalty {
 public:
  GuidancePenalty(const Guidance* guidance, const SgmOptions& o) : guidance_(guidance), nd_(o.num_disparities) {
    if (guidance_ == nullptr) return;
    options_ = guidance->kind == Guidance::Kind::kHints ? o.hints : o.prior;
    // Gaussian profile sampled at 1/8 px: 1 − exp(−Δ²/(2σ²)).
    profile_.resize(static_cast<size_t>(8 * nd_ + 1));
    for (size_t i = 0; i < profile_.size(); ++i) {
      const double delta = static_cast<double>(i) / 8.0;
      profile_[i] =
          options_.mode == "window"
              ? (delta > options_.window_px ? 1.0f : 0.0f)
              : static_cast<float>(1.0 - std::exp(-delta * delta / (2 * options_.width_px * options_.width_px)));
    }
  }

  void Apply(int y, uint8_t* cost, int width) const {
    if (guidance_ == nullptr) return;
    const float* g = guidance_->disparity.ptr<float>(y);
    const float* v = guidance_->weight.empty() ? nullptr : guidance_->weight.ptr<float>(y);
    for (int x = 0; x < width; ++x) {
      const float weight = v == nullptr ? 1.0f : v[x];
      if (!(g[x] > 0) || !(weight > 0) || g[x] >= nd_) continue;
      uint8_t* c = cost + static_cast<size_t>(x) * nd_;
      const float scale = weight * static_cast<float>(options_.strength);
      for (int d = 0; d < nd_; ++d) {
        const size_t i = std::min<size_t>(static_cast<size_t>(std::abs(d - g[x]) * 8.0f + 0.5f), profile_.size() - 1);
        c[d] = static_cast<uint8_t>(std::min(255.0f, c[d] + scale * profile_[i] + 0.5f));
      }
    }
  }

 private:
  const Guidance* guidance_;
  int nd_;
  GuidanceOptions options_;
  std::vector<float> profile_;
};

// The guide without the pixels where the data contradict it: the unguided estimate
// exists and differs by more than reject_px. The region grows into the unguided
// pass's holes that touch it (the rim and occlusion shadow of an object in front of
// the modelled background have no estimate of their own) and then by 2 px.
Guidance WithoutContradictedGuide(const Guidance& guide, const cv::Mat& unguided, double reject_px) {
  Guidance checked = guide;
  checked.weight =
      guide.weight.empty() ? cv::Mat(guide.disparity.size(), CV_32FC1, cv::Scalar(1)) : guide.weight.clone();
  cv::Mat difference;
  cv::absdiff(unguided, guide.disparity, difference);
  cv::Mat region = (unguided > 0) & (guide.disparity > 0) & (difference > reject_px);
  const cv::Mat reachable = region | (unguided <= 0);
  const cv::Mat step = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  for (int i = 0; i < 64; ++i) {  // morphological reconstruction, bounded
    cv::Mat grown;
    cv::dilate(region, grown, step);
    grown &= reachable;
    if (cv::countNonZero(grown != region) == 0) break;
    region = grown;
  }
  cv::dilate(region, region, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
  checked.weight.setTo(0, region);
  return checked;
}

// Path buffers of one sweep: per row path, the previous and current row; the cost
// row; winner-take-all scratch.
struct SweepBuffers {
  SweepBuffers(int width, int nd, int row_paths)
      : stride(PathStride(nd)),
        paths(static_cast<size_t>(2 * row_paths), std::vector<uint8_t>(static_cast<size_t>(width) * stride)),
        mins(static_cast<size_t>(2 * row_paths), std::vector<uint8_t>(static_cast<size_t>(width))),
        horizontal(static_cast<size_t>(2 * stride)),
        cost(static_cast<size_t>(width) * nd),
        best(width),
        best_cost(width),
        unique(width),
        // The mirrored right-image arrays are written in whole vectors: pad by the widest.
        right_best(static_cast<size_t>(width + nd + 32)),
        right_cost(static_cast<size_t>(width + nd + 32)) {
    for (auto* buffer : PathBuffers()) {
      for (size_t p = 0; p < buffer->size(); p += static_cast<size_t>(stride)) {
        (*buffer)[p] = internal::kSentinelByte;
        (*buffer)[p + static_cast<size_t>(nd) + 1] = internal::kSentinelByte;
      }
    }
  }
  std::vector<std::vector<uint8_t>*> PathBuffers() {
    std::vector<std::vector<uint8_t>*> all{&horizontal};
    for (auto& p : paths) all.push_back(&p);
    return all;
  }
  int stride;
  std::vector<std::vector<uint8_t>> paths, mins;  // [2k] and [2k+1] alternate rows for row path k
  std::vector<uint8_t> horizontal;
  std::vector<uint8_t> cost;
  std::vector<uint16_t> best, best_cost;
  std::vector<uint8_t> unique;
  std::vector<uint16_t> right_best, right_cost;
  long winners = 0, unique_winners = 0, consistent = 0;  // for MatchStats
};

// Turns one row of summed costs into disparities (×16 fixed point, −16 = none).
void FinishRow(const Kernels& k, const SgmOptions& o, const uint16_t* sum, int width, SweepBuffers& b, int16_t* out) {
  const int nd = o.num_disparities;
  internal::RowWinner w{width,
                        nd,
                        o.uniqueness,
                        sum,
                        b.best.data(),
                        b.best_cost.data(),
                        b.unique.data(),
                        b.right_best.data(),
                        b.right_cost.data()};
  k.winner_row(w);
  for (int x = 0; x < width; ++x) {
    const int d = b.best[x];
    out[x] = -16;
    if (d > x) continue;
    ++b.winners;
    if (!b.unique[x]) continue;
    ++b.unique_winners;
    if (o.lr_max_diff >= 0 && std::abs(b.right_best[width - 1 - (x - d)] - d) > o.lr_max_diff) continue;
    ++b.consistent;
    double refined = d;
    if (o.subpixel && d > 0 && d < nd - 1) {
      const uint16_t* s = sum + static_cast<size_t>(x) * nd;
      const double c0 = s[d - 1], c1 = s[d], c2 = s[d + 1];
      const double denominator = c0 - 2 * c1 + c2;
      if (denominator > 0) refined += std::clamp((c0 - c2) / (2 * denominator), -0.5, 0.5);
    }
    out[x] = static_cast<int16_t>(std::lround(refined * 16));
  }
}

}  // namespace

// Rows are shared by the two sweeps through one volume of summed costs: the first
// sweep to claim a row stores its sums there, the second adds its own once the first
// is done with the row, and then finishes the row. Neither ever waits for a row the
// other has not started, so two threads never deadlock; one thread runs the forward
// sweep whole, then the backward one.
struct SemiGlobalMatcher::State {
  SgmOptions options;
  const Kernels* kernels = nullptr;
  cv::Size size;
  std::vector<uint16_t> volume;
  std::unique_ptr<std::atomic<int>[]> row_state;  // 0 free, 1 claimed, 2 stored
  MatchStats stats;

  void Resize(cv::Size s) {
    if (s == size) return;
    size = s;
    volume.assign(static_cast<size_t>(s.area()) * options.num_disparities, 0);
    row_state.reset(new std::atomic<int>[static_cast<size_t>(s.height)]());
  }
};

SemiGlobalMatcher::SemiGlobalMatcher(const SgmOptions& options) : state_(std::make_unique<State>()) {
  const auto problems = options.Relations();
  if (!problems.empty()) throw InputError("stereo: " + problems.front());
  state_->options = options;
  state_->kernels = &KernelsFor(options);
}

SemiGlobalMatcher::~SemiGlobalMatcher() = default;

const char* SemiGlobalMatcher::instruction_set() const { return state_->kernels->name; }

MatchStats SemiGlobalMatcher::last_stats() const { return state_->stats; }

cv::Mat SemiGlobalMatcher::Compute(const cv::Mat& left, const cv::Mat& right, const Guidance* guidance) {
  const SgmOptions& o = state_->options;
  if (guidance != nullptr) {
    const GuidanceOptions& g = guidance->kind == Guidance::Kind::kHints ? o.hints : o.prior;
    if (g.reject_px > 0) {
      CheckPair(left, right, o, guidance);
      const Guidance checked = WithoutContradictedGuide(*guidance, ComputeOnce(left, right, nullptr), g.reject_px);
      return ComputeOnce(left, right, &checked);
    }
  }
  return ComputeOnce(left, right, guidance);
}

cv::Mat SemiGlobalMatcher::ComputeOnce(const cv::Mat& left, const cv::Mat& right, const Guidance* guidance) {
  const SgmOptions& o = state_->options;
  CheckPair(left, right, o, guidance);
  const Kernels& k = *state_->kernels;
  const int width = left.cols, height = left.rows, nd = o.num_disparities;
  state_->Resize(left.size());
  for (int y = 0; y < height; ++y) state_->row_state[y].store(0);
  const cv::Mat census_left = Census(left, o, k);
  cv::Mat census_right;
  cv::flip(Census(right, o, k), census_right, 1);  // mirrored rows: see CostRow
  const GuidancePenalty penalty(guidance, o);
  const int row_paths = o.paths == 8 ? 3 : 1;
  const std::array<uint8_t, 256> p2_table = AdaptedP2Table(o);
  const auto invalid_cost = static_cast<uint8_t>(CensusBits(o));
  cv::Mat fixed_point(height, width, CV_16SC1);

  MatchStats stats[2];
  auto sweep = [&](int dir) {
    SweepBuffers b(width, nd, row_paths);
    for (int i = 0; i < height; ++i) {
      const int y = dir > 0 ? i : height - 1 - i;
      int expected = 0;
      const bool first = state_->row_state[y].compare_exchange_strong(expected, 1);
      k.cost_row(census_left.ptr<uint32_t>(y), census_right.ptr<uint32_t>(y), width, nd, invalid_cost, b.cost.data());
      penalty.Apply(y, b.cost.data(), width);
      internal::RowSweep s;
      s.width = width;
      s.num_disparities = nd;
      s.dir = dir;
      s.row_paths = row_paths;
      s.p1 = static_cast<uint8_t>(o.p1);
      s.p2 = static_cast<uint8_t>(o.p2);
      s.p2_table = p2_table.data();
      s.cost = b.cost.data();
      s.image = left.ptr<uint8_t>(y);
      s.image_prev = i == 0 ? nullptr : left.ptr<uint8_t>(y - dir);
      for (int p = 0; p < row_paths; ++p) {
        const int cur = 2 * p + (i & 1), prev = 2 * p + ((i + 1) & 1);
        s.prev_paths[p] = i == 0 ? nullptr : b.paths[prev].data();
        s.prev_mins[p] = b.mins[prev].data();
        s.cur_paths[p] = b.paths[cur].data();
        s.cur_mins[p] = b.mins[cur].data();
      }
      s.horizontal = b.horizontal.data();
      s.sum = state_->volume.data() + static_cast<size_t>(y) * width * nd;
      s.accumulate = !first;
      if (!first) {
        while (state_->row_state[y].load(std::memory_order_acquire) != 2) std::this_thread::yield();
      }
      k.sweep_row(s);
      if (first)
        state_->row_state[y].store(2, std::memory_order_release);
      else
        FinishRow(k, o, s.sum, width, b, fixed_point.ptr<int16_t>(y));
    }
    stats[dir > 0 ? 0 : 1] = MatchStats{b.winners, b.unique_winners, b.consistent};
  };
  if (o.threads >= 2) {
    std::thread backward(sweep, -1);
    sweep(+1);
    backward.join();
  } else {
    sweep(+1);
    sweep(-1);
  }

  state_->stats = MatchStats{stats[0].winners + stats[1].winners, stats[0].unique + stats[1].unique,
                             stats[0].lr_consistent + stats[1].lr_consistent};
  if (o.speckle_window > 0)
    cv::filterSpeckles(fixed_point, -16, o.speckle_window, std::max(1, static_cast<int>(o.speckle_range_px * 16)));
  cv::Mat disparity;
  fixed_point.convertTo(disparity, CV_32F, 1.0 / 16);
  disparity.setTo(0, fixed_point < 0);
  if (o.median > 0) {
    cv::Mat filtered;
    cv::medianBlur(disparity, filtered, o.median);
    filtered.setTo(0, disparity <= 0);  // the median never creates estimates where there were none
    disparity = filtered;
  }
  if (o.fill_holes) FillHolesRowwise(disparity);
  return disparity;
}

namespace {

cv::Mat OpenCvSgbm(const cv::Mat& left, const cv::Mat& right, const SgmOptions& o) {
  const int mode = o.sgbm_mode == "3way"  ? cv::StereoSGBM::MODE_SGBM_3WAY
                   : o.sgbm_mode == "hh"  ? cv::StereoSGBM::MODE_HH
                   : o.sgbm_mode == "hh4" ? cv::StereoSGBM::MODE_HH4
                                          : cv::StereoSGBM::MODE_SGBM;
  auto sgbm = cv::StereoSGBM::create(0, o.num_disparities, o.sgbm_block, o.sgbm_p1, o.sgbm_p2, o.lr_max_diff, 0,
                                     o.uniqueness, o.speckle_window, static_cast<int>(o.speckle_range_px * 16), mode);
  // OpenCV's thread count is process-wide (see detect/detector.cpp): changed only
  // when it differs, which callers running OpenCV on other threads must avoid.
  if (cv::getNumThreads() != o.threads) cv::setNumThreads(o.threads);
  cv::Mat fixed_point;
  sgbm->compute(left, right, fixed_point);
  cv::Mat disparity;
  fixed_point.convertTo(disparity, CV_32F, 1.0 / 16);
  disparity.setTo(0, fixed_point <= 0);
  return disparity;
}

}  // namespace

std::string SelectedInstructionSet(const SgmOptions& options) { return KernelsFor(options).name; }

SgmOptions OpenCvSgbmBaseline(int threads) {
  SgmOptions o;
  o.matcher = "opencv_sgbm";
  o.sgbm_mode = "3way", o.sgbm_block = 5, o.sgbm_p1 = 200, o.sgbm_p2 = 800;
  o.uniqueness = 10;
  o.speckle_window = 100, o.speckle_range_px = 2;
  o.lr_max_diff = 1;
  o.threads = threads;
  return o;
}

cv::Mat ComputeDisparity(const cv::Mat& left, const cv::Mat& right, const SgmOptions& options,
                         const Guidance* guidance) {
  if (options.matcher == "specht") return SemiGlobalMatcher(options).Compute(left, right, guidance);
  CheckPair(left, right, options, guidance);
  cv::Mat disparity = OpenCvSgbm(left, right, options);
  if (options.fill_holes) FillHolesRowwise(disparity);
  return disparity;
}

void FillHolesRowwise(cv::Mat& disparity) {
  CV_Assert(disparity.type() == CV_32FC1);
  for (int y = 0; y < disparity.rows; ++y) {
    float* row = disparity.ptr<float>(y);
    const int width = disparity.cols;
    int last_valid = -1;
    for (int x = 0; x <= width; ++x) {
      if (x < width && !(row[x] > 0)) continue;
      // Pixels last_valid+1 .. x−1 are a hole between two valid pixels (or a border).
      if (x - last_valid > 1) {
        float fill = 0;
        if (last_valid >= 0 && x < width)
          fill = std::min(row[last_valid], row[x]);
        else if (last_valid >= 0)
          fill = row[last_valid];
        else if (x < width)
          fill = row[x];
        for (int i = last_valid + 1; i < x; ++i) row[i] = fill;
      }
      last_valid = x;
    }
  }
}

}  // namespace specht::stereo
