// The kernel bodies, generic over a vector type V of uint16 lanes (see the four
// sgm_kernels_<isa>.cpp). Included by exactly those files, each compiled with its own
// instruction-set flags; everything here has internal linkage so that no function
// compiled for a wider instruction set can be picked by the linker for another file.
//
// V provides, on uint16 lanes: kLanes, Reg, Mask, Load/Store, Set, Min, HMin (smallest
// lane), Lt/Eq (lane masks; values < 0x8000), Blend(mask, if_false, if_true), Bits
// (mask as an integer, lane i → bit i), Iota(d) (d, d+1, ...); on uint8 lanes: kBytes,
// RegB, LoadB/StoreB, SetB, MinB, AddsB (saturating), SubB, HMinB; and Wide (kBytes
// uint16 lanes): WideZero, WideLoad/WideStore, WideAdd(Wide, RegB) (zero-extending).
#pragma once

#include <cstddef>
#include <cstdint>

#include "internal/sgm_kernels.h"

namespace specht::stereo::internal {
namespace {

// Local helpers instead of <algorithm>: a std:: template instantiated here would be
// compiled for this file's instruction set and could be shared with other files.
inline int MinI(int a, int b) { return a < b ? a : b; }
inline int MaxI(int a, int b) { return a > b ? a : b; }
inline int ClampI(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }

// Centre-symmetric census: one bit per pair of pixels mirrored about the centre,
// I(x + dx, y + dy) < I(x − dx, y − dy), over the half window before the centre in
// raster order ((w·h − 1)/2 bits, 31 for 9×7). Half the comparisons of the full
// census at the same window, and in the experiments of Spangenberg et al. (2013) as
// accurate. Rows are y − h/2 .. y + h/2 (clamped by the caller); columns clamp here.
inline void CensusRowImpl(const uint8_t* const* rows, int width, int window_w, int window_h, uint32_t* out) {
  const int half_w = window_w / 2, half_h = window_h / 2;
  for (int x = 0; x < width; ++x) out[x] = 0;
  const int inner_begin = MinI(half_w, width), inner_end = MaxI(inner_begin, width - half_w);
  for (int dy = -half_h; dy <= 0; ++dy) {
    const uint8_t* a = rows[half_h + dy];
    const uint8_t* b = rows[half_h - dy];
    for (int dx = -half_w; dx <= half_w; ++dx) {
      if (dy == 0 && dx >= 0) break;  // the centre row contributes its left half only
      for (int x = 0; x < inner_begin; ++x)
        out[x] = (out[x] << 1) | uint32_t(a[ClampI(x + dx, 0, width - 1)] < b[ClampI(x - dx, 0, width - 1)]);
      for (int x = inner_begin; x < inner_end; ++x) out[x] = (out[x] << 1) | uint32_t(a[x + dx] < b[x - dx]);
      for (int x = inner_end; x < width; ++x)
        out[x] = (out[x] << 1) | uint32_t(a[ClampI(x + dx, 0, width - 1)] < b[ClampI(x - dx, 0, width - 1)]);
    }
  }
}

inline void CostRowImpl(const uint32_t* left, const uint32_t* right_mirrored, int width, int num_disparities,
                        uint8_t invalid, uint8_t* out) {
  for (int x = 0; x < width; ++x) {
    const uint32_t l = left[x];
    uint8_t* o = out + static_cast<std::size_t>(x) * num_disparities;
    const int valid = MinI(num_disparities, x + 1);
    // census_R(x − d) = right_mirrored[W − 1 − x + d]: contiguous in d.
    const uint32_t* r = right_mirrored + (width - 1 - x);
    for (int d = 0; d < valid; ++d) o[d] = static_cast<uint8_t>(__builtin_popcount(l ^ r[d]));
    for (int d = valid; d < num_disparities; ++d) o[d] = invalid;
  }
}

inline uint8_t AdaptedP2(const RowSweep& s, uint8_t here, uint8_t before) {
  return s.p2_table[here > before ? here - before : before - here];
}

// One pixel, all paths of a sweep at once: for each path k, L_k(p,·) from
// L_k(p−r_k,·) (`before[k]`, with sentinels at −1 and D), and Σ_k L_k added to (or
// stored in) `sum`. Doing the paths together reads the costs and the sum once.
// Path costs are bytes (twice the lanes per instruction); the additions saturate at
// 255, which the bound in sgm_kernels.h keeps out of reach for unguided costs.
template <class V, int kPaths, bool kAccumulate>
inline void PixelStep(const uint8_t* cost, const uint8_t* const* before, const uint8_t* before_min, const uint8_t* p2,
                      uint8_t p1, int num_disparities, uint8_t* const* out, uint8_t* out_min, uint16_t* sum) {
  using RegB = typename V::RegB;
  using Wide = typename V::Wide;
  const RegB vp1 = V::SetB(p1);
  RegB vjump[kPaths], vbefore_min[kPaths], vbest[kPaths];
#pragma GCC unroll 4
  for (int k = 0; k < kPaths; ++k) {
    vbefore_min[k] = V::SetB(before_min[k]);
    vjump[k] = V::AddsB(vbefore_min[k], V::SetB(p2[k]));
    vbest[k] = V::SetB(kSentinelByte);
  }
  for (int d = 0; d < num_disparities; d += V::kBytes) {
    const RegB c = V::LoadB(cost + d);
    Wide total = kAccumulate ? V::WideLoad(sum + d) : V::WideZero();
#pragma GCC unroll 4
    for (int k = 0; k < kPaths; ++k) {
      const RegB same = V::LoadB(before[k] + d);
      const RegB near = V::AddsB(V::MinB(V::LoadB(before[k] + d - 1), V::LoadB(before[k] + d + 1)), vp1);
      const RegB l = V::AddsB(c, V::SubB(V::MinB(V::MinB(same, near), vjump[k]), vbefore_min[k]));
      V::StoreB(out[k] + d, l);
      total = V::WideAdd(total, l);
      vbest[k] = V::MinB(vbest[k], l);
    }
    V::WideStore(sum + d, total);
  }
#pragma GCC unroll 4
  for (int k = 0; k < kPaths; ++k) out_min[k] = V::HMinB(vbest[k]);
}

// Path 0 is horizontal (from the previous pixel of this row), paths 1.. come from the
// previous row at x, x − 1, x + 1.
template <class V, int kPaths, bool kAccumulate>
void SweepRowPaths(const RowSweep& s) {
  const int width = s.width, nd = s.num_disparities, stride = PathStride(nd);
  // The path start: zero costs (so L = C), sentinels at −1 and D.
  alignas(64) uint8_t start[256 + 128] = {};
  start[0] = kSentinelByte;
  start[nd + 1] = kSentinelByte;
  static constexpr int kRowOffsets[3] = {0, -1, +1};
  static constexpr int kPrefetchPixels = 8;

  const uint8_t* before[kPaths];
  uint8_t before_min[kPaths] = {}, p2[kPaths] = {}, out_min[kPaths] = {};
  uint8_t* out[kPaths];
  for (int i = 0; i < width; ++i) {
    const int x = s.dir > 0 ? i : width - 1 - i;
    before[0] = i == 0 ? start + 1 : s.horizontal + ((i - 1) & 1) * stride + 1;
    before_min[0] = i == 0 ? 0 : out_min[0];
    p2[0] = i == 0 ? s.p2 : AdaptedP2(s, s.image[x], s.image[x - s.dir]);
    out[0] = s.horizontal + (i & 1) * stride + 1;
#pragma GCC unroll 4
    for (int k = 1; k < kPaths; ++k) {
      const int xb = x + kRowOffsets[k - 1];
      const bool inside = s.prev_paths[k - 1] != nullptr && xb >= 0 && xb < width;
      before[k] = inside ? s.prev_paths[k - 1] + static_cast<std::size_t>(xb) * stride + 1 : start + 1;
      before_min[k] = inside ? s.prev_mins[k - 1][xb] : 0;
      p2[k] = inside ? AdaptedP2(s, s.image[x], s.image_prev[xb]) : s.p2;
      out[k] = s.cur_paths[k - 1] + static_cast<std::size_t>(x) * stride + 1;
    }
    if (kAccumulate) {
      // The stored sums come from memory (the other sweep wrote them long ago): fetch ahead.
      const int xa = x + kPrefetchPixels * s.dir;
      if (xa >= 0 && xa < width) {
        const char* ahead = reinterpret_cast<const char*>(s.sum + static_cast<std::size_t>(xa) * nd);
        for (int byte = 0; byte < nd * 2; byte += 64) __builtin_prefetch(ahead + byte);
      }
    }
    PixelStep<V, kPaths, kAccumulate>(s.cost + static_cast<std::size_t>(x) * nd, before, before_min, p2, s.p1, nd, out,
                                      out_min, s.sum + static_cast<std::size_t>(x) * nd);
    for (int k = 1; k < kPaths; ++k) s.cur_mins[k - 1][x] = out_min[k];
  }
}

template <class V>
void SweepRowImpl(const RowSweep& s) {
  if (s.row_paths == 3) {
    s.accumulate ? SweepRowPaths<V, 4, true>(s) : SweepRowPaths<V, 4, false>(s);
  } else {
    s.accumulate ? SweepRowPaths<V, 2, true>(s) : SweepRowPaths<V, 2, false>(s);
  }
}

template <class V>
void WinnerRowImpl(const RowWinner& w) {
  using Reg = typename V::Reg;
  const int width = w.width, nd = w.num_disparities;
  // Mirrored right-image minima: entry W−1−x_r; a left pixel x covers W−1−x .. W−1−x+D−1.
  for (int m = 0; m < width + nd; m += V::kLanes) {
    V::Store(w.right_best_cost + m, V::Set(kSentinel));
    V::Store(w.right_best + m, V::Set(0));
  }
  for (int x = 0; x < width; ++x) {
    const uint16_t* s = w.sum + static_cast<std::size_t>(x) * nd;
    Reg vmin = V::Set(kSentinel);
    for (int d = 0; d < nd; d += V::kLanes) vmin = V::Min(vmin, V::Load(s + d));
    const uint16_t best = V::HMin(vmin);
    const int keep = 100 - w.uniqueness;
    uint32_t threshold = (uint32_t{best} * 100 + keep - 1) / keep;
    if (threshold > kSentinel) threshold = kSentinel;
    const Reg vbest = V::Set(best), vthreshold = V::Set(static_cast<uint16_t>(threshold));

    int arg = -1;
    uint64_t close[4] = {0, 0, 0, 0};  // bit d: S(d)·(100 − u) < best·100
    uint16_t* right_cost = w.right_best_cost + (width - 1 - x);
    uint16_t* right_arg = w.right_best + (width - 1 - x);
    for (int d = 0; d < nd; d += V::kLanes) {
      const Reg sv = V::Load(s + d);
      if (arg < 0) {
        const uint64_t equal = V::Bits(V::Eq(sv, vbest));
        if (equal != 0) arg = d + __builtin_ctzll(equal);
      }
      close[d >> 6] |= uint64_t{V::Bits(V::Lt(sv, vthreshold))} << (d & 63);
      const Reg old = V::Load(right_cost + d);
      V::Store(right_arg + d, V::Blend(V::Lt(sv, old), V::Load(right_arg + d), V::Iota(static_cast<uint16_t>(d))));
      V::Store(right_cost + d, V::Min(sv, old));
    }
    for (int n = MaxI(arg - 1, 0); n <= MinI(arg + 1, nd - 1); ++n) close[n >> 6] &= ~(uint64_t{1} << (n & 63));
    w.best[x] = static_cast<uint16_t>(arg);
    w.best_cost[x] = best;
    w.unique[x] = (close[0] | close[1] | close[2] | close[3]) == 0;
  }
}

template <class V>
Kernels MakeKernels(const char* name) {
  return Kernels{name, &CensusRowImpl, &CostRowImpl, &SweepRowImpl<V>, &WinnerRowImpl<V>};
}

}  // namespace
}  // namespace specht::stereo::internal
