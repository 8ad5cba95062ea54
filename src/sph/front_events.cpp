// Weld lines and trapped air (include/sphdem/sph/front_events.hpp,
// docs/physics.md "Weld lines and trapped air").
#include "sphdem/sph/front_events.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sphdem/core/clamped_cast.hpp"

namespace sphdem {

template <int D>
std::vector<WeldMark<D>> mark_weld_lines(const SphParams& sp, const NeighborList<D>& nl,
                                         SphParticles<D>& ps) {
  std::vector<WeldMark<D>> flagged;
  const double support2 = 4.0 * sp.h * sp.h;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid || ps.weld_line[i] != 0 || ps.free_surface[i] == 0.0) continue;
    const Vec<D>& n_i = ps.surface_normal[i];
    const NeighborRow nb = nl.row(i);
    for (std::size_t k = nl.begin(i), e = nl.end(i); k < e; ++k) {
      const std::size_t j = static_cast<std::size_t>(nb[k]);
      if (ps.kind[j] != Kind::Fluid || ps.free_surface[j] == 0.0) continue;
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < support2) || r2 == 0.0) continue;
      const double r = std::sqrt(r2);
      const Vec<D>& n_j = ps.surface_normal[j];
      const bool opposed = n_i.dot(n_j) < -0.5;
      const bool facing = -x_ij.dot(n_i) > 0.5 * r && x_ij.dot(n_j) > 0.5 * r;
      const bool approaching = (ps.v[i] - ps.v[j]).dot(x_ij) < 0.0;
      if (opposed && facing && approaching) {
        ps.weld_line[i] = 1;
        flagged.push_back({i, 0.5 * (ps.x[i] + ps.x[j])});
        break;
      }
    }
  }
  return flagged;
}

template <int D>
VoidGrid<D> make_void_grid(const Box<D>& domain, double spacing) {
  VoidGrid<D> g;
  g.lo = domain.lo;
  g.cell = 0.5 * spacing;
  // Counted as doubles before any cast: an extent of NaN, infinity or a
  // count past the limit is an error, not an integer overflow.
  double cells = 1.0;
  for (int d = 0; d < D; ++d) {
    const double along = std::max(1.0, std::ceil((domain.hi[d] - domain.lo[d]) / g.cell));
    cells *= along;
    if (!(cells <= static_cast<double>(kMaxVoidCells))) {
      throw std::length_error(fmt::format(
          "the trapped-air grid (cells of half the spacing, {:g} m, over the domain) would take "
          "more than 2^31 cells; the domain spans {:.3g} m along axis {}",
          g.cell, domain.hi[d] - domain.lo[d], d));
    }
    g.n[d] = static_cast<std::int64_t>(along);
  }
  return g;
}

namespace {

template <int D>
std::int64_t cell_index(const VoidGrid<D>& g, const std::array<std::int64_t, 3>& c) {
  return c[0] + g.n[0] * (c[1] + g.n[1] * c[2]);
}

}  // namespace

template <int D>
void mark_void_grid(const VoidGrid<D>& g, double spacing, const SphParticles<D>& ps,
                    const std::vector<Shape>& cavity, const std::vector<Shape>& vents,
                    std::vector<double>& marks) {
  marks.resize(static_cast<std::size_t>(3 * g.size()), 0.0);
  if (!vents.empty()) {
    std::array<std::int64_t, 3> c{0, 0, 0};
    for (c[2] = 0; c[2] < g.n[2]; ++c[2])
      for (c[1] = 0; c[1] < g.n[1]; ++c[1])
        for (c[0] = 0; c[0] < g.n[0]; ++c[0]) {
          Vec<D> centre;
          for (int d = 0; d < D; ++d)
            centre[d] = g.lo[d] + (static_cast<double>(c[d]) + 0.5) * g.cell;
          if (!union_contains<D>(cavity, centre))
            marks[static_cast<std::size_t>(3 * cell_index(g, c) + 2)] += 1.0;
        }
  }
  const double r2 = spacing * spacing;
  const int reach = static_cast<int>(std::ceil(spacing / g.cell));
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const bool resin = ps.kind[i] == Kind::Fluid;
    const bool vent = !resin && (vents.empty() || union_contains<D>(vents, ps.x[i]));
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
    for (int d = 0; d < D; ++d) {
      // Clamped before the cast (a NaN or far position): the same cells.
      const std::int64_t c =
          clamped_floor<std::int64_t>((ps.x[i][d] - g.lo[d]) / g.cell, -reach, g.n[d] - 1 + reach);
      lo[d] = std::clamp<std::int64_t>(c - reach, 0, g.n[d] - 1);
      hi[d] = std::clamp<std::int64_t>(c + reach, 0, g.n[d] - 1);
    }
    std::array<std::int64_t, 3> c{0, 0, 0};
    for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2])
      for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
        for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) {
          double d2 = 0;
          for (int d = 0; d < D; ++d) {
            const double centre = g.lo[d] + (static_cast<double>(c[d]) + 0.5) * g.cell;
            d2 += (centre - ps.x[i][d]) * (centre - ps.x[i][d]);
          }
          if (!(d2 <= r2)) continue;  // a NaN position marks nothing
          const auto k = static_cast<std::size_t>(3 * cell_index(g, c));
          marks[k + (resin ? 0 : 1)] += 1.0;
          if (vent) marks[k + 2] += 1.0;
        }
  }
}

