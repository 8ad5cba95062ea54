#pragma once
// Up to 128 64-bit keys sorted in AVX-512 registers by a bitonic network
// (Batcher 1968): the list build's candidates, about 80 per 3D resin
// particle and 69 per 2D cell block, where std::sort's compares are
// branches taken at random (docs/performance.md, "A sorting network for the
// list build's keys"). The network's compares do not depend on the keys,
// so the order is the keys' order whatever they are: the same as std::sort
// for distinct keys. Internal to src/neighbor/cell_candidates.hpp.
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

namespace sphdem::neighbor_detail::bitonic {

// The masked forms with every lane set are the plain instructions; the
// unmasked intrinsics pass GCC 12 an undefined vector that
// -Wmaybe-uninitialized reports.
inline __m512i permute(__m512i index, __m512i v) {
  return _mm512_maskz_permutexvar_epi64(0xff, index, v);
}
inline __m512i lower(__m512i a, __m512i b) {
  return _mm512_maskz_min_epu64(0xff, a, b);
}
inline __m512i higher(__m512i a, __m512i b) {
  return _mm512_maskz_max_epu64(0xff, a, b);
}

// Lane l paired with lane l ^ Dist: the lower lane keeps the smaller key
// (upper: the lanes with bit Dist set take the larger).
template <int Dist>
inline __m512i half_clean_lanes(__m512i v) {
  static_assert(Dist == 1 || Dist == 2 || Dist == 4);
  const __m512i partner = _mm512_set_epi64(7 ^ Dist, 6 ^ Dist, 5 ^ Dist, 4 ^ Dist, 3 ^ Dist,
                                           2 ^ Dist, 1 ^ Dist, 0 ^ Dist);
  constexpr __mmask8 upper = Dist == 1 ? 0xaa : Dist == 2 ? 0xcc : 0xf0;
  const __m512i p = permute(partner, v);
  return _mm512_mask_blend_epi64(upper, lower(v, p), higher(v, p));
}

// Lane l paired with lane l ^ (2S - 1) within blocks of 2S lanes: two
// sorted runs of S lanes become a low and a high bitonic half.
template <int S>
inline __m512i flip_lanes(__m512i v) {
  static_assert(S == 1 || S == 2 || S == 4);
  constexpr int F = 2 * S - 1;
  const __m512i partner = _mm512_set_epi64(7 ^ F, 6 ^ F, 5 ^ F, 4 ^ F, 3 ^ F, 2 ^ F, 1 ^ F, 0 ^ F);
  constexpr __mmask8 upper = S == 1 ? 0xaa : S == 2 ? 0xcc : 0xf0;
  const __m512i p = permute(partner, v);
  return _mm512_mask_blend_epi64(upper, lower(v, p), higher(v, p));
}

// A register whose lanes form a bitonic sequence, sorted.
inline __m512i clean_register(__m512i v) {
  return half_clean_lanes<1>(half_clean_lanes<2>(half_clean_lanes<4>(v)));
}

// Eight keys of one register sorted.
inline __m512i sort_register(__m512i v) {
  v = flip_lanes<1>(v);
  v = half_clean_lanes<1>(flip_lanes<2>(v));
  return clean_register(flip_lanes<4>(v));
}

inline void min_max(__m512i& lo, __m512i& hi) {
  const __m512i a = lo;
  lo = lower(a, hi);
  hi = higher(a, hi);
}

// N registers, each run of B sorted registers (B a power of two, 2B <= N)
// merged with the next into sorted runs of 2B.
template <int N, int B>
inline void merge_runs(__m512i* r) {
  const __m512i reverse = _mm512_set_epi64(0, 1, 2, 3, 4, 5, 6, 7);
  for (int run = 0; run < N; run += 2 * B) {
    // The flip: key p of the run's first half against key 16B - 1 - p.
    for (int k = 0; k < B; ++k) {
      __m512i& a = r[run + k];
      __m512i& b = r[run + 2 * B - 1 - k];
      __m512i high = permute(reverse, b);
      min_max(a, high);
      b = permute(reverse, high);
    }
    // Each half is now bitonic: half-cleaners across registers, then lanes.
    for (int d = B / 2; d >= 1; d /= 2)
      for (int k = run; k < run + 2 * B; ++k)
        if ((k - run) % (2 * d) < d) min_max(r[k], r[k + d]);
    for (int k = run; k < run + 2 * B; ++k) r[k] = clean_register(r[k]);
  }
}

// N registers (a power of two, at most 16) sorted as one run of 8N keys.
template <int N>
inline void sort_registers(__m512i* r) {
  for (int k = 0; k < N; ++k) r[k] = sort_register(r[k]);
  if constexpr (N >= 2) merge_runs<N, 1>(r);
  if constexpr (N >= 4) merge_runs<N, 2>(r);
  if constexpr (N >= 8) merge_runs<N, 4>(r);
  if constexpr (N >= 16) merge_runs<N, 8>(r);
}

// m <= 8N keys sorted in place. The registers are padded with 2^64 - 1,
// which sorts last; a key of that value is equal to the padding, so the
// first m places still hold the m keys in order.
template <int N>
inline void sort_padded(std::uint64_t* key, std::size_t m) {
  __m512i r[N];
  const __m512i top = _mm512_set1_epi64(-1);
  for (int q = 0; q < N; ++q) {
    const std::size_t first = 8 * static_cast<std::size_t>(q);
    const std::size_t left = m > first ? m - first : 0;
    const auto valid = static_cast<__mmask8>(left >= 8 ? 0xff : (1u << left) - 1);
    r[q] = _mm512_mask_loadu_epi64(top, valid, key + first);
  }
  sort_registers<N>(r);
  for (int q = 0; q < N; ++q) {
    const std::size_t first = 8 * static_cast<std::size_t>(q);
    const std::size_t left = m > first ? m - first : 0;
    const auto valid = static_cast<__mmask8>(left >= 8 ? 0xff : (1u << left) - 1);
    _mm512_mask_storeu_epi64(key + first, valid, r[q]);
  }
}

// The most keys the network sorts.
inline constexpr std::size_t kMaxKeys = 128;

// m <= kMaxKeys keys sorted in place, in the fewest registers that hold them.
inline void sort(std::uint64_t* key, std::size_t m) {
  if (m <= 8)
    sort_padded<1>(key, m);
  else if (m <= 16)
    sort_padded<2>(key, m);
  else if (m <= 32)
    sort_padded<4>(key, m);
  else if (m <= 64)
    sort_padded<8>(key, m);
  else
    sort_padded<16>(key, m);
}

}  // namespace sphdem::neighbor_detail::bitonic
