// AVX-512 kernels: 32 uint16 lanes (compiled with -mavx512f -mavx512bw -mavx512vl
// -mavx512vpopcntdq -mbmi2 -mpopcnt). Needs a disparity count that is a multiple of 32.
#include <immintrin.h>

#include "internal/sgm_kernels_impl.h"

namespace specht::stereo::internal {
namespace {

struct Avx512Lanes {
  static constexpr int kLanes = 32;
  using Reg = __m512i;
  using Mask = __mmask32;
  static constexpr int kBytes = 64;
  using RegB = __m512i;
  struct Wide {
    __m512i lo, hi;
  };
  static RegB LoadB(const uint8_t* p) { return _mm512_loadu_si512(p); }
  static void StoreB(uint8_t* p, RegB r) { _mm512_storeu_si512(p, r); }
  static RegB SetB(uint8_t v) { return _mm512_set1_epi8(static_cast<char>(v)); }
  static RegB MinB(RegB a, RegB b) { return _mm512_min_epu8(a, b); }
  static RegB AddsB(RegB a, RegB b) { return _mm512_adds_epu8(a, b); }
  static RegB SubB(RegB a, RegB b) { return _mm512_sub_epi8(a, b); }
  static uint8_t HMinB(RegB r) {
    const __m256i quarter = _mm256_min_epu8(_mm512_castsi512_si256(r), _mm512_extracti64x4_epi64(r, 1));
    const __m128i half = _mm_min_epu8(_mm256_castsi256_si128(quarter), _mm256_extracti128_si256(quarter, 1));
    const __m128i pairs = _mm_min_epu8(half, _mm_srli_epi16(half, 8));
    return static_cast<uint8_t>(_mm_extract_epi16(_mm_minpos_epu16(_mm_and_si128(pairs, _mm_set1_epi16(0xFF))), 0));
  }
  static Wide WideZero() { return {_mm512_setzero_si512(), _mm512_setzero_si512()}; }
  static Wide WideLoad(const uint16_t* p) { return {Load(p), Load(p + 32)}; }
  static void WideStore(uint16_t* p, Wide w) {
    Store(p, w.lo);
    Store(p + 32, w.hi);
  }
  static Wide WideAdd(Wide w, RegB b) {
    return {_mm512_add_epi16(w.lo, _mm512_cvtepu8_epi16(_mm512_castsi512_si256(b))),
            _mm512_add_epi16(w.hi, _mm512_cvtepu8_epi16(_mm512_extracti64x4_epi64(b, 1)))};
  }
  static Reg Load(const uint16_t* p) { return _mm512_loadu_si512(p); }
  static void Store(uint16_t* p, Reg r) { _mm512_storeu_si512(p, r); }
  static Reg Set(uint16_t v) { return _mm512_set1_epi16(static_cast<short>(v)); }
  static Reg Min(Reg a, Reg b) { return _mm512_min_epu16(a, b); }
  static uint16_t HMin(Reg r) {
    const __m256i quarter = _mm256_min_epu16(_mm512_castsi512_si256(r), _mm512_extracti64x4_epi64(r, 1));
    const __m128i half = _mm_min_epu16(_mm256_castsi256_si128(quarter), _mm256_extracti128_si256(quarter, 1));
    return static_cast<uint16_t>(_mm_extract_epi16(_mm_minpos_epu16(half), 0));
  }
  static Mask Lt(Reg a, Reg b) { return _mm512_cmplt_epu16_mask(a, b); }
  static Mask Eq(Reg a, Reg b) { return _mm512_cmpeq_epu16_mask(a, b); }
  static Reg Blend(Mask m, Reg if_false, Reg if_true) { return _mm512_mask_blend_epi16(m, if_false, if_true); }
  static uint32_t Bits(Mask m) { return static_cast<uint32_t>(m); }
  static Reg Iota(uint16_t d) {
    alignas(64) static constexpr uint16_t kIota[32] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15,
                                                       16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31};
    return _mm512_add_epi16(Set(d), _mm512_load_si512(kIota));
  }
};

}  // namespace

const Kernels& Avx512Kernels() {
  static const Kernels kernels = MakeKernels<Avx512Lanes>("avx512");
  return kernels;
}

}  // namespace specht::stereo::internal
