// `sphdem partition` (docs/scaling.md): the report partitions the same cell
// grid a run builds (with implicit fiber bonds too), balances the plate
// case, and says so when there are more ranks than non-empty cells instead
// of failing.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../src/app/partition_command.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/partition_report.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem {
namespace {

const std::string kPlate = std::string(SPHDEM_SOURCE_DIR) + "/inputs/plate.yaml";

// The weights by hand on a 5 x 3 grid of blocks: resin in block (1, 1);
// walls in it, next to it (across a corner too), two blocks away, and in a
// block with no resin near at all.
TEST(Partition, WallsWeighByTheResinNearThem) {
  const CellGrid<2> blocks(Box<2>{Vec<2>(0, 0), Vec<2>(5, 3)}, {false, false, false}, 1.0);
  ASSERT_EQ(blocks.cells(), 15);
  const auto at = [&](long i, long j) { return static_cast<std::size_t>(blocks.index({i, j, 0})); };
  std::vector<std::int64_t> fluid(15, 0), walls(15, 0);
  std::vector<std::uint8_t> holds_resin(15, 0);
  fluid[at(1, 1)] = 4;
  holds_resin[at(1, 1)] = 1;
  walls[at(1, 1)] = 1;  // with the resin: 3
  walls[at(2, 2)] = 2;  // across a corner: 3 each
  walls[at(0, 0)] = 5;  // across the other corner
  walls[at(3, 1)] = 7;  // two blocks away: 1 each
  walls[at(4, 2)] = 1;
  const std::vector<std::int64_t> work = weigh_blocks<2>(blocks, fluid, walls, holds_resin);
  std::vector<std::int64_t> expected(15, 0);
  expected[at(1, 1)] = 4 * 10 + 1 * 3;
  expected[at(2, 2)] = 2 * 3;
  expected[at(0, 0)] = 5 * 3;
  expected[at(3, 1)] = 7 * 1;
  expected[at(4, 2)] = 1;
  EXPECT_EQ(work, expected);
  EXPECT_EQ(kFluidWork, 10);
  EXPECT_EQ(kWallWork, 3);
  EXPECT_EQ(kIdleWallWork, 1);
  // Whether a block holds resin is the caller's flag (a run's: over all
  // ranks), not this rank's count.
  holds_resin[at(4, 1)] = 1;
  EXPECT_EQ(weigh_blocks<2>(blocks, fluid, walls, holds_resin)[at(3, 1)], 7 * 3);
  EXPECT_THROW(weigh_blocks<2>(blocks, fluid, std::vector<std::int64_t>(3, 0), holds_resin),
               std::invalid_argument);
}

TEST(Partition, PlateIsBalancedAtTwoAndFourRanks) {
  const PartitionReport r = partition_report(load_case(kPlate), {1, 2, 4});
  ASSERT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(r.fluid, 10000);
  EXPECT_DOUBLE_EQ(r.rows[0].imbalance, 0.0);
  EXPECT_DOUBLE_EQ(r.rows[0].ghost_fraction, 0.0);  // the plate is not periodic
  for (std::size_t k = 1; k < 3; ++k) {
    const PartitionStats& s = r.rows[k];
    EXPECT_TRUE(s.feasible);
    EXPECT_LT(s.imbalance, 0.2) << s.ranks << " ranks";
    EXPECT_GT(s.ghost_fraction, 0.0);
    EXPECT_GE(s.ghost_fraction_max, s.ghost_fraction);
    EXPECT_GE(s.halo_bytes_max, s.halo_bytes_mean);
    EXPECT_GE(s.neighbors_max, 1);
    EXPECT_LT(s.neighbors_max, s.ranks);
    EXPECT_EQ(s.empty_ranks, 0);
  }
}

// The report must describe the grid a run uses, not a look-alike.
TEST(Partition, GridIsTheRunsGrid) {
  const Case c = load_case(kPlate);
  const Comm self(MPI_COMM_SELF);
  RunOptions opt;
  opt.write_output = false;
  const Simulation<2> sim(c, self, opt);
  const PartitionReport r = partition_report(c, {2});
  EXPECT_EQ(r.dims, sim.decomposition().grid().dims());
  EXPECT_EQ(r.fluid, sim.global_fluid_count());
  EXPECT_EQ(r.wall, sim.global_wall_count());
  EXPECT_DOUBLE_EQ(r.min_cell, r.cutoff);  // no fibers: the cut-off alone
  EXPECT_NE(format_partition_table(r).find("(cells >= cut-off "), std::string::npos);
}

// With implicit bonds a run's cells are at least a fiber's chain reach
// (resin_min_cell): here 1.1 x 7 x 0.25 mm = 1.93 mm against the cut-off's
// 0.83 mm. The report must build, partition and print that grid, not the
// cut-off's.
TEST(Partition, GridIsTheRunsGridWithImplicitBonds) {
  const Case c = load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/plate_fibers_glass.yaml",
                           {"fibers.particles_per_fiber=8", "fibers.count=20"});
  ASSERT_TRUE(c.fibers && c.fibers->implicit_bonds);
  const Comm self(MPI_COMM_SELF);
  RunOptions opt;
  opt.write_output = false;
  const Simulation<2> sim(c, self, opt);
  const PartitionReport r = partition_report(c, {2, 4});
  ASSERT_GT(implicit_chain_reach(c), 2 * r.cutoff);  // else the grids would not differ
  const auto dims = sim.decomposition().grid().dims();
  EXPECT_EQ(r.dims, dims);
  EXPECT_DOUBLE_EQ(r.min_cell, implicit_chain_reach(c));
  EXPECT_EQ(r.fluid, sim.global_fluid_count());
  EXPECT_EQ(r.wall, sim.global_wall_count());
  const std::string table = format_partition_table(r);
  const std::string grid = "cell grid " + std::to_string(dims[0]) + " x " +
                           std::to_string(dims[1]) + " (cells >= 0.001925 m, a fiber's chain reach";
  EXPECT_NE(table.find(grid), std::string::npos) << table;
  for (const PartitionStats& s : r.rows) EXPECT_TRUE(s.feasible) << s.ranks << " ranks";
}

