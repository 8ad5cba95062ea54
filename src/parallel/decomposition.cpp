// Cell grid, METIS partition of the cell graph, relabelling, and the
// broadcast of the cell -> rank map.
#include "partition_graph.hpp"

#include <fmt/format.h>
#include <metis.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>

#include "sphdem/parallel/decomposition.hpp"

namespace sphdem {

namespace detail {

Graph induced_graph(const std::vector<long>& cells, const CellNeighbors& neighbors) {
  Graph g;
  g.xadj.reserve(cells.size() + 1);
  long nb[26];
  for (long c : cells) {
    const int n = neighbors(c, nb);
    for (int k = 0; k < n; ++k) {
      const auto it = std::lower_bound(cells.begin(), cells.end(), nb[k]);
      if (it != cells.end() && *it == nb[k]) {
        g.adjncy.push_back(static_cast<std::int32_t>(it - cells.begin()));
      }
    }
    g.xadj.push_back(static_cast<std::int32_t>(g.adjncy.size()));
  }
  return g;
}

namespace {
// METIS sums vertex weights in idx_t (32 bits here): keep the sum below 2^30.
std::vector<idx_t> metis_weights(const std::vector<std::int64_t>& weight) {
  const std::int64_t total = std::accumulate(weight.begin(), weight.end(), std::int64_t{0});
  const std::int64_t limit = std::int64_t{1} << 30;
  const std::int64_t divisor = total > limit ? total / limit + 1 : 1;
  std::vector<idx_t> out(weight.size());
  for (std::size_t v = 0; v < weight.size(); ++v) {
    out[v] = static_cast<idx_t>(std::max<std::int64_t>(1, weight[v] / divisor));
  }
  return out;
}
}  // namespace

std::vector<int> partition_graph(const Graph& g, const std::vector<std::int64_t>& weight, int parts,
                                 const std::vector<double>& targets) {
  idx_t nvtxs = g.vertices();
  std::vector<int> part(static_cast<std::size_t>(nvtxs), 0);
  if (parts <= 1) return part;
  if (nvtxs <= parts) {
    std::iota(part.begin(), part.end(), 0);
    return part;
  }
  std::vector<idx_t> xadj(g.xadj.begin(), g.xadj.end());
  std::vector<idx_t> adjncy(g.adjncy.begin(), g.adjncy.end());
  adjncy.push_back(0);  // METIS reads adjncy even for a graph without edges
  std::vector<idx_t> vwgt = metis_weights(weight);
  std::vector<idx_t> result(static_cast<std::size_t>(nvtxs), 0);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_UFACTOR] = 30;  // 3 % imbalance, METIS's k-way default, stated
  idx_t ncon = 1, nparts = parts, objval = 0;
  std::vector<real_t> tpwgts;
  if (!targets.empty()) {
    if (static_cast<int>(targets.size()) != parts)
      throw std::invalid_argument("partition_graph: one target per part");
    const double sum = std::accumulate(targets.begin(), targets.end(), 0.0);
    for (double t : targets) tpwgts.push_back(static_cast<real_t>(t / sum));
  }
  const int rc = METIS_PartGraphKway(
      &nvtxs, &ncon, xadj.data(), adjncy.data(), vwgt.data(), nullptr, nullptr, &nparts,
      tpwgts.empty() ? nullptr : tpwgts.data(), nullptr, options, &objval, result.data());
  if (rc != METIS_OK) {
    throw std::runtime_error("sphdem: METIS_PartGraphKway failed (code " + std::to_string(rc) +
                             ") on " + std::to_string(nvtxs) + " cells");
  }
  std::copy(result.begin(), result.end(), part.begin());
  return part;
}

void attach_empty_cells(std::vector<int>& owner, const CellNeighbors& neighbors) {
  std::deque<long> queue;
  for (std::size_t c = 0; c < owner.size(); ++c) {
    if (owner[c] >= 0) queue.push_back(static_cast<long>(c));
  }
  long nb[26];
  while (!queue.empty()) {
    const long c = queue.front();
    queue.pop_front();
    const int n = neighbors(c, nb);
    for (int k = 0; k < n; ++k) {
      int& o = owner[static_cast<std::size_t>(nb[k])];
      if (o >= 0) continue;
      o = owner[static_cast<std::size_t>(c)];
      queue.push_back(nb[k]);
    }
  }
  for (int& o : owner) o = std::max(o, 0);
}

std::vector<int> relabel_parts(const std::vector<int>& old, const std::vector<int>& fresh,
                               const std::vector<std::int64_t>& work, int parts) {
  // Overlaps as a sparse list: a dense parts x parts matrix would not fit
  // rank 0's memory at tens of thousands of ranks.
  std::vector<std::tuple<int, int, std::int64_t>> pairs;  // old, new, work
  pairs.reserve(fresh.size());
  for (std::size_t c = 0; c < fresh.size(); ++c) {
    if (work[c] > 0) pairs.emplace_back(old[c], fresh[c], work[c]);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::tuple<std::int64_t, int, int>> overlap;  // -work, old, new
  for (const auto& [o, n, w] : pairs) {
    if (!overlap.empty() && std::get<1>(overlap.back()) == o && std::get<2>(overlap.back()) == n)
      std::get<0>(overlap.back()) -= w;
    else
      overlap.emplace_back(-w, o, n);
  }
  std::sort(overlap.begin(), overlap.end());  // largest overlap first, ties by rank
  const auto p = static_cast<std::size_t>(parts);
  std::vector<int> rank_of_part(p, -1);
  std::vector<bool> rank_taken(p, false);
  for (const auto& [w, o, n] : overlap) {
    const auto un = static_cast<std::size_t>(n), uo = static_cast<std::size_t>(o);
    if (rank_of_part[un] >= 0 || rank_taken[uo]) continue;
    rank_of_part[un] = o;
    rank_taken[uo] = true;
  }
  std::size_t next = 0;
  for (int& r : rank_of_part) {
    if (r >= 0) continue;
    while (rank_taken[next]) ++next;
    r = static_cast<int>(next);
    rank_taken[next] = true;
  }
  std::vector<int> out(fresh.size());
  for (std::size_t c = 0; c < fresh.size(); ++c) {
    out[c] = rank_of_part[static_cast<std::size_t>(fresh[c])];
  }
  return out;
}

}  // namespace detail

long block_edge(const std::array<long, 3>& dims, long max_blocks) {
  // A CellGrid's dims: within them the sums and the cast below stay in range.
  for (long d : dims) {
    if (d < 1 || d > kMaxGridCells)
      throw std::invalid_argument(fmt::format("block_edge: {} cells along an axis", d));
  }
  const auto count = [&dims](long b) {
    double n = 1;
    for (long d : dims) n *= static_cast<double>((d + b - 1) / b);
    return n;
  };
  const double cells = count(1);
  const double limit = static_cast<double>(std::max(1L, max_blocks));
  // Start just below the answer (the cube root of the ratio in 3D, the
  // square root in 2D: a generous lower bound is the cube root; at most the
  // longest axis) and step up.
  long b = std::max(1L, static_cast<long>(std::floor(std::cbrt(cells / limit))));
  while (count(b) > limit) ++b;
  return b;
}

// ---------------------------------------------------------------- CellGrid

template <int D>
CellGrid<D>::CellGrid(const Box<D>& box, const std::array<bool, 3>& periodic, double min_cell)
    : box_(box), periodic_(periodic) {
  // Counted as doubles before any cast: past kMaxGridCells (a box of
  // absurd extent for the cell) an error, not an out-of-range cast.
  double cells = 1.0;
  for (int k = 0; k < D; ++k) {
    const double len = box.hi[k] - box.lo[k];
    const double along = std::max(1.0, std::floor(len / min_cell));
    cells *= along;
    if (!(cells <= static_cast<double>(kMaxGridCells))) {
      throw std::length_error(fmt::format(
          "the decomposition's cell grid (cells at least {:g} m wide) would take more than 2^40 "
          "cells; the domain spans {:.3g} m along axis {}",
          min_cell, len, k));
    }
    n_[static_cast<std::size_t>(k)] = static_cast<long>(along);
    size_[k] = len / static_cast<double>(n_[static_cast<std::size_t>(k)]);
  }
  for (int k = D; k < 3; ++k) periodic_[static_cast<std::size_t>(k)] = false;
}

template <int D>
CellGrid<D>::CellGrid(const Box<D>& box, const std::array<bool, 3>& periodic, const Coords& cells)
    : box_(box), periodic_(periodic) {
  for (int k = 0; k < D; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    n_[uk] = std::max(1L, cells[uk]);
    size_[k] = (box.hi[k] - box.lo[k]) / static_cast<double>(n_[uk]);
  }
  for (int k = D; k < 3; ++k) periodic_[static_cast<std::size_t>(k)] = false;
}

template <int D>
typename CellGrid<D>::Coords CellGrid<D>::coords(const Vec<D>& x) const {
  Coords c{0, 0, 0};
  for (int k = 0; k < D; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    const double f = std::floor((x[k] - box_.lo[k]) / size_[k]);
    // Clamp in floating point first: a far-away or non-finite position must
    // not overflow the conversion.
    c[uk] = std::isfinite(f) ? static_cast<long>(std::clamp(f, 0.0, double(n_[uk] - 1))) : 0;
  }
  return c;
}

template <int D>
typename CellGrid<D>::Coords CellGrid<D>::coords_of(long cell) const {
  return {cell % n_[0], (cell / n_[0]) % n_[1], cell / (n_[0] * n_[1])};
}

template <int D>
int CellGrid<D>::neighbors(long cell, std::array<long, 26>& out) const {
  const Coords c = coords_of(cell);
  int count = 0;
  const long z_range = D == 3 ? 1 : 0;
  for (long dz = -z_range; dz <= z_range; ++dz)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dx = -1; dx <= 1; ++dx) {
        const Coords o{dx, dy, dz};
        Coords m{0, 0, 0};
        bool inside = true;
        for (std::size_t k = 0; k < 3; ++k) {
          m[k] = c[k] + o[k];
          if (m[k] >= 0 && m[k] < n_[k]) continue;
          if (!periodic_[k]) inside = false;
          m[k] = (m[k] + n_[k]) % n_[k];
        }
        const long id = index(m);
        if (!inside || id == cell) continue;
        // With one or two cells along a periodic axis, offsets alias.
        if (std::find(out.begin(), out.begin() + count, id) != out.begin() + count) continue;
        out[static_cast<std::size_t>(count++)] = id;
      }
  return count;
}

