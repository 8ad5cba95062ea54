// The registry of SPH pair terms (src/sph/sph_terms.hpp) and the pair loop
// generated from it (src/sph/pair_loop.hpp): which combination a case
// selects, which fields its record holds, that the generated loop equals a
// direct sum of the terms' formulas, that a term written outside the
// library joins the loop through a term list alone, and the one-particle-
// per-lane form's helpers (the slot indices of four 16-bit lists, four
// records as lane rows).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "../src/sph/pair_loop.hpp"
#include "../src/sph/pass_loop.hpp"
#include "../src/sph/sph_terms.hpp"

namespace sphdem {
namespace {

using terms::describe_pair_loop;
using terms::SphTerms;

SphParams base_params() {
  SphParams sp;
  sp.h = 1.2e-3;
  sp.spacing = 1.0e-3;
  sp.rho0 = 1000;
  sp.c0 = 10;
  sp.mu = 0.1;
  sp.mu_scale = 1.05;
  sp.grad_scale = 1.03;
  sp.alpha = 0;
  sp.delta = 0;
  sp.anti_clump = true;
  sp.anti_clump_eps = 0.2;
  sp.anti_clump_n = 4;
  sp.eta2 = 0.01 * sp.h * sp.h;
  sp.body_force = {0.5, -9.81, 0.25};
  return sp;
}

bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(SphTermRegistry, SelectsTheTermsAndVariantsTheCaseSwitchesOn) {
  // delta, AV, surface tension, mu, variable mu: 2; clump: 3
  EXPECT_EQ(terms::Registry<SphTerms>::kCombinations, 96u);

  SphParams sp = base_params();  // the channel: Morris + anti-clump n = 4
  auto d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(d.terms, (std::vector<std::string>{"continuity", "pressure", "anti_clump", "morris"}));
  EXPECT_EQ(d.variants, (std::vector<int>{0, 0, 0, 0}));

  sp.anti_clump_n = 3;  // the general exponent
  d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(d.variants, (std::vector<int>{0, 0, 1, 0}));

  sp.delta = 0.1;
  sp.alpha = 0.05;
  d = describe_pair_loop<3, SphTerms>(sp);
  EXPECT_EQ(d.terms, (std::vector<std::string>{"continuity", "delta_sph", "pressure",
                                               "artificial_viscosity", "anti_clump", "morris"}));

  sp = base_params();
  sp.mu = 0;
  sp.anti_clump = false;
  d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(d.terms, (std::vector<std::string>{"continuity", "pressure"}));
  sp.surface_tension = 0.05;  // the continuum surface force (surface_tension.hpp)
  d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(d.terms, (std::vector<std::string>{"continuity", "pressure", "surface_tension"}));
  sp.surface_tension = 0;

  // A viscosity law: the variable-viscosity term instead of Morris's.
  sp = base_params();
  sp.variable_viscosity = true;
  d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(d.terms,
            (std::vector<std::string>{"continuity", "pressure", "anti_clump", "morris_variable"}));

  // Every switch setting picks its own instantiation (visc: none, Morris,
  // a law).
  std::set<std::size_t> seen;
  for (int visc : {0, 1, 2})
    for (double alpha : {0.0, 0.05})
      for (double delta : {0.0, 0.1})
        for (int clump : {0, 4, 2}) {
          sp = base_params();
          sp.mu = visc == 0 ? 0.0 : 0.1;
          sp.variable_viscosity = visc == 2;
          sp.alpha = alpha;
          sp.delta = delta;
          sp.anti_clump = clump != 0;
          sp.anti_clump_n = clump == 0 ? 4 : clump;
          seen.insert(describe_pair_loop<2, SphTerms>(sp).combination);
        }
  EXPECT_EQ(seen.size(), 36u);
}

// Each active term's declared fields, collected at run time from its type.
template <int D, class... T>
void collect_reads(terms::TermList<T...>, const std::string& name, std::vector<std::string>& lanes,
                   std::vector<std::string>& own) {
  (
      [&] {
        if (name != T::name) return;
        lanes = terms::Layout<D, typename T::Reads>::names();
        own = terms::Layout<D, typename terms::OwnReadsOf<T>::type>::names();
      }(),
      ...);
}

TEST(SphTermRegistry, TheRecordHoldsWhatTheActiveTermsDeclareAndNoMore) {
  for (int visc : {0, 1, 2})
    for (double alpha : {0.0, 0.05})
      for (double delta : {0.0, 0.1})
        for (bool clump : {false, true}) {
          SphParams sp = base_params();
          sp.mu = visc == 0 ? 0.0 : 0.1;
          sp.variable_viscosity = visc == 2;
          sp.alpha = alpha;
          sp.delta = delta;
          sp.anti_clump = clump;
          const auto d = describe_pair_loop<2, SphTerms>(sp);
          for (const auto& t : d.terms) {
            std::vector<std::string> lanes, own;
            collect_reads<2>(SphTerms{}, t, lanes, own);
            for (const auto& f : lanes) {
              EXPECT_TRUE(has(d.lanes, f)) << t << " reads lane " << f;
              EXPECT_TRUE(has(d.record, f)) << t << " reads " << f;
            }
            for (const auto& f : own) EXPECT_TRUE(has(d.record, f)) << t << " reads own " << f;
          }
          // Unpadded: 8 bytes per scalar, 16 per 2D vector field.
          EXPECT_GE(d.record_bytes, 8 * d.record.size());
          EXPECT_LE(d.record_bytes, 16 * d.record.size());
        }

  // The channel (Morris + anti-clump): rho is read only for particle i, so
  // it is packed but not gathered; no resin flag; 11 doubles, unpadded.
  SphParams sp = base_params();
  auto d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_TRUE(has(d.record, "rho"));
  EXPECT_FALSE(has(d.lanes, "rho"));
  EXPECT_FALSE(has(d.record, "fluid"));
  EXPECT_FALSE(has(d.record, "delta_weight"));
  EXPECT_TRUE(has(d.lanes, "anti_clump_r"));
  EXPECT_EQ(d.record_bytes, 88u);
  // Continuity and pressure alone: x, v, m, P/rho^2, 6 doubles.
  sp.mu = 0;
  sp.anti_clump = false;
  d = describe_pair_loop<2, SphTerms>(sp);
  EXPECT_EQ(std::set<std::string>(d.record.begin(), d.record.end()),
            (std::set<std::string>{"x", "v", "m", "p_over_rho2"}));
  EXPECT_EQ(d.record_bytes, 48u);
}

// A jittered lattice of resin with a row of walls below, negative pressure
// in places (anti-clump R_a), moving walls (no-slip vw != v).
template <int D>
SphParticles<D> cloud(const SphParams& sp, std::uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SphParticles<D> ps;
  const int n = 5, nz = D == 3 ? 4 : 1;
  std::int64_t id = 0;
  for (int layer = 0; layer < 2; ++layer)  // walls first, then resin: a layout unlike gid order
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < nz; ++k) {
          const bool wall = j == 0;
          if ((layer == 0) != wall) continue;
          Vec<D> x, v;
          x[0] = (i + 0.2 * u(gen)) * sp.spacing;
          x[1] = (j + 0.2 * u(gen)) * sp.spacing;
          if constexpr (D == 3) x[2] = (k + 0.2 * u(gen)) * sp.spacing;
          for (int c = 0; c < D; ++c) v[c] = 0.3 * u(gen);
          const double rho = sp.rho0 * (1.0 + 0.01 * u(gen));
          ps.push_owned(1000 - 7 * id++, wall ? Kind::Wall : Kind::Fluid, -1,
                        rho * std::pow(sp.spacing, D) * (1.0 + 0.1 * u(gen)), x, v, rho);
          const std::size_t p = ps.size() - 1;
          ps.p[p] = 50.0 * u(gen);
          for (int c = 0; c < D; ++c) ps.vwall[p][c] = wall ? 0.3 * u(gen) : v[c];
          ps.viscosity[p] = wall ? 0.0 : 0.1 * (1.5 + u(gen));  // a law's, per particle
        }
  return ps;
}

// The rates as a direct sum of the terms' formulas (the pre-registry loop,
// scalar, with the kernel class).
template <int D>
void direct_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                  std::vector<Vec<D>>& a, std::vector<double>& drho) {
  const WendlandC2<D> kernel(sp.h);
  a.assign(ps.size(), Vec<D>::Zero());
  drho.assign(ps.size(), 0.0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double por2_i = terms::pressure_over_rho2(ps.p[i], ps.rho[i]);
    for (std::size_t b = nl.begin(i); b < nl.end(i); ++b) {
      const auto j = static_cast<std::size_t>(nl.row(i)[b]);
      const Vec<D> x = ps.x[i] - ps.x[j];
      const double r2 = x.squaredNorm(), r = std::sqrt(r2);
      const double F = kernel.f(r) * sp.grad_scale;
      const double por2_j = terms::pressure_over_rho2(ps.p[j], ps.rho[j]);
      const double vol_j = ps.mass[j] / ps.rho[j];
      const Vec<D> w = ps.v[i] - ps.vwall[j];
      drho[i] += terms::continuity(ps.mass[j], F, (ps.v[i] - ps.v[j]).dot(x));
      if (sp.delta > 0 && ps.kind[j] == Kind::Fluid)
        drho[i] += terms::delta_sph(sp.delta * sp.h * sp.c0, ps.rho[i], ps.rho[j], vol_j, F);
      double bracket = por2_i + por2_j;
      if (sp.alpha > 0)
        bracket += terms::artificial_viscosity(sp.alpha * sp.c0 * sp.h, w.dot(x), r2, sp.eta2,
                                               ps.rho[i], ps.rho[j]);
      if (sp.anti_clump)
        bracket += terms::anti_clump(terms::anti_clump_r(sp.anti_clump_eps, por2_i),
                                     terms::anti_clump_r(sp.anti_clump_eps, por2_j), por2_i, por2_j,
                                     kernel.w(r) / kernel.w(sp.spacing), sp.anti_clump_n);
      a[i] -= ps.mass[j] * bracket * F * x;
      if (sp.variable_viscosity) {
        const double mu_j = ps.kind[j] == Kind::Fluid ? ps.viscosity[j] : ps.viscosity[i];
        a[i] += 2.0 * terms::harmonic_mean(ps.viscosity[i], mu_j) * sp.mu_scale / sp.grad_scale /
                ps.rho[i] * vol_j * F * r2 / (r2 + sp.eta2) * w;
      } else if (sp.mu > 0)
        a[i] += terms::morris_viscosity(2.0 * sp.mu * sp.mu_scale / sp.grad_scale / ps.rho[i],
                                        vol_j, F, r2, sp.eta2) *
                w;
    }
    a[i] += to_vec<D>(sp.body_force);
  }
}