template <int D>
std::vector<AirPocket> find_air_pockets(const VoidGrid<D>& g, const std::vector<double>& marks) {
  const std::int64_t n = g.size();
  const auto resin = [&](std::int64_t k) { return marks[static_cast<std::size_t>(3 * k)] > 0; };
  const auto wall = [&](std::int64_t k) { return marks[static_cast<std::size_t>(3 * k + 1)] > 0; };
  const auto vent = [&](std::int64_t k) { return marks[static_cast<std::size_t>(3 * k + 2)] > 0; };
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  std::vector<std::int64_t> stack;
  std::vector<AirPocket> pockets;
  const double cell_size = std::pow(g.cell, D);
  for (std::int64_t start = 0; start < n; ++start) {
    if (seen[static_cast<std::size_t>(start)] || resin(start) || wall(start)) continue;
    // Flood fill one empty region (face neighbours).
    bool open = false;
    std::int64_t count = 0;
    std::array<double, 3> sum{0, 0, 0};
    stack.assign(1, start);
    seen[static_cast<std::size_t>(start)] = 1;
    while (!stack.empty()) {
      const std::int64_t k = stack.back();
      stack.pop_back();
      const std::array<std::int64_t, 3> c{k % g.n[0], (k / g.n[0]) % g.n[1], k / (g.n[0] * g.n[1])};
      ++count;
      for (int d = 0; d < D; ++d) sum[d] += g.lo[d] + (static_cast<double>(c[d]) + 0.5) * g.cell;
      for (int d = 0; d < D; ++d) {
        for (int s = -1; s <= 1; s += 2) {
          std::array<std::int64_t, 3> m = c;
          m[d] += s;
          if (m[d] < 0 || m[d] >= g.n[d]) {
            open = true;  // the border: outside the mold
            continue;
          }
          const std::int64_t q = cell_index(g, m);
          if (vent(q)) open = true;  // air that leaves through a vent: the unfilled cavity
          if (seen[static_cast<std::size_t>(q)] || resin(q) || wall(q)) continue;
          seen[static_cast<std::size_t>(q)] = 1;
          stack.push_back(q);
        }
      }
    }
    // Smaller than one spacing^D (2^D cells): the noise of a particle
    // lifting off a wall, not a pocket.
    if (open || count < (std::int64_t{1} << D)) continue;
    AirPocket p;
    for (int d = 0; d < D; ++d) p.centroid[d] = sum[d] / static_cast<double>(count);
    p.size = static_cast<double>(count) * cell_size;
    pockets.push_back(p);
  }
  return pockets;
}

template std::vector<WeldMark<2>> mark_weld_lines<2>(const SphParams&, const NeighborList<2>&,
                                                     SphParticles<2>&);
template std::vector<WeldMark<3>> mark_weld_lines<3>(const SphParams&, const NeighborList<3>&,
                                                     SphParticles<3>&);
template VoidGrid<2> make_void_grid<2>(const Box<2>&, double);
template VoidGrid<3> make_void_grid<3>(const Box<3>&, double);
template void mark_void_grid<2>(const VoidGrid<2>&, double, const SphParticles<2>&,
                                const std::vector<Shape>&, const std::vector<Shape>&,
                                std::vector<double>&);
template void mark_void_grid<3>(const VoidGrid<3>&, double, const SphParticles<3>&,
                                const std::vector<Shape>&, const std::vector<Shape>&,
                                std::vector<double>&);
template std::vector<AirPocket> find_air_pockets<2>(const VoidGrid<2>&, const std::vector<double>&);
template std::vector<AirPocket> find_air_pockets<3>(const VoidGrid<3>&, const std::vector<double>&);

}  // namespace sphdem
