#pragma once
// Pressure gradient, symmetric form (paper Eq. 5 with its printed sign
// corrected, DESIGN 2.1):
//   dv_i/dt = - sum_j m_j (P_i/rho_i^2 + P_j/rho_j^2 + Pi_ij + R_ij) grad_i W_ij.
// This header gives the P/rho^2 part; artificial_viscosity.hpp gives Pi_ij
// and anti_clump.hpp R_ij. The caller multiplies the bracket by -m_j F x_ij.
namespace sphdem::terms {

inline double pressure_over_rho2(double p, double rho) {
  return p / (rho * rho);
}

}  // namespace sphdem::terms
