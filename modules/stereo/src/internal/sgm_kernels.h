// The inner loops of the semi-global matcher, compiled once per instruction set.
//
// Each sgm_kernels_<isa>.cpp includes sgm_kernels_impl.h with a vector type for its
// instruction set and exports one Kernels table; sgm.cpp picks the table at run time
// (SgmOptions::simd, "auto" = the widest the CPU has). The tables compute identical
// results: every operation is exact integer arithmetic.
#pragma once

#include <cstdint>

namespace specht::stereo::internal {

// Path costs are uint8: every path cost is at most C_max + P2 (census 9×7: 31 + P2),
// below 255 for unguided costs and P2 ≤ 190; guided costs may saturate at 255, which
// only flattens costs that are far from winning. The sum over 8 paths is uint16.
inline constexpr uint8_t kSentinelByte = 0xFF;  // stands for "no neighbour disparity"
inline constexpr uint16_t kSentinel = 0x3FFF;   // the same for uint16 sums (< 0x8000)

// Layout of a path-cost buffer: per pixel `stride` bytes of which [1, D] hold the
// costs of disparities 0..D-1 and [0] and [D+1] hold kSentinelByte.
inline int PathStride(int num_disparities) { return num_disparities + 64; }

// One row of one sweep of the aggregation (Hirschmüller 2008):
//
//   L_r(p,d) = C(p,d) + min( L_r(p−r,d), L_r(p−r,d±1) + P1, min_k L_r(p−r,k) + P2(p) )
//              − min_k L_r(p−r,k)
//
// with P2(p) = max(P1 + 1, P2 · γ / (γ + |I(p) − I(p−r)|)) (smaller across intensity
// edges, where depth edges are likely; γ = 0 keeps P2 constant).
//
// A forward sweep (dir = +1) runs rows top to bottom and, along the row, left to
// right: the horizontal path r = (1,0) and, from the previous row, r = (0,1) and in
// 8-path mode the diagonals r = (1,1), (−1,1). A backward sweep (dir = −1) mirrors it.
struct RowSweep {
  int width = 0;
  int num_disparities = 0;  // D, a multiple of the kernel's byte lanes
  int dir = 1;
  int row_paths = 1;  // 1 (vertical) or 3 (vertical and both diagonals)
  uint8_t p1 = 0, p2 = 0;
  const uint8_t* p2_table = nullptr;    // 256 entries: P2(|ΔI|) as below
  const uint8_t* cost = nullptr;        // width × D, this row
  const uint8_t* image = nullptr;       // width, this row (left image)
  const uint8_t* image_prev = nullptr;  // width, the previous row of the sweep, or null on the first
  // Per row path k: previous row's buffers (null on the first row) and this row's.
  const uint8_t* prev_paths[3] = {nullptr, nullptr, nullptr};
  const uint8_t* prev_mins[3] = {nullptr, nullptr, nullptr};
  uint8_t* cur_paths[3] = {nullptr, nullptr, nullptr};
  uint8_t* cur_mins[3] = {nullptr, nullptr, nullptr};
  uint8_t* horizontal = nullptr;  // 2 × stride scratch for the horizontal path
  uint16_t* sum = nullptr;        // width × D: Σ over this sweep's paths is stored here,
  bool accumulate = false;        // or added to what is there
};

// Winner-take-all of one row of summed costs S (width × D):
//   best[x]   = argmin_d S(x,d) (smallest d on ties), best_cost[x] = its cost,
//   unique[x] = no d with |d − best| > 1 has S(x,d)·(100 − u) < best_cost·100,
//   right_best[W−1−x_r] = argmin_d S(x_r + d, d) (the right image's match, stored
//   mirrored so that one left pixel's disparities map to contiguous entries).
struct RowWinner {
  int width = 0;
  int num_disparities = 0;
  int uniqueness = 0;  // percent
  const uint16_t* sum = nullptr;
  uint16_t* best = nullptr;
  uint16_t* best_cost = nullptr;
  uint8_t* unique = nullptr;
  uint16_t* right_best = nullptr;       // width + D + 32 (mirrored; whole vectors are written)
  uint16_t* right_best_cost = nullptr;  // width + D + 32 (scratch, mirrored)
};

struct Kernels {
  const char* name;
  // Centre-symmetric census of one row (see sgm_kernels_impl.h), row pointers for
  // y − h/2 .. y + h/2 (clamped by the caller).
  void (*census_row)(const uint8_t* const* rows, int width, int window_w, int window_h, uint32_t* out);
  // Matching cost of one row: C(x,d) = popcount(census_L(x) ⊕ census_R(x − d)),
  // `invalid` where x − d < 0. The right row comes mirrored (entry W − 1 − x holds x).
  void (*cost_row)(const uint32_t* left, const uint32_t* right_mirrored, int width, int num_disparities,
                   uint8_t invalid, uint8_t* out);
  void (*sweep_row)(const RowSweep& sweep);
  void (*winner_row)(const RowWinner& winner);
};

const Kernels& ScalarKernels();
const Kernels& Sse41Kernels();
const Kernels& Avx2Kernels();
const Kernels& Avx512Kernels();

}  // namespace specht::stereo::internal
