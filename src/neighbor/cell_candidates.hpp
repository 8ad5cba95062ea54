#pragma once
// The 2D list build's shared candidates (docs/performance.md, "The list
// build"): every particle of one grid cell searches the same block of
// cells, so the block's particles are gathered and put in list order
// (global id, then position for periodic images) once per cell, and each
// particle of the cell keeps those within its cut-off in that order: no
// sort per particle. With AVX-512, eight candidates at a time; with AVX2,
// four (docs/performance.md, "The list build's search with AVX2").
// Internal to src/neighbor/neighbor_list.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SPHDEM_CANDIDATES_AVX512 1
#include "bitonic_keys.hpp"
#elif defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SPHDEM_CANDIDATES_AVX2 1
#endif

#include "sphdem/particles/particles.hpp"

namespace sphdem::neighbor_detail {

// The squared distance every path of the build tests against the cut-off,
// with its roundings spelled out (d0^2, then fused adds), so that the
// vector and the scalar forms keep the same pairs.
template <int D>
double distance2(const Vec<D>& a, const Vec<D>& b) {
  const double d0 = a[0] - b[0];
  double d2 = d0 * d0;
  for (int k = 1; k < D; ++k) {
    const double d = a[k] - b[k];
    d2 = std::fma(d, d, d2);
  }
  return d2;
}

// Two periodic images of one particle share a gid: position breaks the
// tie, so the order never depends on where the images sit in memory.
template <int D>
bool image_before(const SphParticles<D>& ps, std::int32_t a, std::int32_t b) {
  return std::lexicographical_compare(ps.x[a].begin(), ps.x[a].end(), ps.x[b].begin(),
                                      ps.x[b].end());
}

// The most keys sort_keys counts with AVX2 instead of calling std::sort
// (docs/performance.md, "The rebuild's sorts").
inline constexpr std::size_t kCountedKeys = 64;

#if defined(SPHDEM_CANDIDATES_AVX512)
// With AVX-512, the count up to 40 keys and a sorting network up to 128
// (bitonic_keys.hpp): at 20 keys the count takes half the network's time,
// at 86 (a 3D resin particle's candidates) the network 0.8 of the count's
// and a fifth of std::sort's (docs/performance.md, "A sorting network for
// the list build's keys").
inline constexpr std::size_t kCountedKeysAvx512 = 40;
#endif

// Sorts m distinct keys in place. With AVX-512 or AVX2, few keys by a count
// of the keys below each (no branches); with AVX-512, up to 128 by a
// sorting network; more, std::sort.
inline void sort_keys(std::uint64_t* key, std::size_t m, std::vector<std::uint64_t>& spare) {
#if defined(SPHDEM_CANDIDATES_AVX512)
  if (m > kCountedKeysAvx512 && m <= bitonic::kMaxKeys) {
    bitonic::sort(key, m);
    return;
  }
  if (m <= kCountedKeysAvx512) {
    __m512i r[(kCountedKeysAvx512 + 7) / 8];
    const std::size_t regs = (m + 7) / 8;
    const __m512i top = _mm512_set1_epi64(-1);  // above every key (an index is below 2^31)
    for (std::size_t q = 0; q < regs; ++q) {
      const std::size_t left = m - 8 * q;
      const auto valid = static_cast<__mmask8>(left >= 8 ? 0xff : (1u << left) - 1);
      r[q] = _mm512_mask_loadu_epi64(top, valid, key + 8 * q);
    }
    spare.resize(std::max<std::size_t>(spare.size(), m));
    for (std::size_t a = 0; a < m; ++a) {
      const __m512i b = _mm512_set1_epi64(static_cast<long long>(key[a]));
      unsigned below = 0;
      for (std::size_t q = 0; q < regs; ++q)
        below += static_cast<unsigned>(__builtin_popcount(_mm512_cmplt_epu64_mask(r[q], b)));
      spare[below] = key[a];
    }
    std::copy(spare.begin(), spare.begin() + static_cast<std::ptrdiff_t>(m), key);
    return;
  }
#elif defined(SPHDEM_CANDIDATES_AVX2)
  // The same count four keys at a time. AVX2 compares signed 64-bit
  // integers: flipping every key's top bit keeps their unsigned order.
  if (m <= kCountedKeys) {
    __m256i r[kCountedKeys / 4];
    const std::size_t regs = (m + 3) / 4;
    const __m256i flip = _mm256_set1_epi64x(static_cast<long long>(1ULL << 63));
    // The padding, above every flipped key (an index is below 2^31).
    constexpr auto kTop = static_cast<std::uint64_t>(std::numeric_limits<long long>::max());
    for (std::size_t q = 0; q < regs; ++q) {
      alignas(32) std::uint64_t four[4];
      for (std::size_t l = 0; l < 4; ++l)
        four[l] = 4 * q + l < m ? key[4 * q + l] ^ (1ULL << 63) : kTop;
      r[q] = _mm256_load_si256(reinterpret_cast<const __m256i*>(four));
    }
    spare.resize(std::max<std::size_t>(spare.size(), m));
    for (std::size_t a = 0; a < m; ++a) {
      const __m256i b = _mm256_xor_si256(_mm256_set1_epi64x(static_cast<long long>(key[a])), flip);
      unsigned below = 0;
      for (std::size_t q = 0; q < regs; ++q)
        below += static_cast<unsigned>(__builtin_popcount(static_cast<unsigned>(
            _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(b, r[q]))))));
      spare[below] = key[a];
    }
    std::copy(spare.begin(), spare.begin() + static_cast<std::ptrdiff_t>(m), key);
    return;
  }
