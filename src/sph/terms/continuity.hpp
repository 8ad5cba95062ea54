#pragma once
// Continuity equation (paper Eq. 3): drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij.
// With grad_i W_ij = F x_ij this is m_j F (v_ij . x_ij).
// A wall neighbor contributes with the wall's own (prescribed) velocity.
// Always on.
#include "../record_fields.hpp"

namespace sphdem::terms {

// Any lane type (double, or registers of pairs: term_interface.hpp).
inline auto continuity(auto m_j, auto F, auto vx) {
  return m_j * F * vx;
}

struct Continuity {
  static constexpr const char* name = "continuity";
  using Reads = Fields<field::Pos, field::Vel, field::Mass>;
  static constexpr unsigned writes = kDrho;
  static constexpr bool kVectorPair = true;

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    decltype(p.F) vx{};  // v_ij . x_ij
    for (int d = 0; d < P::kDim; ++d) vx += p.lane(field::Vel{}, d) * p.lane(field::Pos{}, d);
    s.drho += continuity(p.lane(field::Mass{}), p.F, vx);
  }
};

}  // namespace sphdem::terms
