// The ambient (air) pressure as a boundary condition (issue 18 parts 2 and 5,
// docs/physics.md "Ambient pressure"): pressures are gauge, the air's
// pressure Pa acts at the free surface (where the gauge pressure is 0) and
// lets a wall hold the resin down to absolute zero. By hand: a flat surface
// feels no net ambient force, which the equation-of-state offset gave it; a
// column at rest keeps its hydrostatic profile at an ambient pressure 28
// times the Tait B; a decelerating piston keeps its resin. The plate case
// (docs/paper-comparison.md "The flow front"): the resin stays on the
// piston through its sharp deceleration, the front events are written, and
// the run is the same at 1 and 2 ranks bitwise.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "resin_rows.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/sph/eos.hpp"
#include "sphdem/sph/kernel.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;
using testing::world;

// --- a flat surface, by hand ----------------------------------------------------------

TEST(AmbientPressure, TheEquationOfStateIsGauge) {
  const TaitEos eos(1000, 10);
  EXPECT_EQ(eos.pressure(1000), 0.0);
  EXPECT_EQ(eos.density(0.0), 1000.0);
}

// The symmetric pressure sum at a particle on the flat top row of a
// half-lattice (rows y = 0, -dp, -2dp, ...) with every particle at the
// absolute pressure Pa: a_y = -sum_j m (2 Pa / rho^2) F(r_ij) y_ij. Only
// neighbours below, so it does not cancel: the push of an equation-of-state
// offset, about Pa / (rho dp), out of the surface. With the outer half
// supplied (the mirror rows y = +dp, +2dp, ... standing for the air at Pa)
// the sum is zero. The dam-break column (rho0 = 1000, dp = 1 mm, h = 1.2 dp)
// without gravity, at Pa = 1e5: gauge pressures carry no Pa, so after one
// step every resin velocity is still exactly zero (the full-lattice value);
// the offset model moved its surface rows at a dt that the hand sum gives.
TEST(AmbientPressure, AFlatSurfaceFeelsNoNetAmbientForce) {
  const double rho = 1000, dp = 1e-3, h = 1.2e-3, pa = 1e5, m = rho * dp * dp;
  const WendlandC2<2> kernel(h);
  double half = 0, full = 0;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j) {
      if (i == 0 && j == 0) continue;
      const double x = -i * dp, y = -j * dp;  // x_i - x_j, particle i at the origin
      const double a = -m * (2 * pa / (rho * rho)) * kernel.f(std::hypot(x, y)) * y;
      full += a;
      if (j <= 0) half += a;
    }
  EXPECT_NEAR(full, 0.0, 1e-9 * std::abs(half));
  EXPECT_GT(half, 0.5 * pa / (rho * dp)) << "the offset pushes the surface out";
  const double dt = 0.25 * h / 10;  // the case's CFL step at c0 = 10 m/s

  const Case c = testing::load_input(
      "validation/dam_break_front.yaml",
      {"body_force=[0, 0]", "numerics.particle_shifting=false", "resin.ambient_pressure=1e5"});
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  sim.advance(1);
  const SphParticles<2>& ps = sim.particles();
  double v_max = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.kind[i] == Kind::Fluid) v_max = std::max(v_max, ps.v[i].norm());
  EXPECT_EQ(v_max, 0.0) << "the offset model's surface rows: " << half * dt << " m/s";
}

// --- a column at rest ----------------------------------------------------------------