#else
  (void)spare;
#endif
  std::sort(key, key + m);
}

// Keys gid << 32 | index in gid order, each run of one gid (periodic
// images) by position.
template <int D>
void sort_packed(const SphParticles<D>& ps, std::uint64_t* key, std::size_t m,
                 std::vector<std::uint64_t>& spare) {
  sort_keys(key, m, spare);
  for (std::size_t a = 0; a + 1 < m;) {
    std::size_t b = a + 1;
    while (b < m && key[b] >> 32 == key[a] >> 32) ++b;
    if (b - a > 1) {
      std::sort(key + a, key + b, [&](std::uint64_t p, std::uint64_t q) {
        return image_before<D>(ps, static_cast<std::int32_t>(p & 0xffffffffU),
                               static_cast<std::int32_t>(q & 0xffffffffU));
      });
    }
    a = b;
  }
}

#if defined(SPHDEM_CANDIDATES_AVX2)
// The byte shuffle that packs the 32-bit lanes of a 4-bit mask's set bits
// to the front, in order (the rest of the register is left as garbage).
struct PackFour {
  alignas(16) std::uint8_t bytes[16][16];
  constexpr PackFour() : bytes{} {
    for (unsigned mask = 0; mask < 16; ++mask) {
      unsigned to = 0;
      for (unsigned lane = 0; lane < 4; ++lane)
        if ((mask >> lane) & 1u) {
          for (unsigned b = 0; b < 4; ++b)
            bytes[mask][4 * to + b] = static_cast<std::uint8_t>(4 * lane + b);
          ++to;
        }
      for (unsigned b = 4 * to; b < 16; ++b) bytes[mask][b] = 0x80;
    }
  }
};
inline constexpr PackFour kPackFour{};
#endif

#if defined(SPHDEM_CANDIDATES_AVX512)
// The distance test of the candidates held one array per axis (x[d], with
// eight doubles to spare past the end) against the point xi: which of the
// eight at k (of those in `valid`) lie within sqrt(rc2), with distance2's
// operations.
template <int D>
class Within8 {
 public:
  Within8(const Vec<D>& xi, double rc2, const std::vector<double> (&x)[D])
      : limit_(_mm512_set1_pd(rc2)) {
    for (int d = 0; d < D; ++d) {
      x_[d] = x[d].data();
      xv_[d] = _mm512_set1_pd(xi[d]);
    }
  }
  __mmask8 operator()(std::size_t k, __mmask8 valid) const {
    __m512d t = _mm512_sub_pd(xv_[0], _mm512_loadu_pd(x_[0] + k));
    __m512d d2 = _mm512_mul_pd(t, t);
    for (int d = 1; d < D; ++d) {
      t = _mm512_sub_pd(xv_[d], _mm512_loadu_pd(x_[d] + k));
      d2 = _mm512_fmadd_pd(t, t, d2);
    }
    return _mm512_mask_cmp_pd_mask(valid, d2, limit_, _CMP_LT_OQ);
  }

