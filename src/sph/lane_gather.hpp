#pragma once
// Step 1 of the pair loop (pair_loop.hpp): copying the declared fields of a
// chunk's neighbours j from their packed records into lane rows,
//   lanes[row * kChunk + k] = rec_j[src]   or   own[rel] - rec_j[src],
// so that step 2 reads contiguous lanes. Two ways, bitwise the same (a copy
// and the same subtraction per value; tests/test_lane_gather.cpp):
//   - GatherLanes::run, one neighbour at a time, element by element
//     (GCC builds each 8-lane vector from scalar loads and inserts);
//   - GatherLanes::four_pairs (with AVX), four neighbours at a time, a
//     transpose in registers: the record's doubles 2p, 2p+1 of neighbours
//     0 and 2 in one 256-bit register, of 1 and 3 in another, then one
//     unpack per lane row (docs/performance.md, "The gather as a
//     transpose").
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "term_interface.hpp"

namespace sphdem::terms {

// Where lane row r comes from: record double src[r], subtracted from
// particle i's record double rel[r] when rel[r] >= 0 (a relative field).
template <std::size_t kRows>
struct LaneSources {
  std::array<int, kRows> src{};
  std::array<int, kRows> rel{};
};

template <int D, class Fs>
struct GatherLanes;
template <int D, class... Fs>
struct GatherLanes<D, Fields<Fs...>> {
  template <class Lanes, class Record>
  static constexpr LaneSources<Lanes::kSize> sources() {
    LaneSources<Lanes::kSize> s;
    (fill_sources<Lanes, Record, Fs>(s), ...);
    return s;
  }

  // Neighbour k of the chunk, record rj (an array element, not a computed
  // pointer: GCC then vectorizes this over k).
  template <class Lanes, class Record, class R>
  static void run(const double* own, const R& rj, std::size_t k, double* lanes) {
    (one<Lanes, Record, Fs>(own, rj, k, lanes), ...);
  }

#if defined(__AVX__)
  // Neighbours k .. k+3 of the chunk (k a multiple of 4), records r[0..3].
  // Reads the record's doubles in pairs, so a record of odd size needs one
  // more double readable after the last record.
  template <class Lanes, class Record>
  static void four_pairs(const double* own, const double* const (&r)[4], std::size_t k,
                         double* lanes) {
    constexpr LaneSources<Lanes::kSize> s = sources<Lanes, Record>();
    [&]<std::size_t... L>(std::index_sequence<L...>) {
      // All rows first, then all stores: a store to lanes could alias the
      // records, and would stop the loads shared by two rows being merged.
      const __m256d rows[] = {row<s.src[L], s.rel[L]>(own, r)...};
      (_mm256_store_pd(lanes + L * kChunk + k, rows[L]), ...);
    }
    (std::make_index_sequence<Lanes::kSize>{});
  }

  template <int kSrc, int kRel>
  static __m256d row(const double* own, const double* const (&r)[4]) {
    constexpr int base = kSrc & ~1;
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r[0] + base)),
                                           _mm_loadu_pd(r[2] + base), 1);  // a0 a1 c0 c1
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r[1] + base)),
                                           _mm_loadu_pd(r[3] + base), 1);  // b0 b1 d0 d1
    const __m256d v = (kSrc & 1) == 0 ? _mm256_unpacklo_pd(a, b) : _mm256_unpackhi_pd(a, b);
    if constexpr (kRel >= 0)
      return _mm256_sub_pd(_mm256_set1_pd(own[kRel]), v);
    else
      return v;
  }
#endif

 private:
  template <class Lanes, class Record, class F>
  static constexpr void fill_sources(LaneSources<Lanes::kSize>& s) {
    constexpr std::size_t lo = Lanes::template offset<F>(), ro = Record::template offset<F>();
    for (std::size_t c = 0; c < width_v<F, D>; ++c) {
      s.src[lo + c] = static_cast<int>(ro + c);
      if constexpr (std::is_void_v<typename F::RelativeTo>)
        s.rel[lo + c] = -1;
      else
        s.rel[lo + c] = static_cast<int>(Record::template offset<typename F::RelativeTo>() + c);
    }
  }

  template <class Lanes, class Record, class F, class R>
  static void one(const double* own, const R& rj, std::size_t k, double* lanes) {
    constexpr std::size_t lo = Lanes::template offset<F>(), ro = Record::template offset<F>();
    for (std::size_t c = 0; c < width_v<F, D>; ++c) {
      if constexpr (std::is_void_v<typename F::RelativeTo>) {
        lanes[(lo + c) * kChunk + k] = rj.v[ro + c];
      } else {
        constexpr std::size_t so = Record::template offset<typename F::RelativeTo>();
        lanes[(lo + c) * kChunk + k] = own[so + c] - rj.v[ro + c];
      }
    }
  }
};

// Whether the pair loop gathers four neighbours at a time (four_pairs).
#if defined(__AVX__)
inline constexpr bool kGatherFour = true;
#else
inline constexpr bool kGatherFour = false;
#endif

}  // namespace sphdem::terms
