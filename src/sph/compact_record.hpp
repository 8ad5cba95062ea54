#pragma once
// The pair loop's compact record (docs/performance.md, "A record of eight
// doubles"). In 2D, when a loop's record holds the mass m, the continuity's
// velocity v, the delta-SPH weight, rho and V = m / rho, and at this step
//   - every particle (owned and ghost) has the same mass, bit for bit,
//   - every wall particle is at rest (v = +0 on each axis),
//   - every resin particle's vwall is its v (wall_boundary.cpp sets it so),
//   - every density is positive,
// three of those fields carry nothing the others do not: m is the one mass,
// v_j is vw_j for resin and +0 for a wall, and the weight is -2 delta h c0 V_j
// for resin and 0 for a wall (delta_sph.hpp). The compact record leaves them
// out and stores rho with the sign bit set at a wall, which says which is
// which. The gather makes the full record's lane rows from it with the same
// bits as gathering the full record (CompactGather, compact_own_rows8), so
// no term sees a difference; the channel's record goes from 12 doubles
// (three quads for the eight-record transpose, lane_gather.hpp) to 8 (two).
// Tests: CompactRecord.* (tests/test_compact_record.cpp).
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "field_layout.hpp"
#include "lane_gather.hpp"
#include "record_fields.hpp"
#include "terms/delta_sph.hpp"

namespace sphdem::terms {

// When the pair loop uses the compact record (PairLoopRun::compact): never;
// where it applies, except for the 1024 runs after a run that found the
// conditions broken (Auto, the default: a moving wall breaks them at every
// step, and checking costs a partial fill); or at every run where it applies
// (EveryRun, for tests).
enum class CompactUse { Off, Auto, EveryRun };
// PairLoopRun::compact's default (tests change it) and how many loop runs
// used the compact record (tests read it).
inline CompactUse& compact_record_default() {
  static CompactUse use = CompactUse::Auto;
  return use;
}
inline std::size_t& compact_record_runs() {
  static std::size_t runs = 0;
  return runs;
}

template <int D, class RecordFields>
struct CompactRecord {
  static constexpr bool kHasDropped =
      D == 2 && contains_v<field::Mass, RecordFields> && contains_v<field::Vel, RecordFields> &&
      contains_v<field::VelWall, RecordFields> && contains_v<field::Rho, RecordFields> &&
      contains_v<field::DeltaWeight, RecordFields> && contains_v<field::Vol, RecordFields>;
  using Fs = typename Without<
      field::DeltaWeight,
      typename Without<field::Vel, typename Without<field::Mass, RecordFields>::type>::type>::type;
  using Layout = terms::Layout<D, Fs>;
  // Worth it where it saves a quad of the eight-record transpose.
  static constexpr bool value = kHasDropped && Layout::kSize <= 8;

  // Whether particle i keeps the conditions above, with m0 the one mass.
  template <class Ps>
  static bool keeps(const Ps& ps, std::size_t i, double m0) {
    if (std::bit_cast<std::uint64_t>(ps.mass[i]) != std::bit_cast<std::uint64_t>(m0)) return false;
    if (!(ps.rho[i] > 0.0)) return false;
    for (int d = 0; d < D; ++d) {
      const std::uint64_t v = std::bit_cast<std::uint64_t>(ps.v[i][d]);
      const std::uint64_t w = ps.kind[i] == Kind::Fluid
                                  ? std::bit_cast<std::uint64_t>(ps.vwall[i][d])
                                  : std::uint64_t{0};
      if (v != w) return false;
    }
    return true;
  }

  // Particle i's compact record: the full record's fields but the three,
  // rho negated at a wall.
  template <class Ps>
  static void fill(const SphParams& sp, const Ps& ps, std::size_t i, double* out) {
    [&]<class... F>(Fields<F...>) {
      double local[Layout::kSize];
      (F::template fill<D>(sp, ps, i, local + Layout::template offset<F>()), ...);
      if constexpr (contains_v<field::Rho, Fs>) {
        if (ps.kind[i] != Kind::Fluid) {
          double& rho = local[Layout::template offset<field::Rho>()];
          rho = -rho;
        }
      }
      for (std::size_t c = 0; c < Layout::kSize; ++c) out[c] = local[c];
    }(Fs{});
  }

