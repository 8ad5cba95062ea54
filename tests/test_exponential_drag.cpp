// Exponential drag (fibers.drag_integration: exponential; docs/physics.md
// "Exponential drag"): the exact two-body exchange against its closed form,
// then end to end against the drag law at the paper resin's step (a
// particle settling at its terminal velocity, a fiber taking up a stream's
// velocity, the explicit drag's trajectory) and, in a melt 1000 times as
// viscous, at a step 1000 times the fibers' drag time, where the explicit
// exchange would be limited to the drag time: stable, the fiber carried by
// the resin, momentum conserved at every step. Ranks: test_coupled_parallel.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/coupling/coupling.hpp"
#include "sphdem/dem/drag_exchange.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/coupling_module.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;

// The two-body exchange: the slip decays as exp(-dt c (1/m + 1/M)), the
// parcel takes the opposite impulse, short steps are the explicit drag and
// long ones end at the common velocity; a rigid resin (M = 0) at its own.
TEST(ExponentialDrag, ExchangeIsTheTwoBodySolution) {
  const double c = 3.0, m = 2.0, big_m = 5.0;
  const Vec<2> u(1.0, -2.0), v(0.25, 0.5);
  for (const double dt : {1e-7, 0.1, 1.0, 100.0}) {
    const Vec<2> j = drag_exchange_impulse<2>(c, m, big_m, dt, Vec<2>(u - v));
    const Vec<2> v1 = v + j / m, u1 = u - j / big_m;
    const Vec<2> expected = (u - v) * std::exp(-dt * c * (1 / m + 1 / big_m));
    EXPECT_LT((u1 - v1 - expected).norm(), 1e-14) << dt;
    EXPECT_LT((m * v1 + big_m * u1 - m * v - big_m * u).norm(), 1e-14) << dt;
  }
  const Vec<2> small = drag_exchange_impulse<2>(c, m, big_m, 1e-7, Vec<2>(u - v));
  EXPECT_NEAR((small - c * 1e-7 * (u - v)).norm() / small.norm(), 0.0, 1e-6);
  const Vec<2> common = (m * v + big_m * u) / (m + big_m);
  EXPECT_LT((v + drag_exchange_impulse<2>(c, m, big_m, 100.0, Vec<2>(u - v)) / m - common).norm(),
            1e-14);
  EXPECT_LT((v + drag_exchange_impulse<2>(c, m, 0.0, 100.0, Vec<2>(u - v)) / m - u).norm(), 1e-14);
}

// Sub-steps compose: ten exchanges of dt/10 are one of dt (the exponential
// is exact), for the velocity, the parcel and the impulse returned to the
// resin; the spin relaxes towards the resin's the same way.
TEST(ExponentialDrag, SubstepsCompose) {
  const auto particle = [] {
    DemParticles<2> ps;
    ps.push_owned(0, 0, Vec<2>::Zero(), 0.1, 1000.0);  // every field at zero
    ps.mass[0] = 2.0;
    ps.inertia[0] = 0.5;
    ps.drag_coeff[0] = 3.0;
    ps.drag_parcel_mass[0] = 5.0;
    ps.drag_velocity[0] = Vec<2>(1.0, -2.0);
    ps.v[0] = Vec<2>(0.25, 0.5);
    ps.torque_coeff[0] = 0.2;
    ps.resin_spin[0] = Rot<2>(4.0);
    return ps;
  };
  DemParticles<2> once = particle(), tenth = particle();
  relax_drag<2>(once, 0, 0.7);
  for (int k = 0; k < 10; ++k) relax_drag<2>(tenth, 0, 0.07);
  EXPECT_LT((once.v[0] - tenth.v[0]).norm(), 1e-14);
  EXPECT_LT((once.drag_velocity[0] - tenth.drag_velocity[0]).norm(), 1e-14);
  EXPECT_LT((once.drag_impulse[0] - tenth.drag_impulse[0]).norm(), 1e-14);
  EXPECT_NEAR(once.omega[0][0], 4.0 * -std::expm1(-0.7 * 0.2 / 0.5), 1e-14);
  EXPECT_NEAR(tenth.omega[0][0], once.omega[0][0], 1e-14);
  EXPECT_NEAR(once.torque_impulse[0][0], 0.5 * once.omega[0][0], 1e-14);
}

