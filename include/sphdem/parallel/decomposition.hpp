#pragma once
// Domain decomposition (docs/parallel.md): a background grid of
// cells no smaller than the neighbor cut-off covers the simulation domain,
// and every cell has an owner rank. A rank owns the particles whose position
// lies in its cells. METIS partitions the graph of non-empty cells weighted
// by the work in them (on rank 0, then broadcast); empty cells join the part
// of the nearest non-empty cell, so resin flowing into an empty region of
// the mold always lands on some rank.
//
// Migration moves particles to the owner of their cell with every field
// whose FieldPolicy.migrate is set. Both are collective over the
// decomposition's communicator; physics never sees any of this.
#include <array>
#include <cstdint>
#include <vector>

#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Work of one particle in the partition weights (integers for METIS): a wall
// particle costs about 0.3 of a resin particle, since it only gathers its
// resin neighbors for the extrapolation and has no rate loop.
inline constexpr std::int64_t kFluidWork = 10;
inline constexpr std::int64_t kWallWork = 3;

template <int D>
std::int64_t particle_work(const SphParticles<D>& ps, std::size_t i) {
  return ps.kind[i] == Kind::Fluid ? kFluidWork : kWallWork;
}

template <int D>
class CellGrid {
 public:
  using Coords = std::array<long, 3>;

  // n_k = floor(L_k / min_cell) cells (at least 1) of size L_k / n_k along
  // each axis, so cells are never smaller than min_cell and tile periodic
  // axes exactly.
  CellGrid(const Box<D>& box, const std::array<bool, 3>& periodic, double min_cell);

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

template <int D>
class Decomposition {
 public:
  // Every cell starts on rank 0; call partition() to spread them.
  Decomposition(const Comm& comm, const Box<D>& domain, const std::array<bool, 3>& periodic,
                double min_cell);

  const Comm& comm() const { return comm_; }
  const CellGrid<D>& grid() const { return grid_; }
  int owner_of_cell(long cell) const { return owner_[static_cast<std::size_t>(cell)]; }
  int owner(const Vec<D>& x) const { return owner_of_cell(grid_.cell_of(x)); }
  const std::vector<int>& owners() const { return owner_; }

  // Work per cell of particles [0, n) of this rank.
  std::vector<std::int64_t> cell_work(const SphParticles<D>& ps, std::size_t n) const;

  // Collective. A new cell -> rank map from the work per cell: this rank's
  // share (summed over ranks), or with `replicated` the global work, the
  // same on every rank. Once a map exists, the new parts are relabelled to
  // keep as much work as possible on its current rank. One rank: no-op.
  void partition(const std::vector<std::int64_t>& work, bool replicated);

  // Collective: max over ranks of the owned work divided by the mean, minus
  // 1 (0 on one rank). Integer sums, so every rank count agrees exactly.
  double imbalance(const SphParticles<D>& ps) const;
  // Collective: the same for any work per cell (this rank's particles'
  // share), summed over ranks and assigned to the cells' current owners
  // (so it is right before migration too).
  double imbalance(const std::vector<std::int64_t>& work) const;

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
  Comm comm_;
  CellGrid<D> grid_;
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

}  // namespace sphdem
