#pragma once
// Which ranks need a ghost copy of a particle (docs/parallel.md, "Halo"):
// shared by the SPH halo and the DEM halo, and the ghost build itself.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "exchange.hpp"
#include "ghost_fields.hpp"
#include "sphdem/parallel/decomposition.hpp"

namespace sphdem::detail {

template <int D>
struct GhostTarget {
  int rank;
  Vec<D> shift;
};

// Distance from x (in cell c along axis k) to the neighbor cell at offset o.
template <int D>
inline double gap(const CellGrid<D>& g, const Vec<D>& x, int k, long c, long o) {
  if (o < 0) return std::max(0.0, x[k] - g.lower(k, c));
  if (o > 0) return std::max(0.0, g.lower(k, c + 1) - x[k]);
  return 0.0;
}

// The coordinates m of the neighbor cell at offset o of cell c, wrapped
// across periodic faces (shift: what the copy's position gains); false
// outside a closed face.
template <int D>
inline bool offset_coords(const CellGrid<D>& g, const typename CellGrid<D>::Coords& c,
                          const std::array<long, 3>& o, Vec<D>& shift,
                          typename CellGrid<D>::Coords& m) {
  m = c;
  shift.setZero();
  for (int k = 0; k < D; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    m[uk] = c[uk] + o[uk];
    if (m[uk] >= 0 && m[uk] < g.dims()[uk]) continue;
    if (!g.periodic(k)) return false;
    const bool below = m[uk] < 0;
    m[uk] += below ? g.dims()[uk] : -g.dims()[uk];
    shift[k] = below ? g.length(k) : -g.length(k);
  }
  return true;
}

// Every (rank, shift) that needs a copy of the owned particle at x: the
// owners of the neighbor cells within `range` of x, except this rank
// without a shift (the particle itself).
template <int D>
inline void ghost_targets(const Decomposition<D>& dec, const Vec<D>& x, double range,
                          std::vector<GhostTarget<D>>& out) {
  out.clear();
  const CellGrid<D>& g = dec.grid();
  const auto c = g.coords(x);
  // A hair wider than the neighbor search (which keeps r^2 < range^2), so
  // rounding in the cell bounds can only add a ghost, never lose one.
  const double r2 = range * range * (1.0 + 1e-9);
  const long z = D == 3 ? 1 : 0;
  for (long oz = -z; oz <= z; ++oz)
    for (long oy = -1; oy <= 1; ++oy)
      for (long ox = -1; ox <= 1; ++ox) {
        const std::array<long, 3> o{ox, oy, oz};
        if (ox == 0 && oy == 0 && oz == 0) continue;
        double d2 = 0.0;
        for (int k = 0; k < D; ++k) {
          const double d =
              gap<D>(g, x, k, c[static_cast<std::size_t>(k)], o[static_cast<std::size_t>(k)]);
          d2 += d * d;
        }
        if (d2 >= r2) continue;
        GhostTarget<D> t{0, Vec<D>::Zero()};
        typename CellGrid<D>::Coords m;
        if (!offset_coords<D>(g, c, o, t.shift, m)) continue;
        t.rank = dec.owner_of_coords(m);
        if (t.rank == dec.comm().rank() && t.shift.isZero(0.0)) continue;
        const auto same = [&](const GhostTarget<D>& u) {
          return u.rank == t.rank && u.shift == t.shift;
        };
        if (std::none_of(out.begin(), out.end(), same)) out.push_back(t);
      }
}

// Whether a cell is interior: its neighbor cells (within the grid) are all
// this rank's and none lies across a periodic face, so a particle in it
// needs no copy anywhere (ghost_targets would find none). Decided once per
// cell visited, so a ghost build looks at the 26 neighbors of the cells
// near a rank boundary only.
template <int D>
class InteriorCells {
 public:
  explicit InteriorCells(const Decomposition<D>& dec)
      : dec_(dec), state_(static_cast<std::size_t>(dec.grid().cells()), kUnknown) {}
  bool contains(const Vec<D>& x) {
    const CellGrid<D>& g = dec_.grid();
    const auto c = g.coords(x);
    std::uint8_t& s = state_[static_cast<std::size_t>(g.index(c))];
    if (s == kUnknown) s = decide(g, c) ? kInterior : kBoundary;
    return s == kInterior;
  }

