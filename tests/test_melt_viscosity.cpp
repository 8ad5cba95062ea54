// Generalized-Newtonian resin (issue 13 part 1, docs/physics.md "Melt
// viscosity"): the viscosity laws against hand computations and their
// limits, the case-file keys and material files, and power-law plane
// Poiseuille flow against its steady profile (docs/validation.md
// "Power-law Poiseuille"), also with Carreau and Cross in their power-law
// limits, on N ranks bitwise equal to one rank.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "../src/sph/terms/viscosity_variable.hpp"
#include "mpi_test_helpers.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "sphdem/sph/viscosity_law.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

// --- the laws against hand computations ------------------------------------

MeltViscosity law(ViscosityLaw l) {
  MeltViscosity m;
  m.law = l;
  return m;
}

TEST(ViscosityLaw, PowerLawByHand) {
  MeltViscosity m = law(ViscosityLaw::PowerLaw);
  m.consistency = 2.0;
  m.n = 0.5;
  m.max = 100.0;
  // 2 * 4^-0.5 = 1; 2 * 0.01^-0.5 = 20.
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 4.0, 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 0.01, 0, 0), 20.0);
  // Zero shear rate: unbounded, capped at max; below min: min.
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 0.0, 0, 0), 100.0);
  m.min = 1.5;
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 4.0, 0, 0), 1.5);
  // n = 1 is Newtonian with mu = K.
  m = law(ViscosityLaw::PowerLaw);
  m.consistency = 0.3;
  m.n = 1.0;
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 123.0, 0, 0), 0.3);
}

TEST(ViscosityLaw, CarreauByHandAndLimits) {
  MeltViscosity m = law(ViscosityLaw::Carreau);
  m.eta0 = 1000.0;
  m.eta_inf = 10.0;
  m.relaxation_time = 0.5;
  m.n = 0.5;
  // gd = 2*sqrt(3)/... : (1 + (0.5*4)^2)^(-0.25) = 5^-0.25.
  EXPECT_NEAR(melt_viscosity(m, 0, 4.0, 0, 0), 10.0 + 990.0 * std::pow(5.0, -0.25), 1e-9);
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 0.0, 0, 0), 1000.0);  // Newtonian plateau eta0
  // Far in the shear-thinning range (eta_inf = 0) it is the power law
  // eta0 lambda^(n-1) gd^(n-1).
  m.eta_inf = 0.0;
  const double gd = 1e6;
  const double power = m.eta0 * std::pow(m.relaxation_time, m.n - 1) * std::pow(gd, m.n - 1);
  EXPECT_NEAR(melt_viscosity(m, 0, gd, 0, 0) / power, 1.0, 1e-6);
  // lambda -> 0: Newtonian eta0.
  m.relaxation_time = 1e-12;
  EXPECT_NEAR(melt_viscosity(m, 0, 10.0, 0, 0), 1000.0, 1e-12);
}

TEST(ViscosityLaw, CrossByHandAndLimits) {
  MeltViscosity m = law(ViscosityLaw::Cross);
  m.eta0 = 1000.0;
  m.tau_star = 2.0e4;
  m.n = 0.25;
  // eta0 gd / tau* = 1000 * 20 / 2e4 = 1: eta = eta0 / 2.
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 20.0, 0, 0), 500.0);
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 0.0, 0, 0), 1000.0);
  // High shear: the power law eta0^n tau*^(1-n) gd^(n-1).
  const double gd = 1e8;
  const double power =
      std::pow(m.eta0, m.n) * std::pow(m.tau_star, 1 - m.n) * std::pow(gd, m.n - 1);
  EXPECT_NEAR(melt_viscosity(m, 0, gd, 0, 0) / power, 1.0, 1e-4);
  // tau* -> infinity: Newtonian eta0.
  m.tau_star = 1e30;
  EXPECT_NEAR(melt_viscosity(m, 0, 1e3, 0, 0), 1000.0, 1e-9);
}

