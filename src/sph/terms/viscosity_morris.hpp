#pragma once
// Laminar viscosity, Morris, Fox & Zhu (1997):
//   dv_i/dt += sum_j m_j (mu_i + mu_j) / (rho_i rho_j) x_ij . grad_i W_ij / (r^2 + eta^2) v_ij
// With x_ij . grad_i W_ij = F r^2 (F < 0) it pulls v_i toward v_j. For a
// wall neighbor v_j is the no-slip velocity 2 v_wall - v_tilde (Adami).
// Reproduces the Poiseuille and Couette profiles (tests/test_channel_flows).
namespace sphdem::terms {

// Scalar factor multiplying v_ij. The rate loop passes the per-particle
// parts, two_mu_over_rho_i = 2 mu / rho_i and vol_j = m_j / rho_j, so the
// pair costs one division (by r^2 + eta^2) instead of two.
inline double morris_viscosity(double two_mu_over_rho_i, double vol_j, double F, double r2,
                               double eta2) {
  return two_mu_over_rho_i * vol_j * F * r2 / (r2 + eta2);
}

}  // namespace sphdem::terms
