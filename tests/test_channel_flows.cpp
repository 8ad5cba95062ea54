// Plane Poiseuille and Couette flow against the start-up series solutions of
// Morris, Fox & Zhu (1997). Tolerances (issue 2): relative L2 error below
// 5 % during the transient and below 2 % at steady state. With 20 particles
// across the channel the measured errors are about 0.5 % (Poiseuille), so
// the bounds leave room for platform differences, not for a wrong wall or
// viscosity term: a wall that slips or a Laplacian off by 5 % fails them.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "validation_helpers.hpp"

namespace sphdem {
namespace {

constexpr double kL = 1e-3, kNu = 1e-6;
// Shear rate against |du/dy| (relative L2 over the particles 2h from both
// plates): measured 0.26 % at nu t/L^2 = 0.05, 0.04 % at steady state.
// 2 % leaves room for platform differences and still fails for a gradient
// without the lattice correction (3.6 % short in 2D) or of the wrong field.
constexpr double kShearRateTolerance = 0.02;

// Runs the case and compares u_x(y) with `exact(y, t)` at nu t / L^2 = 0.05,
// 0.1 and 0.2 (transient) and at t = 1 s (nu t / L^2 = 1: steady, the slowest
// mode has decayed by e^-pi^2). Returns the simulation for further checks.
// `also(sim)` runs after each comparison, for checks of further fields.
std::unique_ptr<Simulation<2>> check_profiles(
    const Case& c, const std::function<double(double, double)>& exact,
    const std::function<void(const Simulation<2>&)>& also = [](const Simulation<2>&) {}) {
  static const Comm comm;
  RunOptions opt;
  opt.write_output = false;
  auto sim = std::make_unique<Simulation<2>>(c, comm, opt);
  auto error_now = [&] {
    const double t = sim->time();
    return testing::relative_l2_ux<2>(sim->particles(), [&](double y) { return exact(y, t); });
  };
  for (double tau : {0.05, 0.1, 0.2}) {
    testing::run_until(*sim, tau * kL * kL / kNu);
    EXPECT_LT(error_now(), 0.05) << "transient at nu t/L^2 = " << tau;
    also(*sim);
  }
  testing::run_until(*sim, 1.0);
  EXPECT_LT(error_now(), 0.02) << "steady state";
  also(*sim);
  return sim;
}

TEST(Poiseuille, TransientAndSteadyProfiles) {
  const Case c = testing::load_input("validation/poiseuille.yaml");
  const double F = c.body_force[0];
  auto sim =
      check_profiles(c, [&](double y, double t) { return testing::poiseuille(y, t, kL, kNu, F); });
  // No cross-flow: the transverse velocity is round-off.
  double vy = 0;
  for (std::size_t i = 0; i < sim->particles().n_owned; ++i) {
    vy = std::max(vy, std::abs(sim->particles().v[i][1]));
  }
  EXPECT_LT(vy, 1e-3 * F * kL * kL / (8 * kNu));
}

// Also the shear-rate pass (requested through output.fields): in the
// interior (2h from both plates) gamma_dot matches |du/dy| of the series.
TEST(Couette, TransientAndSteadyProfiles) {
  const Case c = testing::load_input("validation/couette.yaml",
                                     {"output.fields=[velocity, density, pressure, shear_rate]"});
  const double v0 = c.sliding_walls.at(0).velocity[0];
  int checks = 0;
  check_profiles(
      c, [&](double y, double t) { return testing::couette(y, t, kL, kNu, v0); },
      [&](const Simulation<2>& sim) {
        const double err = testing::relative_l2_shear_rate<2>(
            sim.particles(), 2.0 * c.h(), kL,
            [&](double y) { return std::abs(testing::couette_shear(y, sim.time(), kL, kNu, v0)); });
        std::printf("[          ] t = %.3f s: shear rate relative L2 error %.4f\n", sim.time(),
                    err);
        EXPECT_LT(err, kShearRateTolerance) << "shear rate at t = " << sim.time();
        ++checks;
      });
  EXPECT_EQ(checks, 4);
}

}  // namespace
}  // namespace sphdem
