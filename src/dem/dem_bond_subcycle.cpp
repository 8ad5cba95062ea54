// Bond sub-cycling (docs/dem.md, "Bond sub-cycling"): the bonds' forces and
// everything else evaluated apart, for the impulse multiple-time-step
// integrator of DemDomain::advance (Tuckerman, Berne & Martyna 1992, J.
// Chem. Phys. 97, 1990). Same gather formulation as dem_forces.cpp: each
// owned particle adds its pairs' results in increasing partner gid, so the
// sums are the same on any number of ranks.
#include <algorithm>
#include <cmath>
#include <functional>

#include "dem_bond_chains.hpp"
#include "dem_kernels.hpp"
#include "sphdem/core/clamped_cast.hpp"
#include "sphdem/dem/dem_profile.hpp"
#include "sphdem/dem/drag_exchange.hpp"

namespace sphdem {

namespace {

// An intact bond: its pair is evaluated in the inner steps only.
template <int D>
bool bonded(const DemPair<D>& pr) {
  return pr.bond >= 0;
}

}  // namespace

template <int D>
void compute_dem_bond_forces(const DemParams<D>& p, double dt, DemParticles<D>& ps,
                             DemWorkspace<D>& ws) {
  dem_detail::DemProfile& prof = dem_detail::dem_profile();
  dem_detail::DemTimer t_pairs(prof.pairs);
  BondLawCache<D> laws(p);
  for (DemPair<D>& pr : ws.pairs) {
    if (!bonded(pr)) continue;
    evaluate_pair<D>(p, dt, ps, pr, laws);  // a bond that breaks leaves the set
    if (!pr.active) ws.bond_broke = true;
  }
  t_pairs.stop();
  const dem_detail::DemTimer t_gather(prof.gather);
  const std::size_t n_own = ps.n_owned;
  ws.bond_force.assign(n_own, Vec<D>::Zero());
  ws.bond_torque.assign(n_own, Rot<D>::Zero());
  for (std::size_t i = 0; i < n_own; ++i) {
    Vec<D> f = Vec<D>::Zero();
    Rot<D> t = Rot<D>::Zero();
    gather_pairs<D>(ws, i, f, t, bonded<D>);
    ws.bond_force[i] = f;
    ws.bond_torque[i] = t;
  }
}

template <int D>
void compute_dem_slow_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                             DemParticles<D>& ps, DemWorkspace<D>& ws) {
  dem_detail::DemProfile& prof = dem_detail::dem_profile();
  dem_detail::DemTimer t_pairs(prof.pairs);
  BondLawCache<D> laws(p);
  for (DemPair<D>& pr : ws.pairs)
    if (!bonded(pr)) evaluate_pair<D>(p, dt, ps, pr, laws);
  t_pairs.stop();
  dem_detail::DemTimer t_gather(prof.gather);
  const std::size_t n_own = ps.n_owned;
  for (std::size_t i = 0; i < n_own; ++i) {
    ps.drag_force[i] = p.exponential_drag
                           ? Vec<D>::Zero()
                           : Vec<D>(ps.drag_coeff[i] * (ps.drag_velocity[i] - ps.v[i]));
    Vec<D> f =
        ps.mass[i] * (p.gravity - p.global_damping * ps.v[i]) + ps.f_ext[i] + ps.drag_force[i];
    // The resin's torque, a slow force as the drag (dem_forces.cpp).
    ps.hydro_torque[i] = p.exponential_drag
                             ? Rot<D>::Zero()
                             : Rot<D>(ps.torque_coeff[i] * (ps.resin_spin[i] - ps.omega[i]));
    Rot<D> t = -p.global_damping * ps.inertia[i] * ps.omega[i] + ps.hydro_torque[i];
    gather_pairs<D>(ws, i, f, t, [](const DemPair<D>& pr) { return !bonded(pr); });
    ps.force[i] = f;
    ps.torque[i] = t;
  }
  t_gather.stop();
  const dem_detail::DemTimer t_walls(prof.walls);
  for (std::size_t i = 0; i < n_own; ++i) {
    wall_forces<D>(p, dt, walls, ps, i, ws.wall_items.data() + ws.wall_start[i],
                   ws.wall_start[i + 1] - ws.wall_start[i]);
  }
  ws.forces_valid = true;
}