// ----------------------------------------------------------- Decomposition

namespace {

// Blocks per axis: ceil(n_k / edge).
std::array<long, 3> block_dims(const std::array<long, 3>& cells, long edge) {
  return {(cells[0] + edge - 1) / edge, (cells[1] + edge - 1) / edge, (cells[2] + edge - 1) / edge};
}

}  // namespace

template <int D>
Decomposition<D>::Decomposition(const Comm& comm, const Box<D>& domain,
                                const std::array<bool, 3>& periodic, double min_cell,
                                long max_top_cells)
    : comm_(comm),
      grid_(domain, periodic, min_cell),
      edge_(sphdem::block_edge(grid_.dims(),
                               max_top_cells > 0 ? max_top_cells : max_blocks(comm_.size()))),
      blocks_(domain, periodic, block_dims(grid_.dims(), edge_)),
      owner_(static_cast<std::size_t>(blocks_.cells()), 0) {}

template <int D>
std::vector<std::int64_t> weigh_blocks(const CellGrid<D>& blocks,
                                       const std::vector<std::int64_t>& fluid,
                                       const std::vector<std::int64_t>& walls,
                                       const std::vector<std::uint8_t>& holds_resin) {
  const auto n = static_cast<std::size_t>(blocks.cells());
  if (fluid.size() != n || walls.size() != n || holds_resin.size() != n)
    throw std::invalid_argument("sphdem: weigh_blocks: a count per block expected");
  std::vector<std::int64_t> work(n, 0);
  std::array<long, 26> nb;
  for (std::size_t b = 0; b < n; ++b) {
    work[b] = kFluidWork * fluid[b];
    if (walls[b] == 0) continue;
    bool near = holds_resin[b] != 0;
    const int m = near ? 0 : blocks.neighbors(static_cast<long>(b), nb);
    for (int k = 0; k < m && !near; ++k)
      near = holds_resin[static_cast<std::size_t>(nb[static_cast<std::size_t>(k)])] != 0;
    work[b] += (near ? kWallWork : kIdleWallWork) * walls[b];
  }
  return work;
}