// tests/test_hydrostatic.cpp's column (c0 = 5 m/s, B = 3571 Pa) at the
// atmosphere, Pa = 101325 Pa = 28 B, to 0.1 s: the layer-averaged gauge
// pressure deeper than 3h is rho0 g depth within 2 % (the absolute
// pressure: that plus Pa), the free surface stays where it started and the
// column at rest. With the offset model the surface row is thrown off.
TEST(AmbientPressure, AColumnAtRestKeepsItsHydrostaticProfile) {
  const Case c = testing::load_input("validation/hydrostatic_2d.yaml",
                                     {"resin.ambient_pressure=101325", "numerics.end_time=0.1"});
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  testing::run_until(sim, c.numerics.end_time);
  const double g = 9.81, rho0 = c.resin.density, h = c.h(), dp = c.numerics.spacing;
  const SphParticles<2>& ps = sim.particles();
  double top = -1e300, v_max = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    top = std::max(top, ps.x[i][1]);
    v_max = std::max(v_max, ps.v[i].norm());
  }
  top += 0.5 * dp;
  std::map<long, std::array<double, 3>> layers;  // sum y, sum p, count
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    auto& l = layers[static_cast<long>((top - ps.x[i][1]) / dp)];
    l[0] += ps.x[i][1];
    l[1] += ps.p[i];
    l[2] += 1;
  }
  double worst = 0;
  int checked = 0;
  for (const auto& [k, l] : layers) {
    const double d = top - l[0] / l[2];
    if (d < 3 * h) continue;
    worst = std::max(worst, std::abs(l[1] / l[2] - rho0 * g * d) / (rho0 * g * d));
    ++checked;
  }
  EXPECT_GT(checked, 5);
  EXPECT_LT(worst, 0.02) << "largest relative error of the layer-averaged gauge pressure";
  EXPECT_NEAR(top, 0.02, dp) << "the free surface stays where it started";
  EXPECT_LT(v_max, 0.01 * std::sqrt(g * 0.02)) << "the column must stay at rest";
}

// --- a decelerating piston -------------------------------------------------------------

// A 10 x 10 mm block of resin (c0 = 30 m/s) pushed up a 10 mm channel at
// 1 m/s by a piston that stops within 0.5 ms (2000 m/s^2) at 2 ms; no
// gravity. Holding the block on the piston takes about rho L a = 2e4 Pa of
// tension. With Pa = 0 the wall pulls nothing and the block flies on: a gap
// of several spacings opens (measured 3.2 by 6 ms). With the atmosphere (Pa = 101325 Pa) the wall
// holds down to absolute zero and the block stays on the piston: the gap
// stays below one spacing.
constexpr const char* kPiston = R"(dimension: 2
resin: {density: 1000, viscosity: 0.1, sound_speed: 30}
numerics: {spacing: 5.0e-4, end_time: 0.006, delta_sph: 0.1, artificial_viscosity: 0.02}
mold:
  wall_layers: 3
  shapes: [{box: {min: [0, 0], max: [0.01, 0.04]}}]
fill: [{box: {min: [0, 0], max: [0.01, 0.01]}}]
initial_velocity: [0, 1]
moving_walls:
  - name: piston
    region: {box: {min: [0, -0.002], max: [0.01, 0]}}
    velocity_table: [[0, 0, 1], [0.002, 0, 1], [0.0025, 0, 0]]
)";

// The largest gap between the piston's top row and the resin's bottom row,
// less the one spacing of a resin particle resting on it, over the run.
double largest_piston_gap(double ambient) {
  const Case c = load_case_from_string(kPiston, "piston.yaml",
                                       {"resin.ambient_pressure=" + std::to_string(ambient)});
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  const double dp = c.numerics.spacing;
  double worst = -1e300;
  while (sim.time() < c.numerics.end_time * (1 - 1e-12)) {
    sim.advance(20);
    const SphParticles<2>& ps = sim.particles();
    double piston = -1e300, resin = 1e300;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] == Kind::Fluid)
        resin = std::min(resin, ps.x[i][1]);
      else if (ps.wall[i] == 0)
        piston = std::max(piston, ps.x[i][1]);
    }
    worst = std::max(worst, resin - piston - dp);
  }
  return worst / dp;
}

TEST(AmbientPressure, ADeceleratingPistonDoesNotTearTheResin) {
  const double torn = largest_piston_gap(0.0), held = largest_piston_gap(101325.0);
  std::printf("largest piston gap: %.3f spacings at Pa = 0, %.3f at 101325 Pa\n", torn, held);
  EXPECT_GT(torn, 2.5) << "without the air the block leaves the piston (spacings)";
  EXPECT_LT(held, 1.0) << "with the air it stays on it (spacings)";
}

