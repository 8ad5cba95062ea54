#pragma once
// Shared helpers for the validation tests: load a case from inputs/, run it
// without output to a given time, and the analytic references of
// docs/validation.md.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem::testing {

// Runs that write no files, as most tests want.
inline RunOptions quiet() {
  RunOptions opt;
  opt.write_output = false;
  return opt;
}

// MPI_COMM_WORLD, made once.
inline const Comm& world() {
  static const Comm c;
  return c;
}

inline Case load_input(const std::string& relative, const std::vector<std::string>& sets = {}) {
  return load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/" + relative, sets);
}

// The bench_sph channel (bench/bench_sph.cpp) at 40 x 16 spacings:
// periodic in x, walls below and above, a body force, no free surface;
// anti-clump on. `sets` adds to it (delta-SPH, the skin, the body force).
inline Case small_channel(const std::vector<std::string>& sets = {}) {
  const char* text = R"(name: channel
dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 50}
numerics: {spacing: 3.0e-4, h_over_spacing: 1.2, fixed_dt: 1.4e-6, end_time: 1.0, anti_clump: true}
mold: {wall_layers: 3, shapes: [{box: {min: [0, 0], max: [0.012, 0.0048]}}]}
fill: [{box: {min: [0, 0], max: [0.012, 0.0048]}}]
body_force: [1000, 0]
periodic: [x]
domain: {min: [0, -0.0012], max: [0.012, 0.006]}
output: {progress_every: 1000000}
)";
  return load_case_from_string(text, "channel.yaml", sets);
}

template <int D>
void run_until(Simulation<D>& sim, double t) {
  while (sim.time() < t * (1 - 1e-12)) sim.advance(1);
}

// Morris et al. (1997) start-up Poiseuille flow, physical sign (docs/validation.md section 1).
inline double poiseuille(double y, double t, double L, double nu, double F) {
  double u = F / (2 * nu) * y * (L - y);
  for (int n = 0; n < 400; ++n) {
    const double k = 2 * n + 1;
    u -= 4 * F * L * L / (nu * std::pow(std::numbers::pi, 3) * k * k * k) *
         std::sin(k * std::numbers::pi * y / L) *
         std::exp(-k * k * std::numbers::pi * std::numbers::pi * nu * t / (L * L));
  }
  return u;
}

// Start-up Couette flow, plate at y = L moving at v0 (docs/validation.md section 1).
inline double couette(double y, double t, double L, double nu, double v0) {
  double u = v0 * y / L;
  for (int n = 1; n < 4000; ++n) {
    u += 2 * v0 / (n * std::numbers::pi) * (n % 2 == 0 ? 1.0 : -1.0) *
         std::sin(n * std::numbers::pi * y / L) *
         std::exp(-nu * n * n * std::numbers::pi * std::numbers::pi * t / (L * L));
  }
  return u;
}

// du/dy of the start-up Couette flow above.
inline double couette_shear(double y, double t, double L, double nu, double v0) {
  double g = v0 / L;
  for (int n = 1; n < 4000; ++n) {
    g += 2 * v0 / L * (n % 2 == 0 ? 1.0 : -1.0) * std::cos(n * std::numbers::pi * y / L) *
         std::exp(-nu * n * n * std::numbers::pi * std::numbers::pi * t / (L * L));
  }
  return g;
}

// Relative L2 error of the resin's shear rate (the shear_rate field) against
// g(y), over the particles at least `margin` from y = 0 and y = L.
template <int D, class G>
double relative_l2_shear_rate(const SphParticles<D>& ps, double margin, double L, G&& g) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const double y = ps.x[i][1];
    if (ps.kind[i] != Kind::Fluid || y < margin || y > L - margin) continue;
    const double ga = g(y);
    num += (ps.shear_rate[i] - ga) * (ps.shear_rate[i] - ga);
    den += ga * ga;
  }
  return std::sqrt(num / den);
}

// Relative L2 error of the resin's x velocity against u(y).
template <int D, class F>
double relative_l2_ux(const SphParticles<D>& ps, F&& u) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double ua = u(ps.x[i][1]);
    num += (ps.v[i][0] - ua) * (ps.v[i][0] - ua);
    den += ua * ua;
  }
  return std::sqrt(num / den);
}

}  // namespace sphdem::testing