template <int D>
std::vector<std::int64_t> Decomposition<D>::weigh(const std::vector<std::int64_t>& fluid,
                                                  const std::vector<std::int64_t>& walls) const {
  std::vector<std::uint8_t> holds_resin(fluid.size());
  for (std::size_t b = 0; b < fluid.size(); ++b) holds_resin[b] = fluid[b] > 0 ? 1 : 0;
  comm_.any(std::span<std::uint8_t>(holds_resin));
  return weigh_blocks<D>(blocks_, fluid, walls, holds_resin);
}

template <int D>
std::vector<std::int64_t> Decomposition<D>::cell_work(const SphParticles<D>& ps,
                                                      std::size_t n) const {
  std::vector<std::int64_t> fluid(static_cast<std::size_t>(blocks()), 0);
  std::vector<std::int64_t> walls(fluid.size(), 0);
  for (std::size_t i = 0; i < n; ++i)
    ++(ps.kind[i] == Kind::Fluid ? fluid : walls)[static_cast<std::size_t>(block_of(ps.x[i]))];
  return weigh(fluid, walls);
}

namespace {

template <int D>
detail::CellNeighbors neighbor_function(const CellGrid<D>& grid) {
  return [&grid](long cell, long* out) {
    std::array<long, 26> nb;
    const int n = grid.neighbors(cell, nb);
    std::copy_n(nb.begin(), n, out);
    return n;
  };
}

}  // namespace

