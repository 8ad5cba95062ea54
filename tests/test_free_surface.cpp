// A stable free surface (issue 18 part 2, docs/physics.md "Free surface",
// "Particle shifting", "Jet impacts"; docs/validation.md "Dam break"). The
// ambient pressure: tests/test_ambient_pressure.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/sph/eos.hpp"
#include "sphdem/sph/sph.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;
using testing::world;

// --- detection --------------------------------------------------------------------

// The dam-break column at rest (20 x 40 mm, 1 mm spacing, in the box's
// lower-left corner): the top row and the right column are on the surface,
// with outward normals +y and +x; the particles 3 spacings or more inside,
// and those along the walls (left, floor) away from the open sides, are not.
TEST(FreeSurface, DetectsTheOpenSidesOfAColumnWithOutwardNormals) {
  const Case c =
      testing::load_input("validation/dam_break_front.yaml",
                          {"body_force=[0, 0]", "numerics.particle_shifting=false",
                           "output.fields=[free_surface, surface_normal, position_divergence]"});
  Simulation<2> sim(c, world(), quiet());
  sim.advance(1);
  const SphParticles<2>& ps = sim.particles();
  const double dp = c.numerics.spacing, a = 0.02, H = 0.04;
  int top = 0, side = 0, inside = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double x = ps.x[i][0], y = ps.x[i][1];
    // The side's lowest particles see the floor's wall particles: not on the surface.
    const bool on_top = y > H - dp, on_side = x > a - dp && y > 2 * dp;
    if (on_top && !on_side) {
      ++top;
      EXPECT_EQ(ps.free_surface[i], 1.0) << "top x = " << x;
      EXPECT_NEAR(ps.surface_normal[i][1], 1.0, 0.05) << "top x = " << x;
    } else if (on_side && !on_top) {
      ++side;
      EXPECT_EQ(ps.free_surface[i], 1.0) << "side y = " << y;
      EXPECT_NEAR(ps.surface_normal[i][0], 1.0, 0.05) << "side y = " << y;
    } else if (x < a - 3 * dp && y < H - 3 * dp) {  // the bulk, walls' rows included
      ++inside;
      EXPECT_EQ(ps.free_surface[i], 0.0) << "inside x = " << x << " y = " << y;
      EXPECT_NEAR(ps.position_divergence[i], 2.0, 0.1) << "inside x = " << x << " y = " << y;
    }
  }
  EXPECT_EQ(top, 19);
  EXPECT_EQ(side, 37);
  EXPECT_GT(inside, 500);
}

// --- particle shifting -----------------------------------------------------------

// One particle in the bulk moves by -A h |v| dt grad C~; one on the surface
// keeps only the tangential part of that shift.
TEST(ParticleShifting, BulkFollowsTheGradientSurfaceOnlyTangentially) {
  SphParams sp;
  sp.h = 1.2e-3;
  sp.spacing = 1e-3;
  sp.shifting = 2.0;
  SphParticles<2> ps;
  ps.push_owned(0, Kind::Fluid, -1, 1e-3, Vec<2>(0, 0), Vec<2>(3, 4), 1000);
  ps.push_owned(1, Kind::Fluid, -1, 1e-3, Vec<2>(1, 1), Vec<2>(3, 4), 1000);
  const Vec<2> g(20, -10);  // 1/m
  for (std::size_t i = 0; i < 2; ++i) ps.shifting_gradient[i] = g;
  ps.free_surface[1] = 1.0;
  ps.surface_normal[1] = Vec<2>(0, 1);
  const double dt = 1e-6;
  const NeighborList<2> nl{2.0 * sp.h, 0.1 * sp.h};  // read only by shifting_continuity
  shift_particles<2>(sp, dt, nl, ps, [](SphGroup) {});
  const Vec<2> bulk = -2.0 * sp.h * 5.0 * dt * g;
  EXPECT_NEAR((ps.x[0] - bulk).norm(), 0.0, 1e-18);
  EXPECT_NEAR(ps.x[1][0] - 1.0, bulk[0], 1e-15);  // x = 1 + dx: round-off of 1
  EXPECT_EQ(ps.x[1][1], 1.0);
}