// v += dt/m (F_bond + F_slow): the inner kicks, the slow force held.
template <int D>
void dem_kick_all(const DemParams<D>& p, double dt, DemParticles<D>& ps,
                  const DemWorkspace<D>& ws) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.fixed[i] & kFixedMotion) continue;
    ps.v[i] += (dt / ps.mass[i]) * (ws.bond_force[i] + ps.force[i]);
    ps.omega[i] += (dt / ps.inertia[i]) * (ws.bond_torque[i] + ps.torque[i]);
    ps.drag_impulse[i] += dt * ps.drag_force[i];
    ps.torque_impulse[i] += dt * ps.hydro_torque[i];
    if (p.exponential_drag) relax_drag<D>(ps, i, dt);
  }
}

// The slow forces' trapezoid correction, dt/2 (F_new - F_old)/m, with
// F_old the held force of the outer step (saved in ws after any rebuild).
template <int D>
void dem_slow_correction(double dt, DemParticles<D>& ps, const DemWorkspace<D>& ws) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  const double half = 0.5 * dt;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.fixed[i] & kFixedMotion) continue;
    ps.v[i] += (half / ps.mass[i]) * (ps.force[i] - ws.held_force[i]);
    ps.omega[i] += (half / ps.inertia[i]) * (ps.torque[i] - ws.held_torque[i]);
    ps.drag_impulse[i] += half * (ps.drag_force[i] - ws.held_drag[i]);
    ps.torque_impulse[i] += half * (ps.hydro_torque[i] - ws.held_hydro_torque[i]);
  }
}

template <int D>
void dem_drift(double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  for (std::size_t i = 0; i < ps.n_owned; ++i) ps.x[i] += dt * ps.v[i];
  for (DemWall<D>& w : walls) {
    w.point += dt * w.velocity;
    w.end += dt * w.velocity;
  }
}

// The end of an outer step: the slow forces at the new state and their
// trapezoid correction against the ones held over the step.
template <int D>
void finish_outer_step(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                       DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const std::size_t n = ps.n_owned;
  ws.held_force.assign(ps.force.begin(), ps.force.begin() + static_cast<std::ptrdiff_t>(n));
  ws.held_torque.assign(ps.torque.begin(), ps.torque.begin() + static_cast<std::ptrdiff_t>(n));
  ws.held_drag.assign(ps.drag_force.begin(),
                      ps.drag_force.begin() + static_cast<std::ptrdiff_t>(n));
  ws.held_hydro_torque.assign(ps.hydro_torque.begin(),
                              ps.hydro_torque.begin() + static_cast<std::ptrdiff_t>(n));
  compute_dem_slow_forces(p, dt, walls, ps, ws);
  dem_slow_correction(dt, ps, ws);
}

// The slow forces are held over the inner steps and corrected by the
// trapezoid rule at the end: for the slow forces alone this is velocity
// Verlet exactly (x gains dt v + dt^2/2 a_n, v gains dt/2 (a_n + a_n+1)),
// and a static equilibrium (F_bond + F_slow = 0 at rest) stays put, which
// the impulse form of r-RESPA does not (its kicks shake the bonds at every
// outer step: a glass cantilever settled 3 % off).
template <int D>
void dem_subcycled_step(const DemParams<D>& p, double dt, std::int64_t inner,
                        std::vector<DemWall<D>>& walls, DemParticles<D>& ps, DemWorkspace<D>& ws,
                        const std::function<void()>& refresh_ghosts,
                        const std::function<void()>& settle) {
  if (!ws.forces_valid) compute_dem_slow_forces(p, 0.0, walls, ps, ws);
  // Read again at every outer step (a rebuild reorders the particles), so
  // a restart, which has no bond forces stored, continues bitwise.
  compute_dem_bond_forces(p, 0.0, ps, ws);
  const double h = dt / static_cast<double>(inner);
  for (std::int64_t k = 0; k < inner; ++k) {
    dem_kick_all(p, 0.5 * h, ps, ws);
    dem_drift(h, walls, ps);
    refresh_ghosts();
    compute_dem_bond_forces(p, h, ps, ws);
    dem_kick_all(p, 0.5 * h, ps, ws);
  }
  settle();  // may migrate: the held forces travel in force, torque, drag_force
  finish_outer_step(p, dt, walls, ps, ws);
}

