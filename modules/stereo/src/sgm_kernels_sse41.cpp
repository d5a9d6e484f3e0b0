// SSE4.1 kernels: 8 uint16 lanes (compiled with -msse4.1 -mpopcnt).
#include <smmintrin.h>

#include "internal/sgm_kernels_impl.h"

namespace specht::stereo::internal {
namespace {

struct Sse41Lanes {
  static constexpr int kLanes = 8;
  using Reg = __m128i;
  using Mask = __m128i;
  static constexpr int kBytes = 16;
  using RegB = __m128i;
  struct Wide {
    __m128i lo, hi;
  };
  static RegB LoadB(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
  static void StoreB(uint8_t* p, RegB r) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), r); }
  static RegB SetB(uint8_t v) { return _mm_set1_epi8(static_cast<char>(v)); }
  static RegB MinB(RegB a, RegB b) { return _mm_min_epu8(a, b); }
  static RegB AddsB(RegB a, RegB b) { return _mm_adds_epu8(a, b); }
  static RegB SubB(RegB a, RegB b) { return _mm_sub_epi8(a, b); }
  static uint8_t HMinB(RegB r) {
    const __m128i pairs = _mm_min_epu8(r, _mm_srli_epi16(r, 8));  // low byte of each word: min of its pair
    return static_cast<uint8_t>(_mm_extract_epi16(_mm_minpos_epu16(_mm_and_si128(pairs, _mm_set1_epi16(0xFF))), 0));
  }
  static Wide WideZero() { return {_mm_setzero_si128(), _mm_setzero_si128()}; }
  static Wide WideLoad(const uint16_t* p) { return {Load(p), Load(p + 8)}; }
  static void WideStore(uint16_t* p, Wide w) {
    Store(p, w.lo);
    Store(p + 8, w.hi);
  }
  static Wide WideAdd(Wide w, RegB b) {
    return {_mm_add_epi16(w.lo, _mm_cvtepu8_epi16(b)), _mm_add_epi16(w.hi, _mm_cvtepu8_epi16(_mm_srli_si128(b, 8)))};
  }
  static Reg Load(const uint16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
  static void Store(uint16_t* p, Reg r) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), r); }
  static Reg Set(uint16_t v) { return _mm_set1_epi16(static_cast<short>(v)); }
  static Reg Min(Reg a, Reg b) { return _mm_min_epu16(a, b); }
  static uint16_t HMin(Reg r) { return static_cast<uint16_t>(_mm_extract_epi16(_mm_minpos_epu16(r), 0)); }
  static Mask Lt(Reg a, Reg b) { return _mm_cmplt_epi16(a, b); }
  static Mask Eq(Reg a, Reg b) { return _mm_cmpeq_epi16(a, b); }
  static Reg Blend(Mask m, Reg if_false, Reg if_true) { return _mm_blendv_epi8(if_false, if_true, m); }
  static uint32_t Bits(Mask m) {
    return static_cast<uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(m, _mm_setzero_si128()))) & 0xFFu;
  }
  static Reg Iota(uint16_t d) { return _mm_add_epi16(Set(d), _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7)); }
};

}  // namespace

const Kernels& Sse41Kernels() {
  static const Kernels kernels = MakeKernels<Sse41Lanes>("sse4.1");
  return kernels;
}

}  // namespace specht::stereo::internal