// numerics.shifting_continuity: the shift enters the density as the
// continuity equation's sum, so for equal masses rho_i - m sum_j W_ij (the
// continuity density less the summation density) does not change under a
// shift, up to the shift's second order; without it the density stays put
// while the summation density falls (a shift down grad C spreads the
// particles). A patch of 9 x 9 jittered resin particles on a row of
// walls, shifted as in a step; checked at the 25 inner resin particles.
struct ShiftPatch {
  SphParams sp;
  SphParticles<2> ps;
  NeighborList<2> nl{2.4e-3, 0.24e-3};
  double summation(std::size_t i) const {
    const WendlandC2<2> kernel(sp.h);
    double s = 0.0;
    for (std::size_t j = 0; j < ps.size(); ++j)
      s += ps.mass[j] * kernel.w((ps.x[i] - ps.x[j]).norm());
    return s;
  }
};

ShiftPatch jittered_patch(bool continuity) {
  ShiftPatch b;
  b.sp.h = 1.2e-3;
  b.sp.spacing = 1e-3;
  b.sp.shifting = 2.0;
  b.sp.shifting_continuity = continuity;
  b.sp.grad_scale = gradient_lattice_correction(2, 1.2);
  const double m = 1000 * 1e-6;
  std::int64_t id = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) {
      // a fixed jitter of up to 0.15 dp
      const double jx = 0.15e-3 * std::sin(1.7 * i + 3.1 * j),
                   jy = 0.15e-3 * std::cos(2.3 * i - 1.3 * j);
      b.ps.push_owned(id++, Kind::Fluid, -1, m, Vec<2>(i * 1e-3 + jx, j * 1e-3 + jy),
                      Vec<2>(0.5, 0.0), 1000);
    }
  }
  for (int i = -2; i < 11; ++i)
    b.ps.push_owned(id++, Kind::Wall, -1, m, Vec<2>(i * 1e-3, -1e-3), Vec<2>::Zero(), 1000);
  b.nl.build(b.ps);
  // The shifting gradient sum_j V_j grad W_ij (no tensile part), no surface.
  const WendlandC2<2> kernel(b.sp.h);
  for (std::size_t i = 0; i < b.ps.n_owned; ++i) {
    Vec<2> g = Vec<2>::Zero();
    for (std::size_t j = 0; j < b.ps.size(); ++j) {
      const Vec<2> x_ij = b.ps.x[i] - b.ps.x[j];
      if (j != i)
        g += (b.ps.mass[j] / b.ps.rho[j] * kernel.f(x_ij.norm()) * b.sp.grad_scale) * x_ij;
    }
    b.ps.shifting_gradient[i] = g;
  }
  return b;
}

