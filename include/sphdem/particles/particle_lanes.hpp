#pragma once
// Eight particles at a time (AVX-512), or four (AVX2), in the passes over
// particles that GCC does not vectorize itself (one-byte kinds beside
// D-double vectors): which of particles i .. i + 7 are resin, and the masks
// of their vectors' doubles (docs/performance.md, "The passes over
// particles", "The streaming passes with AVX2").
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__) && defined(__BMI2__)
#include <immintrin.h>
#define SPHDEM_PARTICLE_LANES 1
#elif defined(__AVX2__) && defined(__FMA__)
// Without AVX-512: four particles at a time in the resin's kicks
// (src/solver/resin_leapfrog.hpp), with blends instead of mask registers.
#include <immintrin.h>
#define SPHDEM_PARTICLE_LANES4 1
#endif

#include "sphdem/particles/particles.hpp"

namespace sphdem::lanes {

#if defined(SPHDEM_PARTICLE_LANES)
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

// The first `count` bits (count <= 8): the particles of a group that exist.
inline __mmask8 first(std::size_t count) {
  return count >= 8 ? __mmask8{0xff} : static_cast<__mmask8>((1u << count) - 1u);
}

// Bit l: particle i + l is one of `valid` and of kind k (reads no kind
// outside `valid`).
inline __mmask8 of_kind(const Kind* kind, std::size_t i, __mmask8 valid, Kind k) {
  const __m128i kinds = _mm_maskz_loadu_epi8(valid, kind + i);
  return _mm_mask_cmpeq_epi8_mask(valid, kinds, _mm_set1_epi8(static_cast<char>(k)));
}

// Bit l: particle i + l is resin (a whole group of eight).
inline __mmask8 resin(const Kind* kind, std::size_t i) {
  return of_kind(kind, i, 0xff, Kind::Fluid);
}

// Bit l: particle i + l is one of `valid` and flag[i + l] is not 0.
inline __mmask8 set(const std::int32_t* flag, std::size_t i, __mmask8 valid) {
  return _mm256_mask_test_epi32_mask(valid, _mm256_maskz_loadu_epi32(valid, flag + i),
                                     _mm256_set1_epi32(-1));
}

// Bit l: flag[i + l] is not 0 (a whole group of eight).
inline __mmask8 set(const std::int32_t* flag, std::size_t i) {
  return set(flag, i, 0xff);
}

// GCC 12's unmasked forms of some AVX-512 operations start from an undefined
// register and warn (an error with -Werror); these are the same operations
// through their zero-masked forms with every lane.
// max(a, b): lane l is b[l] unless a[l] > b[l] (a NaN in a keeps b).
inline __m512d max(__m512d a, __m512d b) {
  return _mm512_maskz_max_pd(0xff, a, b);
}

// a b and a + b, each rounded on its own: GCC treats _mm512_mul_pd and
// _mm512_add_pd as plain arithmetic and fuses a product into a sum
// (-ffp-contract=fast); it leaves the forms with a rounding mode alone.
inline __m512d mul(__m512d a, __m512d b) {
  return _mm512_maskz_mul_round_pd(0xff, a, b, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}
inline __m512d add(__m512d a, __m512d b) {
  return _mm512_maskz_add_round_pd(0xff, a, b, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}

// The largest of the eight lanes (none NaN).
inline double largest(__m512d v) {
  v = max(v, _mm512_maskz_shuffle_f64x2(0xff, v, v, 0x4e));  // the other half
  v = max(v, _mm512_maskz_shuffle_f64x2(0xff, v, v, 0xb1));  // the other quarter
  v = max(v, _mm512_maskz_permute_pd(0xff, v, 0x55));        // the other lane
  return _mm512_cvtsd_f64(v);
}

// The D registers of eight particles' D-vectors (particle i + l's doubles
// at p[D (i + l)] ..), the particles not in `valid` read as 0.
template <int D>
void load_vectors(const double* p, std::size_t i, __mmask8 valid, __m512d (&r)[D]) {
  for (int q = 0; q < D; ++q)
    r[q] = _mm512_maskz_loadu_pd(vector_mask<D>(valid, q), p + D * i + 8 * q);
}

// The same from floats, each widened to a double exactly.
template <int D>
void load_vectors(const float* p, std::size_t i, __mmask8 valid, __m512d (&r)[D]) {
  for (int q = 0; q < D; ++q) {
    const __mmask8 m = vector_mask<D>(valid, q);
    r[q] = _mm512_maskz_cvtps_pd(m, _mm256_maskz_loadu_ps(m, p + D * i + 8 * q));
  }
}

// Component d of the eight vectors held as load_vectors gives them: lane l
// is particle l's component d (a permutation: no arithmetic). Its index
// tables are constants and it is always inlined: out of line, in 3D, it
// built them at every call (4 % of the 3D plate's step, docs/performance.md
// "Where a 3D coupled step goes").
namespace component_detail {
// Lane l of component d is double D l + d of the 8 D: from the first two
// registers (indices 0-15 of permutex2var) or from the third (D == 3).
template <int D>
struct Tables {
  alignas(64) long long low[D][8];
  alignas(64) long long high[D][8];
  __mmask8 from_third[D];
  // store_vectors: register q of the stored doubles takes lane l of
  // component 0 or 1 (from_two) or of component 2 (from_last, D == 3).
  alignas(64) long long from_two[D][8];
  alignas(64) long long from_last[D][8];
  __mmask8 last[D];
};
template <int D>
constexpr Tables<D> make_tables() {
  Tables<D> t{};
  for (int d = 0; d < D; ++d) {
    t.from_third[d] = 0;
    for (int l = 0; l < 8; ++l) {
      const int at = D * l + d;
      t.low[d][l] = at < 16 ? at : 0;
      t.high[d][l] = at < 16 ? 0 : at - 16;
      if (at >= 16) t.from_third[d] = static_cast<__mmask8>(t.from_third[d] | (1u << l));
    }
  }
  for (int q = 0; q < D; ++q) {
    t.last[q] = 0;
    for (int k = 0; k < 8; ++k) {
      const int at = 8 * q + k;  // its place among the 8 D doubles
      const int d = at % D, l = at / D;
      t.from_two[q][k] = d == 0 ? l : d == 1 ? 8 + l : 0;
      t.from_last[q][k] = d == 2 ? l : 0;
      if (d == 2) t.last[q] = static_cast<__mmask8>(t.last[q] | (1u << k));
    }
  }
  return t;
}
template <int D>
inline constexpr Tables<D> kTables = make_tables<D>();
}  // namespace component_detail

template <int D>
__attribute__((always_inline)) inline __m512d component(const __m512d (&r)[D], int d) {
  static_assert(D == 2 || D == 3);
  const auto& t = component_detail::kTables<D>;
  __m512d c = _mm512_permutex2var_pd(r[0], _mm512_load_si512(t.low[d]), r[1]);
  if constexpr (D == 3)
    c = _mm512_mask_permutexvar_pd(c, t.from_third[d], _mm512_load_si512(t.high[d]), r[2]);
  return c;
}

// The inverse of component: rows[d] lane l is particle i + l's component
// d; stores the eight particles' D-vectors at p[D i] .. (permutations: no
// arithmetic).
template <int D>
__attribute__((always_inline)) inline void store_vectors(double* p, std::size_t i,
                                                         const __m512d (&rows)[D]) {
  static_assert(D == 2 || D == 3);
  const auto& t = component_detail::kTables<D>;
  for (int q = 0; q < D; ++q) {
    __m512d out = _mm512_permutex2var_pd(rows[0], _mm512_load_si512(t.from_two[q]), rows[1]);
    if constexpr (D == 3)
      out = _mm512_mask_permutexvar_pd(out, t.last[q], _mm512_load_si512(t.from_last[q]), rows[2]);
    _mm512_storeu_pd(p + D * i + 8 * static_cast<std::size_t>(q), out);
  }
}
#endif

#if defined(SPHDEM_PARTICLE_LANES4)
// Bit l: particle i + l is resin (i .. i + 3).
inline unsigned resin4(const Kind* kind, std::size_t i) {
  unsigned bits = 0;
  for (unsigned l = 0; l < 4; ++l) bits |= (kind[i + l] == Kind::Fluid ? 1u : 0u) << l;
  return bits;
}

// Bit l: flag[i + l] is not 0 (i .. i + 3).
inline unsigned set4(const std::int32_t* flag, std::size_t i) {
  unsigned bits = 0;
  for (unsigned l = 0; l < 4; ++l) bits |= (flag[i + l] != 0 ? 1u : 0u) << l;
  return bits;
}

// For each register q of four particles' D-vectors (particle l's doubles
// are D l .. D l + D - 1) and each mask of the four particles, the
// register's doubles that belong to them: all bits set, else 0.
template <int D>
struct VectorMasks4 {
  alignas(32) long long m[D][16][4]{};
  constexpr VectorMasks4() {
    for (int q = 0; q < D; ++q)
      for (unsigned bits = 0; bits < 16; ++bits)
        for (int s = 0; s < 4; ++s) m[q][bits][s] = (bits >> ((4 * q + s) / D)) & 1u ? -1 : 0;
  }
};
template <int D>
inline constexpr VectorMasks4<D> kVectorMasks4{};

// The blend mask of register q for the particles of `bits` (D = 1: a
// scalar field, one double per particle).
template <int D>
__m256d vector_mask4(unsigned bits, int q) {
  return _mm256_castsi256_pd(
      _mm256_load_si256(reinterpret_cast<const __m256i*>(kVectorMasks4<D>.m[q][bits])));
}
#endif

// a b + c in the one-particle forms: fused where the build has FMA (every
// AVX-512 build does, so these forms give the vector forms' bits); without
// it a product and a sum, as GCC computes a b + c there, instead of a call
// to libm's fma per particle.
inline double mul_add(double a, double b, double c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

// Calls f(i) for each i < n with kind[i] == k, in increasing order (with
// AVX-512, 64 kinds compared at a time: the passes that touch only the walls
// skip the resin quickly).
template <class F>
void for_each_of_kind(const Kind* kind, std::size_t n, Kind k, F&& f) {
#if defined(SPHDEM_PARTICLE_LANES)
  const __m512i wanted = _mm512_set1_epi8(static_cast<char>(k));
  for (std::size_t i = 0; i < n; i += 64) {
    const __mmask64 valid = n - i >= 64 ? ~__mmask64{0} : (__mmask64{1} << (n - i)) - 1;
    __mmask64 m =
        _mm512_mask_cmpeq_epi8_mask(valid, _mm512_maskz_loadu_epi8(valid, kind + i), wanted);
    for (; m != 0; m &= m - 1) f(i + static_cast<std::size_t>(__builtin_ctzll(m)));
  }
#else
  for (std::size_t i = 0; i < n; ++i)
    if (kind[i] == k) f(i);
#endif
}

// Calls f(i) for each i < n with v[i] != 0 (a NaN too; -0 is 0), in
// increasing order, eight values compared at a time with AVX-512 and four
// with AVX2: the free-surface flags' scan after the pair loop, where most
// steps find none (docs/performance.md, "The rebuild's sorts").
template <class F>
void for_each_nonzero(const double* v, std::size_t n, F&& f) {
  std::size_t i = 0;
#if defined(SPHDEM_PARTICLE_LANES)
  for (; i + 8 <= n; i += 8) {
    unsigned m = _mm512_cmp_pd_mask(_mm512_loadu_pd(v + i), _mm512_setzero_pd(), _CMP_NEQ_UQ);
    for (; m != 0; m &= m - 1) f(i + static_cast<std::size_t>(__builtin_ctz(m)));
  }
#elif defined(SPHDEM_PARTICLE_LANES4)
  for (; i + 4 <= n; i += 4) {
    auto m = static_cast<unsigned>(_mm256_movemask_pd(
        _mm256_cmp_pd(_mm256_loadu_pd(v + i), _mm256_setzero_pd(), _CMP_NEQ_UQ)));
    for (; m != 0; m &= m - 1) f(i + static_cast<std::size_t>(__builtin_ctz(m)));
  }
#endif
  for (; i < n; ++i)
    if (v[i] != 0.0) f(i);
}

}  // namespace sphdem::lanes
