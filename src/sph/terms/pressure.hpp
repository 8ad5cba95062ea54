#pragma once
// Pressure gradient, symmetric form (paper Eq. 5 with its printed sign
// corrected, docs/physics.md):
//   dv_i/dt = - sum_j m_j (P_i/rho_i^2 + P_j/rho_j^2 + Pi_ij + R_ij) grad_i W_ij.
// This term gives the P/rho^2 part of the bracket; artificial_viscosity.hpp
// gives Pi_ij and anti_clump.hpp R_ij. The pair loop multiplies the bracket
// by -m_j F x_ij. Always on.
#include <cstddef>

#include "../record_fields.hpp"

namespace sphdem::terms {

inline double pressure_over_rho2(double p, double rho) {
  return p / (rho * rho);
}

namespace field {
// P / rho^2, once per particle.
struct PoR2 : ScalarField {
  static constexpr const char* name = "p_over_rho2";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = pressure_over_rho2(ps.p[i], ps.rho[i]);
  }
};
}  // namespace field

struct Pressure {
  static constexpr const char* name = "pressure";
  using Reads = Fields<field::PoR2>;
  static constexpr unsigned writes = kBracket;
  static constexpr bool kVectorPair = true;

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    s.bracket += p.own_value(field::PoR2{}) + p.lane(field::PoR2{});
  }
};

}  // namespace sphdem::terms
