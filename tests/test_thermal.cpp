// Temperature (issue 13 part 2, docs/physics.md "Temperature",
// docs/validation.md "Temperature"): validations against analytic solutions
// (seconds each) and the input errors. Their rank independence is in
// test_parallel (RankIndependence.*Thermal*, *FrozenLayer*).
//  - conduction from a suddenly cooled wall against the erf solution;
//  - Couette flow with viscous heating against Brinkman's steady profile;
//  - a channel with cold walls below the no-flow temperature: the frozen
//    layer grows as sqrt(t), as the erf profile reaching T_noflow says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;
using testing::world;

// erfinv by Newton's method on erf (enough for the test's one value).
double erfinv(double y) {
  double x = 0.0;
  for (int k = 0; k < 60; ++k)
    x -= (std::erf(x) - y) / (2.0 / std::sqrt(std::numbers::pi) * std::exp(-x * x));
  return x;
}

// --- conduction from a suddenly cooled wall -------------------------------------

// Largest |T - T_erf| over the resin within `reach` of either wall, as a
// fraction of T_i - T_s (the two walls of the 6 mm gap are semi-infinite
// problems until their layers meet).
double worst_erf_error(const SphParticles<2>& ps, double t, double a, double gap, double reach) {
  constexpr double kTs = 300, kTi = 500;
  double worst = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double y = ps.x[i][1];
    const double d = std::min(y, gap - y);
    if (d > reach) continue;
    const double exact = kTs + (kTi - kTs) * std::erf(d / (2 * std::sqrt(a * t)));
    worst = std::max(worst, std::abs(ps.temperature[i] - exact) / (kTi - kTs));
  }
  return worst;
}

TEST(Thermal, ConductionFromSuddenlyCooledWallMatchesErf) {
  const Case c = testing::load_input("validation/conduction_wall.yaml");
  const double a = 20.0 / (1000.0 * 2000.0);
  Simulation<2> sim(c, world(), quiet());
  for (double t : {0.01, 0.025}) {
    testing::run_until(sim, t);
    const double err = worst_erf_error(sim.particles(), sim.time(), a, 6e-3, 3e-3);
    std::printf(
        "[          ] t = %.3f s (2 sqrt(a t) = %.2f mm): largest error %.3f %% of T_i - "
        "T_s\n",
        sim.time(), 2e3 * std::sqrt(a * sim.time()), 100 * err);
    EXPECT_LT(err, 0.02) << "at t = " << sim.time();
  }
  EXPECT_EQ(sim.last_dt_limit(), DtLimit::Thermal);
}

// --- Couette flow with viscous heating (Brinkman) ---------------------------------

TEST(Thermal, CouetteViscousHeatingMatchesBrinkman) {
  const Case c = testing::load_input("validation/couette_heating.yaml");
  constexpr double kMu = 1e-2, kU = 1e-2, kK = 2.5e-9, kH = 1e-3, kTw = 300;
  Simulation<2> sim(c, world(), quiet());
  testing::run_until(sim, c.numerics.end_time);
  double num = 0, den = 0, peak = 0;
  for (std::size_t i = 0; i < sim.particles().n_owned; ++i) {
    if (sim.particles().kind[i] != Kind::Fluid) continue;
    const double s = sim.particles().x[i][1] / kH;
    const double rise = kMu * kU * kU / (2 * kK) * s * (1 - s);
    const double got = sim.particles().temperature[i] - kTw;
    num += (got - rise) * (got - rise);
    den += rise * rise;
    peak = std::max(peak, got);
  }
  const double err = std::sqrt(num / den);
  std::printf(
      "[          ] t = %.3f s: peak rise %.3f K (Brinkman %.3f K at mid-gap), relative "
      "L2 error %.3f %%\n",
      sim.time(), peak, kMu * kU * kU / (8 * kK), 100 * err);
  EXPECT_LT(err, 0.02);
}

// --- the frozen layer -------------------------------------------------------------

