#pragma once
// Domain decomposition (docs/parallel.md): a background grid of
// cells no smaller than the neighbor cut-off covers the simulation domain.
// Its cells are grouped into top-level cells ("blocks" of b^D cells, at most
// max(kBlocksPerRank x ranks, min_blocks) of them, as in SWIFT), and every
// block has an owner rank: no rank holds an array the size of the fine grid.
// A rank owns the particles whose position lies in its blocks. METIS
// partitions the graph of non-empty blocks weighted by the work in them (on
// rank 0, then broadcast); empty blocks join the part of the nearest
// non-empty block, so resin flowing into an empty region of the mold always
// lands on some rank.
//
// Migration moves particles to the owner of their cell with every field
// whose FieldPolicy.migrate is set. Both are collective over the
// decomposition's communicator; physics never sees any of this.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Work of one particle in the partition weights (integers for METIS). A
// wall particle next to resin costs about 0.3 of a resin particle: it only
// gathers its resin neighbors for the extrapolation and has no rate loop.
// A wall particle with no resin near (a mold's empty cavity, most of a 3D
// mold's walls at the start) has an empty list: only its share of the list
// build, the kicks and the output, about 0.1 (docs/parallel.md, "Walls away
// from the resin").
inline constexpr std::int64_t kFluidWork = 10;
inline constexpr std::int64_t kWallWork = 3;
inline constexpr std::int64_t kIdleWallWork = 1;

// The most cells of a CellGrid built from a cell size: far from long's
// range in the index arithmetic, and beyond any rank's memory (the halo
// keeps a byte per cell, InteriorCells).
inline constexpr long kMaxGridCells = 1L << 40;

template <int D>
class CellGrid {
 public:
  using Coords = std::array<long, 3>;

  // n_k = floor(L_k / min_cell) cells (at least 1) of size L_k / n_k along
  // each axis, so cells are never smaller than min_cell and tile periodic
  // axes exactly. Throws std::length_error past kMaxGridCells cells.
  CellGrid(const Box<D>& box, const std::array<bool, 3>& periodic, double min_cell);
  // The grid of `cells` cells per axis over `box` (the grid of blocks).
  CellGrid(const Box<D>& box, const std::array<bool, 3>& periodic, const Coords& cells);

  long cells() const { return n_[0] * n_[1] * n_[2]; }
  const Coords& dims() const { return n_; }
  const Box<D>& box() const { return box_; }
  bool periodic(int k) const { return periodic_[static_cast<std::size_t>(k)]; }
  double size(int k) const { return size_[k]; }
  double length(int k) const { return box_.hi[k] - box_.lo[k]; }

  // Cell coordinates of x, clamped into the grid (a particle outside a
  // closed domain is an error the solver reports; it must not crash here).
  Coords coords(const Vec<D>& x) const;
  long index(const Coords& c) const { return (c[2] * n_[1] + c[1]) * n_[0] + c[0]; }
  long cell_of(const Vec<D>& x) const { return index(coords(x)); }
  Coords coords_of(long cell) const;
  // Lower corner of the cell with (possibly out-of-range) coordinate c along k.
  double lower(int k, long c) const { return box_.lo[k] + static_cast<double>(c) * size_[k]; }

  // Cells sharing a face, edge or corner with `cell` (across periodic
  // faces), each once, never `cell` itself. Returns how many were written.
  int neighbors(long cell, std::array<long, 26>& out) const;

 private:
  Box<D> box_;
  std::array<bool, 3> periodic_;
  Coords n_{1, 1, 1};
  Vec<D> size_;
};

// Top-level cells per rank (SWIFT uses a few tens): enough for METIS to
// balance within a few per cent, few enough that the map every rank holds
// and the graph rank 0 partitions grow with the rank count, not the case.
inline constexpr long kBlocksPerRank = 64;
// Below this many top-level cells a block is one cell (4 MB of owners per
// rank at most): small cases keep the finest partition.
inline constexpr long kMinBlocks = 1L << 20;

// The most top-level cells of a decomposition over `ranks` ranks
// (parallel.top_cells_per_rank, parallel.min_top_cells).
inline long max_blocks(int ranks, long min_blocks = kMinBlocks, long per_rank = kBlocksPerRank) {
  return std::max(per_rank * static_cast<long>(ranks), min_blocks);
}

