#pragma once
// Monaghan (1992) artificial viscosity, acting only on approaching pairs:
//   Pi_ij = -alpha c0 h mu_ij / rho_bar,  mu_ij = v_ij . x_ij / (r^2 + eta^2)
// when v_ij . x_ij < 0, else 0. rho_bar = (rho_i + rho_j)/2.
// A select rather than an early return, so the pair loop vectorizes.
namespace sphdem::terms {

inline double artificial_viscosity(double alpha_c0_h, double vx, double r2, double eta2,
                                   double rho_i, double rho_j) {
  const double mu_ij = vx / (r2 + eta2);
  const double pi_ij = -alpha_c0_h * mu_ij * 2.0 / (rho_i + rho_j);
  return vx < 0.0 ? pi_ij : 0.0;
}

}  // namespace sphdem::terms
