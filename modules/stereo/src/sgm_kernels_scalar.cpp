// Portable kernels: one lane, plain C++ (the fallback on any CPU).
#include "internal/sgm_kernels_impl.h"

namespace specht::stereo::internal {
namespace {

struct ScalarLanes {
  static constexpr int kLanes = 1;
  using Reg = uint16_t;
  using Mask = bool;
  static constexpr int kBytes = 1;
  using RegB = uint8_t;
  using Wide = uint16_t;
  static RegB LoadB(const uint8_t* p) { return *p; }
  static void StoreB(uint8_t* p, RegB r) { *p = r; }
  static RegB SetB(uint8_t v) { return v; }
  static RegB MinB(RegB a, RegB b) { return a < b ? a : b; }
  static RegB AddsB(RegB a, RegB b) { return static_cast<RegB>(a + b > 255 ? 255 : a + b); }
  static RegB SubB(RegB a, RegB b) { return static_cast<RegB>(a - b); }
  static uint8_t HMinB(RegB r) { return r; }
  static Wide WideZero() { return 0; }
  static Wide WideLoad(const uint16_t* p) { return *p; }
  static void WideStore(uint16_t* p, Wide w) { *p = w; }
  static Wide WideAdd(Wide w, RegB b) { return static_cast<Wide>(w + b); }
  static Reg Load(const uint16_t* p) { return *p; }
  static void Store(uint16_t* p, Reg r) { *p = r; }
  static Reg Set(uint16_t v) { return v; }
  static Reg Min(Reg a, Reg b) { return a < b ? a : b; }
  static uint16_t HMin(Reg r) { return r; }
  static Mask Lt(Reg a, Reg b) { return a < b; }
  static Mask Eq(Reg a, Reg b) { return a == b; }
  static Reg Blend(Mask m, Reg if_false, Reg if_true) { return m ? if_true : if_false; }
  static uint32_t Bits(Mask m) { return m ? 1u : 0u; }
  static Reg Iota(uint16_t d) { return d; }
};

}  // namespace

const Kernels& ScalarKernels() {
  static const Kernels kernels = MakeKernels<ScalarLanes>("scalar");
  return kernels;
}

}  // namespace specht::stereo::internal
