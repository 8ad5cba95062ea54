// The pair loop's compact record (src/sph/compact_record.hpp,
// docs/performance.md "A record of eight doubles"): where a 2D loop's
// record holds the mass, the continuity's velocity and the delta-SPH
// weight, and every mass is the same, every wall at rest and every resin
// particle's vwall its velocity, the loop gathers records without those
// three and makes their lane rows from the others. The runs must be the
// full record's bit for bit, and the conditions must be checked.
// Rank independence: the RankIndependence.* tests of test_parallel run the
// channel and the dam break with it (the default, CompactUse::Auto).
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "../src/sph/compact_record.hpp"
#include "../src/sph/terms/anti_clump.hpp"
#include "same_particles.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/sph/sph.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using terms::CompactUse;
using testing::quiet;
using testing::world;

// Whether this build's pair loop can use the compact record: the eight-lane
// form (AVX-512).
#if defined(__AVX512F__)
constexpr bool kCompactBuild = true;
#else
constexpr bool kCompactBuild = false;
#endif

// Runs the case `steps` steps with the loop's records chosen by `use`;
// returns the particles and how many loop runs used the compact record.
template <int D>
SphParticles<D> run(const Case& c, int steps, CompactUse use, std::size_t& compact_runs) {
  const CompactUse before = terms::compact_record_default();
  terms::compact_record_default() = use;
  const std::size_t runs0 = terms::compact_record_runs();
  Simulation<D> sim(c, world(), quiet());
  sim.advance(steps);
  compact_runs = terms::compact_record_runs() - runs0;
  terms::compact_record_default() = before;
  return sim.particles();
}

// The same run with the full record and with the compact one where it
// applies: the same bits. Returns how many loop runs used the compact record.
template <int D>
std::size_t expect_same_run(const Case& c, int steps) {
  std::size_t full_runs = 0, compact_runs = 0;
  const SphParticles<D> full = run<D>(c, steps, CompactUse::Off, full_runs);
  const SphParticles<D> compact = run<D>(c, steps, CompactUse::EveryRun, compact_runs);
  EXPECT_EQ(full_runs, 0u);
  EXPECT_GT(testing::expect_same_particles<D>(full, compact), 100);
  return compact_runs;
}

TEST(CompactRecord, ChannelRunIsBitwiseTheFullRecord) {
  const std::size_t runs =
      expect_same_run<2>(testing::small_channel({"numerics.delta_sph=0.1"}), 300);
  // The set-up's loop run and one per step (the channel has no free
  // surface, so no second run).
  if (kCompactBuild) {
    EXPECT_EQ(runs, 301u);
  }
}

// The dam break: a free surface in tension, so the loop runs a second time
// at some steps on the records the free-surface flag changed (a redo,
// pair_loop_with_flag); the redo refills them in the compact form.
TEST(CompactRecord, DamBreakRunIsBitwiseTheFullRecord) {
  // Without shifting and without the flag among the output's fields, only
  // the anti-clump term reads the flag, so the loop computes it on the side
  // (as test_free_surface_flag's dam break).
  const Case c = testing::load_input(
      "validation/dam_break_front.yaml",
      {"numerics.particle_shifting=false", "output.fields=[velocity, density, pressure]"});
  const std::size_t runs = expect_same_run<2>(c, 300);
  std::printf("[          ] %zu loop runs on the compact record\n", runs);
  // More than the set-up's and one per step: some redos ran on it.
  if (kCompactBuild) {
    EXPECT_GT(runs, 301u);
  }
}

// A sliding lid (Couette flow) gives its wall particles a velocity, so the
// conditions do not hold: the loop keeps the full record, with the same bits.
TEST(CompactRecord, NotUsedWhereAWallMoves) {
  const Case c = testing::load_input("validation/couette.yaml", {"numerics.delta_sph=0.1"});
  std::size_t runs = 0;
  const SphParticles<2> ps = run<2>(c, 1, CompactUse::EveryRun, runs);
  bool moving = false;
  for (std::size_t i = 0; i < ps.size(); ++i)
    moving = moving || (ps.kind[i] != Kind::Fluid && (ps.v[i][0] != 0.0 || ps.v[i][1] != 0.0));
  ASSERT_TRUE(moving) << "the lid's particles carry its velocity";
  EXPECT_EQ(expect_same_run<2>(c, 50), 0u);
}

// The conditions one particle at a time (CompactRecord::keeps), each broken
// by hand: another mass (by one ulp), a wall at -0 or moving, a resin
// particle whose vwall is not its velocity, a density of zero.
TEST(CompactRecord, ConditionsAreCheckedBitForBit) {
  using Channel = terms::CompactRecord<
      2, terms::Fields<terms::field::Pos, terms::field::Mass, terms::field::Vel,
                       terms::field::VelWall, terms::field::Rho, terms::field::DeltaWeight,
                       terms::field::PoR2, terms::field::AntiClumpR, terms::field::Vol>>;
  static_assert(Channel::value, "the channel's record becomes compact");
  static_assert(Channel::Layout::kSize == 8, "eight doubles: two quads");
  static_assert(
      !terms::CompactRecord<3,
                            terms::Fields<terms::field::Pos, terms::field::Mass, terms::field::Vel,
                                          terms::field::VelWall, terms::field::Rho,
                                          terms::field::DeltaWeight, terms::field::Vol>>::value,
      "3D keeps the full record");
  SphParticles<2> ps;
  const double m = 0.081;
  ps.push_owned(1, Kind::Fluid, -1, m, Vec<2>(0.0, 0.0), Vec<2>(0.1, -0.2), 900.0);
  ps.push_owned(2, Kind::Wall, -1, m, Vec<2>(0.0, -1e-3), Vec<2>(0.0, 0.0), 901.0);
  ps.vwall[1] = Vec<2>(0.3, 0.4);  // the wall's extrapolated velocity
  EXPECT_TRUE(Channel::keeps(ps, 0, m));
  EXPECT_TRUE(Channel::keeps(ps, 1, m));  // a wall's vwall is its own
  EXPECT_FALSE(Channel::keeps(ps, 0, std::nextafter(m, 1.0)));
  ps.v[1] = Vec<2>(-0.0, 0.0);
  EXPECT_FALSE(Channel::keeps(ps, 1, m)) << "-0 is not +0: v_i - (-0) may differ from v_i";
  ps.v[1] = Vec<2>(0.0, 1e-300);
  EXPECT_FALSE(Channel::keeps(ps, 1, m));
  ps.vwall[0] = Vec<2>(0.1, std::nextafter(-0.2, 0.0));
  EXPECT_FALSE(Channel::keeps(ps, 0, m));
  ps.vwall[0] = ps.v[0];
  ps.rho[0] = 0.0;
  EXPECT_FALSE(Channel::keeps(ps, 0, m)) << "the sign of rho marks the walls";
}

}  // namespace
}  // namespace sphdem