TEST(Thermal, FrozenLayerGrowsAsSqrtTime) {
  const Case c = testing::load_input("validation/frozen_layer.yaml");
  constexpr double kA = 0.2 / (1000.0 * 2000.0), kDp = 1e-4, kWidth = 1e-3;
  const double columns = kWidth / kDp;
  // The erf profile T_s + (T_i - T_s) erf(y / (2 sqrt(a t))) reaches T_noflow at
  // y_f = 2 erfinv((420 - 300) / (500 - 300)) sqrt(a t).
  const double slope = 2 * erfinv(0.6) * std::sqrt(kA);
  Simulation<2> sim(c, world(), quiet());
  double sum_ds = 0, sum_ss = 0;
  for (int k = 1; k <= 10; ++k) {
    testing::run_until(sim, 1.0 * k);
    const SphParticles<2>& ps = sim.particles();
    std::size_t frozen = 0;
    double still = 0, flowing = 0;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] != Kind::Fluid) continue;
      // The front is where T crosses T_noflow; a particle that crossed it
      // during the last step is frozen from the next one on.
      if (ps.temperature[i] < 420) ++frozen;
      if (ps.frozen[i] != 0)
        still = std::max(still, ps.v[i].norm());
      else
        flowing = std::max(flowing, ps.v[i][0]);
    }
    const double thickness = static_cast<double>(frozen) / (2 * columns) * kDp;
    const double expected = slope * std::sqrt(sim.time());
    std::printf(
        "[          ] t = %4.1f s: frozen layer %.3f mm (conduction estimate %.3f mm), "
        "core speed %.3g m/s\n",
        sim.time(), 1e3 * thickness, 1e3 * expected, flowing);
    // The count moves by whole rows of particles: compare from 5 rows on.
    if (expected > 5 * kDp) {
      EXPECT_NEAR(thickness / expected, 1.0, 0.10) << "t = " << sim.time();
    }
    EXPECT_EQ(still, 0.0) << "a frozen particle moves";
    if (expected > 5 * kDp) {
      EXPECT_GT(frozen, 0u);
    }
    EXPECT_GT(flowing, 0.0) << "the core stopped";
    sum_ds += thickness * std::sqrt(sim.time());
    sum_ss += sim.time();
  }
  // Least squares through the origin: thickness = s sqrt(t).
  const double fitted = sum_ds / sum_ss;
  std::printf("[          ] thickness / sqrt(t): %.4g m/s^0.5, conduction estimate %.4g\n", fitted,
              slope);
  EXPECT_NEAR(fitted / slope, 1.0, 0.10);
}

// --- fibers -----------------------------------------------------------------------

// Fibers take the resin's temperature at their position (the Shepard mean of
// the drag's resin velocity): in a resin with T linear in y it is the
// linear field's value there.
TEST(Thermal, FibersTakeTheLocalResinTemperature) {
  const Case c = testing::load_input(
      "validation/coupled_box.yaml",
      {"resin.thermal.temperature=450", "resin.thermal.heat_capacity=2000",
       "resin.thermal.conductivity=0.2", "initial_fields=[{temperature: '400 + 1e4*y'}]"});
  Simulation<2> sim(c, world(), quiet());
  sim.advance(20);
  const DemParticles<2>& dem = sim.dem()->particles();
  std::size_t checked = 0;
  double worst = 0;
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    if (!(dem.shepard_sum[f] > 0.9)) continue;  // fully inside the resin
    ++checked;
    worst = std::max(worst, std::abs(dem.resin_temperature[f] - (400 + 1e4 * dem.x[f][1])));
  }
  std::printf("[          ] %zu fiber particles in the resin: largest difference %.3g K\n", checked,
              worst);
  EXPECT_GT(checked, 50u);
  EXPECT_LT(worst, 1.0);
}

// --- input errors -----------------------------------------------------------------

constexpr const char* kCase = R"(dimension: 2                 # 1
resin:                       # 2
  density: 900               # 3
  viscosity: 0.1             # 4
  sound_speed: 60            # 5
  thermal:                   # 6
    temperature: 503         # 7
    heat_capacity: 2000      # 8
    conductivity: 0.2        # 9
    no_flow_temperature: 400 # 10