 private:
  __m512d xv_[D];
  __m512d limit_;
  const double* x_[D];
};

// The 3D search (NeighborList<3>::build; docs/performance.md, "A fourth
// CPU, AMD Zen 5; the 3D list build's search eight at a time"): the binned
// particles' coordinates, one array per axis, and their keys (gid << 32 |
// index, every gid below 2^32), in bin order, so that a run of cells
// adjacent in memory is one run of candidates, read without a gather.
template <int D>
class BinnedCandidates {
 public:
  // items[0 .. n): the particles in bin order.
  void fill(const SphParticles<D>& ps, const std::int32_t* items, std::size_t n) {
    for (auto& c : x_) c.resize(n + 8);  // whole vectors past the end
    key_.resize(n + 8);
    for (std::size_t s = 0; s < n; ++s) {
      const auto j = static_cast<std::size_t>(items[s]);
      for (int d = 0; d < D; ++d) x_[d][s] = ps.x[j][d];
      key_[s] = static_cast<std::uint64_t>(ps.gid[j]) << 32 | static_cast<std::uint32_t>(j);
    }
  }

  // Appends to out the keys of candidates [s0, s1) within sqrt(rc2) of xi,
  // but `self` (a key); returns the new end. Stores whole vectors: out has
  // room for 8 past the last key kept.
  std::uint64_t* near(const Vec<D>& xi, double rc2, std::uint64_t self, std::size_t s0,
                      std::size_t s1, std::uint64_t* out) const {
    const Within8<D> within(xi, rc2, x_);
    const __m512i me = _mm512_set1_epi64(static_cast<long long>(self));
    for (std::size_t s = s0; s < s1; s += 8) {
      const auto valid = static_cast<__mmask8>(s1 - s >= 8 ? 0xff : (1u << (s1 - s)) - 1);
      const __m512i k = _mm512_loadu_si512(key_.data() + s);
      const __mmask8 keep = _mm512_mask_cmpneq_epi64_mask(within(s, valid), k, me);
      // Compressed in a register and stored whole (CellCandidates::near).
      _mm512_storeu_si512(out, _mm512_maskz_compress_epi64(keep, k));
      out += __builtin_popcount(keep);
    }
    return out;
  }

 private:
  std::vector<double> x_[D];
  std::vector<std::uint64_t> key_;
};
#endif

// One cell's candidates in list order, structure of arrays, padded to a
// multiple of 8 so that vector loads stay inside.
template <int D>
class CellCandidates {
 public:
  // The m keys (gid << 32 | index, every gid below 2^32) as candidates.
  void prepare(const SphParticles<D>& ps, const std::vector<std::uint64_t>& keys, std::size_t m) {
    key_.assign(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(m));
    sort_packed<D>(ps, key_.data(), m, spare_);
    m_ = m;
    const std::size_t padded = (m + 7) / 8 * 8;
    for (int d = 0; d < D; ++d) x_[d].assign(padded, 0.0);
    index_.assign(padded, 0);
    wall_bits_.assign(padded / 8, 0);
    for (std::size_t k = 0; k < m; ++k) {
      const auto j = static_cast<std::int32_t>(key_[k] & 0xffffffffU);
      index_[k] = j;
      for (int d = 0; d < D; ++d) x_[d][k] = ps.x[j][d];
      if (ps.kind[j] == Kind::Wall) wall_bits_[k / 8] |= static_cast<std::uint8_t>(1u << (k % 8));
    }
  }