template <int D>
void expect_loop_matches_direct_sum(const SphParams& sp) {
  SphParticles<D> ps = cloud<D>(sp, 7);
  NeighborList<D> nl(2.0 * sp.h, 0.3 * sp.h);
  nl.build(ps);
  compute_fluid_rates<D>(sp, nl, ps);
  std::vector<Vec<D>> a;
  std::vector<double> drho;
  direct_rates<D>(sp, nl, ps, a, drho);
  double a_scale = 0, drho_scale = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    a_scale = std::max(a_scale, a[i].norm());
    drho_scale = std::max(drho_scale, std::abs(drho[i]));
  }
  ASSERT_GT(a_scale, 0);
  ASSERT_GT(drho_scale, 0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    EXPECT_LE((ps.a[i] - a[i]).norm(), 1e-12 * a_scale) << "particle " << i;
    EXPECT_LE(std::abs(ps.drho[i] - drho[i]), 1e-12 * drho_scale) << "particle " << i;
  }
}

// Calls f with the parameters of every combination of the terms without
// surface tension: viscosity (none, Morris, a law with per-particle
// viscosity), artificial viscosity, delta-SPH, anti-clump (off, n = 4, n = 3).
template <class F>
void for_every_term_combination(const F& f) {
  for (int visc : {0, 1, 2})
    for (double alpha : {0.0, 0.05})
      for (double delta : {0.0, 0.1})
        for (int clump : {0, 4, 3}) {
          SphParams sp = base_params();
          sp.mu = visc == 0 ? 0.0 : 0.1;
          sp.variable_viscosity = visc == 2;
          sp.alpha = alpha;
          sp.delta = delta;
          sp.anti_clump = clump != 0;
          sp.anti_clump_n = clump == 0 ? 4 : clump;
          SCOPED_TRACE(testing::Message() << "visc " << visc << " alpha " << alpha << " delta "
                                          << delta << " clump " << clump);
          f(sp);
        }
}