// A closed box full of resin with DEM particles in it (test_coupled.cpp's).
std::string box_case(const std::string& fibers, const std::string& extra,
                     const std::string& resin = "{density: 900, viscosity: 0.1, sound_speed: 50}") {
  return "dimension: 2\nresin: " + resin +
         "\nnumerics: {spacing: 3.0e-4, end_time: 1.0}\n"
         "mold:\n  shapes:\n    - box: {min: [0, 0], max: [0.012, 0.012]}\n"
         "fill:\n  - box: {min: [0, 0], max: [0.012, 0.012]}\n"
         "fibers:\n  diameter: 2.5e-4\n  density: 2540\n  youngs_modulus: 1.0e8\n"
         "  drag_integration: exponential\n" +
         fibers + extra;
}

CouplingParams drag_params(const Case& c) {
  CouplingParams p;
  p.rho = c.resin.density;
  p.mu = c.resin.viscosity;
  p.eps_min = c.fibers->void_fraction_min;
  return p;
}

// Coupled.TerminalVelocity with the exponential exchange: one particle
// settles at the slip where the drag carries its weight, rho_p g = K U.
// 3 %, as there (SPH pressure noise over 2 ms).
TEST(ExponentialDrag, TerminalVelocity) {
  const Case c = load_case_from_string(
      box_case("  count: 1\n  particles_per_fiber: 1\n"
               "  region: {box: {min: [0.0055, 0.0075], max: [0.0065, 0.0085]}}\n",
               "body_force: [0, -1000]\n"),
      "terminal.yaml");
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  double sum = 0, eps = 0;
  int n = 0;
  while (sim.time() < 6e-3) {
    sim.advance(1);
    if (sim.time() < 4e-3) continue;
    const auto& dem = sim.dem()->particles();
    sum += dem.resin_velocity[0][1] - dem.v[0][1];
    eps = dem.void_fraction[0];
    ++n;
  }
  const double slip = sum / n;
  const double expected = terminal_velocity<2>(drag_params(c), 2540, 2.5e-4, 1000, eps, false);
  std::printf("terminal slip %.5g m/s, drag law %.5g m/s (eps %.4f)\n", slip, expected, eps);
  EXPECT_NEAR(slip / expected, 1.0, 0.03);
}

// A closed 2D shear cell, 6 x 3 mm, lid at 0.03 m/s, one fiber of 4
// particles across the middle (test_coupled_window.cpp's).
std::string shear_case(double viscosity, double c0, const std::string& mode,
                       const std::string& numerics = "") {
  return "dimension: 2\nresin: {density: 900, viscosity: " + std::to_string(viscosity) +
         ", sound_speed: " + std::to_string(c0) +
         "}\n"
         "numerics: {spacing: 3.0e-4, end_time: 1.0" +
         numerics +
         "}\n"
         "mold: {shapes: [{box: {min: [0, 0], max: [0.006, 0.003]}}]}\n"
         "fill: [{box: {min: [0, 0], max: [0.006, 0.003]}}]\n"
         "sliding_walls:\n"
         "  - {name: lid, region: {box: {min: [-0.002, 0.003], max: [0.008, 0.004]}}, "
         "velocity: [0.03, 0]}\n"
         "fibers:\n"
         "  count: 1\n  orientation: 90\n  diameter: 2.5e-4\n  youngs_modulus: 1.0e8\n"
         "  density: 2540\n  drag_integration: " +
         mode +
         "\n"
         "  region: {box: {min: [0.0025, 0.001], max: [0.0035, 0.002]}}\n";
}

constexpr double kWall = 0.03;  // the lid's speed [m/s]

// The fiber's particles after `time` of the paper resin's shear cell, at a
// fixed step of 2e-6 s (below both drag times: the explicit exchange's own).
std::vector<Vec<2>> shear_fiber(const std::string& mode, double time, std::vector<Vec<2>>& v) {
  const Case c =
      load_case_from_string(shear_case(0.1, 3.0, mode, ", fixed_dt: 2.0e-6"), "shear.yaml");
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  while (sim.time() < time) sim.advance(1);
  const auto& dem = sim.dem()->particles();
  std::vector<Vec<2>> x(4);
  v.assign(4, Vec<2>::Zero());
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    x[static_cast<std::size_t>(dem.gid[f])] = dem.x[f];
    v[static_cast<std::size_t>(dem.gid[f])] = dem.v[f];
  }
  return x;
}