numerics:                    # 11
  spacing: 1.0e-3            # 12
  end_time: 0.12             # 13
mold:                        # 14
  shapes:                    # 15
    - box: {min: [0, 0], max: [0.02, 0.02]}    # 16
  temperature: 313           # 17
fill:                        # 18
  - box: {min: [0, 0], max: [0.01, 0.02]}      # 19
)";

std::string with(const std::string& from, const std::string& to,
                 std::string text = std::string(kCase)) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

void expect_error(const std::string& text, int line, const std::string& key,
                  const std::string& message) {
  try {
    const Case c = load_case_from_string(text, "case.yaml");
    Simulation<2> sim(c, world(), quiet());
    ADD_FAILURE() << "no error; expected case.yaml:" << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "case.yaml") << what;
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), key) << what;
    EXPECT_NE(what.find(message), std::string::npos) << what << "\n  expected: " << message;
  }
}

TEST(ThermalErrors, TheCaseLoads) {
  const Case c = load_case_from_string(kCase, "case.yaml");
  ASSERT_TRUE(c.resin.thermal);
  EXPECT_EQ(c.resin.thermal->temperature, 503);
  EXPECT_EQ(c.mold.temperature, 313);
  EXPECT_TRUE(c.warnings.empty());
}

TEST(ThermalErrors, NegativeConductivity) {
  expect_error(with("conductivity: 0.2 ", "conductivity: -0.2"), 9, "resin.thermal.conductivity",
               "must be positive, got -0.2");
}

TEST(ThermalErrors, NegativeHeatCapacity) {
  expect_error(with("heat_capacity: 2000 ", "heat_capacity: -2000"), 8,
               "resin.thermal.heat_capacity", "must be positive, got -2000");
}

TEST(ThermalErrors, MeltBelowNoFlowTemperature) {
  expect_error(with("temperature: 503 ", "temperature: 390 "), 7, "resin.thermal.temperature",
               "is not above no_flow_temperature 400 K");
}

TEST(ThermalErrors, NonPositiveInitialTemperatureExpression) {
  expect_error(std::string(kCase) + "initial_fields:\n  - temperature: '500 - 1e6 * x'\n", 21,
               "initial_fields[0].temperature", "not positive");
}

TEST(ThermalErrors, InitialTemperatureNeedsThermal) {
  const std::string isothermal = R"(dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 60}
numerics: {spacing: 1.0e-3, end_time: 0.12}
mold:
  shapes:
    - box: {min: [0, 0], max: [0.02, 0.02]}
fill:
  - box: {min: [0, 0], max: [0.01, 0.02]}
initial_fields:
  - temperature: 500
)";
  expect_error(isothermal, 10, "initial_fields[0].temperature", "needs resin.thermal");
}

TEST(ThermalErrors, HeatTransferCoefficientNeedsTemperature) {
  expect_error(with("  temperature: 313           # 17\n", "  heat_transfer_coefficient: 1000\n"),
               17, "mold.heat_transfer_coefficient", "only with temperature");
}

// A temperature that looks like Celsius is a warning (it may be meant),
// naming the file, line and key.
TEST(ThermalErrors, CelsiusLookingTemperaturesWarn) {
  const Case c = load_case_from_string(with("temperature: 313 ", "temperature: 40  "), "case.yaml");
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("case.yaml:17: key 'mold.temperature': 40 K looks like degrees "
                               "Celsius"),
            std::string::npos)
      << c.warnings[0];
  const Case melt =
      load_case_from_string(with("no_flow_temperature: 400", "no_flow_temperature: 100",
                                 with("temperature: 503 ", "temperature: 230 ")),
                            "case.yaml");
  ASSERT_EQ(melt.warnings.size(), 2u);
  EXPECT_NE(melt.warnings[0].find("case.yaml:7: key 'resin.thermal.temperature': 230 K"),
            std::string::npos)
      << melt.warnings[0];
}

}  // namespace
}  // namespace sphdem
