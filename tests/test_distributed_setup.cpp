// The distributed set-up (issue 14 part 1, docs/parallel.md "Distributed
// set-up"): each rank fills only the particles of its own top-level cells.
// Compared with the one-rank set-up built in the same process: every
// rank's particles are exactly its share (its cells' particles, no more, no
// fewer, none allocated beyond them), every particle equals the one-rank
// particle of its id in every field bit for bit, and the counts per rank
// sum to the total. Runs at 1 rank (the same code path against the serial
// filling) and at 3.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "../src/solver/distributed_fill.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

// Every field of particle i as raw bytes, with its name (no field is a
// vector<bool>), so that equality is bitwise.
template <int D>
std::vector<std::pair<std::string, std::string>> particle_bytes(const SphParticles<D>& ps,
                                                                std::size_t i) {
  std::vector<std::pair<std::string, std::string>> out;
  ps.for_each_field([&](const char* name, const auto& field, FieldPolicy) {
    const auto& value = field[i];
    out.emplace_back(name, std::string(reinterpret_cast<const char*>(&value), sizeof(value)));
  });
  return out;
}

template <int D>
void expect_share_of_one_rank_set(const Case& c) {
  const Comm comm;
  SphParticles<D> all;
  const InitialCounts serial = build_initial_particles<D>(c, all);
  const double cutoff = 2.0 * c.h();
  Decomposition<D> dec(
      comm, simulation_domain<D>(c), c.periodic, cutoff,
      max_blocks(comm.size(), c.parallel.min_top_cells, c.parallel.top_cells_per_rank));
  SphParticles<D> mine;
  const InitialCounts counts = fill_distributed<D>(c, dec, mine);
  EXPECT_EQ(counts.fluid, serial.fluid);
  EXPECT_EQ(counts.wall, serial.wall);
  ASSERT_EQ(all.n_owned, serial.fluid + serial.wall);

  // This rank's share: the one-rank particles in its cells.
  std::size_t share = 0;
  for (std::size_t i = 0; i < all.n_owned; ++i) share += dec.owner(all.x[i]) == comm.rank();
  EXPECT_EQ(mine.n_owned, share);
  EXPECT_EQ(mine.size(), mine.n_owned);
  EXPECT_LE(mine.x.capacity(), share) << "allocated more than its share";
  EXPECT_EQ(comm.sum(static_cast<std::int64_t>(mine.n_owned)),
            static_cast<std::int64_t>(all.n_owned));
  if (comm.size() > 1) {
    EXPECT_LT(share, all.n_owned) << "one rank holds everything";
  }

  // Ids: as on one rank (there gid i is slot i), each once, resin first.
  std::size_t mismatched = 0, wrong_rank = 0;
  std::int64_t last_fluid = -1, last_wall = -1;
  for (std::size_t i = 0; i < mine.n_owned; ++i) {
    const std::int64_t id = mine.gid[i];
    ASSERT_GE(id, 0);
    ASSERT_LT(static_cast<std::size_t>(id), all.n_owned);
    std::int64_t& last = mine.kind[i] == Kind::Fluid ? last_fluid : last_wall;
    EXPECT_GT(id, last) << "ids not ascending within a kind";
    last = id;
    if (mine.kind[i] == Kind::Wall) {
      EXPECT_GE(id, static_cast<std::int64_t>(serial.fluid));
    }
    if (i > 0 && mine.kind[i] == Kind::Fluid) {
      EXPECT_EQ(mine.kind[i - 1], Kind::Fluid);
    }
    wrong_rank += dec.owner(mine.x[i]) != comm.rank();
    const auto j = static_cast<std::size_t>(id);
    const auto got = particle_bytes(mine, i), want = particle_bytes(all, j);
    for (std::size_t f = 0; f < got.size(); ++f) {
      if (got[f].second == want[f].second) continue;
      if (++mismatched <= 5)
        ADD_FAILURE() << "gid " << id << ": field " << got[f].first << " differs";
    }
  }
  EXPECT_EQ(wrong_rank, 0u);
  EXPECT_EQ(mismatched, 0u);
}

// 2D: a mold of boxes and a polygon (the nozzle), the piston's wall index,
// walls' wall_to_surface, an initial velocity.
TEST(DistributedSetup, PlateSharesMatchOneRank) {
  expect_share_of_one_rank_set<2>(testing::load_input("plate.yaml", {"numerics.spacing=1e-3"}));
}