namespace detail {

// Rank 0's part of partition(): the new cell -> rank map. Also called by
// `sphdem partition` (src/parallel/partition_report.cpp), which must see
// exactly what a run would.
template <int D>
std::vector<int> compute_owners(const CellGrid<D>& grid, const std::vector<std::int64_t>& work,
                                const std::vector<int>& old, bool relabel, int parts,
                                const std::vector<double>& targets) {
  std::vector<long> cells;
  std::vector<std::int64_t> weight;
  for (std::size_t c = 0; c < work.size(); ++c) {
    if (work[c] <= 0) continue;
    cells.push_back(static_cast<long>(c));
    weight.push_back(work[c]);
  }
  const detail::CellNeighbors nb = neighbor_function(grid);
  const std::vector<int> part =
      detail::partition_graph(detail::induced_graph(cells, nb), weight, parts, targets);
  std::vector<int> owner(work.size(), -1);
  for (std::size_t v = 0; v < cells.size(); ++v)
    owner[static_cast<std::size_t>(cells[v])] = part[v];
  detail::attach_empty_cells(owner, nb);
  return relabel ? detail::relabel_parts(old, owner, work, parts) : owner;
}

template std::vector<int> compute_owners<2>(const CellGrid<2>&, const std::vector<std::int64_t>&,
                                            const std::vector<int>&, bool, int,
                                            const std::vector<double>&);
template std::vector<int> compute_owners<3>(const CellGrid<3>&, const std::vector<std::int64_t>&,
                                            const std::vector<int>&, bool, int,
                                            const std::vector<double>&);

std::vector<double> usable_seconds_per_work(std::vector<double> seconds) {
  std::vector<double> measured;
  for (double s : seconds)
    if (std::isfinite(s) && s > 0) measured.push_back(s);
  double median = 1.0;
  if (!measured.empty()) {
    std::sort(measured.begin(), measured.end());
    const std::size_t m = measured.size() / 2;
    median = measured.size() % 2 == 1 ? measured[m] : 0.5 * (measured[m - 1] + measured[m]);
  }
  for (double& s : seconds) {
    s = std::isfinite(s) && s > 0 ? std::clamp(s, median / kMaxTimeFactor, median * kMaxTimeFactor)
                                  : median;
  }
  return seconds;
}

double time_imbalance(const std::vector<std::int64_t>& work, const std::vector<int>& owner,
                      const std::vector<double>& seconds) {
  std::vector<double> t(seconds.size(), 0.0);
  for (std::size_t c = 0; c < work.size(); ++c) {
    const auto r = static_cast<std::size_t>(owner[c]);
    t[r] += seconds[r] * static_cast<double>(work[c]);
  }
  const double total = std::accumulate(t.begin(), t.end(), 0.0);
  if (!(total > 0)) return 0.0;
  return *std::max_element(t.begin(), t.end()) * static_cast<double>(t.size()) / total - 1.0;
}

template <int D>
std::vector<int> owners_for_times(const CellGrid<D>& grid, const std::vector<std::int64_t>& work,
                                  const std::vector<int>& old, const std::vector<double>& seconds) {
  const int parts = static_cast<int>(seconds.size());
  const auto p_count = static_cast<std::size_t>(parts);
  // Part p sized for rank rank_of[p]: its share of the work is that rank's
  // share of the speed.
  const auto targets = [&](const std::vector<int>& rank_of) {
    std::vector<double> t(p_count);
    for (std::size_t p = 0; p < p_count; ++p)
      t[p] = 1.0 / seconds[static_cast<std::size_t>(rank_of[p])];
    return t;
  };
  const auto assign = [](const std::vector<int>& part, const std::vector<int>& rank_of) {
    std::vector<int> out(part.size());
    for (std::size_t c = 0; c < part.size(); ++c)
      out[c] = rank_of[static_cast<std::size_t>(part[c])];
    return out;
  };
  // Which rank the relabelling gives each part of `part` (METIS's numbering).
  const auto relabelled = [&](const std::vector<int>& part, std::vector<int>& rank_of) {
    const std::vector<int> owner = relabel_parts(old, part, work, parts);
    rank_of.assign(p_count, 0);
    for (std::size_t c = 0; c < part.size(); ++c)
      rank_of[static_cast<std::size_t>(part[c])] = owner[c];
    return owner;
  };
  std::vector<std::vector<int>> candidates;
  // The model's parts, relabelled; METIS numbers its parts alike for nearby
  // targets, so the next round sizes each part for the rank this one gave it,
  // until the relabelling agrees with the sizing (a few rounds at most).
  std::vector<int> rank_of;
  candidates.push_back(relabelled(compute_owners<D>(grid, work, old, false, parts), rank_of));
  for (int round = 0; round < 3; ++round) {
    const std::vector<int> part =
        compute_owners<D>(grid, work, old, false, parts, targets(rank_of));
    candidates.push_back(assign(part, rank_of));  // as sized
    std::vector<int> next;
    candidates.push_back(relabelled(part, next));  // as the overlap says
    if (next == rank_of) break;
    rank_of = next;
  }
  // Part r sized for rank r whatever it overlaps: balanced, most work moves.
  std::vector<int> identity(p_count);
  std::iota(identity.begin(), identity.end(), 0);
  candidates.push_back(compute_owners<D>(grid, work, old, false, parts, targets(identity)));
  // The lowest predicted imbalance; within kImbalanceMargin of it, the one
  // that moves the least work.
  std::vector<double> imbalance;
  for (const std::vector<int>& o : candidates)
    imbalance.push_back(time_imbalance(work, o, seconds));
  const double best = *std::min_element(imbalance.begin(), imbalance.end());
  std::size_t chosen = 0;
  std::int64_t least = std::numeric_limits<std::int64_t>::max();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (imbalance[k] > best + kImbalanceMargin) continue;
    std::int64_t moved = 0;
    for (std::size_t c = 0; c < work.size(); ++c)
      if (candidates[k][c] != old[c]) moved += work[c];
    if (moved < least) {
      least = moved;
      chosen = k;
    }
  }
  return candidates[chosen];
}