// --- the plate case --------------------------------------------------------------------

// inputs/plate.yaml (the atmosphere, sigma = 0.03 N/m) at 0.6 mm (a quarter
// of its particles) with its piston stopped at 2-2.5 ms (1 m/s to rest:
// 2000 m/s^2, three times the case's 0.02 s step down), to 5 ms, with the
// weld-line and trapped-air detection on: the resin under the piston stays
// on it (no gap larger than 2 spacings; at Pa = 0 the resin runs on at
// about 1 m/s and leaves a gap of several) and the front events are
// written to the CSV.
Case short_plate() {
  return testing::load_input("plate.yaml",
                             {"numerics.spacing=6e-4", "numerics.end_time=0.005",
                              "resin.ambient_pressure=101325", "resin.surface_tension=0.03",
                              "moving_walls[0].velocity_table=[[0, 0, -1], [0.002, 0, -1], "
                              "[0.0025, 0, 0]]",
                              "output.every_time=0.002", "output.front_events=true",
                              "output.fields=[velocity, pressure, free_surface, weld_line]"});
}

using Row = testing::ResinRow<3>;  // x, y, weld_line

struct PlateState {
  std::vector<Row> rows;  // per resin particle
  double gap = -1e300;    // spacings
};

PlateState run_plate(const Comm& comm, const std::string& out, bool write) {
  const Case c = short_plate();
  RunOptions opt;
  opt.write_output = write;
  opt.output_dir = out;
  if (write && comm.root()) {
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
  }
  Simulation<2> sim(c, comm, opt);
  PlateState s;
  const double dp = c.numerics.spacing;
  while (sim.time() < c.numerics.end_time * (1 - 1e-12)) {
    sim.advance(50);
    const SphParticles<2>& ps = sim.particles();
    double piston = 1e300, resin = -1e300;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] == Kind::Fluid)
        resin = std::max(resin, ps.x[i][1]);
      else if (ps.wall[i] == 0)
        piston = std::min(piston, ps.x[i][1]);
    }
    piston = comm.min(piston);
    resin = comm.max(resin);
    s.gap = std::max(s.gap, (piston - resin - dp) / dp);
  }
  // At end_time run() only writes the last snapshot and the events so far
  // (output.front_events) to <case>_front_events.csv.
  if (write) sim.run();
  const SphParticles<2>& ps = sim.particles();
  s.rows = testing::gather_resin_rows<3>(comm, ps, [&](std::size_t i, double* v) {
    v[0] = ps.x[i][0];
    v[1] = ps.x[i][1];
    v[2] = ps.weld_line[i];
  });
  return s;
}

TEST(PlateFront, TheResinStaysOnThePistonAndTheEventsAreWritten) {
  const std::string out = std::string(SPHDEM_BINARY_DIR) + "/tests/plate_front_short";
  const Comm self(MPI_COMM_SELF);
  const PlateState s = run_plate(self, out, true);
  EXPECT_LT(s.gap, 2.0) << "largest gap between the piston and the resin (spacings)";
  std::ifstream csv(out + "/plate_front_events.csv");
  ASSERT_TRUE(csv.good()) << out << "/plate_front_events.csv";
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("kind"), std::string::npos) << header;
}

TEST(PlateFrontRanks, SameAtEveryRankCount) {
  const std::string out = std::string(SPHDEM_BINARY_DIR) + "/tests/plate_front_ranks";
  PlateState ref;
  if (world().root()) {
    const Comm self(MPI_COMM_SELF);
    ref = run_plate(self, out, false);
  }
  testing_mpi::wait_for_root(world());
  const PlateState got = run_plate(world(), out, false);
  if (!world().root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.rows, got.rows), 0u);
  EXPECT_EQ(ref.gap, got.gap);
}

}  // namespace
}  // namespace sphdem
