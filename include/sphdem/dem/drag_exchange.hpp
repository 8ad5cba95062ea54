#pragma once
// Exponential drag (fibers.drag_integration: exponential; docs/physics.md
// "Exponential drag"). A fiber particle of mass m and the resin it sits in,
// a parcel of mass M moving at u, exchange momentum through the linear drag
// c (u - v), c = K V_f [kg/s]. Alone, the two relax to their common velocity:
// the slip u - v decays as exp(-t c (1/m + 1/M)), and the impulse on the
// particle over dt is exactly
//   J = mu (1 - exp(-dt c / mu)) (u - v),   mu = m M / (m + M),
// the parcel receiving -J: momentum is conserved to round-off and the
// exchange never overshoots, at any dt (the pairwise exact solution of
// Loren-Aguilar & Bate 2014, MNRAS 443, 927, for dust and gas in SPH; the
// two-fluid drag regimes of Laibe & Price 2012, MNRAS 420, 2365). As
// dt -> 0 it is the explicit drag c (u - v) dt.
#include <cmath>

#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

// J on the particle; parcel_mass <= 0 stands for a resin too heavy to move
// (mu = m).
template <int D>
inline Vec<D> drag_exchange_impulse(double c, double m, double parcel_mass, double dt,
                                    const Vec<D>& slip) {
  const double mu = parcel_mass > 0 ? m * parcel_mass / (m + parcel_mass) : m;
  return (-std::expm1(-dt * c / mu) * mu) * slip;
}

// One exchange of owned particle i over dt: v and the parcel's velocity
// (drag_velocity) relax together, the impulse is added to drag_impulse (what
// the resin gets back at the next coupling pass); the spin relaxes towards
// the resin's (held: the torque's reaction is returned through its lever,
// docs/physics.md "Hydrodynamic torque") and the angular impulse goes to
// torque_impulse.
template <int D>
inline void relax_drag(DemParticles<D>& ps, std::size_t i, double dt) {
  if (ps.drag_coeff[i] > 0) {
    const Vec<D> j = drag_exchange_impulse<D>(ps.drag_coeff[i], ps.mass[i], ps.drag_parcel_mass[i],
                                              dt, Vec<D>(ps.drag_velocity[i] - ps.v[i]));
    ps.v[i] += j / ps.mass[i];
    if (ps.drag_parcel_mass[i] > 0) ps.drag_velocity[i] -= j / ps.drag_parcel_mass[i];
    ps.drag_impulse[i] += j;
  }
  if (ps.torque_coeff[i] > 0) {
    const Rot<D> l = (-std::expm1(-dt * ps.torque_coeff[i] / ps.inertia[i]) * ps.inertia[i]) *
                     (ps.resin_spin[i] - ps.omega[i]);
    ps.omega[i] += l / ps.inertia[i];
    ps.torque_impulse[i] += l;
  }
}

}  // namespace sphdem
