// The coupled model's stable window (issue 15, defect 9; docs/physics.md
// "The stable window"). A neutrally buoyant fiber in a shear cell at Mach
// 0.1, a resin spacing below the fiber's diameter, a heavy fiber and a
// viscous resin. The first three pushed the resin to tens to a thousand
// times the wall speed within 300 steps while the drag exchange was
// explicit at the resin's own step (measured before the drag limits: 30,
// 990, 27 times); in the fourth, at the DEM's own sub-step, a fiber
// particle left the mold at step 7. With the limits they stay below the
// wall speed.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include "sphdem/config/config.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/coupled_window.hpp"
#include "sphdem/solver/coupling_module.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;

struct Shear {
  double c0 = 0.3;          // sound speed [m/s]; the wall slides at 0.03 m/s
  double spacing = 3.0e-4;  // resin spacing [m]; the fiber's diameter is 2.5e-4 m
  double density = 900;     // fiber density [kg/m^3]; the resin's is 900
  double viscosity = 0.1;   // resin viscosity [Pa s]
};

// A closed 2D shear cell, 6 x 3 mm, lid sliding at 0.03 m/s, one fiber of
// 4 particles across the middle.
std::string shear_case(const Shear& s) {
  return "dimension: 2\n"
         "resin: {density: 900, viscosity: " +
         std::to_string(s.viscosity) + ", sound_speed: " + std::to_string(s.c0) +
         "}\n"
         "numerics: {spacing: " +
         std::to_string(s.spacing) +
         ", end_time: 1.0}\n"
         "mold: {shapes: [{box: {min: [0, 0], max: [0.006, 0.003]}}]}\n"
         "fill: [{box: {min: [0, 0], max: [0.006, 0.003]}}]\n"
         "sliding_walls:\n"
         "  - {name: lid, region: {box: {min: [-0.002, 0.003], max: [0.008, 0.004]}}, "
         "velocity: [0.03, 0]}\n"
         "fibers:\n"
         "  count: 1\n  orientation: 90\n  diameter: 2.5e-4\n  youngs_modulus: 1.0e8\n"
         "  density: " +
         std::to_string(s.density) +
         "\n"
         "  region: {box: {min: [0.0025, 0.001], max: [0.0035, 0.002]}}\n";
}

constexpr double kWall = 0.03;  // the lid's speed [m/s]

struct Extremes {
  double resin = 0;                      // largest resin speed / wall speed
  double fiber = 0;                      // largest fiber particle speed / wall speed
  bool drag_limited = false;             // the drag limited the resin's step at least once
  bool substep_within_drag_time = true;  // every DEM sub-step <= the fibers' drag time
};

Extremes run_shear(const Shear& s, int steps) {
  const Case c = load_case_from_string(shear_case(s), "shear.yaml");
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  Extremes e;
  for (int k = 0; k < steps; ++k) {
    const double drag_time = sim.coupling()->fiber_drag_time();
    sim.advance(1);
    e.drag_limited = e.drag_limited || sim.last_dt_limit() == DtLimit::Drag;
    const double sub = sim.last_dt() / static_cast<double>(sim.dem_substeps());
    e.substep_within_drag_time = e.substep_within_drag_time && sub <= drag_time * (1 + 1e-12);
    const auto& ps = sim.particles();
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) e.resin = std::max(e.resin, ps.v[i].norm() / kWall);
    const auto& dem = sim.dem()->particles();
    for (std::size_t f = 0; f < dem.n_owned; ++f)
      e.fiber = std::max(e.fiber, dem.v[f].norm() / kWall);
    if (!std::isfinite(e.resin) || !std::isfinite(e.fiber)) break;
  }
  std::printf("resin %.3g, fiber %.3g times the wall speed; drag-limited step: %s\n", e.resin,
              e.fiber, e.drag_limited ? "yes" : "no");
  return e;
}

// Mach 0.1: c0 = 0.3 m/s. The resin's own step (viscous, 1.5e-4 s) is 8
// times the resin's drag time (1.9e-5 s).
TEST(CoupledWindow, MachPointOneShearCell) {
  const Extremes e = run_shear(Shear{}, 300);
  EXPECT_TRUE(e.drag_limited);
  EXPECT_LT(e.resin, 1.0);
  EXPECT_LT(e.fiber, 1.0);
}

// Resin spacing half the fiber's diameter: the resin particles are lighter
// than the fiber's (m_r/m_f = 0.32) and the void fraction at the fiber is
// the clip's.
TEST(CoupledWindow, SpacingBelowFiberDiameter) {
  Shear s;
  s.spacing = 1.25e-4;
  const Extremes e = run_shear(s, 300);
  EXPECT_TRUE(e.drag_limited);
  EXPECT_LT(e.resin, 1.0);
  EXPECT_LT(e.fiber, 1.0);
}

// A fiber 10 times as dense as the resin at c0 = 3 m/s: the resin's own
// step (CFL, 3e-5 s) is within 2 resin drag times, yet the fiber takes
// its resin's momentum and gives it back a step late (docs/physics.md).
TEST(CoupledWindow, HeavyFiber) {
  Shear s;
  s.c0 = 3;
  s.density = 9000;
  const Extremes e = run_shear(s, 300);
  EXPECT_LT(e.resin, 1.0);
  EXPECT_LT(e.fiber, 1.0);
}