// The trapezoidal rule for the bonds (Newmark's average acceleration:
// x_n+1 = x_n + dt v_n + dt^2/4 (a_n + a_n+1)) with the slow forces held as
// in dem_subcycled_step: after the half kick v_half = v_n + dt/2 a_n the
// drift is dt u with (M + dt^2/4 K) u = M v_half, K the bonds' stiffness
// linearised at x_n, one banded solve per chain. The bonds then advance
// by their own (nonlinear, rotating) law over exactly that motion, and the
// second half kick uses their new forces, so momentum is exact and a
// linear chain is integrated by the trapezoidal rule: stable at any step,
// no numerical damping.
template <int D>
void dem_implicit_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls,
                       DemParticles<D>& ps, DemWorkspace<D>& ws,
                       const std::function<void()>& refresh_ghosts,
                       const std::function<void()>& settle) {
  if (!ws.forces_valid) compute_dem_slow_forces(p, 0.0, walls, ps, ws);
  compute_dem_bond_forces(p, 0.0, ps, ws);  // as dem_subcycled_step: restarts bitwise
  dem_kick_all(p, 0.5 * dt, ps, ws);
  refresh_ghosts();  // the chains' half-step velocities
  if (!ws.chains_valid) dem_detail::build_bond_chains(ps, ws);
  dem_detail::solve_bond_chains(p, dt, ps, ws);
  dem_drift(dt, walls, ps);
  refresh_ghosts();
  compute_dem_bond_forces(p, dt, ps, ws);  // the bond law over the drift dt u
  dem_detail::restore_half_velocities(ps, ws);
  dem_kick_all(p, 0.5 * dt, ps, ws);
  settle();
  finish_outer_step(p, dt, walls, ps, ws);
}

template <int D>
std::int64_t dem_bond_substeps(const DemParams<D>& p, double dt) {
  if (!(p.bond_dt > 0) || !(dt > p.bond_dt)) return 1;
  return substep_count(dt / p.bond_dt * (1 - 1e-12), "bond sub-steps per DEM step");
}

// Contacts alone: k_n for the translation, k_t R^2 for the spin (docs/dem.md).
template <int D>
double stable_dem_contact_dt(const DemParams<D>& p, const DemParticles<D>& ps) {
  double dt = std::numeric_limits<double>::infinity();
  const double kt = p.kt_over_kn * p.kn;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (p.kn > 0) dt = std::min(dt, std::sqrt(ps.mass[i] / p.kn));
    const double kr = kt * ps.radius[i] * ps.radius[i];
    if (kr > 0) dt = std::min(dt, std::sqrt(ps.inertia[i] / kr));
  }
  return p.dt_safety * dt;
}

template <int D>
double stable_dem_outer_dt(const DemParams<D>& p, const DemParticles<D>& ps) {
  const double contact = stable_dem_contact_dt(p, ps);
  return std::max(p.bond_dt, p.implicit_bonds ? contact / kImplicitStepsPerContactStep : contact);
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                                 \
  template void compute_dem_bond_forces<D>(const DemParams<D>&, double, DemParticles<D>&,         \
                                           DemWorkspace<D>&);                                     \
  template void compute_dem_slow_forces<D>(const DemParams<D>&, double,                           \
                                           const std::vector<DemWall<D>>&, DemParticles<D>&,      \
                                           DemWorkspace<D>&);                                     \
  template void dem_drift<D>(double, std::vector<DemWall<D>>&, DemParticles<D>&);                 \
  template double stable_dem_contact_dt<D>(const DemParams<D>&, const DemParticles<D>&);          \
  template double stable_dem_outer_dt<D>(const DemParams<D>&, const DemParticles<D>&);            \
  template void dem_subcycled_step<D>(                                                            \
      const DemParams<D>&, double, std::int64_t, std::vector<DemWall<D>>&, DemParticles<D>&,      \
      DemWorkspace<D>&, const std::function<void()>&, const std::function<void()>&);              \
  template void dem_implicit_step<D>(const DemParams<D>&, double, std::vector<DemWall<D>>&,       \
                                     DemParticles<D>&, DemWorkspace<D>&,                          \
                                     const std::function<void()>&, const std::function<void()>&); \
  template std::int64_t dem_bond_substeps<D>(const DemParams<D>&, double);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
