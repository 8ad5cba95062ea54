// The free-surface pass for the anti-clump term alone (issue 19,
// docs/performance.md "The free-surface pass for the anti-clump term"):
// when nothing but the anti-clump term reads the flag, the pass runs as
// FreeSurfacePass::Lite (src/sph/terms/free_surface.hpp, FreeSurfaceFlag):
// div r alone, and only at the particles with P < 0, where the term reads
// it. These tests hold it to the full pass: the same flag bits there, on a
// free surface (the dam break), in a channel without one and in 3D, and the
// same run bitwise. Rank independence: RankIndependence.* in test_parallel
// (DamBreakAntiClumpFlag, PlateWithPiston).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "../src/sph/pass_loop.hpp"
#include "../src/sph/sph_terms.hpp"
#include "same_particles.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/sph/fluid_rates.hpp"
#include "sphdem/sph/sph.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using terms::PassRun;

using testing::quiet;
using testing::world;

// The bench_sph channel (testing::small_channel): no free surface, anti-clump on.
Case channel(std::vector<std::string> sets = {}) {
  return testing::small_channel(sets);
}

// The dam-break column without particle shifting and without the pass's
// fields in the output: only the anti-clump term reads the flag.
Case dam_break(std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(),
              {"numerics.particle_shifting=false", "output.fields=[velocity, density, pressure]"});
  return testing::load_input("validation/dam_break_front.yaml", sets);
}

// The 3D sloshing tank of test_parallel's Sloshing3D (anti-clump on, the default).
Case sloshing_3d(std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(), {"initial_velocity=[0.05, 0.02, 0]"});
  return testing::load_input("validation/hydrostatic_3d.yaml", sets);
}

struct FlagCounts {
  int read_surface = 0;   // P < 0 on the surface (flag 1)
  int read_interior = 0;  // P < 0 inside (flag 0)
  int not_read = 0;       // P >= 0: the Lite leaves 0
};

// Advances the case `steps` steps, then runs the full pass and its Lite on
// the same particles and neighbour lists: the Lite's flag equals the full
// pass's bit for bit wherever the anti-clump term reads it (P < 0) and is 0
// elsewhere.
template <int D>
FlagCounts expect_flag_of_the_full_pass(const Case& c, int steps) {
  const SphParams sp = make_sph_params(c);
  EXPECT_EQ(terms::pass_run<terms::FreeSurfacePass>(sp, terms::SphTerms{}), PassRun::Lite);
  Simulation<D> sim(c, world(), quiet());
  sim.advance(steps);
  SphParticles<D> full = sim.particles();  // owned and ghosts, as the last step left them
  SphParticles<D> lite = full;
  NeighborList<D> nl(2.0 * sp.h, 0.0);
  nl.build(full);
  terms::run_pass<D, terms::FreeSurfacePass>(sp, nl, full);
  std::fill(lite.free_surface.begin(), lite.free_surface.end(), -1.0);
  terms::run_pass<D, terms::FreeSurfaceFlag>(sp, nl, lite);
  FlagCounts n;
  int wrong = 0;  // owned particles where the Lite is not what it should be
  std::size_t first = 0;
  for (std::size_t i = 0; i < full.n_owned; ++i) {
    if (full.kind[i] != Kind::Fluid) {
      EXPECT_EQ(lite.free_surface[i], 0.0);
      continue;
    }
    const bool read = full.p[i] < 0.0;  // field::AntiClumpR is not 0 (epsilon > 0)
    const double expected = read ? full.free_surface[i] : 0.0;
    const bool ok =
        terms::FreeSurfaceFlag::wanted<D>(sp, full, i) == read && lite.free_surface[i] == expected;
    if (!ok && wrong++ == 0) first = i;
    if (!read)
      ++n.not_read;
    else
      (full.free_surface[i] != 0.0 ? n.read_surface : n.read_interior) += 1;
  }
  EXPECT_EQ(wrong, 0) << "first at particle " << first << ": P = " << full.p[first] << ", full "
                      << full.free_surface[first] << ", lite " << lite.free_surface[first];
  std::printf("[          ] P < 0 on the surface %d, inside %d; P >= 0 %d\n", n.read_surface,
              n.read_interior, n.not_read);
  return n;
}

