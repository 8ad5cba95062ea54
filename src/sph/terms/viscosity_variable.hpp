#pragma once
// Laminar viscosity of a generalized-Newtonian resin (docs/physics.md "Melt
// viscosity"): the Morris, Fox & Zhu (1997) term with the pair viscosity
// the harmonic mean of the two particles' (Cleary 1998's form for a
// variable coefficient, continuous flux across a jump in viscosity):
//   dv_i/dt += sum_j m_j 4 mu_i mu_j / ((mu_i + mu_j) rho_i rho_j)
//              x_ij . grad_i W_ij / (r^2 + eta^2) v_ij
// For mu_i = mu_j = mu, 4 mu mu / (2 mu) = 2 mu: the Newtonian term (which
// a Newtonian case keeps, bitwise: viscosity_morris.hpp). A wall neighbour
// takes the resin particle's own viscosity (the no-slip velocity of the
// Adami walls is what it shows). The lattice correction is the same.
// Case-file switch: a law under resin.viscosity (numerics.viscosity_model
// morris).
#include <algorithm>

#include "../record_fields.hpp"
#include "shear_rate.hpp"
#include "sphdem/sph/viscosity_law.hpp"

namespace sphdem::terms {

// The temperature the law reads at particle i: its own (resin.thermal;
// a ghost's arrives with the State exchange), else the case's
// resin.melt_temperature (K).
template <int D>
inline double particle_temperature(const SphParams& sp, const SphParticles<D>& ps, std::size_t i) {
  return sp.thermal ? ps.temperature[i] : sp.melt_temperature;
}

// Every resin particle's viscosity (owned and ghosts: a ghost's shear rate
// and pressure are current when this runs, after the shear-rate pass and
// its forward), so both sides of a pair read the same value on every rank.
template <int D>
void compute_particle_viscosity(const SphParams& sp, SphParticles<D>& ps) {
  for (std::size_t i = 0; i < ps.size(); ++i) {
    ps.viscosity[i] = ps.kind[i] != Kind::Fluid ? 0.0
                      : sp.variable_viscosity
                          ? melt_viscosity(sp.melt, sp.mu, ps.shear_rate[i],
                                           particle_temperature(sp, ps, i), ps.p[i])
                          : sp.mu;
  }
}

// 2 mu_i mu_j / (mu_i + mu_j), the harmonic mean (0 when both are 0).
inline auto harmonic_mean(auto mu_i, auto mu_j) {
  const auto s = mu_i + mu_j;
  return s > 0.0 ? 2.0 * mu_i * mu_j / s : 0.0;
}

namespace field {
// A particle's viscosity (compute_particle_viscosity).
struct Viscosity : ScalarField {
  static constexpr const char* name = "viscosity";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.viscosity[i];
  }
};
}  // namespace field

// O: the type of particle i's values (MorrisViscosityT, viscosity_morris.hpp).
template <class O = double>
struct VariableViscosityT {
  static constexpr const char* name = "morris_variable";
  using Reads = Fields<field::Vol, field::Viscosity, field::Fluid>;
  // The viscosity is a function of the shear rate: reading it makes the
  // shear-rate pass run (pass_loop.hpp).
  using OwnReads = Fields<field::Rho, field::ShearRate>;
  static constexpr unsigned writes = kVisc;
  static constexpr bool kVectorPair = true;
  // Implicit viscosity: src/sph/implicit_viscosity.cpp after the second kick.
  static bool active(const SphParams& sp) {
    return sp.variable_viscosity && !sp.implicit_viscosity;
  }

  double scale;  // mu_scale / grad_scale, F carries grad_scale
  double eta2;
  O mu_i{};
  O scale_over_rho_i{};
  VariableViscosityT(double scale_, double eta2_) : scale(scale_), eta2(eta2_) {}
  template <int D>
  explicit VariableViscosityT(const TermContext<D>& c)
      : scale(c.sp.mu_scale / c.sp.grad_scale), eta2(c.sp.eta2) {}

  template <class I>
  auto for_particle(const I& i) const {
    const auto rho_i = i.own_value(field::Rho{});
    VariableViscosityT<std::remove_const_t<decltype(rho_i)>> bound(scale, eta2);
    bound.mu_i = i.own_value(field::Viscosity{});
    bound.scale_over_rho_i = scale / rho_i;
    return bound;
  }

  template <class P, class Sums>
  void pair(const P& p, Sums& s) const {
    const auto mu_j = p.lane(field::Fluid{}) > 0.5 ? p.lane(field::Viscosity{}) : mu_i;
    const auto two_mu = 2.0 * harmonic_mean(mu_i, mu_j);
    s.visc += two_mu * scale_over_rho_i * p.lane(field::Vol{}) * p.F * p.r2 / (p.r2 + eta2);
  }
};
using VariableViscosity = VariableViscosityT<>;

}  // namespace sphdem::terms