 private:
  static constexpr std::uint8_t kUnknown = 0, kInterior = 1, kBoundary = 2;
  // The cells around c within the grid (beyond a closed face nobody is
  // there), none across a periodic face, all owned here: tested per block
  // of the decomposition the 3^D cells overlap (usually one), not per cell.
  bool decide(const CellGrid<D>& g, const typename CellGrid<D>::Coords& c) const {
    typename CellGrid<D>::Coords lo = c, hi = c;
    for (int k = 0; k < D; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      const long last = g.dims()[uk] - 1;
      if (g.periodic(k) && (c[uk] == 0 || c[uk] == last)) return false;  // a wrapped neighbor
      lo[uk] = std::max(0L, c[uk] - 1);
      hi[uk] = std::min(last, c[uk] + 1);
    }
    return dec_.owns_cells(lo, hi, dec_.comm().rank());
  }
  const Decomposition<D>& dec_;
  std::vector<std::uint8_t> state_;
};

// Collective. Drops the ghosts of `ps` (SPH or DEM particles) and appends
// the new ones after the owned particles, ordered by source rank, then by
// the source's local order, with every kGhost field (positions shifted).
// Fills the plan that the per-step forward exchanges reuse: routes, the
// owned source of each copy sent (grouped by rank) and its periodic shift.
template <int D, class P>
void build_ghosts(const Decomposition<D>& dec, P& ps, double range, GhostPlan<D>& plan,
                  std::vector<char>& send_buf, std::vector<char>& recv_buf) {
  ps.clear_ghosts();
  const MPI_Comm comm = dec.comm().raw();
  const auto ranks = static_cast<std::size_t>(dec.comm().size());

  // Copies grouped by destination rank (counting sort keeps local order).
  std::vector<std::pair<int, std::size_t>> copies;  // rank, owned index
  std::vector<Vec<D>> shifts;
  std::vector<GhostTarget<D>> targets;
  std::vector<std::int64_t> counts(ranks, 0);
  InteriorCells<D> interior(dec);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (interior.contains(ps.x[i])) continue;
    ghost_targets<D>(dec, ps.x[i], range, targets);
    for (const GhostTarget<D>& t : targets) {
      copies.emplace_back(t.rank, i);
      shifts.push_back(t.shift);
      ++counts[static_cast<std::size_t>(t.rank)];
    }
  }
  plan.send = route_from_counts(counts);
  plan.recv = route_from_counts(transpose_counts(comm, counts));
  plan.recv_slot.clear();
  std::vector<std::size_t> next(ranks + 1, 0);
  for (std::size_t r = 0; r < ranks; ++r)
    next[r + 1] = next[r] + static_cast<std::size_t>(counts[r]);
  plan.send_index.assign(copies.size(), 0);
  plan.send_shift.assign(copies.size(), Vec<D>::Zero());
  for (std::size_t k = 0; k < copies.size(); ++k) {
    const std::size_t at = next[static_cast<std::size_t>(copies[k].first)]++;
    plan.send_index[at] = copies[k].second;
    plan.send_shift[at] = shifts[k];
  }

  // Every ghost field once (the constants are never sent again).
  const std::size_t n_own = ps.n_owned;
  // The fields grow by a small margin (resize_field, field_registry.hpp),
  // not by doubling, so a thin halo costs no copy of the owned fields.
  ps.resize(n_own + plan.recv.total());
  ps.n_owned = n_own;
  send_fields(
      comm, plan, ps, [](FieldPolicy p) { return p.ghost; }, send_buf, recv_buf);
}

}  // namespace sphdem::detail
