// Temperature (docs/physics.md "Temperature"): the Cleary & Monaghan (1999)
// pairwise conduction of compute_heat_rates against a hand computation on
// three particles, its exact energy conservation on a random cluster, the
// viscous heating term, and the dummy wall temperature of each wall
// condition.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/sph/kernel.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {
namespace {

SphParams thermal_params() {
  SphParams sp;
  sp.h = 1.2e-3;
  sp.rho0 = 1000;
  sp.eta2 = 0.01 * sp.h * sp.h;
  sp.thermal = true;
  sp.heat_capacity = 2000;
  sp.conductivity = 0.2;
  return sp;
}

template <int D>
void heat_rates(const SphParams& sp, SphParticles<D>& ps) {
  NeighborList<D> nl(2 * sp.h, 0.5 * sp.h);
  nl.build(ps);
  compute_heat_rates<D>(sp, nl, ps);
}

TEST(Heat, ConductionPairHandValue) {
  // 4 m_j / (rho_i rho_j) k_i k_j / (k_i + k_j) F r^2 / (r^2 + eta^2) (T_i - T_j)
  // = 4 * 2 / (1 * 2) * (3 * 6 / 9) * (-5) * 0.09 / 0.1 * (10 - 4) = -216.
  EXPECT_DOUBLE_EQ(conduction_pair(2.0, 1.0, 2.0, 3.0, 6.0, -5.0, 0.09, 0.01, 10.0, 4.0), -216.0);
  // Equal temperatures exchange nothing; a jump in k enters through the
  // harmonic mean (a zero conductivity blocks the flux).
  EXPECT_EQ(conduction_pair(2.0, 1.0, 2.0, 3.0, 6.0, -5.0, 0.09, 0.01, 7.0, 7.0), 0.0);
  EXPECT_EQ(conduction_pair(2.0, 1.0, 2.0, 3.0, 0.0, -5.0, 0.09, 0.01, 10.0, 4.0), 0.0);
}

// Three resin particles in a row, worked out pair by pair: the hot middle
// one cools, the outer ones warm, and the rates are the formula's.
TEST(Heat, ThreeParticlesAgainstHandComputation) {
  const SphParams sp = thermal_params();
  SphParticles<2> ps;
  const double dx = 1e-3, m = 1e-3;
  const double temps[3] = {400.0, 500.0, 430.0};
  const double rhos[3] = {1000.0, 1010.0, 995.0};
  for (int i = 0; i < 3; ++i) {
    ps.push_owned(i, Kind::Fluid, -1, m * (1 + 0.1 * i), Vec<2>(i * dx, 0.3 * i * dx),
                  Vec<2>::Zero(), rhos[i]);
    ps.temperature.back() = temps[i];
  }
  heat_rates<2>(sp, ps);
  const WendlandC2<2> kernel(sp.h);
  const double k = sp.conductivity;
  for (int i = 0; i < 3; ++i) {
    double du = 0.0;
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      const double r2 = (ps.x[i] - ps.x[j]).squaredNorm();
      const double F = kernel.f(std::sqrt(r2));
      // Cleary & Monaghan (1999), written out: x_ij . grad_i W_ij = F r^2.
      du += 4 * ps.mass[j] / (rhos[i] * rhos[j]) * (k * k / (2 * k)) * (F * r2) / (r2 + sp.eta2) *
            (temps[i] - temps[j]);
    }
    const double expected = du / sp.heat_capacity;
    EXPECT_NEAR(ps.dtemp[i], expected, 1e-12 * std::abs(expected)) << "particle " << i;
  }
  EXPECT_LT(ps.dtemp[1], 0.0) << "the hottest particle cools";
  EXPECT_GT(ps.dtemp[0], 0.0);
  // Particles 0 and 2 are 2 dx apart, inside the support 2h = 2.4 dx.
  EXPECT_GT(ps.dtemp[2], 0.0);
}

// The pairwise form is antisymmetric, so sum_i m_i c_p dT_i/dt vanishes up
// to round-off for any cluster of resin particles, masses, densities and
// temperatures (Cleary & Monaghan 1999).
TEST(Heat, ConductionConservesEnergyExactly) {
  const SphParams sp = thermal_params();
  SphParticles<3> ps;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const Vec<3> x(u(rng) * 4e-3, u(rng) * 4e-3, u(rng) * 4e-3);
    ps.push_owned(i, Kind::Fluid, -1, 1e-6 * (0.5 + u(rng)), x, Vec<3>::Zero(), 950 + 100 * u(rng));
    ps.temperature.back() = 300 + 200 * u(rng);
  }
  heat_rates<3>(sp, ps);
  double total = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    total += ps.mass[i] * sp.heat_capacity * ps.dtemp[i];
    scale += std::abs(ps.mass[i] * sp.heat_capacity * ps.dtemp[i]);
  }
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(std::abs(total), 1e-13 * scale) << "energy rate " << total << " of " << scale;
}

// Viscous heating adds mu gamma_dot^2 / (rho c_p) to a particle at the
// temperature of its neighbours.
TEST(Heat, ViscousHeatingHandValue) {
  SphParams sp = thermal_params();
  sp.viscous_heating = true;
  sp.mu = 3.0;
  SphParticles<2> ps;
  for (int i = 0; i < 2; ++i) {
    ps.push_owned(i, Kind::Fluid, -1, 1e-3, Vec<2>(i * 1e-3, 0), Vec<2>::Zero(), 1000);
    ps.temperature.back() = 450;
    ps.shear_rate.back() = 20.0 * (i + 1);
  }
  heat_rates<2>(sp, ps);
  EXPECT_DOUBLE_EQ(ps.dtemp[0], 3.0 * 400.0 / (1000 * 2000));
  EXPECT_DOUBLE_EQ(ps.dtemp[1], 3.0 * 1600.0 / (1000 * 2000));
}

TEST(Heat, DummyWallTemperature) {
  const WallThermalLaw held{false, 300.0, std::numeric_limits<double>::infinity()};
  EXPECT_DOUBLE_EQ(dummy_temperature(held, 0.2, 500.0, 1e-3), 100.0) << "2 T_wall - T~";
  const WallThermalLaw adiabatic{};
  EXPECT_DOUBLE_EQ(dummy_temperature(adiabatic, 0.2, 500.0, 1e-3), 500.0);
  // k/d = 200 W/(m^2 K), htc = 200: T_s halfway, 400 K; dummy 2*400 - 500.
  const WallThermalLaw film{false, 300.0, 200.0};
  EXPECT_DOUBLE_EQ(dummy_temperature(film, 0.2, 500.0, 1e-3), 300.0);
}

TEST(Heat, ThermalTimeStepLimit) {
  SphParams sp = thermal_params();
  sp.c0 = 1e-9;  // the CFL limit far away
  sp.thermal_factor = 0.1;
  Numerics num;
  const TimeStep ts = choose_time_step(num, sp, 0.0, 0.0);
  EXPECT_EQ(ts.limit, DtLimit::Thermal);
  EXPECT_DOUBLE_EQ(ts.dt, 0.1 * sp.h * sp.h * 1000 * 2000 / 0.2);
  EXPECT_STREQ(to_string(DtLimit::Thermal), "thermal");
}

}  // namespace
}  // namespace sphdem
