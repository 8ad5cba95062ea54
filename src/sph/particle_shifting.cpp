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
#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
void shift_particles(const SphParams& sp, double dt, SphParticles<D>& ps) {
  if (!(sp.shifting > 0.0)) return;
  const double cap = 0.1 * sp.h;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    Vec<D> dr = (-sp.shifting * sp.h * ps.v[i].norm() * dt) * ps.shifting_gradient[i];
    if (ps.free_surface[i] != 0.0) {
      const Vec<D> n = ps.surface_normal[i];
      dr -= n.dot(dr) * n;
    }
    const double len = dr.norm();
    if (len > cap) dr *= cap / len;
    ps.x[i] += dr;
  }
}

template void shift_particles<2>(const SphParams&, double, SphParticles<2>&);
template void shift_particles<3>(const SphParams&, double, SphParticles<3>&);

}  // namespace sphdem
