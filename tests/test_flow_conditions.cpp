// Wall conditions by name and initial fields from expressions (issue 18,
// docs/physics.md "Wall conditions", docs/case-file.md "initial_fields"):
// plane Poiseuille flow with Navier slip against its analytic profile, a
// free-slip channel that stays a plug, the Taylor-Green vortex set up by
// expressions against its exponential decay, and the input errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/sph/eos.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

constexpr double kPi = std::numbers::pi;

using testing::quiet;
using testing::world;

// --- wall conditions ----------------------------------------------------------

constexpr double kH = 1e-3, kNu = 1e-6;

// Steady plane Poiseuille flow between Navier-slip plates at y = 0 and
// y = H, slip length b: u = F/(2 nu) [(H/2)^2 - y'^2 + b H], y' = y - H/2.
double navier_poiseuille(double y, double F, double b) {
  const double yc = y - kH / 2;
  return F / (2 * kNu) * (kH * kH / 4 - yc * yc + b * kH);
}

// Issue 18: within 2 % relative L2 of the analytic profile at steady state
// (t = 1.5 s, the start-up transient below 1e-4). Measured: 0.25 % with 20
// particles across. The no-slip profile is 36 % off this one and free slip
// never becomes steady, so a condition that ignores the slip length fails.
TEST(WallConditions, NavierSlipPoiseuilleMatchesTheAnalyticProfile) {
  const Case c = testing::load_input("validation/poiseuille_navier_slip.yaml");
  const double F = c.body_force[0], b = *c.mold.slip_length;
  Simulation<2> sim(c, world(), quiet());
  testing::run_until(sim, c.numerics.end_time);
  const double err = testing::relative_l2_ux<2>(
      sim.particles(), [&](double y) { return navier_poiseuille(y, F, b); });
  std::printf("[          ] Navier slip b = %g m: relative L2 error %.4f at t = %.3f s\n", b, err,
              sim.time());
  EXPECT_LT(err, 0.02);
}

// With slip length 0 the Navier condition is the no-slip one (to round-off:
// the same velocity computed another way).
TEST(WallConditions, NavierSlipWithZeroLengthIsNoSlip) {
  const Case no_slip = testing::load_input("validation/poiseuille.yaml");
  const Case zero = testing::load_input("validation/poiseuille.yaml",
                                        {"mold.wall_condition=navier_slip", "mold.slip_length=0"});
  Simulation<2> a(no_slip, world(), quiet()), b(zero, world(), quiet());
  a.advance(300);
  b.advance(300);
  ASSERT_EQ(a.particles().n_owned, b.particles().n_owned);
  double vmax = 0, diff = 0;
  for (std::size_t i = 0; i < a.particles().n_owned; ++i) {
    vmax = std::max(vmax, a.particles().v[i].norm());
    diff = std::max(diff, (a.particles().v[i] - b.particles().v[i]).norm());
  }
  EXPECT_GT(vmax, 0.0);
  EXPECT_LT(diff, 1e-9 * vmax);
}

// Free slip: the walls exert no shear, so the body force accelerates the
// resin as a plug, u = F t everywhere. Measured spread (max - min)/mean
// 2.5e-7 at t = 0.1 s; with no-slip walls it is about 1.
TEST(WallConditions, FreeSlipChannelStaysAPlug) {
  const Case c =
      testing::load_input("validation/poiseuille.yaml", {"mold.wall_condition=free_slip"});
  Simulation<2> sim(c, world(), quiet());
  testing::run_until(sim, 0.1);
  const SphParticles<2>& ps = sim.particles();
  double lo = 1e300, hi = -1e300, sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    lo = std::min(lo, ps.v[i][0]);
    hi = std::max(hi, ps.v[i][0]);
    sum += ps.v[i][0];
    ++n;
  }
  const double mean = sum / static_cast<double>(n);
  const double plug = c.body_force[0] * sim.time();
  std::printf("[          ] free slip: mean %.6g m/s (F t = %.6g), spread %.3g\n", mean, plug,
              (hi - lo) / mean);
  EXPECT_LT((hi - lo) / mean, 0.01);
  EXPECT_NEAR(mean, plug, 0.01 * plug);
}

// --- initial fields -------------------------------------------------------------