TEST(Partition, MoreRanksThanCellsIsReportedNotFatal) {
  const PartitionReport r = partition_report(load_case(kPlate), {2, 100000});
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_TRUE(r.rows[0].feasible);
  EXPECT_FALSE(r.rows[1].feasible);
  EXPECT_NE(format_partition_table(r).find("more ranks than the"), std::string::npos);
  std::ostringstream csv;
  write_partition_csv(csv, r);
  EXPECT_NE(csv.str().find("100000,12506,"), std::string::npos);  // 10000 resin + 2506 wall
  EXPECT_NE(csv.str().find("more ranks than non-empty top-level cells"), std::string::npos);
}

TEST(Partition, CsvHasOneRowPerRankCount) {
  std::ostringstream csv;
  write_partition_csv(csv, partition_report(load_case(kPlate), {1, 2, 4}));
  std::istringstream in(csv.str());
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header,
            "ranks,particles,nonempty_cells,imbalance,ghost_fraction,ghost_fraction_max,"
            "halo_bytes_max,halo_bytes_mean,neighbors_max,neighbors_mean,empty_ranks,"
            "partition_seconds,blocks,nonempty_blocks,block_edge,map_bytes,root_bytes,note");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 3);
}

// The report partitions what a run at each rank count would: its top-level
// cells (docs/parallel.md), here forced coarse with parallel.min_top_cells.
TEST(Partition, ReportsTheRunsTopLevelCells) {
  const Case c = load_case(kPlate, {"parallel.min_top_cells=1"});
  const PartitionReport r = partition_report(c, {2, 4});
  const long cells = r.dims[0] * r.dims[1] * r.dims[2];
  for (const PartitionStats& s : r.rows) {
    EXPECT_LE(s.blocks, max_blocks(s.ranks, 1)) << s.ranks << " ranks";
    EXPECT_GT(s.block_edge, 1);
    EXPECT_LT(s.blocks, cells);
    EXPECT_LE(s.nonempty_blocks, s.blocks);
    EXPECT_TRUE(s.feasible);
    EXPECT_DOUBLE_EQ(s.map_bytes, 12.0 * static_cast<double>(s.blocks));
    EXPECT_GT(s.root_bytes, s.map_bytes);
    EXPECT_EQ(s.empty_ranks, 0);
  }
  // The default keeps one cell per block for a case this small.
  const PartitionReport fine = partition_report(load_case(kPlate), {4});
  EXPECT_EQ(fine.rows[0].block_edge, 1);
  EXPECT_EQ(fine.rows[0].blocks, cells);
  EXPECT_EQ(fine.rows[0].nonempty_blocks, fine.nonempty_cells);
}

// A grid past 2^40 cells (kMaxGridCells) is bad input naming the case's
// key, the domain or else the mold the domain defaults to, as in a run;
// refused before the particles (the mold here would take about 10^8 wall
// particles).
TEST(Partition, GridPast2To40CellsNamesTheKey) {
  const std::string head = R"(dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 60}
numerics: {spacing: 3.0e-4, end_time: 0.1}
fill: [box: {min: [0, 0], max: [0.03, 0.02]}]
)";
  const std::string small_mold = "mold: {shapes: [box: {min: [0, 0], max: [0.03, 0.03]}]}\n";
  const std::string huge_mold = "mold: {shapes: [box: {min: [0, 0], max: [1.0e4, 1.0e4]}]}\n";
  const std::string huge_domain = "domain: {min: [-5.0e3, -5.0e3], max: [5.0e3, 5.0e3]}\n";
  const struct {
    std::string text, key;
    int line;
  } cases[] = {{head + small_mold + huge_domain, "domain", 6}, {head + huge_mold, "mold", 5}};
  for (const auto& k : cases) {
    const Case c = load_case_from_string(k.text, "huge.yaml");
    try {
      partition_report(c, {2});
      ADD_FAILURE() << k.key << ": accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "huge.yaml") << e.what();
      EXPECT_EQ(e.line(), k.line) << e.what();
      EXPECT_EQ(e.key(), k.key) << e.what();
      EXPECT_NE(std::string(e.what()).find("more than 2^40 cells"), std::string::npos) << e.what();
    }
  }
}

TEST(Partition, RankListParsing) {
  EXPECT_EQ(app::parse_rank_list("64,256,1024,4096"), (std::vector<int>{64, 256, 1024, 4096}));
  EXPECT_EQ(app::parse_rank_list("1"), (std::vector<int>{1}));
  for (const char* bad : {"0", "-4", "x", "2,", "2,,4", "", "1.5", "99999999999"}) {
    EXPECT_THROW(app::parse_rank_list(bad), InputError) << bad;
  }
}

}  // namespace
}  // namespace sphdem
