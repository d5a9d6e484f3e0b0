// AVX2 kernels: 16 uint16 lanes (compiled with -mavx2 -mbmi2 -mpopcnt).
#include <immintrin.h>

#include "internal/sgm_kernels_impl.h"

namespace specht::stereo::internal {
namespace {

struct Avx2Lanes {
  static constexpr int kLanes = 16;
  using Reg = __m256i;
  using Mask = __m256i;
  static constexpr int kBytes = 32;
  using RegB = __m256i;
  struct Wide {
    __m256i lo, hi;
  };
  static RegB LoadB(const uint8_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  static void StoreB(uint8_t* p, RegB r) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), r); }
  static RegB SetB(uint8_t v) { return _mm256_set1_epi8(static_cast<char>(v)); }
  static RegB MinB(RegB a, RegB b) { return _mm256_min_epu8(a, b); }
  static RegB AddsB(RegB a, RegB b) { return _mm256_adds_epu8(a, b); }
  static RegB SubB(RegB a, RegB b) { return _mm256_sub_epi8(a, b); }
  static uint8_t HMinB(RegB r) {
    const __m128i half = _mm_min_epu8(_mm256_castsi256_si128(r), _mm256_extracti128_si256(r, 1));
    const __m128i pairs = _mm_min_epu8(half, _mm_srli_epi16(half, 8));
    return static_cast<uint8_t>(_mm_extract_epi16(_mm_minpos_epu16(_mm_and_si128(pairs, _mm_set1_epi16(0xFF))), 0));
  }
  static Wide WideZero() { return {_mm256_setzero_si256(), _mm256_setzero_si256()}; }
  static Wide WideLoad(const uint16_t* p) { return {Load(p), Load(p + 16)}; }
  static void WideStore(uint16_t* p, Wide w) {
    Store(p, w.lo);
    Store(p + 16, w.hi);
  }
  static Wide WideAdd(Wide w, RegB b) {
    return {_mm256_add_epi16(w.lo, _mm256_cvtepu8_epi16(_mm256_castsi256_si128(b))),
            _mm256_add_epi16(w.hi, _mm256_cvtepu8_epi16(_mm256_extracti128_si256(b, 1)))};
  }
  static Reg Load(const uint16_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  static void Store(uint16_t* p, Reg r) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), r); }
  static Reg Set(uint16_t v) { return _mm256_set1_epi16(static_cast<short>(v)); }
  static Reg Min(Reg a, Reg b) { return _mm256_min_epu16(a, b); }
  static uint16_t HMin(Reg r) {
    const __m128i half = _mm_min_epu16(_mm256_castsi256_si128(r), _mm256_extracti128_si256(r, 1));
    return static_cast<uint16_t>(_mm_extract_epi16(_mm_minpos_epu16(half), 0));
  }
  static Mask Lt(Reg a, Reg b) { return _mm256_cmpgt_epi16(b, a); }
  static Mask Eq(Reg a, Reg b) { return _mm256_cmpeq_epi16(a, b); }
  static Reg Blend(Mask m, Reg if_false, Reg if_true) { return _mm256_blendv_epi8(if_false, if_true, m); }
  static uint32_t Bits(Mask m) { return _pext_u32(static_cast<uint32_t>(_mm256_movemask_epi8(m)), 0x55555555u); }
  static Reg Iota(uint16_t d) {
    return _mm256_add_epi16(Set(d), _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
};

}  // namespace

const Kernels& Avx2Kernels() {
  static const Kernels kernels = MakeKernels<Avx2Lanes>("avx2");
  return kernels;
}

}  // namespace specht::stereo::internal
