#pragma once
// Eight particles at a time in the passes over particles that GCC does not
// vectorize itself (one-byte kinds beside D-double vectors): which of
// particles i .. i + 7 are resin, and the masks of their vectors' doubles
// (docs/performance.md, "The passes over particles").
#include <cstdint>
#include <cstring>

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__BMI2__)
#include <immintrin.h>
#define SPHDEM_PARTICLE_LANES 1
#endif

#include "sphdem/particles/particles.hpp"

namespace sphdem::lanes {

#if defined(SPHDEM_PARTICLE_LANES)
// Bit l: particle i + l is resin.
inline __mmask8 resin(const Kind* kind, std::size_t i) {
  static_assert(sizeof(Kind) == 1);
  std::uint64_t kinds;
  std::memcpy(&kinds, kind + i, sizeof kinds);
  const __m128i k = _mm_cvtsi64_si128(static_cast<long long>(kinds));
  return static_cast<__mmask8>(
      _mm_cmpeq_epi8_mask(k, _mm_set1_epi8(static_cast<char>(Kind::Fluid))) & 0xff);
}

// Bit l: flag[i + l] is not 0.
inline __mmask8 set(const std::int32_t* flag, std::size_t i) {
  return _mm256_test_epi32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(flag + i)),
                                _mm256_set1_epi32(-1));
}

// For a mask of eight particles, the mask of the q-th of the D registers
// that hold their D-vectors (particle l's doubles are D l .. D l + D - 1).
template <int D>
__mmask8 vector_mask(__mmask8 particles, int q) {
  std::uint32_t spread = 0;
  for (int d = 0; d < D; ++d) {
    std::uint32_t pattern = 0;
    for (int l = 0; l < 8; ++l) pattern |= 1u << (D * l + d);
    spread |= _pdep_u32(particles, pattern);
  }
  return static_cast<__mmask8>(spread >> (8 * q));
}
#endif

}  // namespace sphdem::lanes