// The Taylor-Green vortex of inputs/validation/taylor_green.yaml (L = 1 m,
// U = 1 m/s): the velocity mode at x, and its amplitude in the resin's
// velocity (least squares over the particles, at their current positions).
Vec<2> tg_mode(const Vec<2>& x) {
  return {-std::cos(2 * kPi * x[0]) * std::sin(2 * kPi * x[1]),
          std::sin(2 * kPi * x[0]) * std::cos(2 * kPi * x[1])};
}

double tg_amplitude(const SphParticles<2>& ps) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const Vec<2> m = tg_mode(ps.x[i]);
    num += m.dot(ps.v[i]);
    den += m.dot(m);
  }
  return num / den;
}

double kinetic_energy(const SphParticles<2>& ps) {
  double e = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) e += 0.5 * ps.mass[i] * ps.v[i].squaredNorm();
  return e;
}

// The expressions reach every particle: velocity and, through the equation
// of state, density from the pressure expression.
TEST(InitialFields, ExpressionsSetVelocityAndDensity) {
  const Case c = testing::load_input("validation/taylor_green.yaml");
  Simulation<2> sim(c, world(), quiet());
  const SphParticles<2>& ps = sim.particles();
  const TaitEos eos(c.resin.density, c.resin.sound_speed, c.resin.gamma);
  ASSERT_EQ(ps.n_owned, 1600u);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const Vec<2> x = ps.x[i];
    EXPECT_NEAR((ps.v[i] - tg_mode(x)).norm(), 0.0, 1e-14);
    const double p = -0.25 * (std::cos(4 * kPi * x[0]) + std::cos(4 * kPi * x[1]));
    EXPECT_NEAR(ps.rho[i], eos.density(p), 1e-14);
  }
}

// Issue 18: the velocity amplitude decays as exp(-8 pi^2 nu t / L^2), the
// kinetic energy as exp(-16 pi^2 nu t / L^2); the measured rates
// -ln(A(t)/A(0))/t and -ln(E(t)/E(0))/t must be within 5 % of these at
// t = 0.1, 0.15 and 0.2 s (the amplitude then 0.85). Measured: 2.5 % slow
// at 0.1 s (acoustic ringing of the start), 0.4 % (amplitude) and 1.1 %
// (energy) at 0.2 s. 5 % is issue 18's bound; a viscosity 10 % off (rate
// 1.093 of the exact at 0.2 s) or none fails it. The window is
// short on purpose: WCSPH without particle shifting disorders the particles
// where the flow strains them: at t = 0.3 s the amplitude is 7 % below the
// exact one (h = 2.5 dp; at 1.2 dp the particles clump by t = 0.08 s), see
// docs/physics.md "Initial state".
TEST(InitialFields, TaylorGreenVortexDecaysAtTheViscousRate) {
  const Case c = testing::load_input("validation/taylor_green.yaml");
  const double nu = c.resin.viscosity / c.resin.density;
  const double rate = 8 * kPi * kPi * nu;  // L = 1 m
  Simulation<2> sim(c, world(), quiet());
  const double a0 = tg_amplitude(sim.particles()), e0 = kinetic_energy(sim.particles());
  for (double t : {0.1, 0.15, 0.2}) {
    testing::run_until(sim, t);
    const double a = tg_amplitude(sim.particles()) / a0, e = kinetic_energy(sim.particles()) / e0;
    const double a_rate = -std::log(a) / sim.time(), e_rate = -std::log(e) / sim.time();
    std::printf(
        "[          ] t = %.2f s: amplitude %.5f (exact %.5f), decay rate %.4f of the "
        "exact; energy rate %.4f of the exact\n",
        sim.time(), a, std::exp(-rate * sim.time()), a_rate / rate, e_rate / (2 * rate));
    EXPECT_NEAR(a_rate / rate, 1.0, 0.05) << "amplitude at t = " << sim.time();
    EXPECT_NEAR(e_rate / (2 * rate), 1.0, 0.05) << "energy at t = " << sim.time();
  }
}

// --- input errors -----------------------------------------------------------------

constexpr const char* kCase = R"(dimension: 2                 # 1
resin:                       # 2
  density: 900               # 3
  viscosity: 0.1             # 4
  sound_speed: 60            # 5
numerics:                    # 6
  spacing: 1.0e-3            # 7
  end_time: 0.12             # 8
mold:                        # 9
  shapes:                    # 10
    - box: {min: [0, 0], max: [0.02, 0.02]}    # 11
fill:                        # 12
  - box: {min: [0, 0], max: [0.01, 0.02]}      # 13
  - box: {min: [0.01, 0], max: [0.02, 0.02]}   # 14
)";