TEST(ParticleShifting, ContinuityMakesTheDensityFollowTheShift) {
  for (const bool continuity : {false, true}) {
    ShiftPatch b = jittered_patch(continuity);
    std::vector<double> before(b.ps.n_owned), rho0(b.ps.n_owned);
    for (std::size_t i = 0; i < b.ps.n_owned; ++i) {
      before[i] = b.ps.rho[i] - b.sp.grad_scale * b.summation(i);
      rho0[i] = b.ps.rho[i];
    }
    const double dt = 2e-6;  // shifts of at most 1e-3 dp: their second order is negligible
    shift_particles<2>(b.sp, dt, b.nl, b.ps, [](SphGroup) {});
    double moved = 0, worst = 0, summation_change = 0, density_change = 0;
    int inner = 0;
    for (std::size_t i = 0; i < b.ps.n_owned; ++i) {
      const int col = static_cast<int>(b.ps.gid[i]) / 9, row = static_cast<int>(b.ps.gid[i]) % 9;
      if (col < 2 || col > 6 || row < 2 || row > 6) continue;
      ++inner;
      const double after = b.ps.rho[i] - b.sp.grad_scale * b.summation(i);
      worst = std::max(worst, std::abs(after - before[i]));
      summation_change += b.sp.grad_scale * b.summation(i) - (rho0[i] - before[i]);
      density_change += b.ps.rho[i] - rho0[i];
      moved = std::max(moved, b.ps.shift.empty() ? 0.0 : b.ps.shift[i].norm());
    }
    ASSERT_EQ(inner, 25);
    std::printf(
        "[          ] continuity %d: summed summation density change %.4g, density %.4g, worst "
        "%.3g\n",
        continuity, summation_change, density_change, worst);
    EXPECT_LT(summation_change, -1.0);  // the shift spreads the particles
    if (continuity) {
      EXPECT_GT(moved, 1e-7);
      EXPECT_LT(worst, 0.02 * std::abs(summation_change) / inner);
    } else {
      EXPECT_EQ(density_change, 0.0);
    }
  }
}

// Issue 18: the Taylor-Green vortex at the default h = 1.2 dp, which clumps
// without shifting by t = 0.08 s (docs/physics.md "Initial state"), decays
// at the viscous rate within 5 % with it, up to t = 0.3 s.
double tg_amplitude(const SphParticles<2>& ps) {
  constexpr double k = 2 * std::numbers::pi;
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const Vec<2> x = ps.x[i];
    const Vec<2> m(-std::cos(k * x[0]) * std::sin(k * x[1]),
                   std::sin(k * x[0]) * std::cos(k * x[1]));
    num += m.dot(ps.v[i]);
    den += m.dot(m);
  }
  return num / den;
}

// Mean density (clumped particles sum to a higher density) and the vortex's
// amplitude at t = 0.12 L/U, h = 1.2 dp.
struct TgState {
  double rho_rise, amplitude;
};
TgState taylor_green_at_default_h(bool shifting) {
  const Case c = testing::load_input(
      "validation/taylor_green.yaml",
      {"numerics.h_over_spacing=1.2",
       std::string("numerics.particle_shifting=") + (shifting ? "true" : "false"),
       "numerics.shifting_coefficient=6"});
  Simulation<2> sim(c, world(), quiet());
  const double a0 = tg_amplitude(sim.particles());
  testing::run_until(sim, 0.12);
  double rho = 0;
  const SphParticles<2>& ps = sim.particles();
  for (std::size_t i = 0; i < ps.n_owned; ++i) rho += ps.rho[i];
  rho /= static_cast<double>(ps.n_owned) * c.resin.density;
  return {rho - 1.0, tg_amplitude(ps) / a0};
}

// The Taylor-Green vortex at the default h = 1.2 dp clumps without
// shifting (docs/physics.md "Initial state"): its mean density rises 3.5 %
// by t = 0.12 L/U. With shifting (A = 6) it rises 1.0 %, bound 1.5 %; the
// amplitude is then 2.6 % below the exact 0.9095 (measured 0.886; without
// shifting 0.734), so the 5 % decay-rate bound of issue 18 is not met at
// h = 1.2 dp yet (docs/physics.md "Particle shifting").
TEST(ParticleShifting, KeepsTheTaylorGreenVortexFromClumping) {
  const TgState off = taylor_green_at_default_h(false), on = taylor_green_at_default_h(true);
  std::printf(
      "[          ] t = 0.12: mean density +%.2f %% / +%.2f %%, amplitude %.4f / %.4f "
      "(without / with shifting; exact %.4f)\n",
      100 * off.rho_rise, 100 * on.rho_rise, off.amplitude, on.amplitude,
      std::exp(-8 * std::numbers::pi * std::numbers::pi * 0.01 * 0.12));
  EXPECT_GT(off.rho_rise, 0.03);
  EXPECT_LT(on.rho_rise, 0.015);
  EXPECT_GT(on.amplitude, off.amplitude + 0.1);
}

