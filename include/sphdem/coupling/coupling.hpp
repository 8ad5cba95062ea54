#pragma once
// Two-way SPH-DEM coupling, the drag law (paper Eqs. 7, 8, 10; docs/physics.md "Coupling"
// with its errata; docs/physics.md "Coupling"). The pair kernels that the
// loops call (void fraction, Shepard filter, reaction, continuity with the
// void fraction) live in src/coupling/terms/, one per header. Nothing here
// knows about ranks.
//
// Units: SI. In 2D every quantity is per unit depth, as for the SPH and DEM
// particles: a disk's volume is its area pi d^2/4 (m^3 per m of depth), the
// drag is N/m. A DEM particle of depth t (DemParams::thickness) receives
// t times the per-unit-depth drag; with the default t = 1 m they coincide.
//
// Sign convention: the drag F_d acts ON the DEM particle and points along
// the slip vbar - v_f (the resin drags the particle along); the resin
// receives exactly -F_d, spread over the SPH neighbours.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Coupling parameters. Paper: rho = the resin's reference density, mu =
// its viscosity (900 kg/m^3, 0.1 Pa s).
struct CouplingParams {
  double rho = 0;  // resin density in the drag law [kg/m^3]
  double mu = 0;   // resin viscosity [Pa s]
  // A viscosity law: mu is the resin's local viscosity at the fiber particle
  // (the Shepard mean of its resin neighbours', coupling_loops.cpp).
  bool local_viscosity = false;
  double eps_min = 0.4;     // void fraction clip, eps in [eps_min, 1] (docs: why 0.4)
  double eps_switch = 0.8;  // Ergun for eps <= eps_switch, Wen & Yu above (paper Eq. 8)
};

// Volume of a DEM particle of diameter d: the sphere's pi d^3/6 in 3D, the
// disk's area pi d^2/4 in 2D (volume per unit depth).
template <int D>
inline double particle_volume(double d) {
  if constexpr (D == 2) {
    return std::numbers::pi * d * d / 4.0;
  } else {
    return std::numbers::pi * d * d * d / 6.0;
  }
}

// Particle Reynolds number (docs/physics.md "Coupling"): Re = eps rho |vbar - v_f| d / mu.
inline double particle_reynolds(const CouplingParams& c, double eps, double d, double slip) {
  return eps * c.rho * slip * d / c.mu;
}

// C_d Re for the Schiller-Naumann drag coefficient (paper Eq. 10):
// 24 (1 + 0.15 Re^0.687) for Re <= 1000, else 0.44 Re. Finite as Re -> 0
// (-> 24, Stokes), which is how the drag law uses it.
inline double drag_coefficient_times_re(double re) {
  return re <= 1000.0 ? 24.0 * (1.0 + 0.15 * std::pow(re, 0.687)) : 0.44 * re;
}

// C_d itself (paper Eq. 10), for Re > 0.
inline double drag_coefficient(double re) {
  return drag_coefficient_times_re(re) / re;
}

// K = beta / (1 - eps) [kg/(m^3 s)]: the drag per unit particle volume per
// unit slip, F_d = K V_f (vbar - v_f). Computing K directly (instead of
// beta, then dividing) keeps it finite at eps = 1 and at zero slip:
//   Ergun (eps <= eps_switch):  K = 150 (1-eps) mu / (eps d^2) + 1.75 rho |u_r| / d
//   Wen & Yu (eps > eps_switch): K = (3/4) C_d eps rho |u_r| eps^-2.65 / d
//                                  = (3/4) (C_d Re) mu eps^-2.65 / d^2
// (Re contains eps, see particle_reynolds). eps must already be clipped.
inline double drag_k(const CouplingParams& c, double eps, double d, double slip) {
  if (eps <= c.eps_switch) {
    return 150.0 * (1.0 - eps) * c.mu / (eps * d * d) + 1.75 * c.rho * slip / d;
  }
  const double re = particle_reynolds(c, eps, d, slip);
  return 0.75 * drag_coefficient_times_re(re) * c.mu * std::pow(eps, -2.65) / (d * d);
}

// The momentum-exchange coefficient beta [kg/(m^3 s)] of paper Eq. 8 with
// the errata (Wen & Yu's 3/4, not 7.5; the Ergun inertial term divides by
// d_f): beta = (1 - eps) K. docs/validation.md section 5 and OpenFOAM GidaspowErgunWenYu.
inline double drag_beta(const CouplingParams& c, double eps, double d, double slip) {
  return (1.0 - eps) * drag_k(c, eps, d, slip);
}

// Drag on DEM particle f (paper Eq. 7): F_d = beta/(1-eps) (vbar - v_f) V_f,
// with V_f = particle_volume<D>(d) and eps the clipped void fraction at x_f.
template <int D>
inline Vec<D> drag_force(const CouplingParams& c, double eps, double d, double vol,
                         const Vec<D>& vbar, const Vec<D>& v_f) {
  const Vec<D> slip = vbar - v_f;
  return drag_k(c, eps, d, slip.norm()) * vol * slip;
}

// ---- Reference solutions for the validation tests (src/coupling/reference.cpp).

// Terminal velocity [m/s] of one DEM particle of diameter d and density
// rho_p settling under gravity g (> 0, its magnitude) through still resin,
// with the drag above at a fixed void fraction eps as the only resin force:
//   (rho_p - rho_f) g V = K(eps, d, U) V U   (buoyancy = true)
//   rho_p g V           = K(eps, d, U) V U   (buoyancy = false: the paper's
//                                              model has no pressure-gradient
//                                              force on the fibres)
// V cancels, so the 2D (per unit depth) and 3D answers are the same; the
// template computes both sides with particle_volume<D> to show it. Solved
// by bisection to round-off (K U increases with U). Returns 0 if the net
// weight is not positive.
template <int D>
double terminal_velocity(const CouplingParams& c, double rho_p, double d, double g, double eps,
                         bool buoyancy);

// Relaxation time [s] of a particle at rest in a uniform resin flow in the
// Stokes limit (slip -> 0): tau = m / (K V) = rho_p / K(eps, d, 0). The slip
// decays as exp(-t/tau) while the particle Reynolds number stays small. At
// eps > eps_switch, tau = rho_p d^2 eps^2.65 / (18 mu). No added mass (the
// model has none, unlike docs/validation.md section 4's tau).
double stokes_relaxation_time(const CouplingParams& c, double rho_p, double d, double eps);

// The same, when the resin is a finite, uniform body of mass m_resin that
// receives the reaction (a closed or periodic box): the slip then decays at
// K V (1/m_p + 1/m_resin), tau_2 = tau m_resin / (m_resin + m_p).
double two_way_relaxation_time(double tau, double m_particle, double m_resin);

}  // namespace sphdem
