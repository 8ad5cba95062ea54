#pragma once
// Monaghan (2000) tensile-instability ("anti-clump") term:
//   R_ij f_ij^n with f_ij = W(r_ij) / W(dp), n = 4 by default,
//   R_ij = R_i + R_j, R_a = eps |P_a| / rho_a^2 when P_a < 0, else 0;
//   when both pressures are positive R_ij = 0.01 (P_i/rho_i^2 + P_j/rho_j^2).
// It adds a short-range repulsion that stops particles pairing up where
// the pressure is negative.
// Written with selects instead of branches so that the pair loop of
// fluid_rates.cpp vectorizes.
namespace sphdem::terms {

// Per-particle part R_a (0 for non-negative pressure).
inline double anti_clump_r(double eps, double p_over_rho2) {
  return p_over_rho2 < 0.0 ? -eps * p_over_rho2 : 0.0;
}

// R_ij.
inline double anti_clump_coefficient(double r_i, double r_j, double por2_i, double por2_j) {
  return (por2_i > 0.0 && por2_j > 0.0) ? 0.01 * (por2_i + por2_j) : r_i + r_j;
}

// f^n for any n >= 0 (a loop: the rate loop has a fast path for n = 4).
inline double anti_clump_power(double w_ratio, int n) {
  double f = 1.0;
  for (int k = 0; k < n; ++k) f *= w_ratio;
  return f;
}

inline double anti_clump(double r_i, double r_j, double por2_i, double por2_j, double w_ratio,
                         int n) {
  return anti_clump_coefficient(r_i, r_j, por2_i, por2_j) * anti_clump_power(w_ratio, n);
}

}  // namespace sphdem::terms