// At a small step (2e-6 s, below the fiber drag time of 7e-6 s and the
// resin's of 4.4e-6 s) the exponential exchange follows the explicit drag:
// over 10 ms the fiber's particles travel with the shear flow and end within
// 1 % of that travel of the explicit run's positions.
TEST(ExponentialDrag, FollowsTheExplicitDrag) {
  std::vector<Vec<2>> v_exp, v_ref;
  const std::vector<Vec<2>> x0 = shear_fiber("explicit", 0.0, v_ref);
  const std::vector<Vec<2>> ref = shear_fiber("explicit", 0.01, v_ref);
  const std::vector<Vec<2>> got = shear_fiber("exponential", 0.01, v_exp);
  double travel = 0, diff = 0, vdiff = 0, speed = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    travel = std::max(travel, (ref[i] - x0[i]).norm());
    diff = std::max(diff, (got[i] - ref[i]).norm());
    vdiff = std::max(vdiff, (v_exp[i] - v_ref[i]).norm());
    speed = std::max(speed, v_ref[i].norm());
  }
  std::printf("fiber travel %.4g m, exponential - explicit %.3g m (%.3g %%); velocity %.3g %%\n",
              travel, diff, 100 * diff / travel, 100 * vdiff / speed);
  EXPECT_GT(travel, 5e-5);
  EXPECT_LT(diff / travel, 0.01);
  EXPECT_LT(vdiff / speed, 0.05);
}

// A melt 1000 times as viscous (100 Pa s, implicit viscosity) in the
// periodic shear cell of inputs/validation/shear_cell.yaml (walls at
// +-0.1 m/s, the linear profile from t = 0), a glass fiber (2540 kg/m^3):
// the fibers' drag time is about 1e-8 s and the resin's step (CFL, 4e-5 s)
// thousands of them, where the explicit exchange would take as many
// sub-steps and resin steps per step. Exponential: no drag limit, the resin
// below the walls' speed, the fiber carried by the resin (its mean slip
// under 1 % of the walls' speed after 10 ms), drag and reaction cancelling
// at every step.
TEST(ExponentialDrag, ViscousMeltFarBeyondTheExplicitLimit) {
  const Case c = load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/validation/shear_cell.yaml",
                           {"resin.viscosity=100", "numerics.viscous_integration=implicit",
                            "fibers.density=2540", "fibers.drag_integration=exponential"});
  constexpr double kWalls = 0.1;  // the walls' speed [m/s]
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  double resin = 0, fiber = 0, worst = 0, ratio = 1e300;
  bool drag_limited = false;
  while (sim.time() < 0.01) {
    sim.advance(1);
    drag_limited = drag_limited || sim.last_dt_limit() == DtLimit::Drag;
    worst = std::max(worst, sim.coupling_momentum_residual());
    ratio = std::min(ratio, sim.last_dt() / sim.coupling()->fiber_drag_time());
    const auto& ps = sim.particles();
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) resin = std::max(resin, ps.v[i].norm() / kWalls);
    const auto& dem = sim.dem()->particles();
    for (std::size_t f = 0; f < dem.n_owned; ++f) fiber = std::max(fiber, dem.v[f].norm() / kWalls);
    ASSERT_TRUE(std::isfinite(resin) && std::isfinite(fiber));
  }
  // A rigid fiber in shear slips at its ends (it turns slower than the
  // resin's shear): its mean slip, the translation, must vanish.
  const auto& dem = sim.dem()->particles();
  double largest = 0, moved = 0;
  Vec<2> mean_slip = Vec<2>::Zero();
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    largest = std::max(largest, (dem.resin_velocity[f] - dem.v[f]).norm() / kWalls);
    mean_slip += (dem.resin_velocity[f] - dem.v[f]) / static_cast<double>(dem.n_owned);
    moved = std::max(moved, dem.v[f].norm() / kWalls);
  }
  const double slip = mean_slip.norm() / kWalls;
  std::printf(
      "step / fiber drag time >= %.3g; resin %.3g, fiber %.3g times the walls' speed; mean slip "
      "%.3g (largest %.3g); momentum residual %.3g\n",
      ratio, resin, fiber, slip, largest, worst);
  EXPECT_FALSE(drag_limited);
  EXPECT_GT(ratio, 1000.0);
  EXPECT_LT(resin, 1.05);
  EXPECT_LT(fiber, 1.0);
  EXPECT_GT(moved, 0.1) << "the fiber must move with the shear flow";
  EXPECT_LT(slip, 0.01);
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace sphdem
