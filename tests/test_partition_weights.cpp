// `sphdem partition` weighs the cells as a run does (docs/parallel.md,
// "Which weights, when"), for a coupled case whose fibers sit in one corner of
// the resin bath, on two ranks:
//  - its parts are those of the run's distributed set-up at the same rank
//    count: resin and walls weighted, the fibers (placed after it) not;
//  - with --fiber-substeps its weights are those of the run's
//    re-partitions (ResinModule::cell_work, the fibers through
//    add_fiber_work), and its parts then differ from the resin-only ones.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "../src/parallel/partition_graph.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/partition_report.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem {
namespace {

// inputs/plate_fibers_3.8.yaml with 80 fibers in the bath's upper-left
// quarter: the fibers' work is not where the resin's is.
Case corner_fibers_case() {
  return load_case(
      std::string(SPHDEM_SOURCE_DIR) + "/inputs/plate_fibers_3.8.yaml",
      {"fibers.region={box: {min: [-0.015, 0.045], max: [0.0, 0.060]}}", "fibers.count=80"});
}

Simulation<2> coupled_run(const Case& c, const Comm& comm) {
  RunOptions opt;
  opt.write_output = false;
  return Simulation<2>(c, comm, opt);
}

TEST(PartitionWeights, PartsAreTheRunsFirstParts) {
  const Comm world(MPI_COMM_WORLD);
  ASSERT_EQ(world.size(), 2);
  const Case c = corner_fibers_case();
  const Simulation<2> sim = coupled_run(c, world);
  ASSERT_NE(sim.dem(), nullptr);
  ASSERT_EQ(sim.dem()->global_count(), 320);  // 80 fibers of 4 particles
  const Decomposition<2>& dec = sim.decomposition();
  const PartitionReport r = partition_report(c, {2});
  const PartitionStats& s = r.rows.at(0);
  ASSERT_TRUE(s.feasible);
  EXPECT_EQ(s.block_edge, dec.block_edge());
  EXPECT_EQ(s.blocks, dec.blocks());
  EXPECT_EQ(s.owners, dec.block_owners());
  // The imbalance the set-up reports, of the resin and walls it weighs.
  EXPECT_DOUBLE_EQ(s.imbalance, sim.last_imbalance());
  EXPECT_EQ(r.fibers, 0);
  EXPECT_NE(format_partition_table(r).find(
                "work: 10 per resin, 3 per wall particle with resin in its top-level cell or the "
                "next, 1 per other wall particle: the weights of a run's first partition (its "
                "fibers not weighted"),
            std::string::npos);
}

TEST(PartitionWeights, FiberSubstepsWeighAsTheRunsRepartitions) {
  const Comm world(MPI_COMM_WORLD);
  const Case c = corner_fibers_case();
  const Simulation<2> sim = coupled_run(c, world);
  const Decomposition<2>& dec = sim.decomposition();
  // A re-partition's weights at the set-up: no resin step yet, so one
  // sub-step per fiber particle (fiber_particle_work); summed over ranks
  // as a re-partition sums them on rank 0.
  ASSERT_EQ(sim.fibers()->substeps(), 0);
  std::vector<std::int64_t> work = sim.resin()->cell_work();
  world.sum(std::span<std::int64_t>(work));
  std::vector<std::int64_t> resin = dec.cell_work(sim.particles(), sim.particles().n_owned);
  world.sum(std::span<std::int64_t>(resin));
  std::int64_t fiber_work = 0;
  for (std::size_t b = 0; b < work.size(); ++b) fiber_work += work[b] - resin[b];
  ASSERT_EQ(fiber_work, 320 * kDemSubstepWork);  // else the run weighs no fibers

  const PartitionReport fibers = partition_report(c, {2, 4}, /*fiber_substeps=*/1);
  const PartitionReport first = partition_report(c, {2, 4});
  EXPECT_EQ(fibers.fibers, 320);
  EXPECT_NE(format_partition_table(fibers).find(
                "5 x 1 sub-steps = 5 per fiber particle (320 placed): the weights of a coupled "
                "run's re-partitions"),
            std::string::npos);
  for (std::size_t k = 0; k < 2; ++k) {
    const PartitionStats& s = fibers.rows[k];
    ASSERT_TRUE(s.feasible);
    ASSERT_EQ(s.block_edge, 1);  // the run's blocks are cells too: the same graph
    ASSERT_EQ(dec.block_edge(), 1);
    // The serial partition a re-partition computes from these weights
    // (without the relabelling to the previous map, as a first one).
    const std::vector<int> expected =
        detail::compute_owners<2>(dec.block_grid(), work, {}, false, s.ranks);
    EXPECT_EQ(s.owners, expected) << s.ranks << " ranks";
    EXPECT_DOUBLE_EQ(s.imbalance, detail::owner_imbalance(work, expected, s.ranks))
        << s.ranks << " ranks";
    // The fibers in one corner move the parts.
    EXPECT_NE(s.owners, first.rows[k].owners) << s.ranks << " ranks";
  }
}

// A wall particle's weight depends on the resin near it on every rank: rank
// 0 holds resin in block (0, 0), rank 1 walls in the block next to it
// (kWallWork each) and three blocks away (kIdleWallWork each).
TEST(PartitionWeights, WallsNextToAnotherRanksResinWeighAsNearResin) {
  const Comm world(MPI_COMM_WORLD);
  ASSERT_EQ(world.size(), 2);
  const Decomposition<2> dec(world, Box<2>{Vec<2>(0, 0), Vec<2>(6, 2)}, {false, false, false}, 1.0);
  ASSERT_EQ(dec.block_edge(), 1);
  ASSERT_EQ(dec.blocks(), 12);
  SphParticles<2> ps;
  const auto add = [&ps](Kind kind, double x, double y) {
    ps.push_owned(static_cast<std::int64_t>(ps.n_owned), kind, -1, 1.0, Vec<2>(x, y), Vec<2>(0, 0),
                  1000);
  };
  if (world.root()) {
    add(Kind::Fluid, 0.5, 0.5);
    add(Kind::Fluid, 0.6, 0.4);
  } else {
    for (int k = 0; k < 3; ++k) add(Kind::Wall, 1.5, 0.2 + 0.2 * k);  // next to the resin
    for (int k = 0; k < 2; ++k) add(Kind::Wall, 4.5, 0.5);            // three blocks away
  }
  const std::vector<std::int64_t> work = dec.cell_work(ps, ps.n_owned);
  const auto block = [&](double x, double y) {
    return static_cast<std::size_t>(dec.block_of(Vec<2>(x, y)));
  };
  std::vector<std::int64_t> expected(12, 0);
  if (world.root()) {
    expected[block(0.5, 0.5)] = 2 * kFluidWork;
  } else {
    expected[block(1.5, 0.5)] = 3 * kWallWork;
    expected[block(4.5, 0.5)] = 2 * kIdleWallWork;
  }
  EXPECT_EQ(work, expected) << "rank " << world.rank();
  // The imbalance check weighs the same: 20 against 11.
  EXPECT_DOUBLE_EQ(dec.imbalance(ps), 20.0 * 2 / 31.0 - 1.0);
}

TEST(PartitionWeights, FiberSubstepsNeedFibers) {
  const Case plate = load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/plate.yaml");
  try {
    partition_report(plate, {2}, 3);
    FAIL() << "fiber sub-steps accepted for a case without fibers";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--fiber-substeps"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sphdem