TEST(SphPairLoop, EqualsTheDirectSumOfTheTermsInEveryCombination) {
  for_every_term_combination([](const SphParams& sp) {
    expect_loop_matches_direct_sum<2>(sp);
    expect_loop_matches_direct_sum<3>(sp);
  });
}

// The shipped cases' terms (the channel: continuity, delta-SPH, pressure,
// anti-clump, Morris, the free-surface flag on the side; with artificial
// viscosity or a viscosity law too) are written for registers, so with AVX
// their loop computes them on the gathered registers; a term that is not
// (surface tension) sends the loop through the lane rows in memory. Fails when a term loses
// kVectorPair (the loop would be correct, and about 1.1 times slower).
TEST(SphPairLoop, TheShippedTermsRunInRegistersWithAvx) {
#if defined(__AVX__)
  constexpr bool kAvx = true;
#else
  constexpr bool kAvx = false;
#endif
  SphParams sp = base_params();
  sp.mu = 0.1;
  sp.delta = 0.1;
  sp.anti_clump = true;
  sp.anti_clump_n = 4;
  for (double alpha : {0.0, 0.05}) {
    sp.alpha = alpha;
    EXPECT_EQ((describe_pair_loop<2, SphTerms>(sp).in_registers), kAvx) << "alpha " << alpha;
    EXPECT_EQ((describe_pair_loop<3, SphTerms>(sp).in_registers), kAvx) << "alpha " << alpha;
  }
  sp.variable_viscosity = true;
  EXPECT_EQ((describe_pair_loop<2, SphTerms>(sp).in_registers), kAvx) << "a viscosity law";
  // With AVX, one particle per lane wherever the terms run in registers.
#if defined(__AVX__)
  EXPECT_TRUE((describe_pair_loop<2, SphTerms>(sp).one_per_lane));
  EXPECT_TRUE((describe_pair_loop<3, SphTerms>(sp).one_per_lane));
#endif
  sp.surface_tension = 0.03;
  EXPECT_FALSE((describe_pair_loop<2, SphTerms>(sp).in_registers));
  EXPECT_FALSE((describe_pair_loop<2, SphTerms>(sp).one_per_lane));
}