TEST(ViscosityLaw, CrossWlfByHand) {
  MeltViscosity m = law(ViscosityLaw::CrossWlf);
  m.n = 0.3;
  m.tau_star = 3.0e4;
  m.d1 = 1.0e14;
  m.d2 = 263.15;
  m.d3 = 0.0;
  m.a1 = 30.0;
  m.a2_tilde = 51.6;
  // At T = D2: eta0 = D1.
  EXPECT_DOUBLE_EQ(cross_wlf_zero_shear(m, 263.15, 0.0), 1.0e14);
  // At 503.15 K: eta0 = D1 exp(-30 * 240 / 291.6).
  const double eta0 = 1.0e14 * std::exp(-30.0 * 240.0 / 291.6);
  EXPECT_NEAR(cross_wlf_zero_shear(m, 503.15, 0.0) / eta0, 1.0, 1e-12);
  EXPECT_NEAR(melt_viscosity(m, 0, 1000.0, 503.15, 0.0) /
                  (eta0 / (1.0 + std::pow(eta0 * 1000.0 / 3.0e4, 0.7))),
              1.0, 1e-12);
  // Pressure raises T* by D3 p (and A2 with it): at D3 = 1e-7 K/Pa and
  // 100 MPa the melt is as viscous as 10 K colder at zero pressure.
  m.d3 = 1.0e-7;
  EXPECT_NEAR(cross_wlf_zero_shear(m, 503.15, 1.0e8) / (1.0e14 * std::exp(-30.0 * 230.0 / 291.6)),
              1.0, 1e-12);
  // Below the no-flow temperature: max.
  m.no_flow_temperature = 400.0;
  m.max = 1e7;
  EXPECT_DOUBLE_EQ(melt_viscosity(m, 0, 1000.0, 390.0, 0.0), 1e7);
}

// --- the case-file keys -------------------------------------------------------

std::string base_case(const std::string& resin_extra) {
  return "dimension: 2\n"
         "resin:\n"
         "  density: 900\n" +
         resin_extra +
         "  sound_speed: 10\n"
         "numerics: {spacing: 1.0e-3, end_time: 0.01}\n"
         "mold: {shapes: [{box: {min: [0, 0], max: [0.01, 0.01]}}]}\n"
         "fill: [{box: {min: [0, 0], max: [0.01, 0.01]}}]\n";
}

