#pragma once
// The resin's pair loop, generated from a list of terms (sph_terms.hpp;
// what a term is: term_interface.hpp). For the terms a case switches on it
//   0. packs one record per particle with the fields those terms declare
//      (and only those), computing prepared fields such as P/rho^2 or
//      anti-clump's R_a once per particle, back to back (in 2D, where every
//      mass is the same and the walls are at rest, without the three fields
//      the others then determine: compact_record.hpp);
//   per owned resin particle i, per chunk of up to kChunk neighbours:
//   1. gathers the declared lanes of each neighbour j into short
//      contiguous arrays (x_ij, v_ij, the neighbour's scalars);
//   2. runs one branch-free loop over the lanes that the compiler
//      vectorizes: the kernel values, then every active term's pair
//      function in list order (pairs beyond the support get F = 0, a select
//      instead of a `continue`, and contribute exact zeros);
//   3. sums the per-pair contributions in list order.
// With AVX, when every active term's pair() is written for any lane type
// (kVectorPair, term_interface.hpp), steps 1 and 2 run in registers: the
// gather transposes eight (AVX-512) or four neighbours into registers and the
// terms are computed on them straight away, so no lane row is stored and
// loaded again (docs/performance.md, "Steps 1 and 2 in registers"). Both
// forms run the same step-2 code (pair_step), on one double or on a
// register of them. The register form puts one owned particle in each lane
// instead (eight with AVX-512, four with AVX2), slot k holding each one's
// k-th neighbour, so each lane sums its own list in order and step 3
// disappears (docs/performance.md, "One particle per lane", "One particle
// per lane with AVX2").
// The neighbour list is sorted by global id, and step 3 is a plain
// sequential sum in that order, so the result does not depend on the
// particle layout or the rank count (docs/performance.md).
//
// Which terms are on (and their compile-time variants) is a mixed-radix
// number, one digit per term; the loop is instantiated for every
// combination and a table picks the one for the case, so a term that is
// off costs nothing and no dispatch code names a term.
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "compact_record.hpp"
#include "field_layout.hpp"
#include "lane_gather.hpp"
#include "record_fields.hpp"
#include "sphdem/core/scratch.hpp"
#include "sphdem/neighbor/neighbor.hpp"

namespace sphdem::terms {

// ---- Terms: on/off, variants, the combination table ------------------------

template <class T>
concept OptionalTerm = requires(const SphParams& sp) {
  { T::active(sp) } -> std::convertible_to<bool>;
};
template <class T>
concept VariantTerm = requires(const SphParams& sp) {
  { T::variants } -> std::convertible_to<int>;
  { T::variant(sp) } -> std::convertible_to<int>;
};
template <class T>
constexpr int variants_of() {
  if constexpr (VariantTerm<T>)
    return T::variants;
  else
    return 1;
}
// A term's digit: 0 = off (optional terms only), then one per variant.
template <class T>
inline constexpr int states_v = variants_of<T>() + (OptionalTerm<T> ? 1 : 0);
template <class T>
int state_of(const SphParams& sp) {
  int v = 0;
  if constexpr (VariantTerm<T>) v = T::variant(sp);
  if constexpr (OptionalTerm<T>)
    return T::active(sp) ? 1 + v : 0;
  else
    return v;
}

template <class T>
struct OwnReadsOf {
  using type = Fields<>;
};
template <class T>
requires requires {
  typename T::OwnReads;
}
struct OwnReadsOf<T> {
  using type = typename T::OwnReads;
};

// A term switched on in one of its variants.
template <class T, int V>
struct Selected {
  using Term = T;
  static constexpr int kVariant = V;
};

template <class... Ls>
struct Concat {
  using type = TermList<>;
};
template <class... A>
struct Concat<TermList<A...>> {
  using type = TermList<A...>;
};
template <class... A, class... B, class... Rest>
struct Concat<TermList<A...>, TermList<B...>, Rest...> {
  using type = typename Concat<TermList<A..., B...>, Rest...>::type;
};

template <class List>
struct Registry;
template <class... Ts>
struct Registry<TermList<Ts...>> {
  static constexpr std::size_t kTerms = sizeof...(Ts);
  static constexpr std::array<int, kTerms> kStates{states_v<Ts>...};
  static constexpr std::size_t kCombinations = (std::size_t{1} * ... * states_v<Ts>);

  // The combination a case selects.
  static std::size_t combination(const SphParams& sp) {
    const std::array<int, kTerms> s{state_of<Ts>(sp)...};
    std::size_t c = 0, radix = 1;
    for (std::size_t k = 0; k < kTerms; ++k) {
      c += static_cast<std::size_t>(s[k]) * radix;
      radix *= static_cast<std::size_t>(kStates[k]);
    }
    return c;
  }
  // Digit k of combination c.
  static constexpr int state(std::size_t c, std::size_t k) {
    std::size_t radix = 1;
    for (std::size_t m = 0; m < k; ++m) radix *= static_cast<std::size_t>(kStates[m]);
    return static_cast<int>((c / radix) % static_cast<std::size_t>(kStates[k]));
  }

