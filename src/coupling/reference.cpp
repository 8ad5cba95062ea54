// Reference solutions of the coupling's drag law, for the validation tests
// (include/sphdem/coupling/coupling.hpp): terminal settling velocity and the Stokes
// relaxation time.
#include <cmath>

#include "sphdem/coupling/coupling.hpp"

namespace sphdem {

template <int D>
double terminal_velocity(const CouplingParams& c, double rho_p, double d, double g, double eps,
                         bool buoyancy) {
  const double vol = particle_volume<D>(d);
  const double weight = (buoyancy ? rho_p - c.rho : rho_p) * g * vol;
  if (!(weight > 0.0)) return 0.0;
  const auto excess = [&](double u) { return drag_k(c, eps, d, u) * vol * u - weight; };
  // Bracket: drag(0) = 0 < weight; double until the drag exceeds it.
  double lo = 0.0, hi = 1e-6;
  while (excess(hi) < 0.0) {
    lo = hi;
    hi *= 2.0;
  }
  // Bisection to adjacent doubles (K u is monotone in u).
  for (int it = 0; it < 2000; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (excess(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

template double terminal_velocity<2>(const CouplingParams&, double, double, double, double, bool);
template double terminal_velocity<3>(const CouplingParams&, double, double, double, double, bool);

double stokes_relaxation_time(const CouplingParams& c, double rho_p, double d, double eps) {
  return rho_p / drag_k(c, eps, d, 0.0);
}

double two_way_relaxation_time(double tau, double m_particle, double m_resin) {
  return tau * m_resin / (m_resin + m_particle);
}

}  // namespace sphdem