std::string error_of(const std::string& text) {
  try {
    load_case_from_string(text, "case.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ViscosityKeys, PlainNumberStaysNewtonian) {
  const Case c = load_case_from_string(base_case("  viscosity: 0.1\n"), "case.yaml");
  EXPECT_EQ(c.resin.melt.law, ViscosityLaw::Newtonian);
  EXPECT_EQ(c.resin.viscosity, 0.1);
  const SphParams sp = make_sph_params(c);
  EXPECT_FALSE(sp.variable_viscosity);
}

TEST(ViscosityKeys, LawsAndTheirErrors) {
  const Case c = load_case_from_string(
      base_case("  viscosity: {model: cross, zero_shear_viscosity: 50, tau_star: 1.0e4, n: 0.4}\n"),
      "case.yaml");
  EXPECT_EQ(c.resin.melt.law, ViscosityLaw::Cross);
  EXPECT_EQ(c.resin.viscosity, 50.0);  // the largest: eta0
  EXPECT_TRUE(make_sph_params(c).variable_viscosity);

  const std::string unknown = error_of(base_case("  viscosity: {model: crosswlf, n: 0.3}\n"));
  EXPECT_NE(unknown.find("case.yaml:4: key 'resin.viscosity.model'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("newtonian, power_law, carreau, cross, cross_wlf"), std::string::npos)
      << unknown;
  EXPECT_NE(unknown.find("did you mean 'cross_wlf'"), std::string::npos) << unknown;

  const std::string negative =
      error_of(base_case("  viscosity: {model: power_law, consistency: -2, n: 0.5, max: 1}\n"));
  EXPECT_NE(negative.find("key 'resin.viscosity.consistency'"), std::string::npos) << negative;
  EXPECT_NE(negative.find("positive"), std::string::npos) << negative;

  const std::string no_max =
      error_of(base_case("  viscosity: {model: power_law, consistency: 2, n: 0.5}\n"));
  EXPECT_NE(no_max.find("max"), std::string::npos) << no_max;

  const std::string foreign = error_of(
      base_case("  viscosity: {model: cross, zero_shear_viscosity: 50, tau_star: 1, n: 0.4, "
                "d1: 3}\n"));
  EXPECT_NE(foreign.find("key 'resin.viscosity.d1': does not apply to model 'cross'"),
            std::string::npos)
      << foreign;
}

const std::string kWlf =
    "  viscosity:\n"
    "    model: cross_wlf\n"
    "    n: 0.3\n"
    "    tau_star: 3.0e4\n"
    "    d1: 1.0e14\n"
    "    d2: D2\n"
    "    a1: 30\n"
    "    a2_tilde: 51.6\n"
    "    no_flow_temperature: 400\n";

std::string wlf(const std::string& d2, const std::string& melt) {
  std::string s = kWlf;
  s.replace(s.find("D2"), 2, d2);
  return s + (melt.empty() ? "" : "  melt_temperature: " + melt + "\n");
}

TEST(ViscosityKeys, CrossWlfTemperatures) {
  const Case c = load_case_from_string(base_case(wlf("263.15", "503.15")), "case.yaml");
  EXPECT_TRUE(c.warnings.empty());
  EXPECT_NEAR(c.resin.viscosity / (1.0e14 * std::exp(-30.0 * 240.0 / 291.6)), 1.0, 1e-12);
  // D2 in Celsius (50 degC for a PA66): a warning naming file, line and key.
  const Case celsius = load_case_from_string(base_case(wlf("50", "503.15")), "case.yaml");
  ASSERT_EQ(celsius.warnings.size(), 1u);
  EXPECT_NE(celsius.warnings[0].find("case.yaml:9: key 'resin.viscosity.d2'"), std::string::npos)
      << celsius.warnings[0];
  EXPECT_NE(celsius.warnings[0].find("Celsius"), std::string::npos);
  // A melt temperature in Celsius is below no-flow: an error after the warning.
  const std::string cold = error_of(base_case(wlf("263.15", "230")));
  EXPECT_NE(cold.find("case.yaml:13: key 'resin.melt_temperature'"), std::string::npos) << cold;
  EXPECT_NE(cold.find("below the no-flow temperature 400 K"), std::string::npos) << cold;
  const std::string none = error_of(base_case(wlf("263.15", "")));
  EXPECT_NE(none.find("melt_temperature"), std::string::npos) << none;
}

// One Celsius rule for every temperature key (docs/case-file.md
// "resin.thermal"): below 250 K a warning, whichever key. A D2 of 230 K was
// silent while the viscosity keys warned only below 200 K.
TEST(ViscosityKeys, OneCelsiusRuleForEveryTemperature) {
  const Case d2 = load_case_from_string(base_case(wlf("230", "503.15")), "case.yaml");
  ASSERT_EQ(d2.warnings.size(), 1u);
  EXPECT_NE(d2.warnings[0].find("key 'resin.viscosity.d2': 230 K looks like degrees Celsius"),
            std::string::npos)
      << d2.warnings[0];
  EXPECT_NE(d2.warnings[0].find("below 250 K"), std::string::npos) << d2.warnings[0];
  EXPECT_TRUE(load_case_from_string(base_case(wlf("255", "503.15")), "case.yaml").warnings.empty());
}

// With resin.thermal the law reads each particle's own temperature (a cold
// particle near the mold is more viscous), the melt temperature is the
// thermal block's, and giving it twice is an error.
TEST(ViscosityKeys, CrossWlfReadsTheParticleTemperature) {
  const std::string thermal =
      "  thermal: {temperature: 503.15, heat_capacity: 2000, conductivity: 0.2}\n";
  const Case c = load_case_from_string(base_case(wlf("263.15", "") + thermal), "case.yaml");
  EXPECT_NEAR(c.resin.viscosity / (1.0e14 * std::exp(-30.0 * 240.0 / 291.6)), 1.0, 1e-12);
  const std::string twice = error_of(base_case(wlf("263.15", "503.15") + thermal));
  EXPECT_NE(twice.find("key 'resin.melt_temperature'"), std::string::npos) << twice;
  EXPECT_NE(twice.find("give it once"), std::string::npos) << twice;

  const SphParams sp = make_sph_params(c);
  ASSERT_TRUE(sp.thermal && sp.variable_viscosity);
  SphParticles<2> ps;
  for (std::int64_t i = 0; i < 2; ++i) {
    ps.push_owned(i, Kind::Fluid, -1, 1e-6, Vec<2>(0.001 * double(i), 0), Vec<2>::Zero(), 900);
    ps.shear_rate[std::size_t(i)] = 100.0;
  }
  ps.temperature[0] = 503.15;
  ps.temperature[1] = 453.15;
  terms::compute_particle_viscosity(sp, ps);
  EXPECT_DOUBLE_EQ(ps.viscosity[0], melt_viscosity(c.resin.melt, sp.mu, 100.0, 503.15, 0.0));
  EXPECT_DOUBLE_EQ(ps.viscosity[1], melt_viscosity(c.resin.melt, sp.mu, 100.0, 453.15, 0.0));
  EXPECT_GT(ps.viscosity[1], 1.5 * ps.viscosity[0]);  // 642 against 408 Pa s
}

// Every grade of the material library loads, with the source it cites.
TEST(ViscosityKeys, MaterialLibrary) {
  for (const char* grade : {"pp_typical.yaml", "pa66_typical.yaml"}) {
    const std::string path = std::string(SPHDEM_SOURCE_DIR) + "/inputs/materials/" + grade;
    const Case c = load_case_from_string(
        base_case("  material: " + path + "\n  melt_temperature: 553.15\n"), "case.yaml");
    EXPECT_EQ(c.resin.melt.law, ViscosityLaw::CrossWlf) << grade;
    EXPECT_EQ(c.resin.melt.material, path);
    EXPECT_TRUE(c.warnings.empty()) << grade;
    // Shear thinning at molding shear rates: 1e3 1/s well below eta0.
    const double eta0 = melt_viscosity(c.resin.melt, 0, 0.0, 553.15, 0.0);
    EXPECT_GT(eta0, 10.0) << grade;
    EXPECT_LT(melt_viscosity(c.resin.melt, 0, 1e3, 553.15, 0.0), 0.5 * eta0) << grade;
  }
  const std::string both =
      error_of(base_case("  viscosity: 1\n  material: " + std::string(SPHDEM_SOURCE_DIR) +
                         "/inputs/materials/pp_typical.yaml\n  melt_temperature: 503\n"));
  EXPECT_NE(both.find("either viscosity or material"), std::string::npos) << both;
  const std::string missing = error_of(base_case("  material: no_such_grade.yaml\n"));
  EXPECT_NE(missing.find("key 'resin.material': cannot open material file"), std::string::npos)
      << missing;
}

// docs/physics.md "Injection pressure": the paper's plate (0.1 Pa s) is
// carried by its sound speed; a real melt's viscous pressure drop is not,
// and `check` says which sound speed would carry it.
bool warns_pressure(const Case& c) {
  for (const std::string& w : c.warnings)
    if (w.find("viscous pressure drop") != std::string::npos) return true;
  return false;
}

TEST(ViscosityKeys, PressureWarning) {
  EXPECT_FALSE(warns_pressure(testing::load_input("plate.yaml")));
  const Case melt =
      testing::load_input("plate.yaml", {"resin.material=materials/pp_typical.yaml",
                                         "resin.melt_temperature=503.15", "resin.viscosity=null"});
  ASSERT_TRUE(warns_pressure(melt));
  for (const std::string& w : melt.warnings) {
    if (w.find("viscous pressure drop") != std::string::npos) {
      EXPECT_NE(w.find("a sound speed of"), std::string::npos) << w;
    }
  }
}

// With resin.thermal the estimate takes the law at the melt's initial
// temperature: the real-melt plate (Cross-WLF PP at 503.15 K, piston 1 m/s,
// gap 4 mm, so 6 U / W = 1500 1/s) gives by hand eta0 = 1.5e12
// exp(-25 x 240 / 291.6) = 1.74e3 Pa s and eta = eta0 / (1 + (eta0 1500 /
// 3e4)^0.7) = 73 Pa s, not the law's max (1e7 Pa s) of a cold particle.
TEST(ViscosityKeys, PressureWarningAtTheMeltTemperature) {
  const Case melt = testing::load_input("plate_melt_pp.yaml");
  ASSERT_TRUE(warns_pressure(melt));
  for (const std::string& w : melt.warnings) {
    if (w.find("viscous pressure drop") == std::string::npos) continue;
    const auto at = w.find(": eta ");
    ASSERT_NE(at, std::string::npos) << w;
    const double eta = std::stod(w.substr(at + 6));
    EXPECT_NEAR(eta, 73.0, 2.0) << w;
  }
}

// The injection pressure series: a row per snapshot for the piston, its
// speed and the face pressure the run reports (docs/physics.md "Injection
// pressure").
TEST(InjectionPressure, CsvSeriesPerSnapshot) {
  const Case c = testing::load_input("plate.yaml");
  const std::string dir = std::string(SPHDEM_BINARY_DIR) + "/melt_work/plate";
  std::filesystem::remove_all(dir);
  RunOptions opt;
  opt.output_dir = dir;
  opt.max_steps = 30;
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, opt);
  sim.run();
  std::ifstream in(dir + "/plate_injection_pressure.csv");
  ASSERT_TRUE(in) << "no injection pressure series";
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time_s,step,wall,speed_m_per_s,pressure_pa");
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 2u);  // the first and the last snapshot
  EXPECT_EQ(rows[0].rfind("0,0,piston,1,", 0), 0u) << rows[0];
  EXPECT_NE(rows[1].find(",30,piston,"), std::string::npos) << rows[1];
  const double p = std::stod(rows[1].substr(rows[1].rfind(',') + 1));
  EXPECT_TRUE(std::isfinite(p));
  EXPECT_GT(p, 0.0);  // the piston pushes the bath
}

// --- power-law plane Poiseuille ---------------------------------------------------

constexpr double kL = 1e-3, kH = 0.5e-3, kRhoG = 0.1;  // rho g = 1000 * 1e-4

// u(y) = n/(n+1) (rho g/K)^(1/n) (H^((n+1)/n) - |y - H|^((n+1)/n)).
double power_law_poiseuille(double y, double n, double K) {
  const double e = (n + 1) / n;
  return n / (n + 1) * std::pow(kRhoG / K, 1 / n) *
         (std::pow(kH, e) - std::pow(std::abs(y - kH), e));
}

// The overrides that start the case on the power-law profile of (n, K).
std::vector<std::string> start_on_profile(double n, double K) {
  return {
      fmt::format("initial_fields[0].velocity=['({n}/({n}+1))*({g}/{K})^(1/{n})*({H}^(({n}+1)/"
                  "{n}) - abs(y - {H})^(({n}+1)/{n}))', 0]",
                  fmt::arg("n", n), fmt::arg("K", K), fmt::arg("g", kRhoG), fmt::arg("H", kH))};
}

struct Variant {
  const char* name;
  std::vector<std::string> sets;
  double n, K;  // the power law it is (in its limit)
};

std::vector<Variant> variants() {
  std::vector<Variant> v;
  v.push_back({"power law n = 0.5", start_on_profile(0.5, 2.5e-4), 0.5, 2.5e-4});
  auto s08 = start_on_profile(0.8, 5e-4);
  s08.push_back("resin.viscosity.n=0.8");
  s08.push_back("resin.viscosity.consistency=5e-4");
  v.push_back({"power law n = 0.8", s08, 0.8, 5e-4});
  // Carreau with eta0 lambda^(n-1) = K: the power law wherever lambda gd >> 1
  // (lambda gd = 64 at the walls); eta0 takes the place of `max`.
  auto carreau = start_on_profile(0.5, 2.5e-4);
  carreau.push_back(
      "resin.viscosity={model: carreau, zero_shear_viscosity: 1.0e-2, relaxation_time: 1600, n: "
      "0.5}");
  v.push_back({"carreau in its power-law limit", carreau, 0.5, 2.5e-4});
  return v;
}

double run_and_compare(const Case& c, double n, double K, double t_end) {
  static const Comm comm(MPI_COMM_SELF);
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  testing::run_until(sim, t_end);
  return testing::relative_l2_ux<2>(sim.particles(),
                                    [&](double y) { return power_law_poiseuille(y, n, K); });
}

// Steady profile within 2 % (relative L2) after 3 viscous times.
TEST(PowerLawPoiseuille, SteadyProfile) {
  for (const Variant& v : variants()) {
    const Case c = testing::load_input("validation/poiseuille_power_law.yaml", v.sets);
    const double err = run_and_compare(c, v.n, v.K, c.numerics.end_time);
    std::printf("[          ] %s: relative L2 error %.4f at t = %g s\n", v.name, err,
                c.numerics.end_time);
    EXPECT_LT(err, 0.02) << v.name;
  }
}

// Cross in its Newtonian limit (tau* -> infinity: eta = eta0 (1 - 2e-8)
// here) runs the variable-viscosity term with equal viscosities, which is
// the Newtonian term up to round-off: the same flow as the Newtonian resin.
// (Cross's power-law limit converges slowly, as (eta0 gd / tau*)^(n-1):
// ViscosityLaw.CrossByHandAndLimits checks it at gd = 1e8.)
TEST(PowerLawPoiseuille, CrossNewtonianLimit) {
  const auto ux = [](const std::vector<std::string>& sets) {
    const Case c = testing::load_input("validation/poiseuille_power_law.yaml", sets);
    const Comm self(MPI_COMM_SELF);
    RunOptions opt;
    opt.write_output = false;
    Simulation<2> sim(c, self, opt);
    testing::run_until(sim, 0.05);
    std::vector<std::pair<std::int64_t, double>> u;
    const auto& ps = sim.particles();
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) u.emplace_back(ps.gid[i], ps.v[i][0]);
    std::sort(u.begin(), u.end());
    return u;
  };
  const auto newtonian = ux({"resin.viscosity=1.25e-3"});
  const auto cross = ux(
      {"resin.viscosity={model: cross, zero_shear_viscosity: 1.25e-3, tau_star: 1.0e12, n: 0.5}"});
  ASSERT_EQ(newtonian.size(), cross.size());
  double num = 0, den = 0;
  for (std::size_t k = 0; k < newtonian.size(); ++k) {
    num += std::pow(cross[k].second - newtonian[k].second, 2);
    den += std::pow(newtonian[k].second, 2);
  }
  const double diff = std::sqrt(num / den);
  std::printf("[          ] cross (tau* = 1e12) against newtonian: relative L2 %.3g\n", diff);
  EXPECT_LT(diff, 1e-6);
}

// The same start with a Newtonian resin of the wall viscosity drifts to its
// parabola: the check above can fail.
TEST(PowerLawPoiseuille, NewtonianDriftsAway) {
  const Case c =
      testing::load_input("validation/poiseuille_power_law.yaml", {"resin.viscosity=1.25e-3"});
  const double err = run_and_compare(c, 0.5, 2.5e-4, c.numerics.end_time);
  std::printf("[          ] newtonian from the power-law profile: relative L2 error %.4f\n", err);
  EXPECT_GT(err, 0.1);
}

// --- N ranks against one --------------------------------------------------------

struct Row {
  std::int64_t gid = 0;
  double value[6] = {};
};

std::vector<Row> run_rows(const Comm& comm, int steps) {
  const Case c =
      testing::load_input("validation/poiseuille_power_law.yaml",
                          {"parallel.balance_every=25", "parallel.imbalance_threshold=0.001"});
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  sim.advance(steps);
  const auto& ps = sim.particles();
  std::vector<Row> rows;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    rows.push_back(
        {ps.gid[i], {ps.x[i][0], ps.x[i][1], ps.v[i][0], ps.v[i][1], ps.rho[i], ps.viscosity[i]}});
  }
  return testing_mpi::gather_rows(comm, rows);
}

TEST(PowerLawPoiseuilleParallel, RankIndependent) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  constexpr int kSteps = 300;
  std::vector<Row> ref;
  if (world.root()) ref = run_rows(Comm(MPI_COMM_SELF), kSteps);
  testing_mpi::wait_for_root(world);
  const std::vector<Row> got = run_rows(world, kSteps);
  if (!world.root()) return;
  ASSERT_EQ(ref.size(), got.size());
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref, got), 0u);
}

}  // namespace
}  // namespace sphdem