void expect_error(const std::string& extra, int line, const std::string& key,
                  const std::string& message, bool build = false) {
  try {
    const Case c = load_case_from_string(std::string(kCase) + extra, "case.yaml");
    if (build) Simulation<2> sim(c, world(), quiet());
    ADD_FAILURE() << "no error; expected case.yaml:" << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "case.yaml") << what;
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), key) << what;
    EXPECT_NE(what.find(message), std::string::npos) << what << "\n  expected: " << message;
  }
}

TEST(WallConditionErrors, NegativeSlipLength) {
  expect_error(
      "sliding_walls:\n  - name: lid\n    region: {box: {min: [0, 0.02], max: [0.02, "
      "0.03]}}\n    velocity: [0, 0]\n    wall_condition: navier_slip\n"
      "    slip_length: -1.0e-4\n",
      20, "sliding_walls[0].slip_length", "must be zero or positive, got -1.0e-4");
}

TEST(WallConditionErrors, NavierSlipNeedsASlipLength) {
  std::string text(kCase);
  text.replace(text.find("mold:                        # 9"), 32,
               "mold:\n  wall_condition: navier_slip");
  try {
    load_case_from_string(text, "case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 9) << e.what();
    EXPECT_NE(std::string(e.what()).find("slip_length"), std::string::npos) << e.what();
  }
}

TEST(WallConditionErrors, SlipLengthOnlyWithNavierSlip) {
  expect_error(
      "moving_walls:\n  - name: piston\n    region: {box: {min: [0, 0.02], max: [0.02, "
      "0.03]}}\n    velocity_table: [[0, 0, 0]]\n    wall_condition: free_slip\n"
      "    slip_length: 1.0e-4\n",
      20, "moving_walls[0].slip_length", "only with wall_condition: navier_slip");
}

TEST(WallConditionErrors, UnknownCondition) {
  expect_error(
      "sliding_walls:\n  - name: lid\n    region: {box: {min: [0, 0.02], max: [0.02, "
      "0.03]}}\n    velocity: [0, 0]\n    wall_condition: free_slp\n",
      19, "sliding_walls[0].wall_condition", "free_slip");
}

TEST(InitialFieldErrors, BadExpression) {
  expect_error("initial_fields:\n  - velocity: ['sin(x', 0]\n", 16, "initial_fields[0].velocity[0]",
               "bad expression 'sin(x'");
  expect_error("initial_fields:\n  - pressure: 'q * x'\n", 16, "initial_fields[0].pressure",
               "bad expression 'q * x'");
}

TEST(InitialFieldErrors, WrongNumberOfComponents) {
  expect_error("initial_fields:\n  - velocity: [1, 2, 3]\n", 16, "initial_fields[0].velocity",
               "expected 2 expressions");
}

TEST(InitialFieldErrors, NoSuchFillRegion) {
  expect_error("initial_fields:\n  - fill: 2\n    velocity: [1, 0]\n", 16, "initial_fields[0].fill",
               "no fill[2]");
}

// Not finite at some particle of its region: found when the particles are
// made, reported at the expression (x > 0.01 holds only in fill[1]).
TEST(InitialFieldErrors, NotFiniteAtAParticle) {
  expect_error("initial_fields:\n  - fill: 1\n    velocity: [0, 'sqrt(0.01 - x)']\n", 17,
               "initial_fields[0].velocity[1]", "'sqrt(0.01 - x)' is", /*build=*/true);
  expect_error("initial_fields:\n  - density: '900 / (x - x)'\n", 16, "initial_fields[0].density",
               "is inf", /*build=*/true);
}

// The fill index selects the resin of one fill shape only.
TEST(InitialFields, PerFillRegion) {
  const Case c =
      load_case_from_string(std::string(kCase) +
                                "initial_velocity: [0.5, 0]\ninitial_fields:\n  - fill: 1\n"
                                "    velocity: ['2 * y', '-1']\n",
                            "case.yaml");
  Simulation<2> sim(c, world(), quiet());
  const SphParticles<2>& ps = sim.particles();
  int left = 0, right = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    if (ps.x[i][0] < 0.01) {
      EXPECT_EQ(ps.v[i], Vec<2>(0.5, 0));
      ++left;
    } else {
      EXPECT_EQ(ps.v[i], Vec<2>(2 * ps.x[i][1], -1));
      ++right;
    }
  }
  EXPECT_EQ(left, 200);
  EXPECT_EQ(right, 200);
}

}  // namespace
}  // namespace sphdem