// With AVX the loop puts one owned particle per lane (pair_loop.hpp,
// kOnePerLane: eight lanes with AVX-512, four with AVX);
// PairLoopRun::per_particle forces one particle at a time.
// Both must give the same bits in every combination of terms, with the
// free-surface flag on the side and the close-neighbour search: each lane
// sums its own list in order, and a lane past the end of a shorter list adds
// only the far record's exact zeros. The clouds' lists differ in length
// (walls, edges), so the groups are ragged. Fails when a lane past its
// list's end adds anything else (shown by leaving the far record among the
// particles: docs/performance.md, "One particle per lane with AVX2").
// What the runs found, so that the test knows it saw flags and close pairs.
struct OnePerLaneSeen {
  std::size_t flagged = 0, close = 0;
};

template <int D>
OnePerLaneSeen expect_one_per_lane_bitwise(const SphParams& sp, std::uint32_t seed) {
  const SphParticles<D> start = cloud<D>(sp, seed);
  NeighborList<D> nl(2.0 * sp.h, 0.3 * sp.h);
  nl.build(start);
  SphParticles<D> lanes = start, one = start;
  terms::CloseNeighbours close_lanes{0.5 * sp.spacing * sp.spacing, {}};
  terms::CloseNeighbours close_one = close_lanes;
  terms::PairLoopRun run;
  run.side = terms::pair_loop_computes<D, SphTerms, terms::FreeSurfaceFlag>(sp);
  run.close = &close_lanes;
  terms::run_pair_loop<D, SphTerms>(sp, nl, lanes, run);
  run.per_particle = true;
  run.close = &close_one;
  terms::run_pair_loop<D, SphTerms>(sp, nl, one, run);
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < start.n_owned; ++i) {
    if (start.kind[i] != Kind::Fluid) continue;
    ++fluid;
    for (int d = 0; d < D; ++d)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes.a[i][d]),
                std::bit_cast<std::uint64_t>(one.a[i][d]))
          << "particle " << i << " axis " << d;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes.drho[i]),
              std::bit_cast<std::uint64_t>(one.drho[i]))
        << "particle " << i;
    EXPECT_EQ(lanes.free_surface[i], one.free_surface[i]) << "particle " << i;
  }
  EXPECT_GT(fluid, 8u) << "more than one group of lanes";
  EXPECT_EQ(close_lanes.particles, close_one.particles);
  OnePerLaneSeen seen;
  for (std::size_t i = 0; i < start.n_owned; ++i) seen.flagged += one.free_surface[i] != 0.0;
  seen.close = close_one.particles.size();
  return seen;
}

// The cloud's resin particles follow its walls in memory, so with AVX-512
// most groups are eight particles in a row, whose results the loop stores
// as whole registers, and the last group of each cloud is not.
TEST(SphPairLoop, OneParticlePerLaneGivesTheBitsOfOneAtATime) {
  OnePerLaneSeen seen[2];
  for_every_term_combination([&](const SphParams& sp) {
    for (std::uint32_t seed : {7u, 11u}) {
      const OnePerLaneSeen s2 = expect_one_per_lane_bitwise<2>(sp, seed);
      const OnePerLaneSeen s3 = expect_one_per_lane_bitwise<3>(sp, seed);
      for (int k = 0; k < 2; ++k) {
        const OnePerLaneSeen& s = k == 0 ? s2 : s3;
        seen[k].flagged += s.flagged;
        seen[k].close += s.close;
      }
    }
  });
  for (int k = 0; k < 2; ++k) {
    EXPECT_GT(seen[k].flagged, 0u) << (k == 0 ? "2D" : "3D") << ": no free-surface flag set";
    EXPECT_GT(seen[k].close, 0u) << (k == 0 ? "2D" : "3D") << ": no close pair";
  }
}

// The one-particle-per-lane form's slot indices, four lanes of 16-bit lists
// at a time (narrow_slots4): the indices the fill element by element gives,
// the far record past each list's end, for lists of every length against
// every other (whole and partial blocks of four, empty lanes) and offsets of
// both signs. Each row lies at the end of its own array, so a read past it
// would leave the array.
TEST(SphPairLoop, NarrowSlotsAreTheListsSlotBySlot) {
#if defined(__AVX2__)
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> offset(-32767, 32767);
  const std::int32_t far = 1 << 30;
  int cases = 0;
  for (std::size_t l0 = 0; l0 <= 9; ++l0) {
    for (std::size_t l1 : {std::size_t{0}, std::size_t{1}, std::size_t{4}, std::size_t{7}}) {
      for (std::size_t l2 : {std::size_t{3}, std::size_t{8}}) {
        for (std::size_t l3 : {std::size_t{0}, std::size_t{5}, std::size_t{12}}) {
          const std::size_t len[4] = {l0, l1, l2, l3};
          std::vector<std::int16_t> rows[4];
          const std::int16_t* row[4];
          std::int32_t base[4];
          for (int l = 0; l < 4; ++l) {
            rows[l].resize(len[l]);
            for (auto& o : rows[l]) o = static_cast<std::int16_t>(offset(rng));
            row[l] = rows[l].data();
            base[l] = 40000 + 1000 * l;
          }
          const std::size_t slots = std::max({l0, l1, l2, l3}) + 1;
          std::vector<std::int32_t> got(4 * (slots + 3), -1);
          terms::narrow_slots4(row, base, len, slots, far, got.data());
          for (std::size_t k = 0; k < slots; ++k)
            for (std::size_t l = 0; l < 4; ++l)
              ASSERT_EQ(got[k * 4 + l], k < len[l] ? base[l] + rows[l][k] : far)
                  << "slot " << k << " lane " << l << " of lists " << l0 << ' ' << l1 << ' ' << l2
                  << ' ' << l3;
          ++cases;
        }
      }
    }
  }
  EXPECT_EQ(cases, 10 * 4 * 2 * 3);
#else
  GTEST_SKIP() << "narrow_slots4 is built with AVX2 only";
#endif
}