template std::vector<int> owners_for_times<2>(const CellGrid<2>&, const std::vector<std::int64_t>&,
                                              const std::vector<int>&, const std::vector<double>&);
template std::vector<int> owners_for_times<3>(const CellGrid<3>&, const std::vector<std::int64_t>&,
                                              const std::vector<int>&, const std::vector<double>&);

}  // namespace detail

namespace detail {

double owner_imbalance(const std::vector<std::int64_t>& work, const std::vector<int>& owner,
                       int parts) {
  std::vector<std::int64_t> per_rank(static_cast<std::size_t>(parts), 0);
  for (std::size_t c = 0; c < work.size(); ++c)
    per_rank[static_cast<std::size_t>(owner[c])] += work[c];
  const std::int64_t total = std::accumulate(per_rank.begin(), per_rank.end(), std::int64_t{0});
  if (total == 0) return 0.0;
  const std::int64_t most = *std::max_element(per_rank.begin(), per_rank.end());
  return static_cast<double>(most) * parts / static_cast<double>(total) - 1.0;
}

}  // namespace detail

template <int D>
double Decomposition<D>::partition(const std::vector<std::int64_t>& work, bool replicated) {
  if (comm_.size() == 1) return 0.0;
  return partition_on_root(work, replicated, [&](const std::vector<std::int64_t>& total) {
    owner_ = detail::compute_owners(blocks_, total, owner_, partitioned_, comm_.size());
    return detail::owner_imbalance(total, owner_, comm_.size());
  });
}