// --- jet impact ----------------------------------------------------------------------

// inputs/validation/jet_impact.yaml: a block of resin 10 x 10 mm fired at
// the left wall of a closed box (c0 = 10 m/s), without gravity: no resin
// particle may cross the wall surface at x = 0, and the density stays
// positive.
struct JetResult {
  double min_x = 1e9, min_rho = 1e9;
  bool blew_up = false;
};

JetResult fire_jet(bool repulsion, double v) {
  const Case c =
      testing::load_input("validation/jet_impact.yaml",
                          {std::string("numerics.wall_repulsion=") + (repulsion ? "true" : "false"),
                           "initial_velocity=[" + std::to_string(-v) + ", 0]"});
  Simulation<2> sim(c, world(), quiet());
  JetResult r;
  try {
    while (sim.time() < c.numerics.end_time * (1 - 1e-12)) {
      sim.advance(1);
      const SphParticles<2>& ps = sim.particles();
      for (std::size_t i = 0; i < ps.n_owned; ++i) {
        if (ps.kind[i] != Kind::Fluid) continue;
        r.min_x = std::min(r.min_x, ps.x[i][0]);
        r.min_rho = std::min(r.min_rho, ps.rho[i]);
      }
    }
  } catch (const std::exception&) {
    r.blew_up = true;
  }
  return r;
}

// At 2 and 2.5 m/s (Mach 0.2, 0.25) the wall repulsion keeps every resin
// particle in front of the wall (measured: closest 0.20 and 0.13 mm);
// without it resin runs 0.49 and 1.24 mm into the wall. At 3 m/s the
// block itself tears (density below zero), wall or not: beyond weak
// compressibility.
TEST(JetImpact, NoResinCrossesTheWall) {
  for (double v : {2.0, 2.5}) {
    const JetResult r = fire_jet(true, v);
    std::printf("[          ] %.1f m/s: closest x = %.4g mm, lowest density %.6g\n", v,
                r.min_x * 1e3, r.min_rho);
    EXPECT_FALSE(r.blew_up) << v << " m/s";
    EXPECT_GT(r.min_x, 0.0) << v << " m/s";
    EXPECT_GT(r.min_rho, 0.0) << v << " m/s";
  }
}

// The same jets without the safeguard cross the wall: the test above can fail.
TEST(JetImpact, WithoutTheWallRepulsionResinCrossesTheWall) {
  for (double v : {2.0, 2.5}) {
    const JetResult r = fire_jet(false, v);
    std::printf("[          ] %.1f m/s, no repulsion: closest x = %.4g mm\n", v, r.min_x * 1e3);
    EXPECT_LT(r.min_x, 0.0) << v << " m/s";
  }
}

// --- dam break ------------------------------------------------------------------------

// Martin & Moyce (1952), n^2 = 2: the surge front Z = x/a against T = t
// sqrt(2 g/a), as read from their figure (also tabulated by Koshizuka &
// Oka 1996, Nucl. Sci. Eng. 123:421).
struct FrontPoint {
  double T, Z;
};
constexpr FrontPoint kMartinMoyce[] = {{0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67},
                                       {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33},
                                       {2.20, 2.56}, {2.32, 2.78}, {2.51, 3.00}};

double measured_z(double T) {
  for (std::size_t k = 0; k + 1 < std::size(kMartinMoyce); ++k) {
    const FrontPoint a = kMartinMoyce[k], b = kMartinMoyce[k + 1];
    if (T >= a.T && T <= b.T) return a.Z + (b.Z - a.Z) * (T - a.T) / (b.T - a.T);
  }
  return std::nan("");
}

// The front: the largest x of a resin particle within 3 spacings of the
// floor (a splash above it does not count).
double front(const SphParticles<2>& ps, double dp) {
  double x = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.kind[i] == Kind::Fluid && ps.x[i][1] < 3 * dp) x = std::max(x, ps.x[i][0]);
  return x;
}

