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
//     transpose");
//   - GatherLanes::eight_quads (with AVX-512), eight at a time, the same
//     transpose on quads of doubles in 512-bit registers.
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

  // The chunk of neighbours idx[0, cnt) of the records rec, the widest way
  // this build has (kGatherWidth): idx must hold the last neighbour again in
  // idx[cnt .. cnt + 2] (a block of eight starts only where it holds five
  // or more, k + 4 < cnt), and the lanes' rows room for kChunk values. The
  // pair loop's step 1 (pair_loop.hpp).
  // Inlined: as a call, the 2D channel's loop took 1.03 times as long.
  template <class Lanes, class Record, class R>
  [[gnu::always_inline]] static inline void chunk(const double* own, const R* rec,
                                                  const std::int32_t* idx, std::size_t cnt,
                                                  double* lanes);

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
    // All rows first, then all stores: a store to lanes could alias the
    // records, and would stop the loads shared by two rows being merged.
    __m256d regs[Lanes::kSize];
    rows<Lanes, Record>(own, r, regs);
    for (std::size_t L = 0; L < Lanes::kSize; ++L) _mm256_store_pd(lanes + L * kChunk + k, regs[L]);
  }

  // The lane rows of neighbours r[0..W-1] in registers, row L in out[L]: W = 4
  // with row (256-bit), W = 8 with row8 (512-bit). The pair loop computes its
  // terms on them when it can (pair_loop.hpp, "steps 1 and 2 in registers").
  // own: particle i's record (double), or registers of W doubles holding
  // one particle per lane (pair_loop.hpp, "one particle per lane").
  template <class Lanes, class Record, std::size_t W, class Reg, class O>
  [[gnu::always_inline]] static inline void rows(const O* own, const double* const (&r)[W],
                                                 Reg* out) {
    rows_of<Lanes, Record>(own, r, out, std::make_index_sequence<Lanes::kSize>{});
  }
  // (A function rather than a lambda: GCC would not inline the lambda into
  // the pair loop.)
  template <class Lanes, class Record, std::size_t W, class Reg, class O, std::size_t... L>
  [[gnu::always_inline]] static inline void rows_of(const O* own, const double* const (&r)[W],
                                                    Reg* out, std::index_sequence<L...>) {
    constexpr LaneSources<Lanes::kSize> s = sources<Lanes, Record>();
    if constexpr (W == 4) {
      ((out[L] = row<s.src[L], s.rel[L]>(own, r)), ...);
    } else {
#if defined(__AVX512F__)
      ((out[L] = row8<s.src[L], s.rel[L]>(own, r)), ...);
#endif
    }
  }

  template <int kSrc, int kRel, class O>
  [[gnu::always_inline]] static inline __m256d row(const O* own, const double* const (&r)[4]) {
    constexpr int base = kSrc & ~1;
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r[0] + base)),
                                           _mm_loadu_pd(r[2] + base), 1);  // a0 a1 c0 c1
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(r[1] + base)),
                                           _mm_loadu_pd(r[3] + base), 1);  // b0 b1 d0 d1
    const __m256d v = (kSrc & 1) == 0 ? _mm256_unpacklo_pd(a, b) : _mm256_unpackhi_pd(a, b);
    if constexpr (kRel < 0)
      return v;
    else if constexpr (std::is_same_v<O, double>)
      return _mm256_sub_pd(_mm256_set1_pd(own[kRel]), v);
    else
      return _mm256_sub_pd(own[kRel], v);
  }
#endif