// A resin 1000 times as viscous and a fiber 10 times lighter than the
// resin: the fibers' drag time (5.6e-10 s) is far below the DEM's stable
// step (7.3e-9 s) and the resin's drag-limited step holds several DEM
// steps; the sub-steps follow the drag time.
TEST(CoupledWindow, ViscousResinSubsteps) {
  Shear s;
  s.viscosity = 100;
  s.density = 90;
  const Extremes e = run_shear(s, 200);
  EXPECT_TRUE(e.substep_within_drag_time);
  EXPECT_LT(e.resin, 1.0);
  EXPECT_LT(e.fiber, 1.0);
}

// A restart continues a drag-limited run bitwise: the limits of the next
// step come from the checkpoint (attributes resin_drag_rate and
// fiber_drag_time), not from a coupling pass the restart does not repeat.
TEST(CoupledWindow, RestartKeepsTheDragLimits) {
  const Case c = load_case_from_string(shear_case(Shear{}), "shear.yaml");
  const Comm self(MPI_COMM_SELF);
  const std::string dir = "coupled_window_restart";
  std::filesystem::remove_all(dir);
  RunOptions opt = quiet();
  opt.output_dir = dir;
  const std::int64_t n = 30;
  Simulation<2> straight(c, self, opt);
  straight.advance(2 * n);
  std::string path;
  {
    Simulation<2> half(c, self, opt);
    half.advance(n);
    path = half.write_checkpoint();
  }
  Simulation<2> again(c, self, opt);
  again.restart_from(path);
  again.advance(2 * n - again.step());
  EXPECT_EQ(again.last_dt_limit(), DtLimit::Drag);
  EXPECT_EQ(again.last_dt(), straight.last_dt());
  EXPECT_EQ(again.time(), straight.time());
  // Velocities by global id, resin and fibers.
  const auto by_gid = [](const auto& ps) {
    std::map<std::int64_t, Vec<2>> m;
    for (std::size_t i = 0; i < ps.n_owned; ++i) m[ps.gid[i]] = ps.v[i];
    return m;
  };
  EXPECT_TRUE(by_gid(again.particles()) == by_gid(straight.particles()));
  EXPECT_TRUE(by_gid(again.dem()->particles()) == by_gid(straight.dem()->particles()));
  std::filesystem::remove_all(dir);
}

// A lone particle sees 1 - (7/16) (d/h)^2 of its own volume in 2D
// (docs/physics.md "Coupling": 0.789 at the paper's h/d = 1.44).
TEST(CoupledWindow, LoneFiberVoidFraction) {
  EXPECT_NEAR(lone_fiber_void_fraction<2>(0.36e-3, 0.25e-3, 1), 1 - 0.4375 / (1.44 * 1.44), 1e-12);
  EXPECT_NEAR(lone_fiber_void_fraction<3>(0.36e-3, 0.25e-3, 1), 1 - 0.21875 / (1.44 * 1.44 * 1.44),
              1e-12);
  // Neighbours along the fiber only add solid.
  EXPECT_LT(lone_fiber_void_fraction<2>(0.36e-3, 0.25e-3, 4),
            lone_fiber_void_fraction<2>(0.36e-3, 0.25e-3, 1));
}

// `sphdem check` prints the window, and warns where the drag limits the
// step and where the clip decides the void fraction.
TEST(CoupledWindow, CheckReport) {
  Shear s;
  s.spacing = 1.25e-4;
  const Case c = load_case_from_string(shear_case(s), "shear.yaml");
  const Comm self(MPI_COMM_SELF);
  const Simulation<2> sim(c, self, quiet());
  const CoupledWindow w = coupled_window<2>(c, sim, 1e-4);
  EXPECT_NEAR(w.resin_drag_time * sim.coupling()->resin_drag_rate(), 1.0, 1e-12);
  EXPECT_LT(w.fiber_void_fraction, 0.4);
  // At the spacing it names, a lone fiber sits on the clip.
  EXPECT_NEAR(lone_fiber_void_fraction<2>(1.2 * w.spacing_at_clip, 2.5e-4, 4), 0.4, 1e-9);
  std::ostringstream out;
  print_coupled_window(w, c, out);
  std::printf("%s", out.str().c_str());
  EXPECT_NE(out.str().find("warning: the drag limits the resin's step"), std::string::npos);
  EXPECT_NE(out.str().find("warning: the fibers' own volume fills the averaging kernel"),
            std::string::npos);
  // The default spacing (3e-4 m) is above the clip: no such warning.
  const Case coarse = load_case_from_string(shear_case(Shear{}), "shear.yaml");
  const Simulation<2> coarse_sim(coarse, self, quiet());
  std::ostringstream coarse_out;
  print_coupled_window(coupled_window<2>(coarse, coarse_sim, 1e-6), coarse, coarse_out);
  EXPECT_EQ(coarse_out.str().find("warning"), std::string::npos);
}

}  // namespace
}  // namespace sphdem