// The largest relative distance of the computed front from Martin & Moyce
// at T = 1, 1.5, 2, 2.5.
double worst_front(const std::vector<std::string>& sets) {
  const Case c = testing::load_input("validation/dam_break_front.yaml", sets);
  const double a = 0.02, g = 9.81, dp = c.numerics.spacing;
  Simulation<2> sim(c, world(), quiet());
  double worst = 0;
  for (double T : {1.0, 1.5, 2.0, 2.5}) {
    testing::run_until(sim, T / std::sqrt(2 * g / a));
    const double z = (front(sim.particles(), dp) + 0.5 * dp) / a, ref = measured_z(T);
    std::printf("[          ] T = %.2f: Z = %.3f (Martin & Moyce %.3f, %+.1f %%)\n", T, z, ref,
                100 * (z / ref - 1));
    worst = std::max(worst, std::abs(z / ref - 1));
  }
  return worst;
}

TEST(DamBreak, FrontFollowsMartinMoyce) {
  const double worst = worst_front({});
  // Measured: +14.5, +16.1, +11.9, +10.4 % at T = 1, 1.5, 2, 2.5. Computed
  // fronts run ahead of this experiment (the gate's opening delays it;
  // Colagrossi & Landrini 2003, J. Comput. Phys. 191:448), hence 20 %.
  EXPECT_LT(worst, 0.20);
}

// The same without particle shifting, the resin's tension bounded instead
// (resin.tensile_strength 0, docs/physics.md "Cavitation").
TEST(DamBreak, FrontFollowsMartinMoyceWithoutShifting) {
  const double worst =
      worst_front({"numerics.particle_shifting=false", "resin.tensile_strength=0"});
  EXPECT_LT(worst, 0.20);
}

// --- input errors ----------------------------------------------------------------------

constexpr const char* kCase = R"(dimension: 2                 # 1
resin:                       # 2
  density: 900               # 3
  viscosity: 0.1             # 4
  sound_speed: 60            # 5
mold:                        # 6
  shapes:                    # 7
    - box: {min: [0, 0], max: [0.02, 0.02]}    # 8
fill:                        # 9
  - box: {min: [0, 0], max: [0.01, 0.02]}      # 10
numerics:                    # 11
  spacing: 1.0e-3            # 12
  end_time: 0.12             # 13
)";

void expect_error(const std::string& text, int line, const std::string& key,
                  const std::string& message) {
  try {
    load_case_from_string(text, "case.yaml");
    ADD_FAILURE() << "no error; expected case.yaml:" << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), key) << what;
    EXPECT_NE(what.find(message), std::string::npos) << what << "\n  expected: " << message;
  }
}

TEST(FreeSurfaceErrors, NegativeAmbientPressure) {
  std::string text(kCase);
  const std::string line5 = "  sound_speed: 60            # 5\n";
  text.replace(text.find(line5), line5.size(), line5 + "  ambient_pressure: -5\n");
  expect_error(text, 6, "resin.ambient_pressure", "must be zero or positive");
}

TEST(FreeSurfaceErrors, NegativeTensileStrength) {
  std::string text(kCase);
  const std::string line5 = "  sound_speed: 60            # 5\n";
  text.replace(text.find(line5), line5.size(), line5 + "  tensile_strength: -1\n");
  expect_error(text, 6, "resin.tensile_strength", "must be zero or positive");
}

TEST(FreeSurfaceErrors, ImpossibleShiftingCoefficient) {
  expect_error(std::string(kCase) + "  shifting_coefficient: 0\n", 14,
               "numerics.shifting_coefficient", "0");
  expect_error(std::string(kCase) + "  shifting_coefficient: 8\n", 14,
               "numerics.shifting_coefficient", "8");
}

}  // namespace
}  // namespace sphdem