// Each of rows[0 .. size) against lanes_of's values for the records rec.
template <class VR, std::size_t W>
void expect_rows_are_lanes_of(const VR* rows, const double* const (&rec)[W], std::size_t size) {
  for (std::size_t c = 0; c < size; ++c) {
    VR want;
    terms::lanes_of(rec, c, want);
    double a[W], b[W];
    __builtin_memcpy(a, &rows[c], sizeof a);
    __builtin_memcpy(b, &want, sizeof b);
    for (std::size_t l = 0; l < W; ++l) EXPECT_EQ(a[l], b[l]) << "row " << c << " lane " << l;
  }
}

// Four records as lane rows in registers (records_to_lanes4): lanes_of's
// values for every row, for records of an even and of an odd length.
template <std::size_t kSize>
void expect_records_to_lanes4() {
#if defined(__AVX__)
  double recs[4][kSize];
  for (int l = 0; l < 4; ++l)
    for (std::size_t c = 0; c < kSize; ++c) recs[l][c] = 100.0 * l + static_cast<double>(c) + 0.25;
  const double* const rec[4] = {recs[0], recs[1], recs[2], recs[3]};
  __m256d rows[kSize];
  terms::records_to_lanes4(rec, rows);
  expect_rows_are_lanes_of(rows, rec, kSize);
#endif
}

TEST(SphPairLoop, RecordsToLanesFourAtATime) {
#if defined(__AVX__)
  expect_records_to_lanes4<12>();
  expect_records_to_lanes4<11>();
  expect_records_to_lanes4<1>();
#else
  GTEST_SKIP() << "records_to_lanes4 is built with AVX only";
#endif
}

// narrow_slots8 (AVX-512) against the lists slot by slot, for lists of
// 0-19 entries: whole and partial blocks of eight, empty lanes, offsets of
// both signs, each row at the end of its own array (the masked loads read
// nothing past it: the sanitize-native preset runs this test under ASan;
// the sanitize preset builds without AVX-512, so it skips there).
TEST(SphPairLoop, NarrowSlotsEightAtATimeAreTheListsSlotBySlot) {
#if defined(SPHDEM_NARROW_SLOTS8)
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> offset(-32767, 32767);
  std::uniform_int_distribution<std::size_t> length(0, 19);
  const std::int32_t far = 1 << 30;
  for (int c = 0; c < 400; ++c) {
    std::size_t len[8];
    std::vector<std::int16_t> rows[8];
    const std::int16_t* row[8];
    std::int32_t base[8];
    for (int l = 0; l < 8; ++l) {
      // Every length 0-8 in lane l of some case, then random ones.
      len[l] = c < 9 ? static_cast<std::size_t>((c + l) % 9) : length(rng);
      rows[l].resize(len[l]);
      for (auto& o : rows[l]) o = static_cast<std::int16_t>(offset(rng));
      row[l] = rows[l].data();
      base[l] = 40000 + 1000 * l;
    }
    const std::size_t slots = *std::max_element(len, len + 8) + 1;
    std::vector<std::int32_t> got(8 * (slots + 7), -1);
    terms::narrow_slots8(row, base, len, slots, far, got.data());
    for (std::size_t k = 0; k < slots; ++k)
      for (std::size_t l = 0; l < 8; ++l)
        ASSERT_EQ(got[k * 8 + l], k < len[l] ? base[l] + rows[l][k] : far)
            << "case " << c << " slot " << k << " lane " << l << " of length " << len[l];
  }
#else
  GTEST_SKIP() << "narrow_slots8 is built with AVX-512 (F, BW, VL) only";
#endif
}

// Eight records as lane rows in registers (records_to_lanes8): lanes_of's
// values for every row, for records of 12, 11, 9 and 1 doubles.
template <std::size_t kSize>
void expect_records_to_lanes8() {
#if defined(__AVX512F__)
  // Three readable doubles after each record, as kRecordSpare gives.
  std::vector<double> recs(8 * kSize + 3, -1.0);
  const double* rec[8];
  for (int l = 0; l < 8; ++l) {
    for (std::size_t c = 0; c < kSize; ++c)
      recs[l * kSize + c] = 100.0 * l + static_cast<double>(c) + 0.25;
    rec[l] = recs.data() + l * kSize;
  }
  __m512d rows[kSize];
  terms::records_to_lanes8<terms::GatherLanes<2, terms::Fields<>>>(
      rec, rows, std::make_index_sequence<kSize>{});
  expect_rows_are_lanes_of(rows, rec, kSize);
#endif
}

