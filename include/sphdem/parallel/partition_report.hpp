#pragma once
// What a run at many ranks would see, without running it (`sphdem
// partition`, docs/scaling.md): the case's initial particles, the cell grid
// and weights of the decomposition, and for each rank count the METIS
// partition a run would start from (the same code path,
// detail::compute_owners), measured for load imbalance, ghosts, halo
// volume and neighbor ranks. Serial; needs no more than one MPI rank.
//
// The weights (docs/parallel.md, "Which weights, when"): a run's first partition
// (the distributed set-up) weighs resin and wall particles only, kFluidWork
// and kWallWork each, as a restart's does: the fibers of a coupled run are
// placed after it, on its cells. Its re-partitions (every
// parallel.balance_every steps, past parallel.imbalance_threshold) add the
// fibers' work, fiber_particle_work(sub-steps of the last resin step) per
// fiber particle. fiber_substeps > 0 weighs the placed fibers so, at that
// many sub-steps.
#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Bytes per ghost of one Halo::forward(group) (docs/parallel.md, "The
// step"): the sizes of the group's fields in the registry (particles.hpp).
// State goes to every ghost, WallState to the wall ghosts.
std::size_t forward_bytes(int dim, SphGroup group);

struct PartitionStats {
  int ranks = 0;
  // False when there are more ranks than non-empty top-level cells: a run
  // would give ranks only empty ones (nothing below is measured then).
  bool feasible = true;
  int empty_ranks = 0;            // ranks METIS left without particles
  double imbalance = 0;           // max / mean - 1 of the weighted work
  double ghost_fraction = 0;      // all ghosts / all owned particles
  double ghost_fraction_max = 0;  // max over ranks of ghosts / owned
  double halo_bytes_max = 0;      // received per step by one rank
  double halo_bytes_mean = 0;     // mean over ranks
  int neighbors_max = 0;          // ranks exchanging ghosts with one rank
  double neighbors_mean = 0;
  double partition_seconds = 0;  // graph, METIS, empty blocks (rank 0 in a run)
  // The partition: the rank of every block of the block grid below, as a
  // run's Decomposition::block_owners (empty when not feasible).
  std::vector<int> owners;
  // The top-level cells (blocks) a run at this rank count partitions
  // (Decomposition::block_grid): all of them, the non-empty ones, the
  // block edge in cells.
  long blocks = 0, nonempty_blocks = 0, block_edge = 1;
  double map_bytes = 0;   // per rank: the block -> rank map and a work per block
  double root_bytes = 0;  // rank 0 in addition: summed work, graph, METIS's copy, parts
};

struct PartitionReport {
  std::string case_name;
  int dimension = 2;
  double spacing = 0, cutoff = 0;
  // The cells' smallest edge, as in a run (resin_min_cell): the cut-off, or
  // a fiber's chain reach with implicit bonds when that is larger.
  double min_cell = 0;
  std::int64_t fluid = 0, wall = 0;
  bool has_fibers = false;            // the case has fibers
  std::int64_t fiber_substeps = 0;    // > 0: the fibers are weighted, at this many sub-steps
  std::int64_t fibers = 0;            // fiber particles weighted (placed as a run places them)
  std::array<long, 3> dims{1, 1, 1};  // cells per axis
  long nonempty_cells = 0;
  double setup_seconds = 0;  // particles, grid and weights
  std::vector<PartitionStats> rows;
};

// Builds the case's particles and partitions their graph of top-level cells
// for every rank count in `ranks` (each >= 1), as a run on that many ranks
// would: with the weights of its first partition, or with fiber_substeps >
// 0 those of a coupled run's re-partitions at the initial positions, the
// fibers at fiber_substeps DEM sub-steps per resin step. Throws InputError
// for a bad case, or naming --fiber-substeps for fiber sub-steps in a case
// without fibers.
PartitionReport partition_report(const Case& c, const std::vector<int>& ranks,
                                 std::int64_t fiber_substeps = 0);

// What the report's work counts, one line ("10 per resin, 3 per wall
// particle: ...").
std::string partition_work_text(const PartitionReport& r);

// The report as an aligned table (what `sphdem partition` prints).
std::string format_partition_table(const PartitionReport& r);

// One header line, then one row per rank count; an infeasible rank count
// has empty measurements and a note.
void write_partition_csv(std::ostream& out, const PartitionReport& r);

}  // namespace sphdem
