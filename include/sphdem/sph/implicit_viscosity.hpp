#pragma once
// Implicit (backward-Euler) laminar viscosity, docs/physics.md "Implicit
// viscosity". The explicit Morris term (src/sph/terms/viscosity_morris.hpp,
// viscosity_variable.hpp) is
//   dv_i/dt = sum_j K_ij (v_i - v_j),
//   K_ij = 2 mu_ij mu_scale / rho_i  m_j / rho_j  F_ij r^2 / (r^2 + eta^2) <= 0,
// mu_ij the harmonic mean of the two viscosities (a wall neighbour: mu_i),
// v_j a wall's no-slip (Adami) value. Explicit, it limits the step to
// 0.125 h^2 rho / mu. After the second kick the implicit scheme instead
// solves, over the resin particles that are not frozen (the unknowns),
//   m_i u_i - dt m_i sum_j K_ij (u_i - u_j) = m_i v_i,
// with the walls' no-slip values and the frozen particles' velocities held
// at their values at the start of the solve (known), and the viscosity
// frozen over the solve. m_i K_ij is symmetric in i and j, so the matrix is
// symmetric positive definite (diagonally dominant with positive diagonal):
// Jacobi-preconditioned conjugate gradients (Saad, Iterative Methods for
// Sparse Linear Systems, 2003, alg. 9.1).
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
// by the solution u of the system above, starting from u = v. Reads the
// walls' vwall (current after the rates) and the frozen flag; writes
// visc_u and visc_free. Collective through the hooks.
template <int D>
ViscousSolveStats solve_implicit_viscosity(const SphParams& sp, double dt, double tolerance,
                                           int max_iterations, const NeighborList<D>& nl,
                                           SphParticles<D>& ps, const ViscousSolveHooks& hooks);

}  // namespace sphdem
