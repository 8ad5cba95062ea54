#pragma once
// Implicit bonds (docs/dem.md, "Implicit bonds"): the bonded clusters of
// the owned particles and their per-chain linear solve, for
// dem_implicit_step (dem_bond_subcycle.cpp).
#include "sphdem/dem/dem.hpp"

namespace sphdem::dem_detail {

// Lists in ws every bonded cluster (a fiber, or a piece of a broken one)
// that holds an owned particle, following the intact bonds of the owned
// particles and the ghosts (each bond from its slot's particle to the
// partner's copy nearest to it). Throws SimulationError when a member's
// bond partner is absent: the fiber is not whole on this rank.
template <int D>
void build_bond_chains(DemParticles<D>& ps, DemWorkspace<D>& ws);

// For every chain, the drift velocity u (and spin) of the trapezoidal rule
// under its bonds, (M + dt^2/4 K) u = M v with v the current (half-step)
// velocities and K the bonds' linearised stiffness at the current
// positions; the owned members' v and omega become u, their v saved in
// ws.v_half/omega_half (restore_half_velocities puts it back). Members
// fixed in motion keep their velocity. The chain's members in gid order,
// its bonds in gid order: the same solve on every rank that holds it.
template <int D>
void solve_bond_chains(const DemParams<D>& p, double dt, DemParticles<D>& ps, DemWorkspace<D>& ws);

template <int D>
void restore_half_velocities(DemParticles<D>& ps, const DemWorkspace<D>& ws);

}  // namespace sphdem::dem_detail
