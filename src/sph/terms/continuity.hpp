#pragma once
// Continuity equation (paper Eq. 3): drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij.
// With grad_i W_ij = F x_ij this is m_j F (v_ij . x_ij).
// A wall neighbor contributes with the wall's own (prescribed) velocity.
// The rate loop passes the dot product vx = v_ij . x_ij.
namespace sphdem::terms {

inline double continuity(double m_j, double F, double vx) {
  return m_j * F * vx;
}

}  // namespace sphdem::terms
