// Particle shifting (numerics.particle_shifting, docs/physics.md "Particle
// shifting"): after the second kick every owned resin particle moves by
//   dr_i = -A h |v_i| dt grad C~_i            (Skillen et al. 2013, CMAME 265:163)
// down the gradient of its concentration with Lind's tensile correction
// (Lind et al. 2012, JCP 231:1499), grad C~ from the free-surface pass
// (src/sph/terms/free_surface.hpp). On the free surface only the part
// tangent to it is kept, dr_i = (I - n_i n_i^T) dr_i (Lind et al. 2012;
// Khayyer et al. 2017, Appl. Ocean Res. 63:170), so the surface does not
// diffuse outward. One shift is capped at 0.1 h, well inside the Verlet
// skin, so a violent step cannot throw a particle past its neighbours.
//
// A shift down grad C is a descent of sum_ij W_ij: it always spreads the
// particles, and a continuity density does not see it, so nothing pulls
// them back (the fountain channel spread 6 % per second, docs/validation.md
// section 17). With numerics.shifting_continuity the shift enters the
// density as a displacement enters the continuity equation
// (terms/continuity.hpp):
//   rho_i += sum_j m_j (dr_i - dr_j) . grad_i W_ij,
// over resin and wall neighbours (walls: dr = 0), at the positions before
// the shift. With equal masses the continuity density is then
// rho0 dp^2 sum_j W_ij plus a constant per particle under both the flow
// and the shift, so a spread lowers the pressure and the resin closes up.
// Neighbours in list (global-id) order: rank-count independent.
#include <cmath>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

namespace {

template <int D>
Vec<D> particle_shift(const SphParams& sp, double dt, const SphParticles<D>& ps, std::size_t i) {
  Vec<D> dr = (-sp.shifting * sp.h * ps.v[i].norm() * dt) * ps.shifting_gradient[i];
  if (ps.free_surface[i] != 0.0) {
    const Vec<D> n = ps.surface_normal[i];
    dr -= n.dot(dr) * n;
  }
  const double cap = 0.1 * sp.h;
  const double len = dr.norm();
  if (len > cap) dr *= cap / len;
  return dr;
}

// The continuity equation's sum over the shifts (the formula above).
template <int D>
void add_shift_density(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    double drho = 0.0;
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) continue;
      const double F = kernel.f(std::sqrt(r2)) * sp.grad_scale;
      drho += ps.mass[j] * F * (ps.shift[i] - ps.shift[j]).dot(x_ij);
    }
    ps.rho[i] += drho;
  }
}

}  // namespace

template <int D>
void shift_particles(const SphParams& sp, double dt, const NeighborList<D>& nl, SphParticles<D>& ps,
                     const std::function<void(SphGroup)>& forward) {
  if (!(sp.shifting > 0.0)) return;
  if (!sp.shifting_continuity) {
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) ps.x[i] += particle_shift<D>(sp, dt, ps, i);
    return;
  }
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    ps.shift[i] = ps.kind[i] == Kind::Fluid ? particle_shift<D>(sp, dt, ps, i) : Vec<D>::Zero();
  forward(SphGroup::Shift);
  add_shift_density<D>(sp, nl, ps);
  for (std::size_t i = 0; i < ps.n_owned; ++i) ps.x[i] += ps.shift[i];
}

template void shift_particles<2>(const SphParams&, double, const NeighborList<2>&, SphParticles<2>&,
                                 const std::function<void(SphGroup)>&);
template void shift_particles<3>(const SphParams&, double, const NeighborList<3>&, SphParticles<3>&,
                                 const std::function<void(SphGroup)>&);

}  // namespace sphdem