TEST(SphPairLoop, RecordsToLanesEightAtATime) {
#if defined(__AVX512F__)
  expect_records_to_lanes8<12>();
  expect_records_to_lanes8<11>();
  expect_records_to_lanes8<9>();
  expect_records_to_lanes8<1>();
#else
  GTEST_SKIP() << "records_to_lanes8 is built with AVX-512 only";
#endif
}

// A term written outside the library: a per-particle prepared field (the
// record computes it once per particle), a per-particle part and a pair
// function. It joins the loop through a term list alone.
namespace field {
struct Tag : terms::ScalarField {
  static constexpr const char* name = "tag";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = 1.0 + static_cast<double>(ps.gid[i] % 5);
  }
};
}  // namespace field

struct TaggedDensityRate {
  static constexpr const char* name = "tagged";
  using Reads = terms::Fields<field::Tag>;
  using OwnReads = terms::Fields<terms::field::Rho>;
  static constexpr unsigned writes = terms::kDrho;
  static bool active(const SphParams& sp) { return sp.delta > 0; }  // a switch for the test

  double scale, own_part = 0;
  template <int D>
  explicit TaggedDensityRate(const terms::TermContext<D>& c) : scale(c.sp.delta) {}
  template <class I>
  TaggedDensityRate for_particle(const I& i) const {
    TaggedDensityRate b = *this;
    b.own_part = scale * i.own_value(terms::field::Rho{});
    return b;
  }
  template <class P>
  void pair(const P& p, terms::PairSums& s) const {
    s.drho += own_part * p.lane(field::Tag{}) * p.F;
  }
};

TEST(SphPairLoop, ATermOutsideTheLibraryJoinsThroughTheListAlone) {
  using List = terms::TermList<terms::Continuity, TaggedDensityRate, terms::Pressure>;
  SphParams sp = base_params();
  sp.delta = 0.5;
  const auto d = describe_pair_loop<2, List>(sp);
  EXPECT_EQ(d.terms, (std::vector<std::string>{"continuity", "tagged", "pressure"}));
  EXPECT_TRUE(has(d.lanes, "tag"));

  SphParticles<2> ps = cloud<2>(sp, 11);
  NeighborList<2> nl(2.0 * sp.h, 0.3 * sp.h);
  nl.build(ps);
  terms::run_pair_loop<2, List>(sp, nl, ps);
  const WendlandC2<2> kernel(sp.h);
  int checked = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    double drho = 0.0;
    Vec<2> a = to_vec<2>(sp.body_force);
    for (std::size_t b = nl.begin(i); b < nl.end(i); ++b) {
      const auto j = static_cast<std::size_t>(nl.row(i)[b]);
      const Vec<2> x = ps.x[i] - ps.x[j];
      const double F = kernel.f(x.norm()) * sp.grad_scale;
      drho += ps.mass[j] * F * (ps.v[i] - ps.v[j]).dot(x);
      drho += sp.delta * ps.rho[i] * (1.0 + static_cast<double>(ps.gid[j] % 5)) * F;
      a -= ps.mass[j] *
           (terms::pressure_over_rho2(ps.p[i], ps.rho[i]) +
            terms::pressure_over_rho2(ps.p[j], ps.rho[j])) *
           F * x;
    }
    EXPECT_NEAR(ps.drho[i], drho, 1e-12 * std::abs(drho) + 1e-12);
    EXPECT_LE((ps.a[i] - a).norm(), 1e-12 * a.norm());
    ++checked;
  }
  EXPECT_GT(checked, 10);

  // Switched off, the loop is continuity and pressure only.
  SphParticles<2> off = ps;
  sp.delta = 0;
  terms::run_pair_loop<2, List>(sp, nl, off);
  terms::run_pair_loop<2, terms::TermList<terms::Continuity, terms::Pressure>>(sp, nl, ps);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    EXPECT_EQ(off.drho[i], ps.drho[i]);
    EXPECT_EQ(off.a[i], ps.a[i]);
  }
}

