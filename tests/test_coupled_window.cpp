// The coupled model's stable window (issue 15, defect 9; docs/physics.md
// "Coupling", "The stable window").
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sphdem/config/config.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem {
namespace {

RunOptions quiet() {
  RunOptions opt;
  opt.write_output = false;
  return opt;
}

struct Shear {
  double c0 = 0.3;          // sound speed [m/s]; the wall slides at 0.03 m/s
  double spacing = 3.0e-4;  // resin spacing [m]; the fiber's diameter is 2.5e-4 m
  double density = 900;     // fiber density [kg/m^3]; the resin's is 900
  bool eps_continuity = true;
};

// A closed 2D shear cell, 6 x 3 mm, lid sliding at 0.03 m/s, one fiber of
// 4 particles across the middle.
std::string shear_case(const Shear& s) {
  return "dimension: 2\n"
         "resin: {density: 900, viscosity: 0.1, sound_speed: " +
         std::to_string(s.c0) +
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
         "  void_fraction_in_continuity: " +
         (s.eps_continuity ? "true" : "false") +
         "\n"
         "  region: {box: {min: [0.0025, 0.001], max: [0.0035, 0.002]}}\n";
}

// Largest resin speed over `steps` steps, in units of the wall speed.
double max_speed_over_wall(const Case& c, int steps, bool print) {
  const Comm self(MPI_COMM_SELF);
  Simulation<2> sim(c, self, quiet());
  double worst = 0;
  for (int k = 1; k <= steps; ++k) {
    sim.advance(1);
    const auto& ps = sim.particles();
    double vmax = 0;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) vmax = std::max(vmax, ps.v[i].norm());
    if (!std::isfinite(vmax)) return INFINITY;
    worst = std::max(worst, vmax / 0.03);
    if (print &&
        (k % 50 == 0 || k <= (std::getenv("FIRST") ? std::atoi(std::getenv("FIRST")) : 0))) {
      std::printf("step %d t %.4g dt %.3g (%s) vmax/U %.3g", k, sim.time(), sim.last_dt(),
                  to_string(sim.last_dt_limit()), vmax / 0.03);
      if (sim.dem()) {
        const auto& dem = sim.dem()->particles();
        std::printf(" dt*rate %.3g", sim.last_dt() * sim.coupling()->resin_drag_rate());
        std::printf(" vf %.3g drag %.3g tau %.3g eps %.3f", dem.v[1].norm(),
                    dem.mean_drag[1].norm(), dem.mass[1] / dem.drag_coeff[1], dem.void_fraction[1]);
      }
      std::printf("\n");
    }
  }
  return worst;
}

TEST(CoupledWindow, Probe) {
  Shear s;
  if (const char* e = std::getenv("C0")) s.c0 = std::atof(e);
  if (const char* e = std::getenv("DX")) s.spacing = std::atof(e);
  if (const char* e = std::getenv("RHOP")) s.density = std::atof(e);
  if (const char* e = std::getenv("EPSC")) s.eps_continuity = std::atoi(e) != 0;
  const int steps = std::getenv("STEPS") ? std::atoi(std::getenv("STEPS")) : 300;
  std::string text = shear_case(s);
  if (std::getenv("NOFIB")) text = text.substr(0, text.find("fibers:"));
  const Case c = load_case_from_string(text, "shear.yaml");
  std::printf("worst %.3g\n", max_speed_over_wall(c, steps, true));
}

}  // namespace
}  // namespace sphdem