  template <std::size_t C, class Seq>
  struct SelectImpl;
  template <std::size_t C, std::size_t... K>
  struct SelectImpl<C, std::index_sequence<K...>> {
    using type = typename Concat<std::conditional_t<
        (!OptionalTerm<Ts> || state(C, K) > 0),
        TermList<Selected<Ts, (state(C, K) - (OptionalTerm<Ts> ? 1 : 0))>>, TermList<>>...>::type;
  };
  // The active terms of combination C, in list order.
  template <std::size_t C>
  using Select = typename SelectImpl<C, std::index_sequence_for<Ts...>>::type;
};

// A pass whose output a term's record fields read and that the pair loop
// can compute on the side (a term's optional `using SidePass = P;`, P a pass
// of pass_loop.hpp with one sum): the anti-clump term's free-surface flag.
template <class T>
struct SidePassOfTerm {
  using type = void;
};
template <class T>
requires requires {
  typename T::SidePass;
}
struct SidePassOfTerm<T> {
  using type = typename T::SidePass;
};
template <class Sel>
struct SidePassOf {
  using type = void;
};
template <class S, class... Rest>
struct SidePassOf<TermList<S, Rest...>> {
  using own = typename SidePassOfTerm<typename S::Term>::type;
  using type =
      std::conditional_t<std::is_void_v<own>, typename SidePassOf<TermList<Rest...>>::type, own>;
};
template <class Sub, class L>
struct SubsetOf;
template <class... Fs, class L>
struct SubsetOf<Fields<Fs...>, L> : std::bool_constant<(contains_v<Fs, L> && ...)> {};
// The side pass when the loop gathers all its lanes anyway, else void.
template <class P, class LaneFields>
struct SideIfGathered {
  using type = std::conditional_t<SubsetOf<typename P::Reads, LaneFields>::value, P, void>;
};
template <class LaneFields>
struct SideIfGathered<void, LaneFields> {
  using type = void;
};

// What the selected terms need: the outputs they write, the lanes they read
// per neighbour, and the record (lanes, relative sources, own-only fields).
template <int D, class Sel>
struct Needs;
template <int D, class... S>
struct Needs<D, TermList<S...>> {
  static constexpr unsigned kWrites = (0u | ... | S::Term::writes);
  // The loop itself reads x_ij (kernel), m_j (bracket) and v_i - vw_j (visc).
  using Core = typename MergeAll<
      false, Fields<field::Pos>,
      std::conditional_t<(kWrites & kBracket) != 0, Fields<field::Mass>, Fields<>>,
      std::conditional_t<(kWrites & kVisc) != 0, Fields<field::VelWall>, Fields<>>>::type;
  using LaneFields = typename MergeAll<false, Core, typename S::Term::Reads...>::type;
  using RecordFields = typename MergeAll<true, Fields<>, LaneFields,
                                         typename OwnReadsOf<typename S::Term>::type...>::type;
  using Lanes = Layout<D, LaneFields>;
  using Record = Layout<D, RecordFields>;
  // The pass this loop can compute on the side (PairLoopRun::side), or void.
  using Side = typename SideIfGathered<typename SidePassOf<TermList<S...>>::type, LaneFields>::type;
  // No padding to whole cache lines: 88 bytes per particle on the channel
  // instead of 128 (docs/performance.md, "Memory per particle").
  static constexpr std::size_t kStride = Record::kSize;
};

// ---- The loop ---------------------------------------------------------------

// One particle's record, its fields back to back (unpadded: the records are
// the largest per-particle array after the fields).
template <std::size_t kStride>
struct PackedRecord {
  double v[kStride];
};

template <class T, int D>
T make_term(const TermContext<D>& c) {
  if constexpr (std::is_constructible_v<T, const TermContext<D>&>)
    return T(c);
  else
    return T{};
}

template <class T, class I>
auto for_particle(const T& t, const I& own) {
  if constexpr (requires { t.for_particle(own); })
    return t.for_particle(own);
  else
    return t;
}

template <class S, class T, class P, class Sums>
void pair_of(const T& t, const P& p, Sums& s) {
  if constexpr (VariantTerm<T>)
    t.template pair<S::kVariant>(p, s);
  else
    t.pair(p, s);
}

template <int D, class Fs>
struct FillRecord;
template <int D, class... Fs>
struct FillRecord<D, Fields<Fs...>> {
  // Through a local array: its stores cannot alias the particle arrays,
  // so fields computed from the same inputs (P/rho^2, R_a) share the loads
  // and the division. Copied element by element (an aggregate copy would
  // stop the vectorization of the loop over particles).
  template <class Record>
  static void run(const SphParams& sp, const SphParticles<D>& ps, std::size_t i, double* out) {
    double local[Record::kSize];
    (Fs::template fill<D>(sp, ps, i, local + Record::template offset<Fs>()), ...);
    for (std::size_t c = 0; c < Record::kSize; ++c) out[c] = local[c];
  }
};

// The owned resin particles with some neighbour closer than sqrt(within2)
// (resin or wall), in index order: the pair loop finds them from the r^2 it
// computes anyway, so the wall repulsion (wall_repulsion.cpp) walks only
// their lists instead of every list (docs/performance.md, "The wall
// repulsion inside the pair loop"). A superset is fine: the repulsion
// tests each pair exactly.
struct CloseNeighbours {
  double within2 = -1.0;  // below 0: nobody is close (the search is off)
  std::vector<std::uint32_t> particles;
};

// One run of the pair loop (run_pair_loop).
struct PairLoopRun {
  CloseNeighbours* close = nullptr;
  // Also compute the loop's side pass (Needs::Side) into its output field,
  // from the lanes and kernel values the loop has anyway, summed in list
  // order as the pass sums them (docs/performance.md, "The free-surface
  // flag inside the pair loop"). The records read that field as it is.
  bool side = false;
  // Set: only these owned resin particles, after filling the records of
  // `refill` again (a second run of the same loop, once a side pass's output
  // has changed some records; the other records are kept from the first run).
  const std::vector<std::uint32_t>* redo = nullptr;
  const std::vector<std::uint32_t>* refill = nullptr;
  // One particle at a time even where the loop would put one particle per
  // lane (kOnePerLane): the two forms do the same operations, and a test
  // compiled without multiply-add contraction checks that they give the
  // same bits (with it, GCC may fuse differently in the two: tests/unit.cmake).
  bool per_particle = false;
  // When to use the compact record (compact_record.hpp).
  CompactUse compact = compact_record_default();
};

// On a lambda of the pair loop: inline it wherever it is called. Without it
// GCC kept the one-particle-per-lane form's slot lambdas out of line once the
// plate's terms (artificial viscosity, anti-clump, delta-SPH) made the loop
// large, and the lanes' sums went through memory at every slot: the plate's
// loop took 1.12 times the time of one particle at a time instead of 0.96
// (docs/performance.md, "The plate's loop kept inline; the coupling's walks").
#define SPHDEM_INLINE __attribute__((always_inline))

// Square roots of one double or of a register of doubles (the pair loop's r).
inline double lane_sqrt(double x) {
  return std::sqrt(x);
}
#if defined(__AVX__)
inline __m256d lane_sqrt(__m256d x) {
  return _mm256_sqrt_pd(x);
}
#endif
#if defined(__AVX512F__)
// The masked form with every lane set is the plain instruction; the unmasked
// intrinsic passes GCC 12 an undefined vector that -Wmaybe-uninitialized reports.
inline __m512d lane_sqrt(__m512d x) {
  return _mm512_mask_sqrt_pd(x, 0xFF, x);
}
#endif

// The one-particle-per-lane form's lane operations (rates_loop, kOnePerLane)
// on a register VR of doubles, AVX-512's eight or AVX's four (deduced, not
// spelled: GCC drops a register type's attributes from an explicit template
// argument, and says so).
// Lane l of out: p[l][c].
template <class VR, std::size_t W>
void lanes_of(const double* const (&p)[W], std::size_t c, VR& out) {
  static_assert(sizeof(VR) == W * sizeof(double));
  double v[W];
  for (std::size_t l = 0; l < W; ++l) v[l] = p[l][c];
  __builtin_memcpy(&out, v, sizeof(VR));
}
// sum + x as its own addition: the empty asm hides where x came from, so GCC
// cannot fuse the add with a product that made x (one particle at a time
// adds x from memory).
template <class VR>
VR lane_add(VR sum, VR x) {
  __asm__("" : "+v"(x));
  return sum + x;
}
#if defined(__AVX__)
// Four records' first kSize doubles as lane rows, rows[c] lane l =
// rec[l][c] (lanes_of for every c at once): two doubles of each record at
// a time, records 0 and 2 in one register and 1 and 3 in another, then one
// unpack per row, the gather's transpose (lane_gather.hpp). The same values
// as lanes_of, in registers instead of through memory.
template <std::size_t kSize>
SPHDEM_INLINE inline void records_to_lanes4(const double* const (&rec)[4], __m256d (&rows)[kSize]) {
  std::size_t c = 0;
  for (; c + 1 < kSize; c += 2) {
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(rec[0] + c)),
                                           _mm_loadu_pd(rec[2] + c), 1);
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(rec[1] + c)),
                                           _mm_loadu_pd(rec[3] + c), 1);
    rows[c] = _mm256_unpacklo_pd(a, b);
    rows[c + 1] = _mm256_unpackhi_pd(a, b);
  }
  if (c < kSize) rows[c] = _mm256_setr_pd(rec[0][c], rec[1][c], rec[2][c], rec[3][c]);
}
#endif