TEST(FreeSurfaceFlag, SameFlagAsTheFullPassOnTheDamBreak) {
  // 300 steps: the column slumps, its corner thins into tension.
  const FlagCounts n = expect_flag_of_the_full_pass<2>(dam_break(), 300);
  EXPECT_GT(n.read_surface, 0);
  EXPECT_GT(n.read_interior, 0);
  EXPECT_GT(n.not_read, 0);
}

TEST(FreeSurfaceFlag, SameFlagAsTheFullPassInAChannel) {
  // Here every resin particle is in tension (P < 0) after 300 steps: the
  // Lite computes every flag, all 0.
  const FlagCounts n = expect_flag_of_the_full_pass<2>(channel(), 300);
  EXPECT_EQ(n.read_surface, 0);  // no free surface
  EXPECT_GT(n.read_interior, 0);
}

TEST(FreeSurfaceFlag, SameFlagAsTheFullPassIn3D) {
  const FlagCounts n = expect_flag_of_the_full_pass<3>(sloshing_3d(), 100);
  EXPECT_GT(n.read_surface, 0);
  EXPECT_GT(n.read_interior + n.not_read, 0);
}

// The same case with the Lite (the default) and with the full pass (asked for
// by output.fields, which changes nothing else): the same bits after `steps`.
template <int D>
void expect_same_run(const Case& lite_case, const Case& full_case, int steps) {
  EXPECT_EQ(terms::pass_run<terms::FreeSurfacePass>(make_sph_params(lite_case), terms::SphTerms{}),
            PassRun::Lite);
  EXPECT_EQ(terms::pass_run<terms::FreeSurfacePass>(make_sph_params(full_case), terms::SphTerms{}),
            PassRun::Full);
  Simulation<D> a(lite_case, world(), quiet());
  Simulation<D> b(full_case, world(), quiet());
  a.advance(steps);
  b.advance(steps);
  const SphParticles<D>& pa = a.particles();
  const SphParticles<D>& pb = b.particles();
  ASSERT_FALSE(pb.position_divergence.empty());  // the full pass ran
  EXPECT_GT(testing::expect_same_particles<D>(pa, pb), 100);
}

TEST(FreeSurfaceFlag, DamBreakRunIsBitwiseTheFullPasses) {
  expect_same_run<2>(dam_break(), dam_break({"output.fields=[velocity, position_divergence]"}),
                     300);
}

TEST(FreeSurfaceFlag, ChannelRunIsBitwiseTheFullPasses) {
  expect_same_run<2>(channel(), channel({"output.fields=[velocity, position_divergence]"}), 300);
}

