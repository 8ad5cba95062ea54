#pragma once
// Monaghan (1992) artificial viscosity, acting only on approaching pairs:
//   Pi_ij = -alpha c0 h mu_ij / rho_bar,  mu_ij = v_ij . x_ij / (r^2 + eta^2)
// when v_ij . x_ij < 0, else 0. rho_bar = (rho_i + rho_j)/2. v_ij uses the
// velocity the viscous terms see (a wall's no-slip value).
// A select rather than an early return, so the pair loop vectorizes.
// Case-file switch: numerics.artificial_viscosity (alpha) > 0.
#include "../record_fields.hpp"

namespace sphdem::terms {

inline auto artificial_viscosity(double alpha_c0_h, auto vx, auto r2, double eta2, auto rho_i,
                                 auto rho_j) {
  const auto mu_ij = vx / (r2 + eta2);
  const auto pi_ij = -alpha_c0_h * mu_ij * 2.0 / (rho_i + rho_j);
  return vx < 0.0 ? pi_ij : 0.0;
}

struct ArtificialViscosity {
  static constexpr const char* name = "artificial_viscosity";
  using Reads = Fields<field::Pos, field::VelWall, field::Rho>;
  static constexpr unsigned writes = kBracket;
  static constexpr bool kVectorPair = true;
  static bool active(const SphParams& sp) { return sp.alpha > 0; }

  double alpha_c0_h, eta2;
  template <int D>
  explicit ArtificialViscosity(const TermContext<D>& c)
      : alpha_c0_h(c.sp.alpha * c.sp.c0 * c.sp.h), eta2(c.sp.eta2) {}

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    decltype(p.F) wx{};
    for (int d = 0; d < P::kDim; ++d) wx += p.lane(field::VelWall{}, d) * p.lane(field::Pos{}, d);
    s.bracket += artificial_viscosity(alpha_c0_h, wx, p.r2, eta2, p.own_value(field::Rho{}),
                                      p.lane(field::Rho{}));
  }
};

}  // namespace sphdem::terms