#if defined(__AVX512F__)
  // Neighbours k .. k+7 of the chunk (k a multiple of 8), records r[0..7]:
  // the record's doubles 4q .. 4q+3 of neighbours n and n+4 in one 512-bit
  // register, then two unpacks and one two-source permute per lane row,
  // 0.6 instructions per value where four_pairs takes 1 (docs/performance.md,
  // "The gather eight at a time"). Reads the record's doubles in fours, so
  // up to three more doubles must be readable after the last record
  // (kRecordSpare).
  template <class Lanes, class Record>
  static void eight_quads(const double* own, const double* const (&r)[8], std::size_t k,
                          double* lanes) {
    __m512d regs[Lanes::kSize];
    rows<Lanes, Record>(own, r, regs);
    for (std::size_t L = 0; L < Lanes::kSize; ++L) _mm512_store_pd(lanes + L * kChunk + k, regs[L]);
  }

  template <int kSrc, int kRel, class O>
  [[gnu::always_inline]] static inline __m512d row8(const O* own, const double* const (&r)[8]) {
    constexpr int base = kSrc & ~3;
    // The masked forms with every lane set are the plain instructions; the
    // unmasked intrinsics pass GCC 12 an undefined vector that
    // -Wmaybe-uninitialized reports.
    constexpr __mmask8 kAll = 0xFF;
    const auto pair = [&](int a) {  // neighbours a and a + 4: [a0 a1 a2 a3 e0 e1 e2 e3]
      const __m512d lo = _mm512_castpd256_pd512(_mm256_loadu_pd(r[a] + base));
      return _mm512_mask_insertf64x4(lo, kAll, lo, _mm256_loadu_pd(r[a + 4] + base), 1);
    };
    const __m512d z0 = pair(0), z1 = pair(1), z2 = pair(2), z3 = pair(3);
    // Even kSrc: doubles 0 and 2 of each 128-bit lane; odd: 1 and 3.
    const auto unpack = [&](__m512d p, __m512d q) {
      return (kSrc & 1) == 0 ? _mm512_mask_unpacklo_pd(p, kAll, p, q)
                             : _mm512_mask_unpackhi_pd(p, kAll, p, q);
    };
    const __m512d a = unpack(z0, z1), b = unpack(z2, z3);
    // a = [n0 n1 . . n4 n5 . .], b = [n2 n3 . . n6 n7 . .]: take the first
    // or the second double pair of each 256-bit half (kSrc & 2).
    const __m512i pick = (kSrc & 2) == 0 ? _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0)
                                         : _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    const __m512d v = _mm512_permutex2var_pd(a, pick, b);
    if constexpr (kRel < 0)
      return v;
    else if constexpr (std::is_same_v<O, double>)
      return _mm512_sub_pd(_mm512_set1_pd(own[kRel]), v);
    else
      return _mm512_sub_pd(own[kRel], v);
  }

  // chunk's way with eight_quads. A call of its own: inlined into the
  // pair loop, the 3D plate took about 1.06 times as long
  // (docs/performance.md, "The gather eight at a time").
  template <class Lanes, class Record, class R>
  [[gnu::noinline]] static void eights(const double* own, const R* rec, const std::int32_t* idx,
                                       std::size_t cnt, double* lanes) {
    std::size_t k = 0;
    for (; k + 4 < cnt; k += 8) {
      const double* const r[8] = {rec[idx[k]].v,     rec[idx[k + 1]].v, rec[idx[k + 2]].v,
                                  rec[idx[k + 3]].v, rec[idx[k + 4]].v, rec[idx[k + 5]].v,
                                  rec[idx[k + 6]].v, rec[idx[k + 7]].v};
      eight_quads<Lanes, Record>(own, r, k, lanes);
    }
    for (; k < cnt; k += 4) {
      const double* const r[4] = {rec[idx[k]].v, rec[idx[k + 1]].v, rec[idx[k + 2]].v,
                                  rec[idx[k + 3]].v};
      four_pairs<Lanes, Record>(own, r, k, lanes);
    }
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

// How many neighbours the pair loop gathers at a time in D dimensions:
// four (four_pairs) with AVX, else one (run); eight (eight_quads) in 3D
// with AVX-512. Measured (docs/performance.md, "The gather eight at a
// time"): eight at a time takes a quarter off the 3D plate's run and
// makes the 2D channel's 1.05 times slower, whose records sit in L1 and
// whose 512-bit shuffles cost two of the 256-bit ones.
template <int D>
inline constexpr std::size_t kGatherWidth =
#if defined(__AVX512F__)
    D == 3 ? 8 : 4;
#elif defined(__AVX__)
    4;
#else
    1;
#endif

template <int D, class... Fs>
template <class Lanes, class Record, class R>
inline void GatherLanes<D, Fields<Fs...>>::chunk(const double* own, const R* rec,
                                                 const std::int32_t* idx, std::size_t cnt,
                                                 double* lanes) {
  std::size_t k = 0;
#if defined(__AVX512F__)
  if constexpr (kGatherWidth<D> == 8) {
    // Eight at a time, then a last block of at most four, four at a time.
    eights<Lanes, Record>(own, rec, idx, cnt, lanes);
    return;
  }
#endif
#if defined(__AVX__)
  for (; k < cnt; k += 4) {
    const double* const r[4] = {rec[idx[k]].v, rec[idx[k + 1]].v, rec[idx[k + 2]].v,
                                rec[idx[k + 3]].v};
    four_pairs<Lanes, Record>(own, r, k, lanes);
  }
#endif
  if constexpr (kGatherWidth<D> == 1)
    for (; k < cnt; ++k) run<Lanes, Record>(own, rec[idx[k]], k, lanes);
}

// The doubles readable after the last of the packed records of kStride
// doubles: the gather reads records in fours (eight_quads) or pairs
// (four_pairs) of doubles.
// With AVX-512 the pair loop reads eight neighbours at a time in registers
// (rows) in 2D too (pair_loop.hpp).
template <int D, std::size_t kStride>
inline constexpr std::size_t kRecordSpare =
#if defined(__AVX512F__)
    (4 - kStride % 4) % 4;
#else
    kGatherWidth<D> == 4 ? kStride % 2 : 0;
#endif

#if defined(__AVX512F__)
// Eight records' first kSize doubles as lane rows, rows[c] lane l =
// rec[l][c] (lanes_of for every c at once), by the gather's eight-at-a-time
// transpose (GatherLanes::row8, above). Reads each record's
// doubles in fours: up to three doubles after rec[l] + kSize must be
// readable (kRecordSpare).
template <class Gather, std::size_t... C>
[[gnu::always_inline]] inline void records_to_lanes8(const double* const (&rec)[8], __m512d* rows,
                                                     std::index_sequence<C...>) {
  ((rows[C] =
        Gather::template row8<static_cast<int>(C), -1>(static_cast<const double*>(nullptr), rec)),
   ...);
}
#endif

}  // namespace sphdem::terms