  // The candidates within sqrt(rc2) of xi (distance2), but `self` and, for
  // a wall particle, the walls, in list order into out; returns their
  // count. out has room for size() + 8 (whole vectors are stored).
  std::size_t near(const Vec<D>& xi, std::int32_t self, bool wall_i, double rc2,
                   std::int32_t* out) const {
    std::size_t n = 0;
    const std::int32_t* const index = index_.data();
    const std::uint8_t* const walls = wall_bits_.data();
#if defined(SPHDEM_CANDIDATES_AVX512)
    const Within8<D> within(xi, rc2, x_);
    const __m256i own = _mm256_set1_epi32(self);
    const auto no_walls = static_cast<std::uint8_t>(wall_i ? 0xff : 0);
    for (std::size_t k = 0; k < m_; k += 8) {
      const std::size_t left = m_ - k;
      const auto valid = static_cast<__mmask8>(left >= 8 ? 0xff : (1u << left) - 1);
      const __m256i id = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + k));
      __mmask8 keep = within(k, valid);
      keep &= _mm256_cmpneq_epi32_mask(id, own);
      keep &= static_cast<__mmask8>(~(walls[k / 8] & no_walls));
      // Compressed in a register and stored whole: a compressing store to
      // memory is microcoded and slow on some CPUs (AMD Zen 4).
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + n),
                          _mm256_maskz_compress_epi32(keep, id));
      n += static_cast<std::size_t>(__builtin_popcount(keep));
    }
#elif defined(SPHDEM_CANDIDATES_AVX2)
    // Four at a time, the kept indices packed to the front of a register
    // (kPackFour) and stored whole: no branch on the distance test, which
    // goes either way about as often (the scalar form mispredicted it).
    const double* x[D];
    __m256d xv[D];
    for (int d = 0; d < D; ++d) {
      x[d] = x_[d].data();
      xv[d] = _mm256_set1_pd(xi[d]);
    }
    const __m256d limit = _mm256_set1_pd(rc2);
    const __m128i own = _mm_set1_epi32(self);
    const unsigned no_walls = wall_i ? 0xffu : 0u;
    for (std::size_t k = 0; k < m_; k += 4) {
      const std::size_t left = m_ - k;
      const unsigned valid = left >= 4 ? 0xfu : (1u << left) - 1u;
      __m256d t = _mm256_sub_pd(xv[0], _mm256_loadu_pd(x[0] + k));
      __m256d d2 = _mm256_mul_pd(t, t);
      for (int d = 1; d < D; ++d) {
        t = _mm256_sub_pd(xv[d], _mm256_loadu_pd(x[d] + k));
        d2 = _mm256_fmadd_pd(t, t, d2);
      }
      const __m128i id = _mm_loadu_si128(reinterpret_cast<const __m128i*>(index + k));
      unsigned keep =
          valid & static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(d2, limit, _CMP_LT_OQ)));
      keep &= ~static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(id, own))));
      keep &= ~((walls[k / 8] & no_walls) >> (k % 8));
      keep &= 0xfu;
      const __m128i pack = _mm_load_si128(reinterpret_cast<const __m128i*>(kPackFour.bytes[keep]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + n), _mm_shuffle_epi8(id, pack));
      n += static_cast<std::size_t>(__builtin_popcount(keep));
    }
#else
    for (std::size_t k = 0; k < m_; ++k) {
      Vec<D> xj;
      for (int d = 0; d < D; ++d) xj[d] = x_[d][k];
      const bool wall_k = (walls[k / 8] >> (k % 8)) & 1u;
      if (index[k] != self && !(wall_i && wall_k) && distance2<D>(xi, xj) < rc2)
        out[n++] = index[k];
    }
#endif
    return n;
  }

  std::size_t size() const {
    return m_;
  }

 private:
  std::vector<std::uint64_t> key_, spare_;
  std::vector<double> x_[D];
  std::vector<std::int32_t> index_;
  std::vector<std::uint8_t> wall_bits_;  // bit k % 8 of byte k / 8: candidate k is a wall
  std::size_t m_ = 0;
};

}  // namespace sphdem::neighbor_detail
