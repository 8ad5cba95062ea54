#pragma once
// The serial steps of a (re)partition, run on rank 0 only (decomposition.cpp
// broadcasts the result). Separate functions so tests can check each.
#include <cstdint>
#include <functional>
#include <vector>

namespace sphdem {
template <int D>
class CellGrid;
}

namespace sphdem::detail {

// A graph in compressed rows (the METIS layout): the neighbors of vertex v
// are adjncy[xadj[v] .. xadj[v+1]).
struct Graph {
  std::vector<std::int32_t> xadj{0};
  std::vector<std::int32_t> adjncy;
  std::int32_t vertices() const { return static_cast<std::int32_t>(xadj.size()) - 1; }
};

// Neighbors of a cell of the full grid: writes them to `out`, returns count.
using CellNeighbors = std::function<int(long cell, long* out)>;

// The subgraph of the cell graph induced by `cells` (sorted cell indices).
Graph induced_graph(const std::vector<long>& cells, const CellNeighbors& neighbors);

// METIS k-way partition of `g` with vertex weights `weight` into `parts`
// parts (weights scaled down if their sum would overflow METIS's 32-bit
// integers). Fewer vertices than parts: vertex v goes to part v. Throws
// std::runtime_error when METIS fails.
// `targets`: each part's fraction of the total weight (METIS's tpwgts,
// summing to 1); empty: equal parts.
std::vector<int> partition_graph(const Graph& g, const std::vector<std::int64_t>& weight, int parts,
                                 const std::vector<double>& targets = {});

// Owners for every cell: `owner` holds the part of the partitioned cells and
// -1 elsewhere; a breadth-first search from the partitioned cells (in cell
// order) gives each other cell the part of its nearest partitioned cell.
// Cells that no partitioned cell reaches go to part 0.
void attach_empty_cells(std::vector<int>& owner, const CellNeighbors& neighbors);

// Renames the parts of `fresh` so that as much work as possible keeps its
// rank from `old`: greedy on the overlap (old rank, new part) -> work, the
// largest overlap first; parts left over take the unused ranks in order.
std::vector<int> relabel_parts(const std::vector<int>& old, const std::vector<int>& fresh,
                               const std::vector<std::int64_t>& work, int parts);

// The whole serial partition: METIS on the graph of the cells with work > 0
// (weights: `work`), empty cells attached to their nearest part, and with
// `relabel` the parts renamed to keep work on its rank from `old`. Returns
// the owner of every cell of `grid`. A run calls it on its grid of blocks
// (top-level cells, Decomposition::block_grid), so its cost grows with the
// rank count, not with the case.
template <int D>
std::vector<int> compute_owners(const CellGrid<D>& grid, const std::vector<std::int64_t>& work,
                                const std::vector<int>& old, bool relabel, int parts,
                                const std::vector<double>& targets = {});

// Balancing measured time (parallel.balance_weight: time; docs/parallel.md).
// Each rank's seconds per unit of work as measured (not a positive finite
// number: nothing measured), made usable: an unmeasured rank takes the
// median of the measured ones (1 when none is), and each is kept within a
// factor kMaxTimeFactor of that median (one stalled interval must not
// empty a rank, nor one outlier move the others).
inline constexpr double kMaxTimeFactor = 3.0;
std::vector<double> usable_seconds_per_work(std::vector<double> seconds);

// max / mean - 1 of the predicted times: rank r takes seconds[r] per unit
// of the work of the cells it owns; 0 without work.
double time_imbalance(const std::vector<std::int64_t>& work, const std::vector<int>& owner,
                      const std::vector<double>& seconds);

// The owners that balance the predicted times, all partitions of the
// model's work by METIS. Candidates: the model's equal parts relabelled to
// `old`; parts sized by the speeds (1 / seconds) of the ranks the
// relabelling gave them, assigned as sized and as relabelled (up to three
// rounds, until the two agree); parts sized for rank r taken by rank r
// whatever they overlap. Among those within kImbalanceMargin of the lowest
// predicted time imbalance, the one that moves the least work.
inline constexpr double kImbalanceMargin = 0.02;
template <int D>
std::vector<int> owners_for_times(const CellGrid<D>& grid, const std::vector<std::int64_t>& work,
                                  const std::vector<int>& old, const std::vector<double>& seconds);

// max / mean - 1 of the work per part when cell c (work[c]) goes to part
// owner[c]; 0 without work.
double owner_imbalance(const std::vector<std::int64_t>& work, const std::vector<int>& owner,
                       int parts);

}  // namespace sphdem::detail
