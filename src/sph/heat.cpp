// Temperature of the resin (docs/physics.md "Temperature"): conduction in
// the pairwise form of Cleary & Monaghan (1999, JCP 148:227) and viscous
// heating, and the dummy temperature of the wall particles. Gather
// formulation: each owned resin particle sums over its neighbour list in
// global-id order, so the rate does not depend on the rank count.
#include <cmath>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

double dummy_temperature(const WallThermalLaw& law, double conductivity, double t_mean, double d) {
  if (law.adiabatic) return t_mean;
  double t_surface = law.temperature;
  if (std::isfinite(law.htc) && d > 0.0) {
    const double g = conductivity / d;  // the resin's conductance to the surface
    t_surface = (g * t_mean + law.htc * law.temperature) / (g + law.htc);
  }
  return 2.0 * t_surface - t_mean;
}

template <int D>
void compute_heat_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  const double k = sp.conductivity;
  // The Morris-type Laplacian's lattice correction (sph.hpp), as for the
  // viscosity: the same discrete second moment.
  const double scale = sp.mu_scale / sp.heat_capacity;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const Vec<D> xi = ps.x[i];
    const double rho_i = ps.rho[i], t_i = ps.temperature[i];
    double du = 0.0;
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      const double r2 = (xi - ps.x[j]).squaredNorm();
      const double F = kernel.f(std::sqrt(r2));
      du += conduction_pair(ps.mass[j], rho_i, ps.rho[j], k, k, F, r2, sp.eta2, t_i,
                            ps.temperature[j]);
    }
    double rate = scale * du;
    if (sp.viscous_heating) {
      const double g = ps.shear_rate[i];
      // A viscosity law's particle viscosity, else the Newtonian mu.
      const double mu = sp.variable_viscosity ? ps.viscosity[i] : sp.mu;
      rate += mu * g * g / (rho_i * sp.heat_capacity);
    }
    ps.dtemp[i] = rate;
  }
}

template void compute_heat_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_heat_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
