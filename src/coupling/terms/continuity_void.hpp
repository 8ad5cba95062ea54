#pragma once
// Continuity with the local void fraction (the paper's "local averaging
// technique"; docs/physics.md "Coupling" gives the derivation and the
// stability notes). The averaged mass balance d(eps rho)/dt = -eps rho div v
// along the resin's path gives, for the INTRINSIC density rho (the one the
// equation of state, the walls and delta-SPH keep using):
//   drho_i/dt = (1/eps_i) [ sum_j m_j (v_i - v_j) . grad_i W_ij
//                         + rho_i sum_f V_f (v_i - v_f) . grad_i W_if ]
// The first sum is the plain continuity sum of paper Eq. 3 (continuity.hpp,
// resin and wall neighbours j); the second is d phi_i/dt of
// void_fraction.hpp (DEM neighbours f, after clipping), i.e.
// -(rho_i/eps_i) D eps_i/Dt: resin is squeezed where fibres arrive and
// expands where they leave. With no DEM particle near i (eps_i = 1, rate 0)
// it is paper Eq. 3 exactly. The delta-SPH diffusion term is added outside,
// not divided by eps.
namespace sphdem::terms {

// fluid_sum = sum_j m_j F v_ij . x_ij, phi_rate = clipped d phi_i/dt,
// eps_i = clipped void fraction at x_i.
inline double continuity_void_fraction(double fluid_sum, double rho_i, double phi_rate,
                                       double eps_i) {
  return (fluid_sum + rho_i * phi_rate) / eps_i;
}

}  // namespace sphdem::terms
