// The stable DEM step of a bonded fiber against the exact velocity-Verlet
// bound (issue 19, docs/performance.md "The DEM sub-step's bound"):
// velocity Verlet on a linear system is stable for omega_max dt < 2
// (e.g. Hairer, Lubich and Wanner, Acta Numerica 12, 2003), with
// omega_max the largest eigen-frequency of K x = omega^2 M x. For the
// plate's fibers (4 disks of R = 0.125 mm, E = 1e8 Pa, kbar* = 0.25,
// glass density) the linearised parallel-bond stiffness (Potyondy and Cundall
// 2004: normal kbar_n A, shear kbar_s A at the contact point, bending
// kbar_n I) gives omega_max; the run's own loops must stay bounded just
// below 2 / omega_max and blow up just above it, which checks both the
// analytic matrix and the code. stable_dem_dt's sum of spring stiffnesses
// (dt_safety 1) is then compared with that bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "sphdem/dem/dem.hpp"

namespace sphdem {
namespace {

constexpr int kParticles = 4;
constexpr double kRadius = 0.125e-3, kDensity = 2540, kE = 1e8;

DemSystem<2> plate_fiber() {
  DemSystem<2> sys;
  sys.params.youngs_modulus = kE;
  sys.params.kbar_star = 0.25;
  // Contacts as the plate's (0.01 kbar_n A); bonded neighbours get none.
  sys.params.kn = 0.01 * kE / (2 * kRadius) * 2 * kRadius * sys.params.thickness;
  sys.params.dt_safety = 1.0;
  for (int i = 0; i < kParticles; ++i)
    sys.add_particle(Vec<2>(2 * kRadius * i, 0), kRadius, kDensity);
  for (int i = 0; i + 1 < kParticles; ++i) sys.add_bond(i, i + 1);
  return sys;
}

constexpr int kDofs = 3 * kParticles;  // (x, y, theta) per particle
using Matrix = std::array<std::array<double, kDofs>, kDofs>;

// The largest eigenvalue of a symmetric matrix (cyclic Jacobi rotations).
double largest_eigenvalue(Matrix a) {
  for (int sweep = 0; sweep < 50; ++sweep) {
    for (int p = 0; p < kDofs; ++p) {
      for (int q = p + 1; q < kDofs; ++q) {
        const auto up = static_cast<std::size_t>(p), uq = static_cast<std::size_t>(q);
        if (a[up][uq] == 0.0) continue;
        const double theta = (a[uq][uq] - a[up][up]) / (2 * a[up][uq]);
        const double t = std::copysign(1.0, theta) / (std::abs(theta) + std::hypot(theta, 1.0));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (auto& row : a) {
          const double x = row[up], y = row[uq];
          row[up] = c * x - s * y;
          row[uq] = s * x + c * y;
        }
        for (std::size_t k = 0; k < kDofs; ++k) {
          const double x = a[up][k], y = a[uq][k];
          a[up][k] = c * x - s * y;
          a[uq][k] = s * x + c * y;
        }
      }
    }
  }
  double m = a[0][0];
  for (std::size_t i = 0; i < kDofs; ++i) m = std::max(m, a[i][i]);
  return m;
}

// omega_max of the straight fiber along x: M^-1/2 K M^-1/2's largest eigenvalue.
double fiber_omega_max(const DemSystem<2>& sys) {
  const auto& p = sys.params;
  const double rbar = p.lambda * kRadius, t = p.thickness;
  const double area = 2 * rbar * t, inertia = 2.0 / 3.0 * rbar * rbar * rbar * t;
  const double kn = kE / (2 * kRadius), ks = kn / p.kbar_star;
  Matrix k{};
  // Energy 1/2 c (g . q)^2 for each spring, g its strain per coordinate.
  auto spring = [&](const std::array<std::pair<int, double>, 4>& g, double c) {
    for (const auto& [i, gi] : g)
      for (const auto& [j, gj] : g)
        k[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] += c * gi * gj;
  };
  for (int i = 0; i + 1 < kParticles; ++i) {
    const int a = 3 * i, b = 3 * (i + 1);
    spring({{{b, 1}, {a, -1}, {0, 0}, {0, 0}}}, kn * area);  // stretch along the normal
    spring({{{b + 1, 1}, {a + 1, -1}, {a + 2, -kRadius}, {b + 2, -kRadius}}},
           ks * area);                                                  // contact-point slip
    spring({{{b + 2, 1}, {a + 2, -1}, {0, 0}, {0, 0}}}, kn * inertia);  // relative rotation
  }
  std::array<double, kDofs> inv_sqrt_m{};
  for (std::size_t i = 0; i < kParticles; ++i) {
    inv_sqrt_m[3 * i] = inv_sqrt_m[3 * i + 1] = 1 / std::sqrt(sys.particles.mass[i]);
    inv_sqrt_m[3 * i + 2] = 1 / std::sqrt(sys.particles.inertia[i]);
  }
  for (std::size_t i = 0; i < kDofs; ++i)
    for (std::size_t j = 0; j < kDofs; ++j) k[i][j] *= inv_sqrt_m[i] * inv_sqrt_m[j];
  return std::sqrt(largest_eigenvalue(k));
}

// Largest kinetic + elastic energy over `steps` steps at dt, relative to
// the start, from small random velocities and spins (every mode excited).
double energy_growth(double dt, int steps) {
  DemSystem<2> sys = plate_fiber();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < sys.particles.size(); ++i) {
    sys.particles.v[i] = 1e-3 * Vec<2>(u(rng), u(rng));
    sys.particles.omega[i][0] = 1e-3 / kRadius * u(rng);
  }
  const double e0 = sys.kinetic_energy() + sys.elastic_energy();
  double e_max = e0;
  for (int s = 0; s < steps; ++s) {
    sys.step(dt);
    const double e = sys.kinetic_energy() + sys.elastic_energy();
    if (!(e < 1e12 * e0)) return std::numeric_limits<double>::infinity();
    e_max = std::max(e_max, e);
  }
  return e_max / e0;
}

TEST(DemStableStep, FiberBlowsUpAtTheVerletBound) {
  const DemSystem<2> sys = plate_fiber();
  const double dt_crit = 2 / fiber_omega_max(sys);
  // Stable just below: the energy a Verlet step shows swings by at most
  // 1 / (1 - (omega dt / 2)^2) = 5.3 at omega dt = 1.8.
  EXPECT_LT(energy_growth(0.9 * dt_crit, 3000), 10.0);
  // Unstable just above: the highest mode grows by about 1.9 per step.
  EXPECT_GT(energy_growth(1.05 * dt_crit, 3000), 1e6);
}

TEST(DemStableStep, SpringSumBoundIsBelowTheVerletBound) {
  const DemSystem<2> sys = plate_fiber();
  const double dt_crit = 2 / fiber_omega_max(sys);
  const double dt_sum = sys.stable_dt();  // dt_safety 1
  // The shear spring's coupling of the spins limits both: 2.11 times
  // apart for this fiber, so the paper cases' dt_safety 0.6 runs at 0.28
  // of the stable step (0.3, before, at 1/7) and dt_safety below 2 stays
  // stable.
  EXPECT_NEAR(dt_crit / dt_sum, 2.113, 0.01);
  EXPECT_LT(0.3 * dt_sum, dt_crit / 7.0);
  EXPECT_LT(0.6 * dt_sum, 0.3 * dt_crit);
}

}  // namespace
}  // namespace sphdem
