// The DEM forces (pairs gathered per owned particle, body, external and
// wall forces) and the velocity-Verlet sub-step.
//
// Gather formulation (docs/dem.md, "Pairs"): every pair with an owned
// particle is evaluated once per rank that owns one of its two particles,
// from identical inputs (ghosts are exact copies), into a per-pair result;
// each owned particle then adds its pairs' results in increasing partner
// gid. The sums, and so the trajectories, are bitwise the same on any
// number of ranks, with no reverse communication.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dem_kernels.hpp"
#include "sphdem/dem/dem_profile.hpp"
#include "sphdem/dem/drag_exchange.hpp"

namespace sphdem {

template <int D>
void compute_dem_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                        DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const std::size_t n_own = ps.n_owned;
  dem_detail::DemProfile& prof = dem_detail::dem_profile();
  dem_detail::DemTimer t_pairs(prof.pairs);
  BondLawCache<D> laws(p);
  for (DemPair<D>& pr : ws.pairs) evaluate_pair<D>(p, dt, ps, pr, laws);
  t_pairs.stop();
  dem_detail::DemTimer t_gather(prof.gather);
  for (std::size_t i = 0; i < n_own; ++i) {
    // The resin's drag, linear in the particle's own velocity with the
    // coefficient and resin velocity of the last coupling pass (so it stays
    // stable however many sub-steps the SPH step holds).
    // (Exponential drag: no force, the kicks relax v instead; drag_exchange.hpp.)
    ps.drag_force[i] = p.exponential_drag
                           ? Vec<D>::Zero()
                           : Vec<D>(ps.drag_coeff[i] * (ps.drag_velocity[i] - ps.v[i]));
    Vec<D> f =
        ps.mass[i] * (p.gravity - p.global_damping * ps.v[i]) + ps.f_ext[i] + ps.drag_force[i];
    // The resin's torque, linear in the spin the same way (coupling_loops.hpp).
    ps.hydro_torque[i] = p.exponential_drag
                             ? Rot<D>::Zero()
                             : Rot<D>(ps.torque_coeff[i] * (ps.resin_spin[i] - ps.omega[i]));
    Rot<D> t = -p.global_damping * ps.inertia[i] * ps.omega[i] + ps.hydro_torque[i];
    gather_pairs<D>(ws, i, f, t, [](const DemPair<D>&) { return true; });
    ps.force[i] = f;
    ps.torque[i] = t;
  }
  t_gather.stop();
  dem_detail::DemTimer t_walls(prof.walls);
  for (std::size_t i = 0; i < n_own; ++i) {
    wall_forces<D>(p, dt, walls, ps, i, ws.wall_items.data() + ws.wall_start[i],
                   ws.wall_start[i + 1] - ws.wall_start[i]);
  }
  ws.forces_valid = true;
}

template <int D>
void dem_kick_drift(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls,
                    DemParticles<D>& ps) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  const double half = 0.5 * dt;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (!(ps.fixed[i] & kFixedMotion)) {
      ps.v[i] += (half / ps.mass[i]) * ps.force[i];
      ps.omega[i] += (half / ps.inertia[i]) * ps.torque[i];
      ps.drag_impulse[i] += half * ps.drag_force[i];  // what the resin must get back
      ps.torque_impulse[i] += half * ps.hydro_torque[i];
      if (p.exponential_drag) relax_drag<D>(ps, i, half);
    }
    ps.x[i] += dt * ps.v[i];
  }
  for (DemWall<D>& w : walls) {
    w.point += dt * w.velocity;
    w.end += dt * w.velocity;
  }
}

// The incremental springs advance by the half-step velocities times dt,
// i.e. by exactly the displacement of the drift.
template <int D>
void dem_force_kick(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                    DemParticles<D>& ps, DemWorkspace<D>& ws) {
  compute_dem_forces(p, dt, walls, ps, ws);
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  const double half = 0.5 * dt;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.fixed[i] & kFixedMotion) continue;
    ps.v[i] += (half / ps.mass[i]) * ps.force[i];
    ps.omega[i] += (half / ps.inertia[i]) * ps.torque[i];
    ps.drag_impulse[i] += half * ps.drag_force[i];
    ps.torque_impulse[i] += half * ps.hydro_torque[i];
    if (p.exponential_drag) relax_drag<D>(ps, i, half);
  }
}

template <int D>
void dem_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
              DemWorkspace<D>& ws) {
  if (!ws.pairs_valid) dem_build_pairs(p, walls, ps, ws);
  if (!ws.forces_valid) compute_dem_forces(p, 0.0, walls, ps, ws);
  dem_kick_drift(p, dt, walls, ps);
  if (dem_max_displacement2(ps, walls, ws) > 0.25 * ws.skin * ws.skin) {
    dem_store_pair_state(ps, ws);
    dem_build_pairs(p, walls, ps, ws);
  }
  dem_force_kick(p, dt, walls, ps, ws);
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                                  \
  template void compute_dem_forces<D>(const DemParams<D>&, double, const std::vector<DemWall<D>>&, \
                                      DemParticles<D>&, DemWorkspace<D>&);                         \
  template void dem_step<D>(const DemParams<D>&, double, std::vector<DemWall<D>>&,                 \
                            DemParticles<D>&, DemWorkspace<D>&);                                   \
  template void dem_kick_drift<D>(const DemParams<D>&, double, std::vector<DemWall<D>>&,           \
                                  DemParticles<D>&);                                               \
  template void dem_force_kick<D>(const DemParams<D>&, double, const std::vector<DemWall<D>>&,     \
                                  DemParticles<D>&, DemWorkspace<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
