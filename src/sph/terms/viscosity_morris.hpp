#pragma once
// Laminar viscosity, Morris, Fox & Zhu (1997):
//   dv_i/dt += sum_j m_j (mu_i + mu_j) / (rho_i rho_j) x_ij . grad_i W_ij / (r^2 + eta^2) v_ij
// With x_ij . grad_i W_ij = F r^2 (F < 0) it pulls v_i toward v_j. For a
// wall neighbor v_j is the no-slip velocity 2 v_wall - v_tilde (Adami).
// Reproduces the Poiseuille and Couette profiles (tests/test_channel_flows).
// Case-file switch: numerics.viscosity_model (morris, none).
#include "../record_fields.hpp"

namespace sphdem::terms {

// Scalar factor multiplying v_ij. The caller passes the per-particle
// parts, two_mu_over_rho_i = 2 mu / rho_i and vol_j = m_j / rho_j, so the
// pair costs one division (by r^2 + eta^2) instead of two.
inline auto morris_viscosity(auto two_mu_over_rho_i, auto vol_j, auto F, auto r2, double eta2) {
  return two_mu_over_rho_i * vol_j * F * r2 / (r2 + eta2);
}

// O: the type of particle i's values, double, or a register of them when
// the pair loop runs one particle per lane (pair_loop.hpp, "one particle per
// lane").
template <class O = double>
struct MorrisViscosityT {
  static constexpr const char* name = "morris";
  using Reads = Fields<field::Vol>;
  using OwnReads = Fields<field::Rho>;
  static constexpr unsigned writes = kVisc;  // the loop multiplies it by v_i - vw_j
  static constexpr bool kVectorPair = true;
  // A viscosity law runs viscosity_variable.hpp instead; implicit
  // viscosity, src/sph/implicit_viscosity.cpp after the second kick.
  static bool active(const SphParams& sp) {
    return sp.mu > 0 && !sp.variable_viscosity && !sp.implicit_viscosity;
  }

  double two_mu;  // 2 mu, over grad_scale since F carries it
  double eta2;
  O two_mu_over_rho_i{};
  MorrisViscosityT(double two_mu_, double eta2_) : two_mu(two_mu_), eta2(eta2_) {}
  template <int D>
  explicit MorrisViscosityT(const TermContext<D>& c)
      : two_mu(2.0 * c.sp.mu * c.sp.mu_scale / c.sp.grad_scale), eta2(c.sp.eta2) {}

  template <class I>
  auto for_particle(const I& i) const {
    const auto rho_i = i.own_value(field::Rho{});
    MorrisViscosityT<std::remove_const_t<decltype(rho_i)>> bound(two_mu, eta2);
    bound.two_mu_over_rho_i = two_mu / rho_i;
    return bound;
  }

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    s.visc += morris_viscosity(two_mu_over_rho_i, p.lane(field::Vol{}), p.F, p.r2, eta2);
  }
};
using MorrisViscosity = MorrisViscosityT<>;

}  // namespace sphdem::terms