#if defined(__AVX2__)
// The one-particle-per-lane form's slot indices for four lanes whose lists
// are all 16-bit (NeighborRow::narrow): out[k * 4 + l] = row[l][k] +
// base[l] for k < len[l], `far` for len[l] <= k < slots. Four slots at a
// time: each lane's four offsets widened and added to its index, then a 4 x
// 4 transpose in registers and four 16-byte stores, where the fill element
// by element stored each index on its own. out must have room for 4 times
// slots rounded up to a multiple of four. No row is read past its end.
inline void narrow_slots4(const std::int16_t* const (&row)[4], const std::int32_t (&base)[4],
                          const std::size_t (&len)[4], std::size_t slots, std::int32_t far,
                          std::int32_t* out) {
  const __m128i far4 = _mm_set1_epi32(far);
  for (std::size_t k = 0; k < slots; k += 4) {
    __m128i v[4];
    for (int l = 0; l < 4; ++l) {
      if (k >= len[l]) {
        v[l] = far4;
        continue;
      }
      const std::size_t have = len[l] - k;
      std::int64_t four = 0;  // the row's next offsets, zeros past its end
      if (have >= 4)
        __builtin_memcpy(&four, row[l] + k, sizeof four);
      else
        for (std::size_t t = 0; t < have; ++t)
          four |= static_cast<std::int64_t>(static_cast<std::uint16_t>(row[l][k + t])) << (16 * t);
      v[l] = _mm_add_epi32(_mm_cvtepi16_epi32(_mm_cvtsi64_si128(four)), _mm_set1_epi32(base[l]));
      if (have < 4) {  // positions t >= have take the far record
        const __m128i past =
            _mm_cmpgt_epi32(_mm_setr_epi32(0, 1, 2, 3), _mm_set1_epi32(static_cast<int>(have) - 1));
        v[l] = _mm_blendv_epi8(v[l], far4, past);
      }
    }
    const __m128i t0 = _mm_unpacklo_epi32(v[0], v[1]), t1 = _mm_unpacklo_epi32(v[2], v[3]);
    const __m128i t2 = _mm_unpackhi_epi32(v[0], v[1]), t3 = _mm_unpackhi_epi32(v[2], v[3]);
    __m128i* const o = reinterpret_cast<__m128i*>(out + 4 * k);
    _mm_storeu_si128(o, _mm_unpacklo_epi64(t0, t1));
    _mm_storeu_si128(o + 1, _mm_unpackhi_epi64(t0, t1));
    _mm_storeu_si128(o + 2, _mm_unpacklo_epi64(t2, t3));
    _mm_storeu_si128(o + 3, _mm_unpackhi_epi64(t2, t3));
  }
}
#endif

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__)
#define SPHDEM_NARROW_SLOTS8 1
// narrow_slots4 for eight lanes (AVX-512): out[k * 8 + l] = row[l][k] +
// base[l] for k < len[l], `far` for len[l] <= k < slots. Eight slots at a
// time: each lane's eight offsets loaded under a mask (no row is read past
// its end), widened and added to its index, the slots past its end given
// `far`; then an 8 x 8 transpose in registers and eight 32-byte stores.
// out must have room for 8 times slots rounded up to a multiple of eight.
inline void narrow_slots8(const std::int16_t* const (&row)[8], const std::int32_t (&base)[8],
                          const std::size_t (&len)[8], std::size_t slots, std::int32_t far,
                          std::int32_t* out) {
  const __m256i far8 = _mm256_set1_epi32(far);
  for (std::size_t k = 0; k < slots; k += 8) {
    __m256 v[8];
    for (int l = 0; l < 8; ++l) {
      __m256i s = far8;
      if (k < len[l]) {
        const std::size_t have = len[l] - k;
        const auto in = static_cast<__mmask8>(have >= 8 ? 0xFF : (1u << have) - 1);
        const __m256i off = _mm256_cvtepi16_epi32(_mm_maskz_loadu_epi16(in, row[l] + k));
        s = _mm256_mask_add_epi32(far8, in, off, _mm256_set1_epi32(base[l]));
      }
      v[l] = _mm256_castsi256_ps(s);
    }
    // v[l] holds lane l's slots k .. k+7; out's row k+s wants slot s of
    // every lane.
    __m256 t[8], u[8];
    for (int p = 0; p < 8; p += 2) {
      t[p] = _mm256_unpacklo_ps(v[p], v[p + 1]);
      t[p + 1] = _mm256_unpackhi_ps(v[p], v[p + 1]);
    }
    for (int p = 0; p < 8; p += 4) {
      u[p] = _mm256_shuffle_ps(t[p], t[p + 2], _MM_SHUFFLE(1, 0, 1, 0));
      u[p + 1] = _mm256_shuffle_ps(t[p], t[p + 2], _MM_SHUFFLE(3, 2, 3, 2));
      u[p + 2] = _mm256_shuffle_ps(t[p + 1], t[p + 3], _MM_SHUFFLE(1, 0, 1, 0));
      u[p + 3] = _mm256_shuffle_ps(t[p + 1], t[p + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    __m256i* const o = reinterpret_cast<__m256i*>(out + 8 * k);
    for (int s = 0; s < 4; ++s) {
      _mm256_storeu_si256(o + s, _mm256_castps_si256(_mm256_permute2f128_ps(u[s], u[s + 4], 0x20)));
      _mm256_storeu_si256(o + s + 4,
                          _mm256_castps_si256(_mm256_permute2f128_ps(u[s], u[s + 4], 0x31)));
    }
  }
}
#endif

// Whether this build has narrow_slots8.
#if defined(SPHDEM_NARROW_SLOTS8)
inline constexpr bool kNarrowSlots8 = true;
#else
inline constexpr bool kNarrowSlots8 = false;
#endif

// records_to_lanes8: lane_gather.hpp.

// r2 < least ? r2 : least, lane by lane.
template <class VR>
VR lane_least(VR least, VR r2) {
  return r2 < least ? r2 : least;
}

// The distance of one pair (V = double) or of a block of pairs in
// registers: |x_ij|^2 and |x_ij|.
template <class V>
struct PairDistance {
  V r2, r;
};

// What step 2 of the pair loop gives for one pair (V = double) or for a
// block of pairs in registers.
template <class V, int D>
struct PairOut {
  V acc[D];  // the pair's acceleration
  V drho;    // its density rate
  V side;    // its part of the side pass's sum (when there is one)
  V r2;
};

// Whether steps 1 and 2 run in registers for the terms of Sel and the side
// pass Side (void: none): with AVX, when every one of them computes on
// registers (VectorPairTerm, term_interface.hpp).
template <class Sel, class Side>
struct InRegisters;
template <class... S, class Side>
struct InRegisters<TermList<S...>, Side> {
#if defined(__AVX__) && !defined(SPHDEM_PAIRS_IN_MEMORY)
  static constexpr bool value =
      (VectorPairTerm<typename S::Term> && ...) && (std::is_void_v<Side> || VectorPairTerm<Side>);
#else
  static constexpr bool value = false;
#endif
};

template <int D, class List, std::size_t C>
void rates_loop(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                const PairLoopRun& run) {
  using Sel = typename Registry<List>::template Select<C>;
  using N = Needs<D, Sel>;
  using Lanes = typename N::Lanes;
  using Record = typename N::Record;
  using Side = typename N::Side;
  constexpr bool kSide = !std::is_void_v<Side>;
  constexpr bool kInRegisters = InRegisters<Sel, Side>::value;
  // One owned particle per lane (with AVX: eight lanes with AVX-512, else
  // four): docs/performance.md, "One particle per lane" and "One particle
  // per lane with AVX2". SPHDEM_PAIRS_PER_PARTICLE keeps one particle at a time.
#if defined(__AVX__) && !defined(SPHDEM_PAIRS_PER_PARTICLE)
  constexpr bool kOnePerLane = kInRegisters;
#else
  constexpr bool kOnePerLane = false;
#endif
  constexpr std::size_t kStride = N::kStride;
  constexpr unsigned kWrites = N::kWrites;

  const WendlandC2<D> kernel(sp.h);
  const TermContext<D> ctx{sp, kernel, kernel.w(0.0) / 16.0};

  // 0. The records (every particle, ghosts included); a second run (redo)
  // fills only those whose inputs changed.
  // They live in the scratch the list build shares (sphdem/core/scratch.hpp).
  const std::size_t n = ps.size();
  // With the doubles after the last record that the gather reads
  // (kRecordSpare, lane_gather.hpp).
  // One record more, the far record (index n), for the one-particle-per-lane
  // form.
  PackedRecord<kStride>* rec = reinterpret_cast<PackedRecord<kStride>*>(
      shared_scratch((n + 1) * kStride + kRecordSpare<D, kStride>));
  // The compact record (compact_record.hpp) where this build and this loop
  // can use it and every particle keeps its conditions at this step; a redo
  // keeps the first run's choice. A run that finds them broken leaves the
  // next 1024 runs of this loop on the full record (a moving wall breaks them
  // at every step, and the check would otherwise cost a partial fill each
  // time).
  using Compact = CompactRecord<D, typename N::RecordFields>;
#if defined(__AVX512F__)
  constexpr bool kCompactable = Compact::value && kOnePerLane;
#else
  constexpr bool kCompactable = false;
#endif
  using CL = typename Compact::Layout;
  PackedRecord<CL::kSize>* crec = reinterpret_cast<PackedRecord<CL::kSize>*>(rec);
  static thread_local bool compact_first = false;  // the choice of the last first run
  static thread_local int compact_rest = 0;
  bool compact = false;
  if constexpr (kCompactable) {
    if (run.redo != nullptr) {
      compact = compact_first;
    } else if (run.compact != CompactUse::Off && !run.per_particle && n > 0) {
      if (compact_rest > 0 && run.compact == CompactUse::Auto) {
        --compact_rest;
      } else {
        compact = true;
        const double m0 = ps.mass[0];
        for (std::size_t i = 0; i < n && compact; ++i) {
          compact = Compact::keeps(ps, i, m0);
          if (compact) Compact::fill(sp, ps, i, crec[i].v);
        }
        if (!compact) compact_rest = 1024;
      }
    }
    if (run.redo == nullptr) compact_first = compact;
    if (compact) ++compact_record_runs();
  }
  if (run.redo == nullptr) {
    if (!compact)
      for (std::size_t i = 0; i < n; ++i)
        FillRecord<D, typename N::RecordFields>::template run<Record>(sp, ps, i, rec[i].v);
  } else {
    for (const std::uint32_t j : *run.refill) {
      if constexpr (kCompactable) {
        if (compact) {
          Compact::fill(sp, ps, j, crec[j].v);
          continue;
        }
      }
      FillRecord<D, typename N::RecordFields>::template run<Record>(sp, ps, j, rec[j].v);
    }
  }
  // The far record: record 0's values at a position kFar from the origin on
  // every axis, far beyond the support of any particle, so that a pair with
  // it has t = 0 and F = 0 and every term gives exact zeros (as for every
  // pair beyond the support, step 2 below) from finite values (kFar^2 and its
  // products with a particle's fields stay finite). The one-particle-per-lane
  // form pads the shorter lists of a group with it.
  constexpr double kFar = 1e20;
  if (n > 0 && compact) {
    for (std::size_t c = 0; c < CL::kSize; ++c) crec[n].v[c] = crec[0].v[c];
    for (int d = 0; d < D; ++d) crec[n].v[CL::template offset<field::Pos>() + d] = kFar;
  } else if (n > 0) {
    for (std::size_t c = 0; c < kStride; ++c) rec[n].v[c] = rec[0].v[c];
    for (int d = 0; d < D; ++d) rec[n].v[Record::template offset<field::Pos>() + d] = kFar;
  }

  [&]<class... S>(TermList<S...>) {
    const std::tuple<typename S::Term...> terms{make_term<typename S::Term>(ctx)...};
    const double support2 = 4.0 * sp.h * sp.h;
    const double grad_scale = sp.grad_scale;
    const double inv_h = 1.0 / sp.h;
    // F = kF t^3: -10 C / h^2 with the lattice correction folded in once.
    const double kF = -10.0 * ctx.kw * inv_h * inv_h * grad_scale;
    CloseNeighbours* const close = run.redo == nullptr ? run.close : nullptr;
    const double close2 = close != nullptr ? close->within2 : -1.0;
    if (close != nullptr) close->particles.clear();
    [[maybe_unused]] const bool side = kSide && run.side && run.redo == nullptr;
    const std::uint32_t* const redo = run.redo != nullptr ? run.redo->data() : nullptr;
    const std::size_t count = run.redo != nullptr ? run.redo->size() : ps.n_owned;
    Vec<D> g;
    for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
    constexpr std::size_t kPos = Lanes::template offset<field::Pos>();
    alignas(64) double lanes[Lanes::kSize * kChunk];
    alignas(64) double acc_lane[D][kChunk];                             // per-pair acceleration
    alignas(64) double drho_lane[kChunk];                               // per-pair density rate
    [[maybe_unused]] alignas(64) double side_lane[kSide ? kChunk : 1];  // the side pass's parts

    // 2. Pair terms, branch-free: for one pair (V = double, row(r) reads
    // lane row r of the chunk in memory; GCC vectorizes the loop that calls
    // this) or for a block of pairs held in registers (V a register of
    // doubles, row(r) the gather's register). view(reads, own_reads, r2, r,
    // q, t, F) is a term's view of the pair(s). Pairs beyond the support get
    // F = 0 (a select, not a branch) and contribute exact zeros.
    // The head of step 2: the pairs' r^2 and r (the one-particle-per-lane
    // form computes them a slot ahead: below).
    const auto pair_distance = [&]<class V>(std::type_identity<V>, const auto& row) SPHDEM_INLINE {
      V r2{};
      for (int d = 0; d < D; ++d) {
        const V x = row(kPos + d);
        r2 += x * x;
      }
      return PairDistance<V>{r2, lane_sqrt(r2)};
    };
    // The rest of step 2, given the head.
    const auto pair_rest = [&]<class V>(std::type_identity<V>, const auto& bound, const auto& row,
                                        const auto& view,
                                        const PairDistance<V>& dist) SPHDEM_INLINE {
      PairOut<V, D> o{};
      const V r2 = dist.r2, r = dist.r;
      o.r2 = r2;
      const V q = r * inv_h;
      const V t = r2 < support2 ? 2.0 - q : V{};
      // WendlandC2::f (kernel.hpp), the same operations without the branch.
      const V F = kF * (t * t) * t;
      BasicPairSums<V> s;
      std::apply(
          [&](const auto&... b) {
            (pair_of<S>(b,
                        view(std::type_identity<typename S::Term::Reads>{},
                             std::type_identity<typename OwnReadsOf<typename S::Term>::type>{}, r2,
                             r, q, t, F),
                        s),
             ...);
          },
          bound);
      V pf{};
      if constexpr ((kWrites & kBracket) != 0)
        // (m_j F) as continuity's: one product for both.
        pf = row(Lanes::template offset<field::Mass>()) * F * s.bracket;
      for (int d = 0; d < D; ++d) {
        const V x = row(kPos + d);
        o.acc[d] = V{};
        if constexpr ((kWrites & kVisc) != 0) {
          const V w = row(Lanes::template offset<field::VelWall>() + d);
          if constexpr ((kWrites & kBracket) != 0)
            o.acc[d] = s.visc * w - pf * x;
          else
            o.acc[d] = s.visc * w;
        } else if constexpr ((kWrites & kBracket) != 0) {
          o.acc[d] = -(pf * x);
        }
      }
      o.drho = (kWrites & kDrho) != 0 ? s.drho : V{};
      if constexpr (kSide) {
        V part[1];
        Side{}.pair(view(std::type_identity<typename Side::Reads>{}, std::type_identity<Fields<>>{},
                         r2, r, q, t, F),
                    part);
        o.side = part[0];
      }
      return o;
    };
    const auto pair_step = [&]<class V>(std::type_identity<V> v, const auto& bound, const auto& row,
                                        const auto& view) {
      return pair_rest(v, bound, row, view, pair_distance(v, row));
    };

    if constexpr (kOnePerLane) {
      if (!run.per_particle) {
#if defined(__AVX__)
        // (VR deduced, not spelled: GCC drops __m512d's attributes from an
        // explicit template argument, and says so.)
        // kCompact: the records are compact ones (compact_record.hpp).
        const auto per_lane = [&]<class VR, bool kCompact>(const VR*,
                                                           std::bool_constant<kCompact>) {
          // One particle per lane (docs/performance.md, "One particle per
          // lane"): W owned resin particles at a time (eight with AVX-512,
          // four with AVX), slot k holding each one's k-th neighbour. Each
          // lane's sums then run in its list's order by themselves, as step
          // 3's do, and no per-pair result, lane row or remainder block is
          // stored; a lane past its list's end adds the far record's exact
          // zeros to a sum that started at +0, so the bits are those of one
          // particle at a time.
          using Gather = GatherLanes<D, typename N::LaneFields>;
          constexpr int W = sizeof(VR) / sizeof(double);
          static thread_local std::vector<std::int32_t> slot_index;
          // The compact record's one mass and the delta-SPH weight's factor.
          [[maybe_unused]] const VR compact_mass = splat<VR>(n > 0 ? ps.mass[0] : 0.0);
          [[maybe_unused]] const VR compact_weight = splat<VR>(Compact::weight_factor(sp));
          std::size_t at = 0;
          while (at < count) {
            std::uint32_t ids[W];
            int m = 0;
#if defined(SPHDEM_PARTICLE_LANES)
            // Eight resin particles in a row (most groups): one compare.
            if constexpr (W == 8)
              if (redo == nullptr && at + W <= count && lanes::resin(ps.kind.data(), at) == 0xff) {
                for (int l = 0; l < W; ++l) ids[l] = static_cast<std::uint32_t>(at + l);
                m = W;
                at += W;
              }
#endif
            if (m == 0)
              for (; at < count && m < W; ++at) {
                const std::size_t i = redo != nullptr ? redo[at] : at;
                if (ps.kind[i] == Kind::Fluid) ids[m++] = static_cast<std::uint32_t>(i);
              }
            if (m == 0) break;
            for (int l = m; l < W; ++l) ids[l] = ids[m - 1];
            // The particles' records, one lane each.
            const double* own_rec[W];
            for (int l = 0; l < W; ++l) own_rec[l] = kCompact ? crec[ids[l]].v : rec[ids[l]].v;
            VR own_rows[Record::kSize];
            if constexpr (W == 4) {
              records_to_lanes4(own_rec, own_rows);
            } else {
#if defined(__AVX512F__)
              if constexpr (kCompact)
                compact_own_rows8<Gather, Record, CL, typename N::RecordFields>(
                    own_rec, own_rows, compact_mass, compact_weight,
                    std::make_index_sequence<CL::kSize>{});
              else
                records_to_lanes8<Gather>(own_rec, own_rows,
                                          std::make_index_sequence<Record::kSize>{});
#else
              for (std::size_t c = 0; c < Record::kSize; ++c) lanes_of(own_rec, c, own_rows[c]);
#endif
            }
            const auto bound = std::make_tuple(for_particle(
                std::get<typename S::Term>(terms),
                OwnView<Record,
                        typename MergeAll<false, typename S::Term::Reads,
                                          typename OwnReadsOf<typename S::Term>::type>::type,
                        VR>{own_rows})...);
            // The lists slot by slot; past a list's end the far record, whose
            // exact zeros leave the lane's sums as they are (a sum that starts
            // at +0 is never -0, and x + (+-0) == x otherwise), so each lane's
            // bits are those of one particle at a time. One slot more than
            // the longest list: the loop gathers a slot ahead.
            std::size_t most = 0;
            for (int l = 0; l < m; ++l) most = std::max(most, nl.end(ids[l]) - nl.begin(ids[l]));
            const auto far = static_cast<std::int32_t>(n);
            // (Room for the narrow fill's whole blocks of W slots.)
            slot_index.resize(W * (most + W));
            bool narrow = false;
#if defined(__AVX2__)
            if constexpr (W == 4 || kNarrowSlots8) {
              const std::int16_t* row[W] = {};
              std::int32_t base[W] = {};
              std::size_t len[W] = {};
              narrow = true;
              for (int l = 0; l < m && narrow; ++l) {
                const NeighborRow nb = nl.row(ids[l]);
                narrow = nb.narrow() != nullptr;
                if (!narrow) break;
                row[l] = nb.narrow() + nl.begin(ids[l]);
                base[l] = nb.base();
                len[l] = nl.end(ids[l]) - nl.begin(ids[l]);
              }
              if (narrow) {
                if constexpr (W == 4)
                  narrow_slots4(row, base, len, most + 1, far, slot_index.data());
#if defined(SPHDEM_NARROW_SLOTS8)
                else
                  narrow_slots8(row, base, len, most + 1, far, slot_index.data());
#endif
              }
            }
#endif
            for (int l = 0; l < W && !narrow; ++l) {
              std::size_t k = 0;
              if (l < m) {
                const NeighborRow nb = nl.row(ids[l]);
                for (std::size_t b = nl.begin(ids[l]), e = nl.end(ids[l]); b < e; ++b, ++k)
                  slot_index[k * W + l] = nb[b];
              }
              for (; k <= most; ++k) slot_index[k * W + l] = far;
            }
            VR acc[D];
            for (int d = 0; d < D; ++d) acc[d] = splat<VR>(0.0);
            VR drho = splat<VR>(0.0), side_sum = splat<VR>(0.0), r2min = splat<VR>(1e300);
            // Slot k's lane rows, r^2 and r.
            struct Slot {
              VR rows[Lanes::kSize];
              PairDistance<VR> dist;
            };
            const auto gather_slot = [&](std::size_t k, Slot& out) SPHDEM_INLINE {
              const std::int32_t* const j = slot_index.data() + k * W;
              const double* rj[W];
              for (int l = 0; l < W; ++l) rj[l] = kCompact ? crec[j[l]].v : rec[j[l]].v;
#if defined(__AVX512F__)
              if constexpr (kCompact)
                CompactGather<Gather, Lanes, Record, CL, typename N::LaneFields>::rows(
                    own_rows, rj, out.rows, compact_mass, compact_weight,
                    std::make_index_sequence<Lanes::kSize>{});
              else
#endif
                Gather::template rows<Lanes, Record>(own_rows, rj, out.rows);
              out.dist = pair_distance(std::type_identity<VR>{},
                                       [&](std::size_t row) { return out.rows[row]; });
            };
            // A slot's terms from its gather, added to the lanes' sums.
            const auto slot_terms = [&](const Slot& cur) SPHDEM_INLINE {
              const PairOut<VR, D> o = pair_rest(
                  std::type_identity<VR>{}, bound, [&](std::size_t row) { return cur.rows[row]; },
                  [&]<class R, class O>(std::type_identity<R>, std::type_identity<O>, VR r2, VR r,
                                        VR q, VR t, VR F) {
                    return RegisterPairView<D, Lanes, Record, R, O, VR, VR>{
                        cur.rows, own_rows, r2, r, q, t, F};
                  },
                  cur.dist);
              for (int d = 0; d < D; ++d) acc[d] = lane_add(acc[d], o.acc[d]);
              drho = lane_add(drho, o.drho);
              if constexpr (kSide) side_sum = lane_add(side_sum, o.side);
              // r2min = r2 < r2min ? r2 : r2min, as the other forms (the far
              // record's r2, about 1e40, is never close).
              r2min = lane_least(r2min, o.r2);
            };
            // Slot k + 1's gather and square root come before slot k's terms,
            // so the one's long chain (the square root's latency) overlaps the
            // other's work: without it the core waits on each slot in turn
            // (docs/performance.md, "One particle per lane with AVX2"). Two
            // slots per turn, the two Slots trading roles, so that no slot's
            // rows are copied from one to the other.
            Slot even, odd;
            gather_slot(0, even);
            for (std::size_t k = 0; k < most; k += 2) {
              gather_slot(k + 1, odd);
              slot_terms(even);
              if (k + 1 == most) break;
              gather_slot(k + 2, even);
              slot_terms(odd);
            }
            double acc_out[D][W], drho_out[W], side_out[W], r2_out[W];
            for (int d = 0; d < D; ++d) __builtin_memcpy(acc_out[d], &acc[d], sizeof(VR));
            __builtin_memcpy(drho_out, &drho, sizeof(VR));
            __builtin_memcpy(side_out, &side_sum, sizeof(VR));
            __builtin_memcpy(r2_out, &r2min, sizeof(VR));
            // Eight particles in a row (most groups): their a, drho, close
            // neighbours and side flag as whole registers, with the
            // operations the loop below does one particle at a time.
            bool in_a_row = false, side_in_a_row = false;
#if defined(SPHDEM_PARTICLE_LANES)
            if constexpr (W == 8) {
              in_a_row = m == W && ids[W - 1] - ids[0] == W - 1;
              if (in_a_row) {
                VR a_rows[D];
                for (int d = 0; d < D; ++d) a_rows[d] = lane_add(acc[d], splat<VR>(g[d]));
                lanes::store_vectors<D>(ps.a.data()->data(), ids[0], a_rows);
                _mm512_storeu_pd(ps.drho.data() + ids[0], drho);
                if (close2 > 0.0)
                  for (__mmask8 near = _mm512_cmp_pd_mask(r2min, splat<VR>(close2), _CMP_LT_OQ);
                       near != 0; near = static_cast<__mmask8>(near & (near - 1)))
                    close->particles.push_back(ids[__builtin_ctz(near)]);
                if constexpr (kSide) {
                  if constexpr (requires { Side::template flags8<D>(sp, r2min, r2min); } &&
                                contains_v<typename Side::WantedFrom, typename N::RecordFields>) {
                    side_in_a_row = true;
                    if (side)
                      _mm512_storeu_pd(
                          Side::output(ps).data() + ids[0],
                          Side::template flags8<D>(
                              sp, own_rows[Record::template offset<typename Side::WantedFrom>()],
                              side_sum));
                  }
                }
              }
            }
#endif
            // What the registers did not store, one particle at a time.
            const bool all_stored = in_a_row && (!kSide || side_in_a_row);
            for (int l = 0; l < m && !all_stored; ++l) {
              const std::size_t i = ids[l];
              if (!in_a_row) {
                Vec<D> a;
                for (int d = 0; d < D; ++d) a[d] = acc_out[d][l];
                ps.a[i] = a + g;
                ps.drho[i] = drho_out[l];
                if (close2 > 0.0 && r2_out[l] < close2)
                  close->particles.push_back(static_cast<std::uint32_t>(i));
              }
              if constexpr (kSide) {
                if (side && !side_in_a_row) {
                  bool side_i = true;
                  if constexpr (requires { Side::wanted_from(sp, 0.0); } &&
                                contains_v<typename Side::WantedFrom, typename N::RecordFields>)
                    // From the particle's record, computed once already
                    // (FreeSurfaceFlag::WantedFrom).
                    side_i = Side::wanted_from(
                        sp, own_rec[l][kCompact
                                           ? CL::template offset<typename Side::WantedFrom>()
                                           : Record::template offset<typename Side::WantedFrom>()]);
                  else if constexpr (requires { Side::template wanted<D>(sp, ps, i); })
                    side_i = Side::template wanted<D>(sp, ps, i);
                  const double sums[1] = {side_out[l]};
                  Side::output(ps)[i] = side_i ? Side{}.template finish<D>(sums) : 0.0;
                }
              }
            }
          }
        };
#if defined(__AVX512F__)
        if constexpr (kCompactable) {
          if (compact)
            per_lane(static_cast<const __m512d*>(nullptr), std::true_type{});
          else
            per_lane(static_cast<const __m512d*>(nullptr), std::false_type{});
        } else {
          per_lane(static_cast<const __m512d*>(nullptr), std::false_type{});
        }
#else
        per_lane(static_cast<const __m256d*>(nullptr), std::false_type{});
#endif
#endif
        return;
      }
    }
    for (std::size_t at = 0; at < count; ++at) {
      const std::size_t i = redo != nullptr ? redo[at] : at;
      if (ps.kind[i] != Kind::Fluid) continue;
      const double* own = rec[i].v;
      const auto bound = std::make_tuple(for_particle(
          std::get<typename S::Term>(terms),
          OwnView<Record, typename MergeAll<false, typename S::Term::Reads,
                                            typename OwnReadsOf<typename S::Term>::type>::type>{
              own})...);
      Vec<D> acc = Vec<D>::Zero();
      double drho_sum = 0.0;
      [[maybe_unused]] double side_sum[1] = {};  // as the pass's sums start
      // The side pass's value only where its readers read it (its wanted).
      [[maybe_unused]] bool side_i = false;
      if constexpr (kSide) {
        side_i = side;
        if constexpr (requires { Side::template wanted<D>(sp, ps, i); })
          side_i = side_i && Side::template wanted<D>(sp, ps, i);
      }
      int near = 0;  // some neighbour within close2
      const NeighborRow nb = nl.row(i);

      // Steps 1 and 2 for a block of pairs in registers (rows: the gather's
      // lane rows) from pair k of the chunk on: the rows are never stored and
      // loaded again.
      [[maybe_unused]] const auto pairs_in_registers = [&]<class V>(const V* rows, std::size_t k,
                                                                    V& r2min) {
        const PairOut<V, D> o = pair_step(
            std::type_identity<V>{}, bound, [&](std::size_t row) { return rows[row]; },
            [&]<class R, class O>(std::type_identity<R>, std::type_identity<O>, V r2, V r, V q, V t,
                                  V F) {
              return RegisterPairView<D, Lanes, Record, R, O, V>{rows, own, r2, r, q, t, F};
            });
        for (int d = 0; d < D; ++d) __builtin_memcpy(acc_lane[d] + k, &o.acc[d], sizeof(V));
        __builtin_memcpy(drho_lane + k, &o.drho, sizeof(V));
        if constexpr (kSide) __builtin_memcpy(side_lane + k, &o.side, sizeof(V));
        r2min = o.r2 < r2min ? o.r2 : r2min;
      };

      for (std::size_t b = nl.begin(i), e = nl.end(i); b < e; b += kChunk) {
        const std::size_t cnt = std::min(kChunk, e - b);

        // 1. Gather: eight or four neighbours at a time where AVX-512 or AVX
        // is there (the last block repeats the chunk's last neighbour; step 2
        // reads k < cnt). The chunk's indices decoded once (16- or 32-bit
        // lists, NeighborRow), padded with the last one to a whole block.
        using Gather = GatherLanes<D, typename N::LaneFields>;
        alignas(64) std::int32_t idx[kChunk + 3];
        for (std::size_t k = 0; k < cnt; ++k) idx[k] = nb[b + k];
        idx[cnt] = idx[cnt + 1] = idx[cnt + 2] = nb[b + cnt - 1];  // cnt >= 1

        if constexpr (kInRegisters) {
#if defined(__AVX__)
          // Steps 1 and 2 in registers: eight neighbours at a time with
          // AVX-512 while a block holds five or more, then four at a time
          // (docs/performance.md, "Steps 1 and 2 in registers").
          std::size_t k = 0;
#if defined(__AVX512F__)
          __m512d r2min8 = splat<__m512d>(1e300);
          for (; k + 4 < cnt; k += 8) {
            const double* const r8[8] = {rec[idx[k]].v,     rec[idx[k + 1]].v, rec[idx[k + 2]].v,
                                         rec[idx[k + 3]].v, rec[idx[k + 4]].v, rec[idx[k + 5]].v,
                                         rec[idx[k + 6]].v, rec[idx[k + 7]].v};
            __m512d rows[Lanes::kSize];
            Gather::template rows<Lanes, Record>(own, r8, rows);
            pairs_in_registers(rows, k, r2min8);
          }
#endif
          __m256d r2min4 = splat<__m256d>(1e300);
          for (; k < cnt; k += 4) {
            const double* const r4[4] = {rec[idx[k]].v, rec[idx[k + 1]].v, rec[idx[k + 2]].v,
                                         rec[idx[k + 3]].v};
            __m256d rows[Lanes::kSize];
            Gather::template rows<Lanes, Record>(own, r4, rows);
            pairs_in_registers(rows, k, r2min4);
          }
          if (close2 > 0.0) {
            for (int m = 0; m < 4; ++m) near |= r2min4[m] < close2 ? 1 : 0;
#if defined(__AVX512F__)
            for (int m = 0; m < 8; ++m) near |= r2min8[m] < close2 ? 1 : 0;
#endif
          }
#endif
        } else {
          Gather::template chunk<Lanes, Record>(own, rec, idx, cnt, lanes);

          // 2. Pair terms (vectorized by GCC).
          for (std::size_t k = 0; k < cnt; ++k) {
            const PairOut<double, D> o = pair_step(
                std::type_identity<double>{}, bound,
                [&](std::size_t row) { return lanes[row * kChunk + k]; },
                [&]<class R, class O>(std::type_identity<R>, std::type_identity<O>, double r2,
                                      double r, double q, double t, double F) {
                  return PairView<D, Lanes, Record, R, O>{lanes, k, own, r2, r, q, t, F};
                });
            for (int d = 0; d < D; ++d) acc_lane[d][k] = o.acc[d];
            drho_lane[k] = o.drho;
            if constexpr (kSide) side_lane[k] = o.side;
          }

          // Some neighbour within close2 (a loop of its own: inside step 2's
          // loop the reduction made GCC version that loop).
          if (close2 > 0.0)
            for (std::size_t k = 0; k < cnt; ++k) {
              double r2 = 0.0;
              for (int d = 0; d < D; ++d) {
                const double x = lanes[(kPos + d) * kChunk + k];
                r2 += x * x;
              }
              near |= r2 < close2 ? 1 : 0;
            }
        }

        // 3. Sum in list (global-id) order.
        for (std::size_t k = 0; k < cnt; ++k) {
          for (int d = 0; d < D; ++d) acc[d] += acc_lane[d][k];
          drho_sum += drho_lane[k];
        }
        if constexpr (kSide)
          if (side_i)
            for (std::size_t k = 0; k < cnt; ++k) side_sum[0] += side_lane[k];
      }
      ps.a[i] = acc + g;
      ps.drho[i] = drho_sum;
      if (near != 0) close->particles.push_back(static_cast<std::uint32_t>(i));
      // The side pass's value where it is read, 0 elsewhere (as the pass).
      if constexpr (kSide)
        if (side) Side::output(ps)[i] = side_i ? Side{}.template finish<D>(side_sum) : 0.0;
    }
  }(Sel{});
}

// What one combination runs: its terms (with variants) and its record.
struct LoopDescription {
  std::size_t combination = 0;
  std::vector<std::string> terms;
  std::vector<int> variants;
  std::vector<std::string> record;  // fields packed per particle
  std::vector<std::string> lanes;   // fields gathered per neighbour
  std::size_t record_bytes = 0;
  bool in_registers = false;  // steps 1 and 2 in registers (InRegisters)
  bool one_per_lane = false;  // and one particle per lane (kOnePerLane)
};

template <int D, class List, std::size_t C>
LoopDescription describe_loop() {
  using N = Needs<D, typename Registry<List>::template Select<C>>;
  LoopDescription out;
  out.combination = C;
  [&]<class... S>(TermList<S...>) {
    out.terms = {S::Term::name...};
    out.variants = {S::kVariant...};
  }(typename Registry<List>::template Select<C>{});
  out.record = N::Record::names();
  out.lanes = N::Lanes::names();
  out.record_bytes = N::kStride * sizeof(double);
  out.in_registers =
      InRegisters<typename Registry<List>::template Select<C>, typename N::Side>::value;
#if defined(__AVX__) && !defined(SPHDEM_PAIRS_PER_PARTICLE)
  out.one_per_lane = out.in_registers;
#endif
  return out;
}

template <int D, class List>
using LoopFn = void (*)(const SphParams&, const NeighborList<D>&, SphParticles<D>&,
                        const PairLoopRun&);

template <int D, class List, std::size_t... C>
constexpr std::array<LoopFn<D, List>, sizeof...(C)> loop_table(std::index_sequence<C...>) {
  return {&rates_loop<D, List, C>...};
}
template <int D, class List, std::size_t... C>
std::array<LoopDescription (*)(), sizeof...(C)> description_table(std::index_sequence<C...>) {
  return {&describe_loop<D, List, C>...};
}

template <int D, class List, class P, std::size_t... C>
constexpr std::array<bool, sizeof...(C)> side_table(std::index_sequence<C...>) {
  return {
      std::is_same_v<typename Needs<D, typename Registry<List>::template Select<C>>::Side, P>...};
}

// Continuity and momentum of every owned resin particle from the terms of
// List that sp switches on (or of run.redo's), as PairLoopRun says.
template <int D, class List>
void run_pair_loop(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                   const PairLoopRun& run) {
  static constexpr auto table =
      loop_table<D, List>(std::make_index_sequence<Registry<List>::kCombinations>{});
  table[Registry<List>::combination(sp)](sp, nl, ps, run);
}

// The same; with close, also the particles with a neighbour within
// close->within2 (CloseNeighbours).
template <int D, class List>
void run_pair_loop(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                   CloseNeighbours* close = nullptr) {
  PairLoopRun run;
  run.close = close;
  run_pair_loop<D, List>(sp, nl, ps, run);
}

// Whether the loop sp selects can compute pass P on the side (PairLoopRun::side).
template <int D, class List, class P>
bool pair_loop_computes(const SphParams& sp) {
  static constexpr auto table =
      side_table<D, List, P>(std::make_index_sequence<Registry<List>::kCombinations>{});
  return table[Registry<List>::combination(sp)];
}

// The combination run_pair_loop picks for sp, for tests and logs.
template <int D, class List>
LoopDescription describe_pair_loop(const SphParams& sp) {
  static const auto table =
      description_table<D, List>(std::make_index_sequence<Registry<List>::kCombinations>{});
  return table[Registry<List>::combination(sp)]();
}

}  // namespace sphdem::terms
