#pragma once
// Generalized-Newtonian viscosity laws eta(shear rate, T, p) of a polymer
// melt (docs/physics.md "Melt viscosity"):
//   power law  eta = K gd^(n-1)                                (Ostwald-de Waele)
//   Carreau    eta = eta_inf + (eta0 - eta_inf) (1 + (lambda gd)^2)^((n-1)/2)   (Carreau 1972)
//   Cross      eta = eta0 / (1 + (eta0 gd / tau*)^(1-n))       (Cross 1965)
//   Cross-WLF  eta0(T, p) = D1 exp(-A1 (T - T*) / (A2 + T - T*)),
//              T* = D2 + D3 p,  A2 = A2~ + D3 p,  then Cross   (Williams, Landel & Ferry 1955;
//              the form of Kennedy & Zheng, "Flow Analysis of Injection Molds", 2013)
// every one clamped to [min, max]. Header-only: the SPH solver evaluates it
// per particle, the config checks and `sphdem check` estimate with it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sphdem/config/case.hpp"

namespace sphdem {

// The upper limit: `max`, or +infinity when none was given.
inline double viscosity_ceiling(const MeltViscosity& m) {
  return m.max ? *m.max : std::numeric_limits<double>::infinity();
}

// Cross-WLF's zero-shear viscosity at temperature T [K] and pressure p [Pa]
// (negative pressures of the weakly compressible resin count as 0). At or
// below T* (and below the no-flow temperature) the melt does not flow: +inf,
// which the clamp turns into `max`.
inline double cross_wlf_zero_shear(const MeltViscosity& m, double T, double p) {
  const double pp = std::max(p, 0.0);
  const double t_star = m.d2 + m.d3 * pp;
  const double a2 = m.a2_tilde + m.d3 * pp;
  const double dt = T - t_star;
  const double inf = std::numeric_limits<double>::infinity();
  if (m.no_flow_temperature && T < *m.no_flow_temperature) return inf;
  if (!(a2 + dt > 0.0)) return inf;
  return m.d1 * std::exp(-m.a1 * dt / (a2 + dt));
}

// The Cross law with zero-shear viscosity eta0.
inline double cross_law(double eta0, double n, double tau_star, double gamma_dot) {
  if (!std::isfinite(eta0)) return eta0;
  return eta0 / (1.0 + std::pow(eta0 * gamma_dot / tau_star, 1.0 - n));
}

// The unclamped law at shear rate gamma_dot [1/s], temperature T [K] and
// pressure p [Pa] (T and p are read by Cross-WLF only).
inline double viscosity_law(const MeltViscosity& m, double newtonian, double gamma_dot, double T,
                            double p) {
  switch (m.law) {
    case ViscosityLaw::Newtonian:
      return newtonian;
    case ViscosityLaw::PowerLaw:
      // 0^(n-1) is +inf for n < 1 (the clamp's max) and 0 for n > 1.
      return m.consistency * std::pow(gamma_dot, m.n - 1.0);
    case ViscosityLaw::Carreau: {
      const double lg = m.relaxation_time * gamma_dot;
      return m.eta_inf + (m.eta0 - m.eta_inf) * std::pow(1.0 + lg * lg, 0.5 * (m.n - 1.0));
    }
    case ViscosityLaw::Cross:
      return cross_law(m.eta0, m.n, m.tau_star, gamma_dot);
    case ViscosityLaw::CrossWlf:
      return cross_law(cross_wlf_zero_shear(m, T, p), m.n, m.tau_star, gamma_dot);
  }
  return newtonian;
}

// The viscosity a particle takes: the law clamped to [min, max].
inline double melt_viscosity(const MeltViscosity& m, double newtonian, double gamma_dot, double T,
                             double p) {
  const double eta = viscosity_law(m, newtonian, gamma_dot, T, p);
  return std::clamp(eta, m.min, viscosity_ceiling(m));
}

}  // namespace sphdem
