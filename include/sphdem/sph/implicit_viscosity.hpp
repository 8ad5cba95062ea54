#pragma once
// Implicit (backward-Euler) laminar viscosity, docs/physics.md "Implicit
// viscosity". The explicit Morris term (src/sph/terms/viscosity_morris.hpp,
// viscosity_variable.hpp) is
//   dv_i/dt = sum_j K_ij (v_i - v_j),
//   K_ij = 2 mu_ij mu_scale / rho_i  m_j / rho_j  F_ij r^2 / (r^2 + eta^2) <= 0,
// mu_ij the harmonic mean of the two viscosities (a wall neighbour: mu_i),
// v_j a wall's dummy (Adami) value. Explicit, it limits the step to
// 0.125 h^2 rho / mu. After the second kick the implicit scheme instead
// solves, over the resin particles that are not frozen (the unknowns),
//   m_i u_i - dt m_i sum_j K_ij (u_i - u_j) = m_i v_i,
// where a wall neighbour j shows the dummy value of the solution itself,
//   u_j = dummy_velocity(law_j, vw_j, sum_k A_jk u_k),  A_jk = W_jk / sum_k W_jk
// over its resin neighbours k (no-slip: u_j = 2 vw_j - sum_k A_jk u_k), as
// the explicit term sees it, and the frozen particles keep their velocities
// (known). The viscosity is frozen over the solve. The resin-resin part is
// symmetric (m_i K_ij = m_j K_ji), the walls' part is not (A_jk is a Shepard
// weight); the matrix is strictly diagonally dominant (|A| rows sum to 1, the
// slip map has norm <= 1): BiCGSTAB (van der Vorst, SIAM J. Sci. Stat.
// Comput. 13 (1992) 631; Saad, Iterative Methods for Sparse Linear Systems,
// 2nd ed., SIAM 2003, alg. 7.7) with a Jacobi right preconditioner.
//
// Holding the walls' values at those of the rates (before the kick) instead,
// as this solve did until issue 13 part 3's fix, shows a resin driven by a
// body force F walls that move at -F dt / 2 at steady state: start-up
// Poiseuille 13 % slow at dt = 2.5e-5 s (docs/physics.md).
//
// Physics never calls MPI: the caller supplies the ghost refresh and the
// sums over ranks. The dot products are exact sums (sphdem/core/
// exact_sum.hpp), each row's sum runs in the neighbour list's global-id
// order, so the iterates, the iteration count and the result are bitwise
// the same at every rank count.
#include <functional>
#include <span>
#include <vector>

#include "sphdem/core/exact_sum.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

// What the solve needs from the ranks.
struct ViscousSolveHooks {
  std::function<void(SphGroup)> forward;             // refresh a group on the ghosts
  std::function<void(std::span<double>)> max;        // element-wise max over ranks, in place
  std::function<void(std::span<Int128>)> exact_sum;  // element-wise exact sum, in place
};

struct ViscousSolveStats {
  int iterations = 0;
  double residual = 0;  // |r| / |b| at the end (|b| = 0: 0)
  bool converged = false;
};

// The coefficients K_ij of the owned resin particles' rows, one per
// neighbour-list entry (0 for a pair beyond the support and for the rows of
// walls), and S_i = sum_j K_ij. Reads rho, mass and (with a law) the
// viscosity of owned particles and ghosts.
template <int D>
struct ViscousOperator {
  std::vector<double> coeff;
  std::vector<double> row_sum;
  void build(const SphParams& sp, const NeighborList<D>& nl, const SphParticles<D>& ps);
  // (L u)_i = sum_j K_ij (u_i - u_j) for every owned resin particle (other
  // rows: 0), u given for every particle, ghosts included: the explicit
  // term's acceleration when u is the velocity the pair loop sees (vwall).
  void apply(const NeighborList<D>& nl, const SphParticles<D>& ps, const std::vector<Vec<D>>& u,
             std::vector<Vec<D>>& out) const;
};

// Replaces the velocity v of every owned resin particle that is not frozen
// by the solution u of the system above, starting from u = v + dt visc_acc
// (the last solve's viscous acceleration, which it then updates). Reads the
// walls' own velocities v (and wall_to_surface for a slip law) and the
// frozen flag; wall_slip[k] is the condition of wall k (ps.wall), the
// others (index -1 or beyond) have sp.mold_wall. Writes visc_u and
// visc_free. Collective through the hooks.
template <int D>
ViscousSolveStats solve_implicit_viscosity(const SphParams& sp, double dt, double tolerance,
                                           int max_iterations, const NeighborList<D>& nl,
                                           SphParticles<D>& ps,
                                           std::span<const WallSlipLaw> wall_slip,
                                           const ViscousSolveHooks& hooks);

// The density's share of the solve (after the second density kick): that
// kick's rate read the velocities before the solve, the drift of the next
// step reads the solve's, and the leapfrog's density averages two rates, so
// it misses the continuity equation's term of the displacement dt/2 du,
// du = dt visc_acc the solve's change of velocity:
//   rho_i += sum_j m_j (d_i - d_j) . grad_i W_ij,   d = dt/2 du
// (walls and frozen resin d = 0), as for a particle shift. Reads visc_acc,
// writes visc_u (d, forwarded with SphGroup::Viscous). Collective.
template <int D>
void add_viscous_density(const SphParams& sp, double dt, const NeighborList<D>& nl,
                         SphParticles<D>& ps, const std::function<void(SphGroup)>& forward);

}  // namespace sphdem
