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
// Only the resin particles with a wall particle in their list walk it
// (NeighborList::resin_near_walls: in the 3D plate a fraction of the
// resin); the others add a zero vector, as the full walk gave them.
#include <algorithm>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
void add_wall_repulsion(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  if (!sp.wall_repulsion) return;
  const double r0 = 0.9 * sp.spacing;
  const double r0_2 = r0 * r0;
  const double strength = sp.c0 * sp.c0;
  const std::int32_t* nb = nl.indices();
  const std::vector<std::int32_t>& near = nl.resin_near_walls();
  std::size_t next = 0;  // the next particle of `near`
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    Vec<D> acc = Vec<D>::Zero();
    const bool walls_listed = next < near.size() && static_cast<std::size_t>(near[next]) == i;
    if (!walls_listed) {
      ps.a[i] += acc;
      continue;
    }
    ++next;
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

template void add_wall_repulsion<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void add_wall_repulsion<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
