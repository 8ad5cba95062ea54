// Two-way SPH-DEM coupling end to end (issue 5, docs/physics.md
// "Coupling"): momentum balance of drag and reaction at every step, a
// particle settling at the drag law's terminal velocity, a fiber taking up
// the resin's velocity with the drag law's time constant. The two reference
// solutions run on one rank (MPI_COMM_SELF; tests/dem.cmake runs them at 1
// rank only), the momentum balance on 1 and 2 ranks. The comparison of N
// ranks with one is tests/test_coupled_parallel.cpp.
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/coupling/coupling.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;

// A closed box full of resin with DEM particles in it.
std::string box_case(const std::string& fibers, const std::string& extra,
                     const std::string& resin = "{density: 900, viscosity: 0.1, sound_speed: 50}") {
  return R"(dimension: 2
resin: )" +
         resin + R"(

numerics: {spacing: 3.0e-4, end_time: 1.0}
mold:
  shapes:
    - box: {min: [0, 0], max: [0.012, 0.012]}
fill:
  - box: {min: [0, 0], max: [0.012, 0.012]}
fibers:
  diameter: 2.5e-4
  density: 2540
  youngs_modulus: 1.0e8
)" + fibers +
         extra;
}

CouplingParams drag_params(const Case& c) {
  CouplingParams p;
  p.rho = c.resin.density;
  p.mu = c.resin.viscosity;
  p.eps_min = c.fibers->void_fraction_min;
  return p;
}

// One particle (a one-particle fiber) released at rest under gravity in
// still resin settles at the slip where the drag carries its weight. The
// model has no buoyancy on fibers (docs/physics.md "Coupling"), so rho_p g = K(eps, U) U,
// with eps the void fraction at the particle (its own volume smoothed by
// the kernel). The slip is measured against the Shepard resin velocity.
// 3 %: the slip is averaged over 2 ms of SPH pressure noise.
TEST(Coupled, TerminalVelocity) {
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

// A fiber at rest across a uniform resin stream: its slip decays with the
// drag law's time constant. Each particle i relaxes at rate K_i V / m; the
// bonded fiber at the mean rate. The resin around it gets the reaction, so
// the slip (vbar - v) closes faster than the fiber alone would, by the
// factor 1 + (the resin's share): the change of vbar over the fiber's
// change, measured. A heavy resin (10x) keeps that share small (5 %) and
// a slow stream (0.02 m/s) keeps Re at 0.01, where K is the Stokes-limit
// value. The void fraction is kept out of the continuity equation here:
// with it, the resin must speed up through the fiber (div u = -(1/eps)
// Deps/Dt), which it does through pressure waves that ring around vbar
// (docs/physics.md), and the test is of the drag law. 5 %: the issue's
// tolerance; measured 0.1 %.
TEST(Coupled, FiberRelaxation) {
  const Case c = load_case_from_string(
      box_case("  count: 1\n  orientation: 90\n  void_fraction_in_continuity: false\n"
               "  region: {box: {min: [0.0055, 0.0045], max: [0.0065, 0.0075]}}\n",
               "initial_velocity: [0.02, 0]\n", "{density: 9000, viscosity: 0.1, sound_speed: 50}"),
      "relax.yaml");
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  const auto& dem = sim.dem()->particles();
  const auto mean_x = [&](const std::vector<Vec<2>>& v) {
    double s = 0;
    for (std::size_t i = 0; i < 4; ++i) s += v[i][0];
    return s / 4;
  };
  // Predicted time constant of the fiber alone (Stokes-limit K at t = 0).
  const CouplingParams p = drag_params(c);
  double rate = 0;
  for (std::size_t i = 0; i < 4; ++i)
    rate += 1.0 / stokes_relaxation_time(p, 2540, 2.5e-4, dem.void_fraction[i]);
  const double tau = 4.0 / rate;
  std::vector<double> t, slip, vf, vbar;
  while (sim.time() < 5 * tau) {
    sim.advance(1);
    t.push_back(sim.time());
    vf.push_back(mean_x(dem.v));
    vbar.push_back(mean_x(dem.resin_velocity));
    slip.push_back(vbar.back() - vf.back());
  }
  // e-folding time of the slip, by log-linear fit over 0.2 tau .. 3 tau.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 0.2 * tau || t[k] > 3 * tau) continue;
    const double y = std::log(slip[k]);
    sx += t[k];
    sy += y;
    sxx += t[k] * t[k];
    sxy += t[k] * y;
    ++n;
  }
  const double fitted = -(n * sxx - sx * sx) / (n * sxy - sx * sy);
  // The resin's share: the ratio of vbar's change to the fiber's change.
  const double resin_share = (vbar.front() - vbar.back()) / (vf.back() - vf.front());
  const double expected = tau / (1 + resin_share);
  std::printf(
      "fiber relaxation: tau fitted %.4g s, drag law %.4g s (fiber alone %.4g s, resin "
      "share %.3f), %d points\n",
      fitted, expected, tau, resin_share, n);
  EXPECT_NEAR(fitted / expected, 1.0, 0.05);
  EXPECT_GT(n, 10);
}

// Momentum: the drags on the fibers and the reactions on the resin cancel
// at every step, to round-off. The residual is 0 when there is no drag, so
// the drag must be a sizeable fraction of the fibers' weight at every step;
// on several ranks, fibers must sit near a rank border (their drag and its
// reaction then involve particles of two ranks).
TEST(Coupled, MomentumBalanceEveryStep) {
  const Case c = load_case_from_string(
      box_case("  count: 12\n  region: {box: {min: [0.002, 0.002], max: [0.010, 0.010]}}\n",
               "initial_velocity: [0.3, 0.1]\nbody_force: [0, -500]\n"),
      "momentum.yaml");
  const Comm world;
  Simulation<2> sim(c, world, quiet());
  const DemParticles<2>& fibers = sim.dem()->particles();
  double weight = 0;
  for (std::size_t f = 0; f < fibers.n_owned; ++f) weight += fibers.mass[f] * 500;
  weight = world.sum(weight);
  double worst = 0, weakest = std::numeric_limits<double>::infinity();
  std::int64_t ghost_fibers = 0;
  for (int s = 0; s < 300; ++s) {
    sim.advance(1);
    worst = std::max(worst, sim.coupling_momentum_residual());
    double drag = 0;
    for (std::size_t f = 0; f < fibers.n_owned; ++f) drag += fibers.mean_drag[f].norm();
    weakest = std::min(weakest, world.sum(drag));
    ghost_fibers += static_cast<std::int64_t>(fibers.size() - fibers.n_owned);
  }
  ghost_fibers = world.sum(ghost_fibers);
  if (world.root())
    std::printf("weakest total drag %.3g N (fibers' weight %.3g N), %lld ghost fiber samples\n",
                weakest, weight, static_cast<long long>(ghost_fibers));
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(weakest, 0.1 * weight) << "a step with (almost) no drag balances trivially";
  EXPECT_GT(sim.dem_substeps(), 0);
  if (world.size() > 1) {
    EXPECT_GT(ghost_fibers, 0) << "no fiber near a rank border";
  }
}

}  // namespace
}  // namespace sphdem
