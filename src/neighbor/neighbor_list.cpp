#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "sphdem/neighbor/neighbor.hpp"

namespace sphdem {

namespace {

template <int D>
struct Grid {
  Vec<D> lo;
  double inv_cell = 1;
  std::array<long, 3> n{1, 1, 1};

  long coord(const Vec<D>& x, int k) const {
    const long c = static_cast<long>(std::floor((x[k] - lo[k]) * inv_cell));
    return std::clamp(c, 0L, n[k] - 1);
  }
  long index(const Vec<D>& x) const {
    long id = 0;
    for (int k = D - 1; k >= 0; --k) id = id * n[k] + coord(x, k);
    return id;
  }
  long cells() const { return n[0] * n[1] * n[2]; }
};

template <int D>
Grid<D> make_grid(const std::vector<Vec<D>>& x, std::size_t count, double cell) {
  Grid<D> g;
  Vec<D> hi;
  g.lo.setConstant(std::numeric_limits<double>::infinity());
  hi.setConstant(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < count; ++i) {
    g.lo = g.lo.cwiseMin(x[i]);
    hi = hi.cwiseMax(x[i]);
  }
  if (count == 0) {
    g.lo.setZero();
    hi.setZero();
  }
  g.inv_cell = 1.0 / cell;
  for (int k = 0; k < D; ++k) {
    g.n[k] = std::max(1L, static_cast<long>(std::floor((hi[k] - g.lo[k]) * g.inv_cell)) + 1);
  }
  return g;
}

// Counting sort of particles into cells.
template <int D>
void bin(const Grid<D>& g, const std::vector<Vec<D>>& x, std::size_t count,
         std::vector<std::int32_t>& start, std::vector<std::int32_t>& items) {
  start.assign(static_cast<std::size_t>(g.cells()) + 1, 0);
  // Scratch kept across rebuilds (no fresh pages at every rebuild).
  thread_local std::vector<std::int32_t> cell_of, fill;
  cell_of.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    cell_of[i] = static_cast<std::int32_t>(g.index(x[i]));
    ++start[static_cast<std::size_t>(cell_of[i]) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  items.resize(count);
  fill.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < count; ++i) items[fill[cell_of[i]]++] = static_cast<std::int32_t>(i);
}

}  // namespace

template <int D>
void NeighborList<D>::build(const SphParticles<D>& ps) {
  const std::size_t n = ps.size(), n_own = ps.n_owned;
  const double rc = cutoff(), rc2 = rc * rc;
  const Grid<D> g = make_grid<D>(ps.x, n, rc);
  bin<D>(g, ps.x, n, cell_start_, cell_items_);

  offset_.assign(n_own + 1, 0);
  index_.clear();
  index_.reserve(n_own * (D == 2 ? 24 : 60));
  for (std::size_t i = 0; i < n_own; ++i) {
    const Vec<D>& xi = ps.x[i];
    const bool wall_i = ps.kind[i] == Kind::Wall;
    std::array<long, 3> c{0, 0, 0}, lo{0, 0, 0}, hi{0, 0, 0};
    for (int k = 0; k < D; ++k) {
      c[k] = g.coord(xi, k);
      lo[k] = std::max(0L, c[k] - 1);
      hi[k] = std::min(g.n[k] - 1, c[k] + 1);
    }
    const std::size_t first = index_.size();
    for (long cz = lo[2]; cz <= hi[2]; ++cz)
      for (long cy = lo[1]; cy <= hi[1]; ++cy)
        for (long cx = lo[0]; cx <= hi[0]; ++cx) {
          const long cell = (cz * g.n[1] + cy) * g.n[0] + cx;
          for (std::int32_t s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s) {
            const std::int32_t j = cell_items_[s];
            if (static_cast<std::size_t>(j) == i) continue;
            if (wall_i && ps.kind[j] == Kind::Wall) continue;
            if ((xi - ps.x[j]).squaredNorm() < rc2) index_.push_back(j);
          }
        }
    // Two periodic images of one particle share a gid (a period shorter
    // than two cut-offs): their position breaks the tie, so the order never
    // depends on where the images sit in memory.
    std::sort(index_.begin() + static_cast<std::ptrdiff_t>(first), index_.end(),
              [&](std::int32_t a, std::int32_t b) {
                if (ps.gid[a] != ps.gid[b]) return ps.gid[a] < ps.gid[b];
                return std::lexicographical_compare(ps.x[a].begin(), ps.x[a].end(), ps.x[b].begin(),
                                                    ps.x[b].end());
              });
    offset_[i + 1] = index_.size();
  }
  x_at_build_.assign(ps.x.begin(), ps.x.begin() + static_cast<std::ptrdiff_t>(n_own));
  ++builds_;
}

template <int D>
bool NeighborList<D>::needs_rebuild(const SphParticles<D>& ps) const {
  if (x_at_build_.size() != ps.n_owned) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if ((ps.x[i] - x_at_build_[i]).squaredNorm() > limit2) return true;
  }
  return false;
}

template <int D>
void sort_by_cell(SphParticles<D>& ps, double cell) {
  const Grid<D> g = make_grid<D>(ps.x, ps.n_owned, cell);
  // Scratch kept across rebuilds (no fresh pages at every rebuild).
  thread_local std::vector<long> key;
  thread_local std::vector<std::size_t> order;
  key.resize(ps.n_owned);
  for (std::size_t i = 0; i < ps.n_owned; ++i) key[i] = g.index(ps.x[i]);
  order.resize(ps.n_owned);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return key[a] != key[b] ? key[a] < key[b] : ps.gid[a] < ps.gid[b];
  });
  ps.permute_owned(order);
}

template class NeighborList<2>;
template class NeighborList<3>;
template void sort_by_cell<2>(SphParticles<2>&, double);
template void sort_by_cell<3>(SphParticles<3>&, double);

}  // namespace sphdem