  // The delta-SPH weight's factor, as DeltaWeight::fill forms it.
  static double weight_factor(const SphParams& sp) { return -2.0 * (sp.delta * sp.h * sp.c0); }
};

#if defined(__AVX512F__)
// Where lane row L of the full lanes comes from, given the compact record.
struct CompactSource {
  int what;  // 0: gathered; 1: m; 2: v (axis comp); 3: the delta-SPH weight; 4: rho
  int src;   // the compact record's double (what 0 and 4)
  int rel;   // subtracted from own row rel (the full record's order), or -1
  int comp;  // the axis (what 2)
};

template <class Lanes, class Record, class CL, class... F>
constexpr std::array<CompactSource, Lanes::kSize> compact_sources(Fields<F...>) {
  std::array<CompactSource, Lanes::kSize> s{};
  (
      [&] {
        constexpr std::size_t lo = Lanes::template offset<F>();
        for (int c = 0; c < static_cast<int>(width_v<F, 2>); ++c) {
          CompactSource& e = s[lo + static_cast<std::size_t>(c)];
          e.comp = c;
          e.rel = -1;
          if constexpr (!std::is_void_v<typename F::RelativeTo>)
            e.rel = static_cast<int>(Record::template offset<typename F::RelativeTo>()) + c;
          if constexpr (std::is_same_v<F, field::Mass>) {
            e.what = 1;
          } else if constexpr (std::is_same_v<F, field::Vel>) {
            e.what = 2;
          } else if constexpr (std::is_same_v<F, field::DeltaWeight>) {
            e.what = 3;
          } else {
            e.what = std::is_same_v<F, field::Rho> ? 4 : 0;
            e.src = static_cast<int>(CL::template offset<F>()) + c;
          }
        }
      }(),
      ...);
  return s;
}

// The full record's lane rows of neighbours r[0..7] (compact records), in
// registers: rows[L] holds what GatherLanes::rows would give from the full
// records. own: the particles' full own rows (compact_own_rows8).
template <class Gather, class Lanes, class Record, class CL, class LaneFields>
struct CompactGather {
  static constexpr std::array<CompactSource, Lanes::kSize> kSrc =
      compact_sources<Lanes, Record, CL>(LaneFields{});

  template <std::size_t L>
  [[gnu::always_inline]] static inline void gathered(const __m512d* own,
                                                     const double* const (&r)[8], __m512d* out) {
    if constexpr (kSrc[L].what == 0 || kSrc[L].what == 4)
      out[L] = Gather::template row8<kSrc[L].src, kSrc[L].rel>(own, r);
  }
  template <std::size_t L>
  [[gnu::always_inline]] static inline void made(const __m512d* own, __m512d* out, __mmask8 resin,
                                                 __m512d mass, __m512d weight_factor, __m512d vol) {
    constexpr CompactSource e = kSrc[L];
    if constexpr (e.what == 1) {
      out[L] = mass;
    } else if constexpr (e.what == 2) {
      // Resin: v_i - v_j with v_j's bits those of vw_j, the viscosity's row.
      // Wall: v_i - (+0), which is v_i.
      constexpr std::size_t vw = Lanes::template offset<field::VelWall>() + e.comp;
      out[L] = _mm512_mask_blend_pd(resin, own[e.rel], out[vw]);
    } else if constexpr (e.what == 3) {
      out[L] = _mm512_maskz_mul_pd(resin, weight_factor, vol);
    } else if constexpr (e.what == 4) {
      out[L] = _mm512_abs_pd(out[L]);
    }
  }

  template <std::size_t... L>
  [[gnu::always_inline]] static inline void rows(const __m512d* own, const double* const (&r)[8],
                                                 __m512d* out, __m512d mass, __m512d weight_factor,
                                                 std::index_sequence<L...>) {
    (gathered<L>(own, r, out), ...);
    constexpr std::size_t rho = Lanes::template offset<field::Rho>();
    const __mmask8 resin = _mm512_cmp_pd_mask(out[rho], _mm512_setzero_pd(), _CMP_GT_OQ);
    const __m512d vol = out[Lanes::template offset<field::Vol>()];
    (made<L>(own, out, resin, mass, weight_factor, vol), ...);
  }
};

// Eight particles' full own rows (the full record's order, as
// records_to_lanes8 gives them) from their compact records; every one is
// resin, so v is vw, rho is stored positive and the weight is the factor
// times V.
template <class Gather, class Record, class CL, class RecordFields, std::size_t... C>
[[gnu::always_inline]] inline void compact_own_rows8(const double* const (&rec)[8], __m512d* rows,
                                                     __m512d mass, __m512d weight_factor,
                                                     std::index_sequence<C...>) {
  __m512d compact[CL::kSize];
  records_to_lanes8<Gather>(rec, compact, std::index_sequence<C...>{});
  [&]<class... F>(Fields<F...>) {
    (
        [&] {
          constexpr std::size_t o = Record::template offset<F>();
          if constexpr (std::is_same_v<F, field::Mass>) {
            rows[o] = mass;
          } else if constexpr (std::is_same_v<F, field::Vel>) {
            for (std::size_t c = 0; c < 2; ++c)
              rows[o + c] = compact[CL::template offset<field::VelWall>() + c];
          } else if constexpr (std::is_same_v<F, field::DeltaWeight>) {
            rows[o] = _mm512_mul_pd(weight_factor, compact[CL::template offset<field::Vol>()]);
          } else {
            for (std::size_t c = 0; c < width_v<F, 2>; ++c)
              rows[o + c] = compact[CL::template offset<F>() + c];
          }
        }(),
        ...);
  }(RecordFields{});
}
#endif

}  // namespace sphdem::terms