template <int D>
template <class OnRoot>
double Decomposition<D>::partition_on_root(const std::vector<std::int64_t>& work, bool replicated,
                                           OnRoot&& on_root) {
  // Only rank 0 needs the sum: the others keep no copy of the vector.
  std::vector<std::int64_t> total;
  const int count = static_cast<int>(work.size());
  if (replicated) {
    if (comm_.root()) total = work;
  } else {
    if (comm_.root()) total.assign(work.size(), 0);
    MPI_Reduce(work.data(), comm_.root() ? total.data() : nullptr, count, MPI_INT64_T, MPI_SUM, 0,
               comm_.raw());
  }
  // Rank 0 partitions; an error there must reach every rank, which would
  // otherwise wait in the broadcast forever.
  std::string error;
  double result[2] = {0.0, 0.0};  // failed, imbalance of the new map
  if (comm_.root()) {
    try {
      result[1] = on_root(total);
    } catch (const std::exception& e) {
      error = e.what();
      result[0] = 1.0;
    }
  }
  MPI_Bcast(result, 2, MPI_DOUBLE, 0, comm_.raw());
  if (result[0] != 0.0)
    throw std::runtime_error(comm_.root() ? error : "sphdem: partitioning failed");
  MPI_Bcast(owner_.data(), static_cast<int>(owner_.size()), MPI_INT, 0, comm_.raw());
  partitioned_ = true;
  return result[1];
}

template <int D>
double Decomposition<D>::imbalance(const SphParticles<D>& ps) const {
  return imbalance(cell_work(ps, ps.n_owned));
}

template <int D>
double Decomposition<D>::imbalance(const std::vector<std::int64_t>& work) const {
  const std::int64_t mine = std::accumulate(work.begin(), work.end(), std::int64_t{0});
  const std::int64_t most = comm_.max(mine), all = comm_.sum(mine);
  if (all == 0) return 0.0;
  return static_cast<double>(most) * comm_.size() / static_cast<double>(all) - 1.0;
}

template <int D>
double Decomposition<D>::time_imbalance(double busy_seconds) const {
  const double busy = std::isfinite(busy_seconds) ? std::max(0.0, busy_seconds) : 0.0;
  const double most = comm_.max(busy), total = comm_.sum(busy);
  if (!(total > 0)) return 0.0;
  return most * comm_.size() / total - 1.0;
}

template <int D>
double Decomposition<D>::partition_by_time(const std::vector<std::int64_t>& work,
                                           double busy_seconds) {
  if (comm_.size() == 1) return 0.0;
  const std::int64_t mine = std::accumulate(work.begin(), work.end(), std::int64_t{0});
  const double seconds =
      mine > 0 ? busy_seconds / static_cast<double>(mine) : std::nan("");  // NaN: not measured
  std::vector<double> all(comm_.root() ? static_cast<std::size_t>(comm_.size()) : 0);
  MPI_Gather(&seconds, 1, MPI_DOUBLE, comm_.root() ? all.data() : nullptr, 1, MPI_DOUBLE, 0,
             comm_.raw());
  return partition_on_root(work, false, [&](const std::vector<std::int64_t>& total) {
    const std::vector<double> s = detail::usable_seconds_per_work(all);
    owner_ = detail::owners_for_times(blocks_, total, owner_, s);
    return detail::time_imbalance(total, owner_, s);
  });
}

template class CellGrid<2>;
template class CellGrid<3>;
template class Decomposition<2>;
template class Decomposition<3>;
template std::vector<std::int64_t> weigh_blocks<2>(const CellGrid<2>&,
                                                   const std::vector<std::int64_t>&,
                                                   const std::vector<std::int64_t>&,
                                                   const std::vector<std::uint8_t>&);
template std::vector<std::int64_t> weigh_blocks<3>(const CellGrid<3>&,
                                                   const std::vector<std::int64_t>&,
                                                   const std::vector<std::int64_t>&,
                                                   const std::vector<std::uint8_t>&);

}  // namespace sphdem