// Initial fields from expressions on a doubly periodic box.
TEST(DistributedSetup, TaylorGreenSharesMatchOneRank) {
  expect_share_of_one_rank_set<2>(testing::load_input("validation/taylor_green.yaml"));
}

// 3D with gravity: the hydrostatic start measures depth from the highest
// resin particle of any rank; coarse top-level cells (blocks of several cells).
TEST(DistributedSetup, HydrostaticColumn3DOnCoarseTopCellsMatchesOneRank) {
  expect_share_of_one_rank_set<3>(
      testing::load_input("validation/hydrostatic_3d.yaml",
                          {"parallel.min_top_cells=1", "parallel.top_cells_per_rank=4"}));
}

// Fibers (issue 14 part 1): each rank places only the fibers whose centre
// lies in its top-level cells; after the set-up each rank holds the fiber
// particles in its cells, each equal to the one-rank placement's particle
// of its id in every restartable field (bonds included), bit for bit, and
// together they are all of them.
TEST(DistributedSetup, FibersMatchOneRankPlacement) {
  const Case c = testing::load_input("validation/coupled_box.yaml", {"fibers.count=60"});
  std::vector<int> wall_owner;
  FiberPlacement serial;
  const DemSystem<2> all = case_fibers<2>(c, wall_owner, serial);
  const Comm comm;
  RunOptions opt;
  opt.write_output = false;
  const Simulation<2> sim(c, comm, opt);
  const DemDomain<2>& dem = *sim.dem();
  const DemParticles<2>& mine = dem.particles();
  EXPECT_EQ(sim.placement().fibers, serial.fibers);
  EXPECT_EQ(sim.placement().tries, serial.tries);
  EXPECT_EQ(comm.sum(static_cast<std::int64_t>(mine.n_owned)),
            static_cast<std::int64_t>(all.particles.size()));
  if (comm.size() > 1) {
    EXPECT_LT(mine.n_owned, all.particles.size()) << "one rank holds all";
  }
  const DemParticles<2>& one = all.particles;
  std::size_t mismatched = 0;
  const auto differs = [&](std::int64_t id, const char* what) {
    if (++mismatched <= 5) ADD_FAILURE() << "gid " << id << ": " << what << " differs";
  };
  for (std::size_t i = 0; i < mine.n_owned; ++i) {
    const auto j = static_cast<std::size_t>(mine.gid[i]);
    ASSERT_LT(j, one.size());
    ASSERT_EQ(one.gid[j], mine.gid[i]);
    if (sim.decomposition().owner(mine.x[i]) != comm.rank()) differs(mine.gid[i], "owner");
    if (!(one.x[j] == mine.x[i])) differs(mine.gid[i], "x");
    if (!(one.v[j] == mine.v[i])) differs(mine.gid[i], "v");
    if (one.fiber[j] != mine.fiber[i]) differs(mine.gid[i], "fiber");
    if (one.radius[j] != mine.radius[i] || one.mass[j] != mine.mass[i])
      differs(mine.gid[i], "mass");
    for (std::size_t b = 0; b < one.bonds[j].size(); ++b) {
      const DemBond<2>&p = one.bonds[j][b], &q = mine.bonds[i][b];
      if (p.partner != q.partner || p.id != q.id || p.broken != q.broken || p.rbar != q.rbar ||
          p.length0 != q.length0)
        differs(mine.gid[i], "bond");
    }
  }
  EXPECT_EQ(mismatched, 0u);
}

// A fill region without a node is an input error on every rank (none waits
// in a collective for a rank that threw).
TEST(DistributedSetup, EmptyFillRegionIsAnErrorOnEveryRank) {
  const Case c =
      testing::load_input("plate.yaml", {"numerics.spacing=1e-3", "fill[0].box.min=[1e-4, 0.0401]",
                                         "fill[0].box.max=[2e-4, 0.0402]"});
  const Comm comm;
  Decomposition<2> dec(comm, simulation_domain<2>(c), c.periodic, 2.0 * c.h());
  SphParticles<2> ps;
  EXPECT_THROW(fill_distributed<2>(c, dec, ps), InputError);
}

}  // namespace
}  // namespace sphdem
