#pragma once
// Local void fraction by kernel averaging of the DEM particle volumes
// (docs/physics.md "Coupling", the paper's "local mean voidage"):
//   eps(x) = 1 - phi(x),   phi(x) = sum_f V_f W(x - x_f),   eps clipped to [eps_min, 1].
// phi is the solid fraction; V_f = particle_volume<D>(d_f) (in 2D the disk
// area, per unit depth). At a DEM particle the sum includes the particle
// itself (V_f W(0)). The kernel is a parameter, so the averaging may use a
// wider smoothing length than the resin's (docs/physics.md: at the paper's
// h/d_f = 1.44 an isolated particle already sees eps = 0.79).
//
// Rate along an SPH particle's path (for the continuity equation):
//   d phi_i/dt = sum_f V_f grad_i W_if . (v_i - v_f) = sum_f V_f F (x_if . v_if),
// the exact time derivative of the kernel sum; d eps_i/dt = -d phi_i/dt.
#include <algorithm>

#include "sphdem/sph/kernel.hpp"

namespace sphdem::terms {

// One DEM particle's share of phi at distance r from it.
template <int D>
inline double solid_fraction(const WendlandC2<D>& k, double vol_f, double r) {
  return vol_f * k.w(r);
}

// eps from the summed solid fraction, clipped to [eps_min, 1].
inline double void_fraction(double phi, double eps_min) {
  return std::clamp(1.0 - phi, eps_min, 1.0);
}

// One DEM particle's share of d phi_i/dt: F = F(r_if) of the kernel,
// vx = (v_i - v_f) . (x_i - x_f).
inline double solid_fraction_rate(double vol_f, double F, double vx) {
  return vol_f * F * vx;
}

// d phi/dt of the CLIPPED void fraction: zero where the clip binds (a
// constant eps does not change), else the raw rate.
inline double clipped_solid_fraction_rate(double phi, double phi_rate, double eps_min) {
  return 1.0 - phi < eps_min ? 0.0 : phi_rate;
}

}  // namespace sphdem::terms
