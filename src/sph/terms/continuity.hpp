#pragma once
// Continuity equation (paper Eq. 3): drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij.
// With grad_i W_ij = F x_ij this is m_j F (v_ij . x_ij).
// A wall neighbor contributes with the wall's own (prescribed) velocity.
#include "sphdem/particles.hpp"

namespace sphdem::terms {

template <int D>
inline double continuity(double m_j, double F, const Vec<D>& v_ij, const Vec<D>& x_ij) {
  return m_j * F * v_ij.dot(x_ij);
}

}  // namespace sphdem::terms