// The wall repulsion walks only the lists of the particles the pair loop
// found with a neighbour within its range (CloseNeighbours): the same bits
// as walking every list, on a cloud where resin sits closer than 0.9 dp to
// the walls (the cloud's jitter is 0.2 dp per axis) and where most resin
// has no neighbour that close, so the short cut is taken.
template <int D>
void expect_repulsion_from_close_particles(std::uint32_t seed) {
  SphParams sp = base_params();
  sp.wall_repulsion = true;
  SphParticles<D> ps = cloud<D>(sp, seed);
  // One resin particle surely inside the range: 0.6 dp above the first wall particle.
  const auto wall = static_cast<std::size_t>(std::find(ps.kind.begin(), ps.kind.end(), Kind::Wall) -
                                             ps.kind.begin());
  const auto resin = static_cast<std::size_t>(
      std::find(ps.kind.begin(), ps.kind.end(), Kind::Fluid) - ps.kind.begin());
  ps.x[resin] = ps.x[wall];
  ps.x[resin][1] += 0.6 * sp.spacing;
  NeighborList<D> nl(2.0 * sp.h, 0.3 * sp.h);
  nl.build(ps);
  SphParticles<D> every = ps, none = ps;
  terms::CloseNeighbours close;
  close.within2 = wall_repulsion_range2<D>(sp);
  terms::run_pair_loop<D, SphTerms>(sp, nl, ps, &close);
  add_wall_repulsion<D>(sp, nl, ps, close.particles);
  terms::run_pair_loop<D, SphTerms>(sp, nl, every);
  terms::run_pair_loop<D, SphTerms>(sp, nl, none);
  add_wall_repulsion<D>(sp, nl, every);  // every owned particle's list

  const double r0 = 0.9 * sp.spacing;
  std::size_t resin_count = 0, pushed = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    ++resin_count;
    bool wall_close = false;
    for (std::size_t b = nl.begin(i); b < nl.end(i); ++b) {
      const auto j = static_cast<std::size_t>(nl.row(i)[b]);
      wall_close = wall_close || (ps.kind[j] == Kind::Wall && (ps.x[i] - ps.x[j]).norm() < r0);
    }
    const bool found =
        std::find(close.particles.begin(), close.particles.end(), i) != close.particles.end();
    if (wall_close) {
      EXPECT_TRUE(found) << "particle " << i;
    }
    EXPECT_EQ(ps.a[i], every.a[i]) << "particle " << i;  // bitwise
    if (ps.a[i] != none.a[i]) ++pushed;
  }
  EXPECT_GT(pushed, 0u);                           // the repulsion acted
  EXPECT_LT(close.particles.size(), resin_count);  // and some lists were skipped
}

TEST(SphPairLoop, TheWallRepulsionVisitsOnlyTheCloseParticles) {
  for (std::uint32_t seed : {3u, 7u, 11u}) {
    expect_repulsion_from_close_particles<2>(seed);
    expect_repulsion_from_close_particles<3>(seed);
  }
}

// A neighbour-sum pass written outside the library (how many neighbours lie
// inside the support, into the registered field shear_rate) and a term that
// reads the result on its neighbours. The engine runs the pass only when
// the term is on, then asks for the pass's group to be forwarded: here the
// "halo" fills the ghosts (the last particles, not owned) by hand, and the
// term's sum over owned particles only matches if that happened between
// the pass and the pair loop.
struct SupportCountPass {
  static constexpr const char* name = "support_count";
  using Reads = terms::Fields<terms::field::Pos>;
  using Output = terms::field::ShearRate;
  static constexpr SphGroup group = SphGroup::ShearRate;
  template <int D>
  static constexpr std::size_t kSums = 1;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.shear_rate;
  }
  template <class P>
  void pair(const P& p, double* s) const {
    s[0] = p.t > 0.0 ? 1.0 : 0.0;
  }
  template <int D>
  double finish(const double* sums) const {
    return 10.0 * sums[0];
  }
};

struct CountDensityRate {
  static constexpr const char* name = "count_rate";
  using Reads = terms::Fields<terms::field::ShearRate>;
  static constexpr unsigned writes = terms::kDrho;
  static bool active(const SphParams& sp) { return sp.delta > 0; }
  template <class P>
  void pair(const P& p, terms::PairSums& s) const {
    s.drho += p.t > 0.0 ? p.lane(terms::field::ShearRate{}) : 0.0;
  }
};

