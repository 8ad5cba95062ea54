// The decomposition's top-level cells (issue 14 part 2, docs/parallel.md,
// "Top-level cells"): blocks of b^D neighbor-search cells, at most
// max(64 x ranks, parallel.min_top_cells) of them. Every fine cell lies in
// exactly one block, every rank holds the same block -> rank map, the map
// is balanced, and a run on coarse blocks gives bitwise the particles of a
// one-rank run.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "../src/parallel/ghost_targets.hpp"
#include "../src/parallel/partition_graph.hpp"
#include "sphdem/parallel/decomposition.hpp"

namespace sphdem {
namespace {

// The block count never exceeds the limit, and b - 1 would exceed it.
TEST(TopCells, BlockEdgeIsTheSmallestThatFits) {
  EXPECT_EQ(block_edge({100, 100, 1}, 1L << 20), 1);
  EXPECT_EQ(block_edge({100, 100, 1}, 100), 10);
  EXPECT_EQ(block_edge({100, 100, 1}, 99), 12);  // 11 still leaves 10 x 10
  EXPECT_EQ(block_edge({7, 5, 3}, 1), 7);
  for (long limit : {1L, 5L, 64L, 1000L, 4096L}) {
    const std::array<long, 3> dims{123, 77, 41};
    const long b = block_edge(dims, limit);
    const auto count = [&](long e) {
      long n = 1;
      for (long d : dims) n *= (d + e - 1) / e;
      return n;
    };
    EXPECT_LE(count(b), limit);
    if (b > 1) {
      EXPECT_GT(count(b - 1), limit);
    }
  }
  EXPECT_EQ(max_blocks(4), kMinBlocks);
  EXPECT_EQ(max_blocks(1L << 16, 16), kBlocksPerRank << 16);
}

// Every fine cell in exactly one block, the block of a position the block
// of its cell, every block holding a cell (periodic axes: partial blocks).
template <int D>
void expect_cells_covered(const Box<D>& box, const std::array<bool, 3>& periodic, long limit) {
  const Decomposition<D> dec(Comm(MPI_COMM_SELF), box, periodic, 0.1, limit);
  ASSERT_LE(dec.blocks(), limit);
  EXPECT_GT(dec.block_edge(), 1) << "the test must exercise coarse blocks";
  std::vector<long> cells_in(static_cast<std::size_t>(dec.blocks()), 0);
  const CellGrid<D>& g = dec.grid();
  for (long c = 0; c < g.cells(); ++c) {
    const long b = dec.block_of_cell(c);
    ASSERT_GE(b, 0);
    ASSERT_LT(b, dec.blocks());
    ++cells_in[static_cast<std::size_t>(b)];
    const auto k = g.coords_of(c);
    Vec<D> centre;
    for (int d = 0; d < D; ++d)
      centre[d] = g.lower(d, k[static_cast<std::size_t>(d)]) + 0.5 * g.size(d);
    EXPECT_EQ(dec.block_of(centre), b);
    // A cell's neighbors lie in its block or in an adjacent one.
    std::array<long, 26> nb, bnb;
    const int n = g.neighbors(c, nb);
    const int m = dec.block_grid().neighbors(b, bnb);
    for (int i = 0; i < n; ++i) {
      const long other = dec.block_of_cell(nb[static_cast<std::size_t>(i)]);
      EXPECT_TRUE(other == b || std::find(bnb.begin(), bnb.begin() + m, other) != bnb.begin() + m);
    }
  }
  EXPECT_EQ(std::accumulate(cells_in.begin(), cells_in.end(), 0L), g.cells());
  EXPECT_EQ(std::count(cells_in.begin(), cells_in.end(), 0L), 0) << "an empty block";
  long full = 1;
  for (int d = 0; d < D; ++d) full *= dec.block_edge();
  EXPECT_LE(*std::max_element(cells_in.begin(), cells_in.end()), full);
}

// Dims outside a CellGrid's are refused: main cast the cube root of
// (2^63)^3 to long (out of range) and overflowed `d + b - 1`.
TEST(TopCells, BlockEdgeRefusesDimsBeyondTheGrids) {
  constexpr long kHuge = std::numeric_limits<long>::max();
  EXPECT_THROW(block_edge({kHuge, kHuge, kHuge}, 1), std::invalid_argument);
  EXPECT_THROW(block_edge({0, 5, 1}, 1), std::invalid_argument);
  EXPECT_EQ(block_edge({kMaxGridCells, 1, 1}, kMaxGridCells), 1);
}

// A box of absurd extent for its cells is an error, not an out-of-range
// cast (main: floor(2e303) cast to long, INT64_MIN on x86, so one cell).
TEST(TopCells, CellGridPast2To40CellsIsRefused) {
  const std::array<bool, 3> closed{false, false, false};
  EXPECT_THROW(CellGrid<2>(Box<2>{Vec<2>(-1e300, 0), Vec<2>(1e300, 1)}, closed, 1e-3),
               std::length_error);
  EXPECT_THROW(CellGrid<3>(Box<3>{Vec<3>(0, 0, 0), Vec<3>(1e5, 1e5, 1e5)}, closed, 1e-3),
               std::length_error);
  const CellGrid<3> g(Box<3>{Vec<3>(0, 0, 0), Vec<3>(1, 2, 3)}, closed, 1e-3);
  EXPECT_EQ(g.cells(), 1000L * 2000 * 3000);
  // A position far outside, infinite or NaN: a cell of the grid.
  for (const double far : {1e300, -1e300, std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    const long c = g.cell_of(Vec<3>(far, far, far));
    EXPECT_GE(c, 0);
    EXPECT_LT(c, g.cells());
  }
}

TEST(TopCells, EveryCellInOneBlock2D) {
  expect_cells_covered<2>({Vec<2>(0, 0), Vec<2>(3.3, 2.1)}, {false, false, false}, 40);
  expect_cells_covered<2>({Vec<2>(0, 0), Vec<2>(3.3, 2.1)}, {true, true, false}, 40);
}

TEST(TopCells, EveryCellInOneBlock3D) {
  expect_cells_covered<3>({Vec<3>(0, 0, 0), Vec<3>(1.7, 1.3, 0.9)}, {true, false, true}, 100);
}

// The serial partition of the blocks, as rank 0 computes it: every block
// owned by one of the parts, every part used, METIS's balance within the
// granularity of 64 blocks per part.
TEST(TopCells, BlocksAreBalanced) {
  const Box<3> box{Vec<3>(0, 0, 0), Vec<3>(4, 4, 4)};
  for (int parts : {4, 16, 64}) {
    const Decomposition<3> dec(Comm(MPI_COMM_SELF), box, {false, false, false}, 0.1,
                               max_blocks(parts, 1));
    EXPECT_GT(dec.block_edge(), 1);
    // Work: one particle per fine cell, so partial blocks weigh less.
    std::vector<std::int64_t> work(static_cast<std::size_t>(dec.blocks()), 0);
    for (long c = 0; c < dec.grid().cells(); ++c)
      work[static_cast<std::size_t>(dec.block_of_cell(c))] += kFluidWork;
    const std::vector<int> owner =
        detail::compute_owners<3>(dec.block_grid(), work, {}, false, parts);
    ASSERT_EQ(owner.size(), work.size());
    std::vector<int> used(static_cast<std::size_t>(parts), 0);
    for (int o : owner) {
      ASSERT_GE(o, 0);
      ASSERT_LT(o, parts);
      used[static_cast<std::size_t>(o)] = 1;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), parts);
    EXPECT_LT(detail::owner_imbalance(work, owner, parts), 0.10) << parts << " parts";
  }
}

// On the ranks of the test: the map is the same on every rank, whatever
// the work each rank reports (summed onto rank 0), every rank owns work,
// the imbalance partition() returns is the map's, and the per-rank
// imbalance (one number per rank) agrees with it once the particles are
// where the map puts them.
TEST(TopCells, MapIsTheSameOnEveryRank) {
  const Comm world;
  const Box<2> box{Vec<2>(0, 0), Vec<2>(6, 4)};
  Decomposition<2> dec(world, box, {true, false, false}, 0.1, max_blocks(world.size(), 1));
  const std::size_t n = static_cast<std::size_t>(dec.blocks());
  // Each rank reports the work of a round-robin share of the fine cells.
  std::vector<std::int64_t> mine(n, 0), all(n, 0);
  for (long c = 0; c < dec.grid().cells(); ++c) {
    const auto b = static_cast<std::size_t>(dec.block_of_cell(c));
    const std::int64_t w = 1 + c % 3;
    all[b] += w;
    if (c % world.size() == world.rank()) mine[b] += w;
  }
  const double planned = dec.partition(mine, /*replicated=*/false);
  std::vector<int> root_map = dec.block_owners();
  MPI_Bcast(root_map.data(), static_cast<int>(n), MPI_INT, 0, world.raw());
  EXPECT_EQ(root_map, dec.block_owners());
  if (world.size() == 1) {
    EXPECT_EQ(planned, 0.0);
    return;
  }
  EXPECT_DOUBLE_EQ(planned, detail::owner_imbalance(all, dec.block_owners(), world.size()));
  EXPECT_LT(planned, 0.10);
  std::vector<std::int64_t> owned(n, 0);  // the work after migration
  for (std::size_t b = 0; b < n; ++b)
    if (dec.block_owners()[b] == world.rank()) owned[b] = all[b];
  EXPECT_GT(std::accumulate(owned.begin(), owned.end(), std::int64_t{0}), 0);
  EXPECT_DOUBLE_EQ(dec.imbalance(owned), planned);
  // Fine cells map to their block's owner, positions to their cell's.
  for (long c = 0; c < dec.grid().cells(); ++c)
    EXPECT_EQ(dec.owner_of_cell(c),
              dec.block_owners()[static_cast<std::size_t>(dec.block_of_cell(c))]);
}

// The ghost build's interior test (detail::InteriorCells, one test per
// block the 3^D cells around a cell overlap) against its definition, cell
// by cell: every neighbor cell within the grid is this rank's and none lies
// across a periodic face. And owner_of_coords is owner_of_cell. Blocks of
// several cells with owners mixed by the partition, a periodic axis and
// closed ones, in 2D and 3D, at 1, 2 and 4 ranks.
template <int D>
void check_interior_cells(const Box<D>& box, const std::array<bool, 3>& periodic, double cell,
                          long max_blocks_) {
  const Comm world;
  Decomposition<D> dec(world, box, periodic, cell, max_blocks_);
  ASSERT_GT(dec.block_edge(), 1);
  const CellGrid<D>& g = dec.grid();
  std::vector<std::int64_t> work(static_cast<std::size_t>(dec.blocks()), 0);
  for (long c = 0; c < g.cells(); ++c)
    if (c % world.size() == world.rank())
      work[static_cast<std::size_t>(dec.block_of_cell(c))] += 1 + c % 5;
  dec.partition(work, /*replicated=*/false);
  detail::InteriorCells<D> interior(dec);
  const long z = D == 3 ? 1 : 0;
  long interior_cells = 0, boundary_cells = 0;
  for (long c = 0; c < g.cells(); ++c) {
    const auto at = g.coords_of(c);
    ASSERT_EQ(dec.owner_of_coords(at), dec.owner_of_cell(c));
    bool expected = true;
    for (long oz = -z; oz <= z; ++oz)
      for (long oy = -1; oy <= 1; ++oy)
        for (long ox = -1; ox <= 1; ++ox) {
          Vec<D> shift;
          typename CellGrid<D>::Coords m;
          if (!detail::offset_coords<D>(g, at, {ox, oy, oz}, shift, m)) continue;
          if (!shift.isZero(0.0) || dec.owner_of_cell(g.index(m)) != world.rank()) expected = false;
        }
    Vec<D> centre;
    for (int k = 0; k < D; ++k)
      centre[k] = g.lower(k, at[static_cast<std::size_t>(k)]) + 0.5 * g.size(k);
    ASSERT_EQ(interior.contains(centre), expected) << "cell " << c;
    (expected ? interior_cells : boundary_cells) += 1;
  }
  // Both answers occur (the test could not fail otherwise).
  EXPECT_GT(interior_cells, 0);
  EXPECT_GT(boundary_cells, 0);
}

TEST(TopCells, InteriorCellsFollowTheirDefinition2D) {
  check_interior_cells<2>(Box<2>{Vec<2>(0, 0), Vec<2>(6, 4)}, {true, false, false}, 0.1, 40);
}

TEST(TopCells, InteriorCellsFollowTheirDefinition3D) {
  check_interior_cells<3>(Box<3>{Vec<3>(0, 0, 0), Vec<3>(3, 2, 1.5)}, {false, true, false}, 0.1,
                          60);
}

}  // namespace
}  // namespace sphdem