// What the solver calls, compute_fluid_passes_and_rates (the flag computed
// inside the pair loop; where a flag is 1 the records are filled again and the
// lists holding one are computed again), against the flag pass followed by
// the pair loop: the same rates and flags, bit for bit. Returns how many
// resin particles were flagged (each makes the loop compute lists again).
template <int D>
int expect_flag_in_the_loop_is_the_pass(const Case& c, int steps) {
  const SphParams sp = make_sph_params(c);
  Simulation<D> sim(c, world(), quiet());
  sim.advance(steps);
  SphParticles<D> pass = sim.particles();
  SphParticles<D> loop = pass;
  NeighborList<D> nl(2.0 * sp.h, 0.0);
  nl.build(pass);
  compute_fluid_passes<D>(sp, nl, pass, [](SphGroup) {});
  compute_fluid_rates<D>(sp, nl, pass);
  // No forward here: the ghosts' flags must be 0 for the two to agree.
  for (std::size_t j = pass.n_owned; j < pass.size(); ++j) EXPECT_EQ(pass.free_surface[j], 0.0);
  std::fill(loop.free_surface.begin(), loop.free_surface.end(), -1.0);
  std::vector<SphGroup> forwarded;
  compute_fluid_passes_and_rates<D>(sp, nl, loop, [&](SphGroup g) { forwarded.push_back(g); });
  EXPECT_EQ(forwarded, std::vector<SphGroup>{SphGroup::FreeSurface});  // from the pair loop
  int flagged = 0, wrong = 0;
  for (std::size_t i = 0; i < pass.n_owned; ++i) {
    bool same = loop.free_surface[i] == pass.free_surface[i] && loop.drho[i] == pass.drho[i];
    for (int d = 0; d < D; ++d) same = same && loop.a[i][d] == pass.a[i][d];
    if (!same && wrong++ == 0)
      ADD_FAILURE() << "first at particle " << i << ": flag " << pass.free_surface[i] << " / "
                    << loop.free_surface[i] << ", drho " << pass.drho[i] << " / " << loop.drho[i];
    flagged += pass.kind[i] == Kind::Fluid && pass.free_surface[i] != 0.0;
  }
  EXPECT_EQ(wrong, 0);
  std::printf("[          ] %d flagged resin particles\n", flagged);
  return flagged;
}

TEST(FreeSurfaceFlag, InsideThePairLoopOnTheDamBreak) {
  EXPECT_GT(expect_flag_in_the_loop_is_the_pass<2>(dam_break(), 300), 0);
}

TEST(FreeSurfaceFlag, InsideThePairLoopInAChannel) {
  EXPECT_EQ(expect_flag_in_the_loop_is_the_pass<2>(channel(), 300), 0);
}

TEST(FreeSurfaceFlag, InsideThePairLoopIn3D) {
  EXPECT_GT(expect_flag_in_the_loop_is_the_pass<3>(sloshing_3d(), 100), 0);
}

// flags8, the flag of eight particles in a row inside the pair loop
// (pair_loop.hpp), is wanted_from ? finish : 0 lane by lane: pressures of
// both signs and +-0, a P / rho^2 whose R_a underflows to 0 (not wanted),
// sums on both sides of the threshold and on it, and a NaN sum (0).
TEST(FreeSurfaceFlag, EightFlagsAreTheFlagsOneAtATime) {
#if defined(__AVX512F__)
  SphParams sp;
  sp.anti_clump = true;
  sp.anti_clump_eps = 0.2;
  const double thr = terms::kFreeSurfaceThreshold<2>;
  const double por2s[] = {-1e-3, 2e-3, 0.0, -0.0, -1e-320, -5.0, 1e-300, -7e-7};
  const double sums[] = {
      1.0,  thr, std::nextafter(thr, 0.0), 0.0, std::numeric_limits<double>::quiet_NaN(),
      -2.0, 3.0, std::nextafter(thr, 10.0)};
  int flagged = 0;
  for (int shift = 0; shift < 8; ++shift) {  // every pressure against every sum
    alignas(64) double por2[8], sum[8], got[8];
    for (int l = 0; l < 8; ++l) {
      por2[l] = por2s[l];
      sum[l] = sums[(l + shift) % 8];
    }
    _mm512_store_pd(
        got, terms::FreeSurfaceFlag::flags8<2>(sp, _mm512_load_pd(por2), _mm512_load_pd(sum)));
    for (int l = 0; l < 8; ++l) {
      const double want = terms::FreeSurfaceFlag::wanted_from(sp, por2[l])
                              ? terms::FreeSurfaceFlag{}.finish<2>(&sum[l])
                              : 0.0;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(got[l]), std::bit_cast<std::uint64_t>(want))
          << "P/rho^2 " << por2[l] << " sum " << sum[l];
      flagged += want != 0.0 ? 1 : 0;
    }
  }
  EXPECT_GT(flagged, 0);
  EXPECT_LT(flagged, 64);
#else
  GTEST_SKIP() << "flags8 is built with AVX-512 only";
#endif
}

}  // namespace
}  // namespace sphdem