TEST(SphPasses, APassRunsBeforeTheLoopWhenAnActiveTermReadsIt) {
  using List = terms::TermList<terms::Continuity, CountDensityRate>;
  using Passes = terms::PassList<SupportCountPass>;
  SphParams sp = base_params();
  sp.delta = 0.5;
  SphParticles<2> ps = cloud<2>(sp, 5);
  ps.n_owned -= 6;  // the last resin particles play ghosts
  NeighborList<2> nl(2.0 * sp.h, 0.3 * sp.h);
  nl.build(ps);
  // The reference: every particle's support count, brute force.
  std::vector<double> count(ps.size(), 0.0);
  for (std::size_t i = 0; i < ps.size(); ++i)
    for (std::size_t j = 0; j < ps.size(); ++j)
      if (i != j && ps.kind[i] == Kind::Fluid && (ps.x[i] - ps.x[j]).norm() < 2.0 * sp.h)
        count[i] += 1.0;

  EXPECT_EQ(terms::needed_passes<List>(sp, Passes{}), std::vector<std::string>{"support_count"});
  std::vector<SphGroup> forwarded;
  terms::run_passes<2, List>(
      sp, nl, ps,
      [&](SphGroup g) {
        forwarded.push_back(g);
        for (std::size_t i = ps.n_owned; i < ps.size(); ++i) ps.shear_rate[i] = 10.0 * count[i];
      },
      Passes{});
  EXPECT_EQ(forwarded, std::vector<SphGroup>{SphGroup::ShearRate});
  terms::run_pair_loop<2, List>(sp, nl, ps);
  int checked = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) {
      EXPECT_EQ(ps.shear_rate[i], 0.0);
      continue;
    }
    ASSERT_EQ(ps.shear_rate[i], 10.0 * count[i]) << "particle " << i;
    double drho = 0.0, sum = 0.0;
    for (std::size_t b = nl.begin(i); b < nl.end(i); ++b) {
      const auto j = static_cast<std::size_t>(nl.row(i)[b]);
      const Vec<2> x = ps.x[i] - ps.x[j];
      drho +=
          ps.mass[j] * WendlandC2<2>(sp.h).f(x.norm()) * sp.grad_scale * (ps.v[i] - ps.v[j]).dot(x);
      if (x.norm() < 2.0 * sp.h) sum += 10.0 * count[j];
    }
    EXPECT_NEAR(ps.drho[i], drho + sum, 1e-12 * std::abs(drho + sum)) << "particle " << i;
    ++checked;
  }
  EXPECT_GT(checked, 10);

  // The term off: the pass does not run, nothing is forwarded.
  sp.delta = 0;
  EXPECT_TRUE(terms::needed_passes<List>(sp, Passes{}).empty());
  std::fill(ps.shear_rate.begin(), ps.shear_rate.end(), -1.0);
  forwarded.clear();
  terms::run_passes<2, List>(
      sp, nl, ps, [&](SphGroup g) { forwarded.push_back(g); }, Passes{});
  EXPECT_TRUE(forwarded.empty());
  EXPECT_EQ(ps.shear_rate[0], -1.0);
  // Named in output.fields, it runs without a term.
  sp.output_fields = {"support_count"};
  EXPECT_EQ(terms::needed_passes<List>(sp, Passes{}), std::vector<std::string>{"support_count"});
}

// The library's passes: the shear rate runs when output.fields names it.
TEST(SphPasses, TheShearRateRunsWhenRequested) {
  SphParams sp = base_params();
  // The anti-clump term off the free surface (the default) needs the
  // free-surface pass (tests/test_front.cpp); here the published form.
  sp.anti_clump_at_surface = true;
  EXPECT_TRUE(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}).empty());
  sp.output_fields = {"velocity", "shear_rate"};
  EXPECT_EQ(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}),
            std::vector<std::string>{"shear_rate"});
  const auto names = sph_output_fields();
  EXPECT_NE(std::find(names.begin(), names.end(), "shear_rate"), names.end());
  // A viscosity law reads the shear rate: the pass runs without the request.
  sp.output_fields = {"velocity"};
  sp.variable_viscosity = true;
  EXPECT_EQ(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}),
            std::vector<std::string>{"shear_rate"});
}

// The anti-clump term reads the free-surface flag (R_a = 0 there) unless
// numerics.anti_clump_at_surface: the free-surface pass then runs.
TEST(SphPasses, TheAntiClumpTermNeedsTheFreeSurface) {
  SphParams sp = base_params();
  EXPECT_EQ(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}),
            std::vector<std::string>{"free_surface"});
  sp.anti_clump_at_surface = true;
  EXPECT_TRUE(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}).empty());
  sp.front_events = true;
  EXPECT_EQ(terms::needed_passes<SphTerms>(sp, terms::SphPasses{}),
            std::vector<std::string>{"free_surface"});
}

// The anti-clump term alone runs the pass's Lite (the flag where P < 0);
// anything else that reads the pass runs the full one (issue 19).
TEST(SphPasses, TheAntiClumpTermAloneRunsTheFlagOnly) {
  using terms::PassRun;
  const auto run = [](const SphParams& sp) {
    return terms::pass_run<terms::FreeSurfacePass>(sp, SphTerms{});
  };
  SphParams sp = base_params();
  EXPECT_EQ(run(sp), PassRun::Lite);
  sp.anti_clump_eps = 0.0;  // R_a = 0 everywhere: nothing reads the flag
  EXPECT_EQ(run(sp), PassRun::Off);
  sp.anti_clump_eps = 0.2;
  sp.anti_clump = false;
  EXPECT_EQ(run(sp), PassRun::Off);
  sp.anti_clump = true;
  for (const char* field : {"free_surface", "surface_normal", "position_divergence"}) {
    sp.output_fields = {"velocity", field};
    EXPECT_EQ(run(sp), PassRun::Full) << field;
  }
  sp.output_fields = {"velocity"};
  EXPECT_EQ(run(sp), PassRun::Lite);
  sp.shifting = 2.0;
  EXPECT_EQ(run(sp), PassRun::Full);
  sp.shifting = 0.0;
  sp.front_events = true;
  EXPECT_EQ(run(sp), PassRun::Full);
  sp.anti_clump = false;
  EXPECT_EQ(run(sp), PassRun::Full);
}

}  // namespace
}  // namespace sphdem
