#pragma once
// Density diffusion, delta-SPH (Molteni & Colagrossi 2009):
//   drho_i/dt += delta h c0 sum_j psi_ij . grad_i W_ij V_j,
//   psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_ij|^2.
// With grad_i W_ij = F x_ij, psi_ij . grad_i W_ij = -2 (rho_j - rho_i) F,
// which is finite at r -> 0. Applied between resin particles only.
// The neighbour's weight -2 delta h c0 V_j (0 for a wall, V_j = m_j / rho_j)
// is a record field, computed once per particle: the pair costs two
// products (docs/performance.md, "The pair's arithmetic").
// Case-file switch: numerics.delta_sph > 0.
#include "../record_fields.hpp"

namespace sphdem::terms {

inline double delta_sph_weight(double delta_h_c0, double vol_j) {
  return -2.0 * delta_h_c0 * vol_j;
}

inline auto delta_sph(auto rho_i, auto rho_j, auto weight_j, auto F) {
  return (rho_j - rho_i) * F * weight_j;
}

inline double delta_sph(double delta_h_c0, double rho_i, double rho_j, double vol_j, double F) {
  return delta_sph(rho_i, rho_j, delta_sph_weight(delta_h_c0, vol_j), F);
}

namespace field {
// -2 delta h c0 m / rho for resin, 0 for walls (delta-SPH is between resin only).
struct DeltaWeight : ScalarField {
  static constexpr const char* name = "delta_weight";
  template <int D>
  static void fill(const SphParams& sp, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.kind[i] == Kind::Fluid
                 ? delta_sph_weight(sp.delta * sp.h * sp.c0, ps.mass[i] / ps.rho[i])
                 : 0.0;
  }
};
}  // namespace field

struct DeltaSph {
  static constexpr const char* name = "delta_sph";
  using Reads = Fields<field::Rho, field::DeltaWeight>;
  static constexpr unsigned writes = kDrho;
  static constexpr bool kVectorPair = true;
  static bool active(const SphParams& sp) { return sp.delta > 0; }

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    s.drho += delta_sph(p.own_value(field::Rho{}), p.lane(field::Rho{}),
                        p.lane(field::DeltaWeight{}), p.F);
  }
};

}  // namespace sphdem::terms
