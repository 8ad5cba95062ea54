// Rebuilds keep the particle fields' memory (issue 19, docs/performance.md
// "Rebuilds"): the reordering of owned particles works in place, the ghost
// append grows the fields by a small margin instead of doubling, so a run's
// rebuilds after the first allocate nothing.
#include <gtest/gtest.h>

#include <cstddef>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem {
namespace {

SphParticles<2> numbered(std::size_t n, std::size_t ghosts) {
  SphParticles<2> ps;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = static_cast<double>(i);
    ps.push_owned(static_cast<std::int64_t>(i), i % 3 == 0 ? Kind::Wall : Kind::Fluid,
                  static_cast<std::int32_t>(i), 1.0 + d, Vec<2>(d, -d), Vec<2>(2 * d, 0.5),
                  900 + d);
  }
  ps.resize(n + ghosts);
  for (std::size_t g = n; g < n + ghosts; ++g) ps.gid[g] = static_cast<std::int64_t>(100 + g);
  return ps;
}

void expect_particle(const SphParticles<2>& ps, std::size_t slot, std::size_t old) {
  const double d = static_cast<double>(old);
  EXPECT_EQ(ps.gid[slot], static_cast<std::int64_t>(old));
  EXPECT_EQ(ps.kind[slot], old % 3 == 0 ? Kind::Wall : Kind::Fluid);
  EXPECT_EQ(ps.wall[slot], static_cast<std::int32_t>(old));
  EXPECT_EQ(ps.mass[slot], 1.0 + d);
  EXPECT_EQ(ps.x[slot], Vec<2>(d, -d));
  EXPECT_EQ(ps.v[slot], Vec<2>(2 * d, 0.5));
  EXPECT_EQ(ps.rho[slot], 900 + d);
  EXPECT_EQ(ps.rho_half[slot], 900 + d);
}

TEST(PermuteOwned, PermutationInPlaceKeepsGhostsAndStorage) {
  SphParticles<2> ps = numbered(7, 2);
  const double* x = ps.x.data()->data();
  const std::int64_t* gid = ps.gid.data();
  const std::vector<std::size_t> order{3, 0, 6, 5, 1, 2, 4};  // cycles (0 3 5 2 6 4 1)
  ps.permute_owned(order);
  for (std::size_t k = 0; k < order.size(); ++k) expect_particle(ps, k, order[k]);
  EXPECT_EQ(ps.gid[7], 107);  // ghosts untouched
  EXPECT_EQ(ps.gid[8], 108);
  EXPECT_EQ(ps.x.data()->data(), x);  // no fresh vectors
  EXPECT_EQ(ps.gid.data(), gid);
}

// The sort by cell's way: gathered into spare room and copied back, the
// same particles in the same slots as following the cycles; with room for
// fewer than all the owned particles' values of a field (a spare one byte
// short, or none), the cycles are followed; either way the fields keep
// their storage and the ghosts.
TEST(PermuteOwned, GatheredIntoSpareRoomAsByCycles) {
  const std::vector<std::int32_t> order{3, 0, 6, 5, 1, 2, 4};
  const std::size_t m = order.size();
  const std::size_t room = widest_field(numbered(m, 2)) * m + 64;
  for (const std::size_t spare_bytes : {room, room - 64 - 1, std::size_t{0}}) {
    SphParticles<2> ps = numbered(m, 2);
    const double* x = ps.x.data()->data();
    // Unaligned on purpose: the permutation aligns within the room it gets.
    std::vector<std::byte> spare(spare_bytes + 1, std::byte{0x5a});
    permute_owned_fields(ps, std::span<const std::int32_t>(order),
                         std::span<std::byte>(spare.data() + 1, spare_bytes));
    for (std::size_t k = 0; k < m; ++k) expect_particle(ps, k, static_cast<std::size_t>(order[k]));
    EXPECT_EQ(ps.gid[m], 107);
    EXPECT_EQ(ps.gid[m + 1], 108);
    EXPECT_EQ(ps.x.data()->data(), x);
  }
  EXPECT_EQ(widest_field(numbered(1, 0)), sizeof(Vec<2>));
}

TEST(PermuteOwned, SeveralCyclesAndFixedPoints) {
  SphParticles<2> ps = numbered(6, 0);
  const std::vector<std::size_t> order{1, 0, 2, 4, 5, 3};
  ps.permute_owned(order);
  for (std::size_t k = 0; k < order.size(); ++k) expect_particle(ps, k, order[k]);
}

TEST(PermuteOwned, IncreasingSubsetCompacts) {
  SphParticles<2> ps = numbered(8, 0);
  const std::vector<std::size_t> stay{0, 2, 3, 7};  // a migration's stayers
  ps.permute_owned(stay);
  for (std::size_t k = 0; k < stay.size(); ++k) expect_particle(ps, k, stay[k]);
  for (std::size_t k = stay.size(); k < 8; ++k) expect_particle(ps, k, k);  // tail kept
}

TEST(PermuteOwned, NotAPermutationIsRefused) {
  SphParticles<2> ps = numbered(4, 0);
  EXPECT_THROW(ps.permute_owned({1, 1, 0}), std::logic_error);
  EXPECT_THROW(ps.permute_owned({2, 0, 5}), std::logic_error);
}

TEST(FieldGrowth, ResizeGrowsBySmallMargin) {
  SphParticles<2> ps = numbered(1000, 0);
  EXPECT_LE(ps.x.capacity(), 1000u + 1000 / 8 + 64);  // not a doubling
  ps.resize(1100);
  EXPECT_GE(ps.x.capacity(), 1100u);
  EXPECT_LE(ps.x.capacity(), 1100u + 1100 / 8 + 64);
  const double* x = ps.x.data()->data();
  ps.resize(1000);
  ps.resize(1100);  // ghosts appended again: no reallocation
  EXPECT_EQ(ps.x.data()->data(), x);
}

// The channel of the LAMMPS peer deck, small, with a skin small enough to
// rebuild every few steps.
TEST(RebuildMemory, RebuildsAfterTheFirstKeepTheFields) {
  const std::string yaml = R"(name: channel
dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 50}
numerics: {spacing: 3.0e-4, h_over_spacing: 1.2, fixed_dt: 1.4e-6, end_time: 1.0, anti_clump: true, neighbor_skin: 0.02}
mold: {wall_layers: 3, shapes: [{box: {min: [0, 0], max: [0.006, 0.003]}}]}
fill: [{box: {min: [0, 0], max: [0.006, 0.003]}}]
body_force: [2000, 0]
periodic: [x]
domain: {min: [0, -0.0012], max: [0.006, 0.0042]}
output: {progress_every: 1000000}
)";
  const Comm comm(MPI_COMM_SELF);
  const Case c = load_case_from_string(yaml, "channel", {});
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  sim.advance(20);
  const SphParticles<2>& ps = sim.particles();
  const double* x = ps.x.data()->data();
  const double* rho = ps.rho.data();
  const std::int64_t* gid = ps.gid.data();
  const std::int64_t builds0 = sim.resin()->neighbor_builds();
  sim.advance(200);
  EXPECT_GT(sim.resin()->neighbor_builds(), builds0 + 3);  // rebuilds happened
  EXPECT_EQ(ps.x.data()->data(), x);
  EXPECT_EQ(ps.rho.data(), rho);
  EXPECT_EQ(ps.gid.data(), gid);
}

}  // namespace
}  // namespace sphdem
