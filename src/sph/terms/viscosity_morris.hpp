#pragma once
// Laminar viscosity, Morris, Fox & Zhu (1997):
//   dv_i/dt += sum_j m_j (mu_i + mu_j) / (rho_i rho_j) x_ij . grad_i W_ij / (r^2 + eta^2) v_ij
// With x_ij . grad_i W_ij = F r^2 (F < 0) it pulls v_i toward v_j. For a
// wall neighbor v_j is the no-slip velocity 2 v_wall - v_tilde (Adami).
// Reproduces the Poiseuille and Couette profiles (tests/test_channel_flows).
#include "sphdem/particles.hpp"

namespace sphdem::terms {

// Scalar factor multiplying v_ij.
inline double morris_viscosity(double m_j, double two_mu, double rho_i, double rho_j, double F,
                               double r2, double eta2) {
  return m_j * two_mu / (rho_i * rho_j) * F * r2 / (r2 + eta2);
}

}  // namespace sphdem::terms
