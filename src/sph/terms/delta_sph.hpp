#pragma once
// Density diffusion, delta-SPH (Molteni & Colagrossi 2009):
//   drho_i/dt += delta h c0 sum_j psi_ij . grad_i W_ij V_j,
//   psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_ij|^2.
// With grad_i W_ij = F x_ij, psi_ij . grad_i W_ij = -2 (rho_j - rho_i) F,
// which is finite at r -> 0. Applied between resin particles only.
// vol_j = m_j / rho_j is precomputed once per particle by the rate loop.
namespace sphdem::terms {

inline double delta_sph(double delta_h_c0, double rho_i, double rho_j, double vol_j, double F) {
  return -2.0 * delta_h_c0 * (rho_j - rho_i) * F * vol_j;
}

}  // namespace sphdem::terms
