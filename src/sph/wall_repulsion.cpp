// The wall's short-range repulsion (numerics.wall_repulsion, docs/physics.md
// "Jet impacts"): a resin particle i closer than r0 = 0.9 dp to a wall
// particle j is pushed away by the Lennard-Jones boundary force of
// Monaghan (1994, JCP 110:399),
//   a_i += D ((r0/r)^12 - (r0/r)^4) x_ij / r^2,   D = c0^2,
// zero at r >= r0. Resin at rest is at least dp from every wall particle
// (a lattice dp/2 from the surface, walls dp/2 behind it), so the force is
// off in ordinary flow; in an impact its potential exceeds the kinetic
// energy of any particle slower than c0 before the particle reaches the
// wall surface (dp/2 in front of the first layer), so no resin crosses a
// wall (tests/test_free_surface.cpp, JetImpact).
// Neighbours in list (global-id) order: the sum is rank-count independent.
// Only the resin particles the pair loop found with a neighbour within r0
// (CloseNeighbours, pair_loop.hpp) are visited; the others have no wall
// within r0, so their sum is empty.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
double wall_repulsion_range2(const SphParams& sp) {
  if (!sp.wall_repulsion) return -1.0;
  const double r0 = 0.9 * sp.spacing;
  // A margin over r0^2: the pair loop's r^2 may round differently from
  // squaredNorm below; this loop decides each pair exactly.
  return r0 * r0 * (1.0 + 1e-6);
}

template <int D>
void add_wall_repulsion(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                        std::span<const std::uint32_t> candidates) {
  if (!sp.wall_repulsion) return;
  const double r0 = 0.9 * sp.spacing;
  const double r0_2 = r0 * r0;
  const double strength = sp.c0 * sp.c0;
  for (const std::uint32_t c : candidates) {
    const std::size_t i = c;
    if (ps.kind[i] != Kind::Fluid) continue;
    Vec<D> acc = Vec<D>::Zero();
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      if (ps.kind[j] != Kind::Wall) continue;
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < r0_2)) continue;
      const double s2 = r0_2 / std::max(r2, 1e-6 * r0_2);  // (r0/r)^2, finite at r = 0
      const double s4 = s2 * s2;
      const double s12 = s4 * s4 * s4;
      acc += (strength * (s12 - s4) / std::max(r2, 1e-6 * r0_2)) * x_ij;
    }
    ps.a[i] += acc;
  }
}

template <int D>
void add_wall_repulsion(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  std::vector<std::uint32_t> all(ps.n_owned);
  for (std::size_t i = 0; i < ps.n_owned; ++i) all[i] = static_cast<std::uint32_t>(i);
  add_wall_repulsion<D>(sp, nl, ps, all);
}

template double wall_repulsion_range2<2>(const SphParams&);
template double wall_repulsion_range2<3>(const SphParams&);
template void add_wall_repulsion<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&,
                                    std::span<const std::uint32_t>);
template void add_wall_repulsion<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&,
                                    std::span<const std::uint32_t>);
template void add_wall_repulsion<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void add_wall_repulsion<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
