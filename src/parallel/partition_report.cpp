// `sphdem partition`: the decomposition a run would start from, at rank
// counts this machine cannot run (docs/scaling.md).
#include "sphdem/parallel/partition_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <ostream>
#include <stdexcept>
#include <utility>

#include "partition_graph.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/timers.hpp"
#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/resin_cells.hpp"

namespace sphdem {

namespace {

// What the cells hold at the start: the resin and wall particles, which
// measure() weighs per block of a rank count exactly as a run does
// (weigh_blocks: Decomposition::cell_work, and fill_distributed for the
// run's first partition), and with fiber sub-steps the placed fibers' work
// (add_fiber_work), as a re-partition of a coupled run weighs them
// (ResinModule::cell_work).
struct CellLoad {
  std::vector<std::int64_t> fiber_work;
  std::vector<std::int64_t> fluid, wall;
  long nonempty() const {
    long n = 0;
    for (std::size_t c = 0; c < fluid.size(); ++c)
      n += fluid[c] + wall[c] + fiber_work[c] > 0 ? 1 : 0;
    return n;
  }
};

template <int D>
CellLoad cell_load(const Decomposition<D>& dec, const SphParticles<D>& ps) {
  CellLoad load;
  load.fiber_work.assign(static_cast<std::size_t>(dec.grid().cells()), 0);
  load.fluid.assign(load.fiber_work.size(), 0);
  load.wall.assign(load.fiber_work.size(), 0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const auto c = static_cast<std::size_t>(dec.grid().cell_of(ps.x[i]));
    ++(ps.kind[i] == Kind::Fluid ? load.fluid : load.wall)[c];
  }
  return load;
}

// The case's fibers placed as a run places them (case_fibers: the same
// fibers at any rank count), their work added to the fine cells; returns
// the fiber particles.
template <int D>
std::int64_t add_fibers(const Case& c, const Decomposition<D>& dec, std::int64_t substeps,
                        CellLoad& load) {
  std::vector<int> wall_owner;
  FiberPlacement placement;
  const DemSystem<D> fibers = case_fibers<D>(c, wall_owner, placement);
  add_fiber_work<D>(dec, fibers.particles, fibers.particles.size(), substeps, load.fiber_work);
  return static_cast<std::int64_t>(fibers.particles.size());
}

// Ghosts at the cell level: every particle of a cell is a ghost on each
// other rank owning a cell of its 3^D stencil (periodic faces included).
// The run's halo also tests the distance to the neighbor cell, so it sends
// somewhat fewer (corner cells only partly): this is an upper bound.
struct HaloCounts {
  std::vector<std::int64_t> ghosts, wall_ghosts;
  std::vector<int> partners;  // ranks sending to or receiving from this one
};

template <int D>
HaloCounts count_halo(const CellGrid<D>& grid, const CellLoad& load, const std::vector<int>& owner,
                      int ranks) {
  const auto p = static_cast<std::size_t>(ranks);
  HaloCounts h{std::vector<std::int64_t>(p, 0), std::vector<std::int64_t>(p, 0),
               std::vector<int>(p, 0)};
  std::vector<std::pair<int, int>> links;
  std::vector<int> targets;
  std::array<long, 26> nb;
  for (std::size_t c = 0; c < owner.size(); ++c) {
    if (load.fluid[c] + load.wall[c] == 0) continue;  // the SPH halo: resin and walls
    const int own = owner[c];
    targets.clear();
    const int n = grid.neighbors(static_cast<long>(c), nb);
    for (int k = 0; k < n; ++k) {
      const int s = owner[static_cast<std::size_t>(nb[static_cast<std::size_t>(k)])];
      if (s != own && std::find(targets.begin(), targets.end(), s) == targets.end())
        targets.push_back(s);
    }
    for (int s : targets) {
      h.ghosts[static_cast<std::size_t>(s)] += load.fluid[c] + load.wall[c];
      h.wall_ghosts[static_cast<std::size_t>(s)] += load.wall[c];
      links.emplace_back(own, s);
      links.emplace_back(s, own);
    }
  }
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  for (const auto& l : links) ++h.partners[static_cast<std::size_t>(l.first)];
  return h;
}

// Imbalance (of the work per block) and owned particles per rank (of the
// fine cells' counts).
void add_balance(const CellLoad& load, const std::vector<std::int64_t>& block_work,
                 const std::vector<int>& block_owner, const std::vector<int>& owner,
                 PartitionStats& s, std::vector<std::int64_t>& owned) {
  const auto p = static_cast<std::size_t>(s.ranks);
  std::vector<std::int64_t> work(p, 0);
  owned.assign(p, 0);
  for (std::size_t b = 0; b < block_owner.size(); ++b)
    work[static_cast<std::size_t>(block_owner[b])] += block_work[b];
  for (std::size_t c = 0; c < owner.size(); ++c)
    owned[static_cast<std::size_t>(owner[c])] += load.fluid[c] + load.wall[c];
  const std::int64_t total = std::accumulate(work.begin(), work.end(), std::int64_t{0});
  const std::int64_t most = *std::max_element(work.begin(), work.end());
  s.imbalance =
      total > 0 ? static_cast<double>(most) * s.ranks / static_cast<double>(total) - 1.0 : 0.0;
  s.empty_ranks = static_cast<int>(std::count(owned.begin(), owned.end(), 0));
}

template <int D>
void add_halo(const CellGrid<D>& grid, const CellLoad& load, const std::vector<int>& owner,
              const std::vector<std::int64_t>& owned, PartitionStats& s) {
  const HaloCounts h = count_halo<D>(grid, load, owner, s.ranks);
  std::int64_t ghosts = 0, particles = 0;
  double bytes_sum = 0;
  for (std::size_t r = 0; r < owned.size(); ++r) {
    ghosts += h.ghosts[r];
    particles += owned[r];
    if (owned[r] > 0) {
      s.ghost_fraction_max = std::max(
          s.ghost_fraction_max, static_cast<double>(h.ghosts[r]) / static_cast<double>(owned[r]));
    }
    const double bytes =
        static_cast<double>(forward_bytes(D, SphGroup::State)) * static_cast<double>(h.ghosts[r]) +
        static_cast<double>(forward_bytes(D, SphGroup::WallState)) *
            static_cast<double>(h.wall_ghosts[r]);
    s.halo_bytes_max = std::max(s.halo_bytes_max, bytes);
    bytes_sum += bytes;
    s.neighbors_max = std::max(s.neighbors_max, h.partners[r]);
    s.neighbors_mean += h.partners[r];
  }
  s.ghost_fraction =
      particles > 0 ? static_cast<double>(ghosts) / static_cast<double>(particles) : 0;
  s.halo_bytes_mean = bytes_sum / s.ranks;
  s.neighbors_mean /= s.ranks;
}

// The bytes of the partition step (decomposition.cpp, partition_graph.hpp):
// on every rank the block -> rank map (int) and its work per block (int64);
// on rank 0 also the summed work, the graph of the non-empty blocks in
// compressed rows (int32, as built and once more as METIS's idx_t), their
// weights (int64 and idx_t) and parts. METIS's own work space, about as
// large again as its graph, is not counted.
template <int D>
void add_memory(const Decomposition<D>& dec, long nonempty, PartitionStats& s) {
  const double blocks = static_cast<double>(dec.blocks());
  const double vertices = static_cast<double>(nonempty);
  const double edges = vertices * (D == 3 ? 26.0 : 8.0);  // interior blocks: every neighbor
  s.map_bytes = blocks * (sizeof(int) + sizeof(std::int64_t));
  s.root_bytes = blocks * (sizeof(std::int64_t) + sizeof(int)) +
                 2 * (vertices + edges) * sizeof(std::int32_t) +
                 vertices * (sizeof(std::int64_t) + 2 * sizeof(std::int32_t) + sizeof(long));
}

template <int D>
PartitionStats measure(const Box<D>& domain, const std::array<bool, 3>& periodic, double min_cell,
                       const CellLoad& load, int ranks, const ParallelSettings& top) {
  PartitionStats s;
  s.ranks = ranks;
  // The decomposition a run on `ranks` ranks builds: its blocks and their work.
  const Decomposition<D> dec(Comm(MPI_COMM_SELF), domain, periodic, min_cell,
                             max_blocks(ranks, top.min_top_cells, top.top_cells_per_rank));
  const CellGrid<D>& grid = dec.grid();
  const auto n_blocks = static_cast<std::size_t>(dec.blocks());
  std::vector<std::int64_t> fluid(n_blocks, 0), walls(n_blocks, 0), fibers(n_blocks, 0);
  for (std::size_t c = 0; c < load.fluid.size(); ++c) {
    const auto b = static_cast<std::size_t>(dec.block_of_cell(static_cast<long>(c)));
    fluid[b] += load.fluid[c];
    walls[b] += load.wall[c];
    fibers[b] += load.fiber_work[c];
  }
  // The whole case's counts on one rank (MPI_COMM_SELF): the run's weights.
  std::vector<std::int64_t> work = dec.weigh(fluid, walls);
  for (std::size_t b = 0; b < n_blocks; ++b) work[b] += fibers[b];
  s.blocks = dec.blocks();
  s.block_edge = dec.block_edge();
  s.nonempty_blocks = std::count_if(work.begin(), work.end(), [](std::int64_t w) { return w > 0; });
  add_memory<D>(dec, s.nonempty_blocks, s);
  s.feasible = ranks <= s.nonempty_blocks;
  if (!s.feasible) return s;
  const auto t0 = std::chrono::steady_clock::now();
  // The initial partition of a run: no previous map, so no relabelling.
  const std::vector<int> block_owner =
      detail::compute_owners<D>(dec.block_grid(), work, {}, false, ranks);
  s.partition_seconds = seconds_since(t0);
  s.owners = block_owner;
  // The owner of every fine cell, for the halo (this serial tool may hold it).
  std::vector<int> owner(load.fluid.size());
  for (std::size_t c = 0; c < owner.size(); ++c)
    owner[c] = block_owner[static_cast<std::size_t>(dec.block_of_cell(static_cast<long>(c)))];
  std::vector<std::int64_t> owned;
  add_balance(load, work, block_owner, owner, s, owned);
  add_halo<D>(grid, load, owner, owned, s);
  return s;
}

// The fine grid (blocks of one cell). A domain too large for its cells
// (past kMaxGridCells) is the case's fault, the domain's or the mold's it
// defaults to, as in a run (ResinModule): an InputError naming the key.
// measure() builds the same grid for every rank count.
template <int D>
Decomposition<D> fine_decomposition(const Case& c, const Box<D>& domain, double min_cell) {
  try {
    return Decomposition<D>(Comm(MPI_COMM_SELF), domain, c.periodic, min_cell,
                            std::numeric_limits<long>::max());
  } catch (const std::length_error& e) {
    throw input_error_at(c, c.domain_lo ? "domain" : "mold", e.what());
  }
}

template <int D>
PartitionReport report(const Case& c, const std::vector<int>& ranks, std::int64_t fiber_substeps) {
  const auto t0 = std::chrono::steady_clock::now();
  PartitionReport r;
  r.case_name = c.name;
  r.dimension = D;
  r.spacing = c.numerics.spacing;
  r.has_fibers = c.fibers.has_value();
  // The grid exactly as the resin module builds it (its NeighborList's
  // cut-off, or a fiber's chain reach with implicit bonds: resin_min_cell),
  // before the particles as there: a domain too large for it is refused at
  // once; the communicator only matters to partition(), which is not called.
  const NeighborList<D> nl(2.0 * c.h(), c.numerics.neighbor_skin * 2.0 * c.h());
  r.cutoff = nl.cutoff();
  r.min_cell = resin_min_cell(c, nl.cutoff());
  // Blocks of one cell: the fine grid's load, which every rank count's
  // blocks then sum.
  const Box<D> domain = simulation_domain<D>(c);
  const Decomposition<D> dec = fine_decomposition<D>(c, domain, r.min_cell);
  r.dims = dec.grid().dims();
  SphParticles<D> ps;
  const InitialCounts counts = build_initial_particles<D>(c, ps);
  r.fluid = static_cast<std::int64_t>(counts.fluid);
  r.wall = static_cast<std::int64_t>(counts.wall);
  CellLoad load = cell_load<D>(dec, ps);
  ps = SphParticles<D>();  // the counts per cell are all that is needed now
  if (fiber_substeps > 0) {
    r.fiber_substeps = fiber_substeps;
    r.fibers = add_fibers<D>(c, dec, fiber_substeps, load);
  }
  r.nonempty_cells = load.nonempty();
  r.setup_seconds = seconds_since(t0);
  for (int p : ranks)
    r.rows.push_back(measure<D>(domain, c.periodic, r.min_cell, load, p, c.parallel));
  return r;
}

template <int D>
std::size_t group_bytes(SphGroup group) {
  return record_bytes(SphParticles<D>(), [group](FieldPolicy p) { return p.in(group_bit(group)); });
}

}  // namespace

std::size_t forward_bytes(int dim, SphGroup group) {
  return dim == 2 ? group_bytes<2>(group) : group_bytes<3>(group);
}

PartitionReport partition_report(const Case& c, const std::vector<int>& ranks,
                                 std::int64_t fiber_substeps) {
  if (fiber_substeps < 0)
    throw std::invalid_argument("sphdem: partition_report: negative fiber sub-steps");
  if (fiber_substeps > 0 && !c.fibers)
    throw InputError("--fiber-substeps", 0, "", "the case has no fibers to weigh");
  return c.dimension == 2 ? report<2>(c, ranks, fiber_substeps)
                          : report<3>(c, ranks, fiber_substeps);
}

std::string partition_work_text(const PartitionReport& r) {
  std::string text = fmt::format(
      "{} per resin, {} per wall particle with resin in its top-level cell or the next, {} "
      "per other wall particle",
      kFluidWork, kWallWork, kIdleWallWork);
  if (r.fiber_substeps > 0) {
    return text + fmt::format(
                      ", {} x {} sub-steps = {} per fiber particle ({} placed): the weights of "
                      "a coupled run's re-partitions",
                      kDemSubstepWork, r.fiber_substeps, fiber_particle_work(r.fiber_substeps),
                      r.fibers);
  }
  return text + ": the weights of a run's first partition" +
         (r.has_fibers ? " (its fibers not weighted: --fiber-substeps weighs them as a "
                         "re-partition does)"
                       : "");
}

std::string format_partition_table(const PartitionReport& r) {
  const int d = r.dimension;
  std::string dims = fmt::format("{}", r.dims[0]);
  for (int k = 1; k < d; ++k) dims += fmt::format(" x {}", r.dims[static_cast<std::size_t>(k)]);
  const std::string cells =
      r.min_cell > r.cutoff
          ? fmt::format(
                "cells >= {:.4g} m, a fiber's chain reach with implicit bonds; cut-off "
                "{:.4g} m",
                r.min_cell, r.cutoff)
          : fmt::format("cells >= cut-off {:.4g} m", r.cutoff);
  std::string out = fmt::format(
      "case '{}' ({}D): {} resin + {} wall particles, spacing {:.4g} m\n"
      "cell grid {} ({}), {} non-empty cells; set-up {:.2f} s\n"
      "work: {}\n"
      "halo per step: {} B per ghost + {} B per wall ghost (forward State, WallState)\n\n",
      r.case_name, d, r.fluid, r.wall, r.spacing, dims, cells, r.nonempty_cells, r.setup_seconds,
      partition_work_text(r), forward_bytes(d, SphGroup::State),
      forward_bytes(d, SphGroup::WallState));
  out += fmt::format(
      "{:>6} {:>10} {:>10} {:>9} {:>9} {:>11} {:>11} {:>9} {:>9} {:>9} {:>10} {:>5} {:>8} "
      "{:>8}\n",
      "ranks", "particles", "imbalance", "ghosts/", "max", "halo kB", "halo kB", "neighbors",
      "neighbors", "METIS", "top cells", "edge", "map MB", "rank 0");
  out += fmt::format(
      "{:>6} {:>10} {:>10} {:>9} {:>9} {:>11} {:>11} {:>9} {:>9} {:>9} {:>10} {:>5} {:>8} "
      "{:>8}\n",
      "", "per rank", "", "owned", "per rank", "max/step", "mean/step", "max", "mean", "s",
      "non-empty", "cells", "per rank", "MB");
  const double particles = static_cast<double>(r.fluid + r.wall);
  for (const PartitionStats& s : r.rows) {
    if (!s.feasible) {
      out += fmt::format(
          "{:>6}  more ranks than the {} non-empty top-level cells: not partitioned "
          "(refine the case with --scale)\n",
          s.ranks, s.nonempty_blocks);
      continue;
    }
    out += fmt::format(
        "{:>6} {:>10.0f} {:>9.1f}% {:>8.1f}% {:>8.1f}% {:>11.1f} {:>11.1f} {:>9} {:>9.1f} "
        "{:>9.3f} {:>10} {:>5} {:>8.2f} {:>8.1f}\n",
        s.ranks, particles / s.ranks, 100 * s.imbalance, 100 * s.ghost_fraction,
        100 * s.ghost_fraction_max, s.halo_bytes_max / 1e3, s.halo_bytes_mean / 1e3,
        s.neighbors_max, s.neighbors_mean, s.partition_seconds, s.nonempty_blocks, s.block_edge,
        s.map_bytes / 1e6, s.root_bytes / 1e6);
    if (s.empty_ranks > 0)
      out += fmt::format("       (ranks left without particles: {})\n", s.empty_ranks);
  }
  return out;
}

void write_partition_csv(std::ostream& out, const PartitionReport& r) {
  out << "ranks,particles,nonempty_cells,imbalance,ghost_fraction,ghost_fraction_max,"
         "halo_bytes_max,halo_bytes_mean,neighbors_max,neighbors_mean,empty_ranks,"
         "partition_seconds,blocks,nonempty_blocks,block_edge,map_bytes,root_bytes,note\n";
  const std::int64_t particles = r.fluid + r.wall;
  for (const PartitionStats& s : r.rows) {
    out << fmt::format("{},{},{},", s.ranks, particles, r.nonempty_cells);
    const std::string blocks = fmt::format("{},{},{},{:.0f},{:.0f}", s.blocks, s.nonempty_blocks,
                                           s.block_edge, s.map_bytes, s.root_bytes);
    if (!s.feasible) {
      out << ",,,,,,,,," << blocks << ",more ranks than non-empty top-level cells\n";
      continue;
    }
    out << fmt::format("{:.6g},{:.6g},{:.6g},{:.0f},{:.0f},{},{:.4g},{},{:.4g},{},\n", s.imbalance,
                       s.ghost_fraction, s.ghost_fraction_max, s.halo_bytes_max, s.halo_bytes_mean,
                       s.neighbors_max, s.neighbors_mean, s.empty_ranks, s.partition_seconds,
                       blocks);
  }
}

}  // namespace sphdem
