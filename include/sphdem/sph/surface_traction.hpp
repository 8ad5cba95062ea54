#pragma once
// The free surface's viscous traction as a linear operator of the velocity
// (src/sph/surface_traction.cpp, docs/physics.md "Viscous traction at the
// free surface"), for the implicit viscous solve (implicit_viscosity.hpp).
// At a surface particle i the explicit term is
//   T_i(u) = (2 mu_i / rho_i) G_i^T g_i,   G_i = L_i B_i^-1,
// with L_i = sum_j w_ij (u_j - u_i) x_ij^T (w_ij = V_j F_ij), linear in u:
//   T_i(u) = sum_j q_ij g_i . (u_j - u_i),   q_ij = (2 mu_i / rho_i) w_ij B_i^-T x_ij.
// The coefficients are frozen over a solve, as the Morris ones are.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
struct SurfaceTractionOperator {
  std::vector<std::size_t> rows;    // owned surface resin particles with an invertible B
  std::vector<std::size_t> offset;  // per row: its first entry in q
  std::vector<Vec<D>> g;            // per row: the Morris weight's colour gradient g_i
  std::vector<Vec<D>> q;            // per row and neighbour-list entry: q_ij (0 beyond 2h)
  // Every flagged resin particle (sp.free_surface_traction, sp.mu > 0); reads
  // x, rho, mass and (with a law) viscosity of owned particles and ghosts.
  void build(const SphParams& sp, const NeighborList<D>& nl, const SphParticles<D>& ps);
  bool empty() const { return rows.empty(); }
  // T_i(u) of row r (i = rows[r]), u given for every particle, ghosts and
  // walls included (the velocity the viscous term sees); neighbours in list
  // order, as the explicit term.
  template <class Velocities>
  Vec<D> row(std::size_t r, const NeighborList<D>& nl, const Velocities& u) const {
    const std::size_t i = rows[r], first = nl.begin(i);
    const NeighborRow nb = nl.row(i);
    Vec<D> t = Vec<D>::Zero();
    for (std::size_t n = first, e = nl.end(i); n < e; ++n)
      t += g[r].dot(u[static_cast<std::size_t>(nb[n])] - u[i]) * q[offset[r] + (n - first)];
    return t;
  }
};

}  // namespace sphdem
