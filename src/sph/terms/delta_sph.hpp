#pragma once
// Density diffusion, delta-SPH (Molteni & Colagrossi 2009):
//   drho_i/dt += delta h c0 sum_j psi_ij . grad_i W_ij V_j,
//   psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_ij|^2.
// With grad_i W_ij = F x_ij, psi_ij . grad_i W_ij = -2 (rho_j - rho_i) F,
// which is finite at r -> 0. Applied between resin particles only.
// vol_j = m_j / rho_j is a record field, computed once per particle.
// Case-file switch: numerics.delta_sph > 0.
#include "../record_fields.hpp"

namespace sphdem::terms {

inline double delta_sph(double delta_h_c0, double rho_i, double rho_j, double vol_j, double F) {
  return -2.0 * delta_h_c0 * (rho_j - rho_i) * F * vol_j;
}

struct DeltaSph {
  static constexpr const char* name = "delta_sph";
  using Reads = Fields<field::Rho, field::Vol, field::Fluid>;
  static constexpr unsigned writes = kDrho;
  static bool active(const SphParams& sp) { return sp.delta > 0; }

  double delta_h_c0;
  template <int D>
  explicit DeltaSph(const TermContext<D>& c) : delta_h_c0(c.sp.delta * c.sp.h * c.sp.c0) {}

  template <class P>
  void pair(const P& p, PairSums& s) const {
    s.drho += p.lane(field::Fluid{}) * delta_sph(delta_h_c0, p.own_value(field::Rho{}),
                                                 p.lane(field::Rho{}), p.lane(field::Vol{}), p.F);
  }
};

}  // namespace sphdem::terms