// The smallest block edge b (in cells, the same along every axis) for which
// the blocks, ceil(n_k / b) along axis k, number at most `max_blocks`.
// Throws std::invalid_argument unless every n_k is in [1, kMaxGridCells].
long block_edge(const std::array<long, 3>& dims, long max_blocks);

// Work per block from the resin and wall particles per block: kFluidWork a
// resin particle; a wall particle kWallWork when its block or one of the
// blocks next to it holds resin (`holds_resin[b]` != 0: block b holds resin
// on some rank), kIdleWallWork otherwise. Serial: the same weights on one
// rank and on many.
template <int D>
std::vector<std::int64_t> weigh_blocks(const CellGrid<D>& blocks,
                                       const std::vector<std::int64_t>& fluid,
                                       const std::vector<std::int64_t>& walls,
                                       const std::vector<std::uint8_t>& holds_resin);

template <int D>
class Decomposition {
 public:
  // Every block starts on rank 0; call partition() to spread them.
  // max_top_cells: the most blocks (default max_blocks(comm.size())).
  Decomposition(const Comm& comm, const Box<D>& domain, const std::array<bool, 3>& periodic,
                double min_cell, long max_top_cells = 0);

  const Comm& comm() const { return comm_; }
  const CellGrid<D>& grid() const { return grid_; }
  // The grid of blocks (its dims and adjacency; cells of the fine grid map
  // to it by block_of_cell, never by position) and the block edge in cells.
  const CellGrid<D>& block_grid() const { return blocks_; }
  long block_edge() const { return edge_; }
  long blocks() const { return blocks_.cells(); }
  // The block holding the cell at coordinates c of grid().
  long block_of_coords(const typename CellGrid<D>::Coords& c) const {
    return blocks_.index({c[0] / edge_, c[1] / edge_, c[2] / edge_});
  }
  long block_of_cell(long cell) const { return block_of_coords(grid_.coords_of(cell)); }
  long block_of(const Vec<D>& x) const { return block_of_coords(grid_.coords(x)); }
  int owner_of_cell(long cell) const {
    return owner_[static_cast<std::size_t>(block_of_cell(cell))];
  }
  // The owner of the cell at coordinates c of grid(): owner_of_cell without
  // decoding an index (three integer divisions instead of seven; the ghost
  // build asks for the neighbours of every cell near a rank boundary).
  int owner_of_coords(const typename CellGrid<D>::Coords& c) const {
    return owner_[static_cast<std::size_t>(block_of_coords(c))];
  }
  // Whether `rank` owns every cell of grid() with coordinates in [lo, hi]
  // (inclusive, within the grid): one test per block the box overlaps.
  bool owns_cells(const typename CellGrid<D>::Coords& lo, const typename CellGrid<D>::Coords& hi,
                  int rank) const {
    for (long bz = lo[2] / edge_; bz <= hi[2] / edge_; ++bz)
      for (long by = lo[1] / edge_; by <= hi[1] / edge_; ++by)
        for (long bx = lo[0] / edge_; bx <= hi[0] / edge_; ++bx)
          if (owner_[static_cast<std::size_t>(blocks_.index({bx, by, bz}))] != rank) return false;
    return true;
  }
  int owner(const Vec<D>& x) const { return owner_[static_cast<std::size_t>(block_of(x))]; }
  // The owner of every block (the whole map: every rank holds it).
  const std::vector<int>& block_owners() const { return owner_; }

  // Collective. Work per block of particles [0, n) of this rank
  // (weigh_blocks: whether a wall particle has resin near is decided over
  // all ranks).
  std::vector<std::int64_t> cell_work(const SphParticles<D>& ps, std::size_t n) const;
  // Collective. weigh_blocks of this rank's resin and wall particles per
  // block, the blocks holding resin found over all ranks (one allreduce of
  // a byte per block).
  std::vector<std::int64_t> weigh(const std::vector<std::int64_t>& fluid,
                                  const std::vector<std::int64_t>& walls) const;

  // Collective. A new block -> rank map from the work per block: this
  // rank's share (summed over ranks onto rank 0), or with `replicated` the
  // global work, the same on every rank. Once a map exists, the new parts
  // are relabelled to keep as much work as possible on its current rank.
  // Returns the imbalance of the new map (rank 0 computes it from the
  // summed work and broadcasts it with the map). One rank: no-op, 0.
  double partition(const std::vector<std::int64_t>& work, bool replicated);

  // Collective: max over ranks of the owned work (cell_work) divided by the
  // mean, minus 1 (0 on one rank). Integer sums, so every rank count agrees
  // exactly.
  double imbalance(const SphParticles<D>& ps) const;
  // Collective: the same for any work per block: each rank's total of its
  // own vector (the work of the particles it holds), then one max and one
  // sum over ranks of that single number, never of the vector.
  double imbalance(const std::vector<std::int64_t>& work) const;

  // Collective (parallel.balance_weight: time; docs/parallel.md, "Balancing
  // measured time"): max over ranks of `busy_seconds` (this rank's compute
  // time since the last check) divided by the mean, minus 1 (0 on one rank).
  double time_imbalance(double busy_seconds) const;
  // Collective. A new map that balances the times the ranks' work is
  // predicted to take: this rank's seconds per unit of work, busy_seconds
  // over its total of `work` (this rank's work per block), is gathered to
  // rank 0, which chooses among METIS partitions of the summed work
  // (detail::owners_for_times). Returns the predicted time imbalance of the
  // new map.
  double partition_by_time(const std::vector<std::int64_t>& work, double busy_seconds);

  // Drops the owned particles (SPH or DEM) that lie in other ranks' cells
  // (no communication: the start, when every rank holds every particle).
  template <class P>
  void keep_owned(P& ps) const {
    ps.clear_ghosts();
    std::vector<std::size_t> keep;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (owner(ps.x[i]) == comm_.rank()) keep.push_back(i);
    ps.permute_owned(keep);
    ps.resize(keep.size());
    ps.n_owned = keep.size();
  }

 private:
  // Sums `work` onto rank 0 (unless `replicated`), where on_root(total)
  // sets owner_ and returns the new map's imbalance; broadcasts both (an
  // error on rank 0 reaches every rank).
  template <class OnRoot>
  double partition_on_root(const std::vector<std::int64_t>& work, bool replicated,
                           OnRoot&& on_root);

  Comm comm_;
  CellGrid<D> grid_;
  long edge_ = 1;
  CellGrid<D> blocks_;
  std::vector<int> owner_;
  bool partitioned_ = false;
};

// Wraps owned positions back into the box along periodic axes. Runs at
// every rebuild, before migration, so a particle's cell is always inside
// the grid.
template <int D>
void wrap_periodic(SphParticles<D>& ps, const Box<D>& box, const std::array<bool, 3>& periodic);
template <int D>
struct DemParticles;
// The same for the fibers' particles (a fiber across a periodic face keeps
// its bonds: the pair list bonds the nearest image, dem_pair_list.cpp).
template <int D>
void wrap_periodic(DemParticles<D>& ps, const Box<D>& box, const std::array<bool, 3>& periodic);

// The partner ranks of one direction of an exchange (migration, halo) and
// where each one's elements sit in the buffer: [offsets[k], offsets[k+1])
// belong to ranks[k]. Ranks in increasing order, so layouts are
// deterministic.
struct MessageRoute {
  std::vector<int> ranks;
  std::vector<std::size_t> offsets{0};
  std::size_t total() const { return offsets.back(); }
};

struct MigrationCounts {
  std::size_t sent = 0;
  std::size_t received = 0;
};

// Collective. Drops the ghosts and sends every owned particle whose cell
// belongs to another rank to that rank, with its migrating fields. Kept
// particles stay in their order; arrivals are appended by source rank.
// Any registry container: SphParticles<D> or DemParticles<D>.
template <int D, class P>
MigrationCounts migrate(const Decomposition<D>& dec, P& ps);

// Collective. As migrate, copying only the particles that change rank:
// arrivals take the departures' slots, so the kept particles' order
// changes (for containers whose results do not depend on the local order,
// the DEM particles: every sum runs in gid order).
template <int D, class P>
MigrationCounts migrate_in_place(const Decomposition<D>& dec, P& ps);

}  // namespace sphdem
