// DEM validation against docs/validation.md: normal impact
// (section 2), Coulomb sliding, cantilever and axial stiffness of a bonded
// chain (section 3 with the bonds of section 6), bond breakage (section 6)
// and energy conservation. Each tolerance is justified where it is used;
// the measured errors are printed for docs/dem.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>

#include "sphdem/dem/dem.hpp"

namespace sphdem {
namespace {

constexpr double kPi = std::numbers::pi;

// The fibers of the paper: d = 0.25 mm, E-glass.
constexpr double kR = 0.125e-3, kRho = 2540, kE = 72e9;

template <int D>
Vec<D> axis(int d, double s = 1.0) {
  return s * Vec<D>::Unit(d);
}

// ---------------------------------------------------------------- impact

struct Impact {
  double e = 0, tc = 0;
};

// Head-on impact at v0, no gravity, friction 0. `pair`: two equal
// particles (m_eff = m/2); otherwise a particle on a plane (m_eff = m).
// The contact starts and ends where the overlap crosses zero, found by
// linear interpolation between steps (the overlap is smooth there).
template <int D>
Impact impact(bool pair, double e, double& tc_exact) {
  DemSystem<D> sys;
  sys.params.kn = 1e5;
  sys.params.restitution = e;
  sys.params.friction = 0;
  const double r = 1e-3, v0 = 0.2;
  if (pair) {
    sys.add_particle(Vec<D>::Zero(), r, kRho);
    sys.add_particle(axis<D>(0, 2.02 * r), r, kRho);
    sys.particles.v[0] = axis<D>(0, 0.5 * v0);
    sys.particles.v[1] = axis<D>(0, -0.5 * v0);
  } else {
    sys.walls.push_back(DemWall<D>::plane(Vec<D>::Zero(), axis<D>(1)));
    sys.add_particle(axis<D>(1, 1.01 * r), r, kRho);
    sys.particles.v[0] = axis<D>(1, -v0);
  }
  const double m = sys.particles.mass[0];
  const double m_eff = pair ? 0.5 * m : m;
  const double ln_e = std::log(e);
  const double cn = -2 * ln_e * std::sqrt(m_eff * 1e5) / std::sqrt(kPi * kPi + ln_e * ln_e);
  tc_exact = kPi / std::sqrt(1e5 / m_eff - std::pow(cn / (2 * m_eff), 2));
  auto overlap = [&] {
    const auto& x = sys.particles.x;
    return pair ? 2 * r - (x[1] - x[0]).norm() : r - x[0][1];
  };
  auto approach_speed = [&] {
    const auto& v = sys.particles.v;
    return pair ? v[0][0] - v[1][0] : -v[0][1];
  };
  const double dt =
      tc_exact /
      400;  // docs/validation.md section 2 asks for <= t_c/50; 400 keeps e's O(dt) error < 0.1 %
  double t_start = -1, t_end = -1, prev = overlap();
  for (int s = 0; s < 100000 && t_end < 0; ++s) {
    sys.step(dt);
    const double now = overlap();
    const double t_cross = sys.time() - dt + dt * (-prev) / (now - prev);
    if (prev <= 0 && now > 0) t_start = t_cross;
    if (prev > 0 && now <= 0) t_end = t_cross;
    prev = now;
  }
  return {-approach_speed() / v0, t_end - t_start};
}

template <int D>
void check_impact(bool pair) {
  for (double e : {0.5, 0.8, 0.95}) {
    double tc = 0;
    const Impact r = impact<D>(pair, e, tc);
    const double err_e = std::abs(r.e / e - 1), err_t = std::abs(r.tc / tc - 1);
    std::printf("impact D=%d %s e=%.2f: e err %.2e, t_c err %.2e\n", D, pair ? "pair" : "wall", e,
                err_e, err_t);
    EXPECT_LT(err_e, 0.01);  // issue 4: 1 %
    EXPECT_LT(err_t, 0.02);  // issue 4: 2 %
  }
}

TEST(DemImpact, WallRestitutionAndDuration2D) {
  check_impact<2>(false);
}
TEST(DemImpact, WallRestitutionAndDuration3D) {
  check_impact<3>(false);
}
TEST(DemImpact, PairRestitutionAndDuration2D) {
  check_impact<2>(true);
}
TEST(DemImpact, PairRestitutionAndDuration3D) {
  check_impact<3>(true);
}

// A moving wall (the piston) hits a particle at rest: in the wall's frame
// the particle arrives at V and leaves at e V, so it ends at (1 + e) V.
// Same discretisation as above: 1 % holds with margin.
template <int D>
void check_moving_wall() {
  DemSystem<D> sys;
  sys.params.kn = 1e5;
  sys.params.restitution = 0.8;
  const double r = 1e-3, V = 0.3;
  sys.walls.push_back(DemWall<D>::plane(axis<D>(1, 2.05 * r), axis<D>(1, -1), axis<D>(1, -V)));
  sys.add_particle(axis<D>(1, r), r, kRho);
  const double dt = 0.01 * std::sqrt(sys.particles.mass[0] / 1e5);
  while (sys.time() < 0.05 * r / V + 0.01) {
    sys.step(dt);
    if (sys.particles.v[0][1] < -V * 1.5 &&
        sys.particles.wall_contacts[0][0].partner == DemContact<D>::kNone)
      break;
  }
  const double err = std::abs(-sys.particles.v[0][1] / (1.8 * V) - 1);
  std::printf("moving wall D=%d: rebound speed err %.2e\n", D, err);
  EXPECT_LT(err, 0.01);
}

TEST(DemImpact, MovingWall2D) {
  check_moving_wall<2>();
}
TEST(DemImpact, MovingWall3D) {
  check_moving_wall<3>();
}

// --------------------------------------------------------------- sliding

// A disk (sphere) launched along a floor at v0 without spin slides, and
// friction mu m g decelerates its centre at mu g until it rolls, at
// t_r = v0 / (3 mu g) for a disk (2 v0 / (7 mu g) for a sphere). The slope
// is measured over [0.2, 0.8] t_r, away from the start and the roll.
template <int D>
void check_sliding() {
  DemSystem<D> sys;
  const double g = 9.81, mu = 0.3, v0 = 0.1, r = 1e-3, kn = 1e5;
  sys.params.kn = kn;
  sys.params.friction = mu;
  sys.params.restitution = 0.5;
  sys.params.gravity = axis<D>(1, -g);
  sys.walls.push_back(DemWall<D>::plane(Vec<D>::Zero(), axis<D>(1)));
  sys.add_particle(Vec<D>::Zero(), r, kRho);
  const double m = sys.particles.mass[0];
  sys.particles.x[0] = axis<D>(1, r - m * g / kn);  // resting overlap: no bounce
  sys.particles.v[0] = axis<D>(0, v0);
  const double t_roll = (D == 2 ? 1.0 / 3.0 : 2.0 / 7.0) * v0 / (mu * g);
  const double dt = sys.stable_dt();
  double t1 = -1, v1 = 0, t2 = -1, v2 = 0;
  while (sys.time() < 0.8 * t_roll) {
    sys.step(dt);
    if (t1 < 0 && sys.time() >= 0.2 * t_roll) {
      t1 = sys.time();
      v1 = sys.particles.v[0][0];
    }
  }
  t2 = sys.time();
  v2 = sys.particles.v[0][0];
  const double decel = (v1 - v2) / (t2 - t1);
  const double err = std::abs(decel / (mu * g) - 1);
  std::printf("sliding D=%d: deceleration err %.2e\n", D, err);
  EXPECT_LT(err, 0.02);  // issue 4: 2 %
}

TEST(DemSliding, DeceleratesAtMuG2D) {
  check_sliding<2>();
}
TEST(DemSliding, DeceleratesAtMuG3D) {
  check_sliding<3>();
}

// --------------------------------------------------------------- chains

// A straight chain of n touching particles along x, bonded in order, the
// first one clamped (velocity and spin held at zero).
template <int D>
DemSystem<D> chain(int n, double r_last = kR) {
  DemSystem<D> sys;
  sys.params.youngs_modulus = kE;
  sys.params.kn = contact_stiffness_from_bond(sys.params, kR);
  sys.params.restitution = 0.5;
  double x = 0;
  for (int i = 0; i < n; ++i) {
    const double r = i + 1 == n ? r_last : kR;
    if (i > 0) x += (i + 1 == n ? kR + r_last : 2 * kR);
    sys.add_particle(axis<D>(0, x), r, kRho, 0);
    if (i > 0) sys.add_bond(i - 1, i);
  }
  sys.particles.fixed[0] = kFixedMotion;
  return sys;
}

template <int D>
double bond_inertia(double rbar) {
  return D == 2 ? 2.0 / 3.0 * std::pow(rbar, 3) : kPi * std::pow(rbar, 4) / 4;
}
template <int D>
double bond_area(double rbar) {
  return D == 2 ? 2.0 * rbar : kPi * rbar * rbar;
}

// Runs with global damping until the tip's speed is negligible; returns the
// tip displacement. gamma = 2 omega_1 (critical for the first bending mode,
// docs/validation.md section 3: omega_1 = 1.875^2 sqrt(E I / (rho_l L^4))).
template <int D>
Vec<D> settle(DemSystem<D>& sys, double omega_1) {
  sys.params.global_damping = 2 * omega_1;
  const std::size_t tip = sys.particles.size() - 1;
  const Vec<D> x0 = sys.particles.x[tip];
  const double dt = sys.stable_dt();
  const auto steps = static_cast<long>(40.0 / (omega_1 * dt));  // e^-40: far below the 5 % needed
  for (long s = 0; s < steps; ++s) sys.step(dt);
  return sys.particles.x[tip] - x0;
}

// Cantilever of N = 10 bonds (11 particles), tip load F with delta/L = 1 %
// (small-deflection theory). The chain's own error is known: the bond
// rotations integrate the linear moment exactly (midpoint rule), the
// deflection integrates the concave rotation by the trapezoid rule, which
// falls short by 1/(4 N^2) = 0.25 %, and the shear springs add
// 3 kbar* (I/A) / (l^2 N^2) (0.06 % in 2D, 0.05 % in 3D). The measured error
// must be within 5 % (the issue) and within 5e-4 of that prediction
// (geometric nonlinearity, O((delta/L)^2) = 1e-4, is what remains).
template <int D>
void check_cantilever() {
  const int n_bonds = 10;
  DemSystem<D> sys = chain<D>(n_bonds + 1);
  const double L = n_bonds * 2 * kR, I = bond_inertia<D>(kR);
  const double delta_target = 0.01 * L;
  const double F = 3 * kE * I * delta_target / std::pow(L, 3);
  sys.particles.f_ext.back() = axis<D>(1, -F);
  sys.invalidate_forces();
  const double rho_l = sys.particles.mass[0] / (2 * kR);
  const double omega_1 = 1.875104 * 1.875104 * std::sqrt(kE * I / (rho_l * std::pow(L, 4)));
  const Vec<D> u = settle(sys, omega_1);
  const double err = -u[1] / delta_target - 1;
  const double l = 2 * kR, n2 = n_bonds * n_bonds;
  const double expected =
      -0.25 / n2 + 3 * sys.params.kbar_star * I / bond_area<D>(kR) / (l * l * n2);
  std::printf("cantilever D=%d: tip deflection err %.3e (chain's own error %.3e)\n", D, err,
              expected);
  EXPECT_LT(std::abs(err), 0.05);
  EXPECT_NEAR(err, expected, 5e-4);
}

TEST(DemCantilever, TipDeflection2D) {
  check_cantilever<2>();
}
TEST(DemCantilever, TipDeflection3D) {
  check_cantilever<3>();
}

// Axial stiffness of the same chain: each bond is a spring kbar_n A with
// kbar_n = E / (2 R), in series over L = 2 R N, so F / u = E A / L exactly
// in the static limit; the 2 % of the issue covers the settling residue.
template <int D>
void check_axial() {
  const int n_bonds = 10;
  DemSystem<D> sys = chain<D>(n_bonds + 1);
  const double L = n_bonds * 2 * kR, A = bond_area<D>(kR);
  const double F = 1e-4 * kE * A;  // strain 1e-4
  sys.particles.f_ext.back() = axis<D>(0, F);
  sys.invalidate_forces();
  const double omega_ax = kPi / (2 * L) * std::sqrt(kE * A / (sys.particles.mass[0] / (2 * kR)));
  const Vec<D> u = settle(sys, omega_ax);
  const double err = (F / u[0]) / (kE * A / L) - 1;
  std::printf("axial D=%d: stiffness err %.3e\n", D, err);
  EXPECT_LT(std::abs(err), 0.02);
}

TEST(DemCantilever, AxialStiffness2D) {
  check_axial<2>();
}
TEST(DemCantilever, AxialStiffness3D) {
  check_axial<3>();
}

// --------------------------------------------------------------- breakage

// A chain of 6 pulled at its free end by a slowly rising force. The last
// particle is thinner (0.8 R), so its bond has the smallest section and,
// in quasi-static tension (every bond carries the load F), the highest
// stress F / A: it must break first, at F = sigma_c A(0.8 R). The ramp
// lasts ~200 periods of the chain's axial mode and is damped critically,
// so inertia and damping carry ~1e-3 of the load: 1 % (the issue) holds.
template <int D>
void check_breakage() {
  DemSystem<D> sys = chain<D>(6, 0.8 * kR);
  const double sigma_c = 2e9;  // the paper's tensile strength
  sys.params.tensile_strength = sigma_c;
  const double F_c = sigma_c * bond_area<D>(0.8 * kR);
  const double L = 5 * 2 * kR, A = bond_area<D>(kR);
  const double omega_ax = kPi / (2 * L) * std::sqrt(kE * A / (sys.particles.mass[0] / (2 * kR)));
  sys.params.global_damping = 2 * omega_ax;
  const double ramp_time = 200 * 2 * kPi / omega_ax, rate = F_c / ramp_time;
  const double dt = sys.stable_dt();
  double F_break = -1, sigma_others = 0;
  while (F_break < 0 && sys.time() < 2 * ramp_time) {
    const double F = rate * (sys.time() + dt);  // the load at the end of the step
    sys.particles.f_ext.back() = axis<D>(0, F);
    sys.step(dt);
    for (int b = 0; b < 4; ++b) sigma_others = std::max(sigma_others, sys.bond(b, b + 1)->sigma);
    for (int b = 0; b < 5; ++b) {
      if (sys.bond(b, b + 1)->broken) {
        EXPECT_EQ(b, 4) << "the wrong bond broke";
        F_break = F;
      }
    }
  }
  // The thicker bonds peak at sigma_c A(0.8 R) / A(R): 0.8 sigma_c in 2D
  // (A = 2 Rbar), 0.64 sigma_c in 3D (A = pi Rbar^2); damping adds ~1e-3.
  EXPECT_LT(sigma_others, (D == 2 ? 0.8 : 0.64) * sigma_c * 1.01);
  for (int b = 0; b < 4; ++b) EXPECT_FALSE(sys.bond(b, b + 1)->broken);
  const double err = F_break / F_c - 1;
  std::printf("breakage D=%d: load at break err %.3e\n", D, err);
  EXPECT_LT(std::abs(err), 0.01);
}

TEST(DemBreakage, WeakestBondBreaksAtPredictedLoad2D) {
  check_breakage<2>();
}
TEST(DemBreakage, WeakestBondBreaksAtPredictedLoad3D) {
  check_breakage<3>();
}

// ---------------------------------------------------------------- energy

// A free chain of 6 bonded particles (no clamp, no damping, no contacts)
// set vibrating and tumbling by random velocities and spins: stretching,
// shear, bending (and twisting) with the contact planes turning, which is
// where an incremental bond law could create or lose energy. Velocity
// Verlet's energy oscillates by O((omega dt)^2) within each vibration, so
// the secular drift is measured between the mean energies of the first and
// last 10^4 of 10^5 steps.
template <int D>
void check_energy() {
  DemSystem<D> sys = chain<D>(6);
  sys.particles.fixed[0] = kFree;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  auto& ps = sys.particles;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (int d = 0; d < D; ++d) ps.v[i][d] = 0.05 * u(rng);  // strains ~1e-5
    for (int d = 0; d < ps.omega[i].size(); ++d) ps.omega[i][d] = 200 * u(rng);
  }
  const double dt = sys.stable_dt();
  const int steps = 100000, window = 10000;
  double first = 0, last = 0, e0 = 0, swing = 0;
  for (int s = 0; s < steps; ++s) {
    sys.step(dt);
    const double e = sys.kinetic_energy() + sys.elastic_energy();
    if (s == 0) e0 = e;
    swing = std::max(swing, std::abs(e / e0 - 1));
    if (s < window) first += e / window;
    if (s >= steps - window) last += e / window;
  }
  const double drift = std::abs(last - first) / e0;
  std::printf("energy D=%d: drift %.2e over 1e5 steps (oscillation within a step %.2e)\n", D, drift,
              swing);
  EXPECT_LT(drift, 1e-6);  // issue 4
}

TEST(DemEnergy, FreeBondedChainConservesEnergy2D) {
  check_energy<2>();
}
TEST(DemEnergy, FreeBondedChainConservesEnergy3D) {
  check_energy<3>();
}

// The same with the benchmark's soft fiber (4 spheres of diameter 1,
// K = kbar_n A = 1, kbar* 5, dt 0.05 in LJ units) at the benchmark's
// particle speeds (strains of 10-20 %) and spinning at up to 1 rad per unit
// time: tumbling, twisting and bending by O(0.1 rad) per vibration and up
// to 0.05 rad per step, so every frame turn of the incremental law counts.
// Contacts between a fiber's own particles, when it folds, are elastic
// (e = 1, no friction). The largest departure from the initial energy over
// 1e5 steps is measured. Two effects remain at these strains, neither
// secular growth: velocity Verlet's O((omega dt)^2) error with omega dt up
// to 0.2 for the spin modes, and the path dependence of an incremental
// (hypoelastic) law at finite strain. Measured: 5.7-6.4 % with the test
// build, 5.9 % (2D) and 10.1 % (3D) with the sanitizer build: the
// trajectories are chaotic, so each build's contraction of multiply-adds
// picks other ones. The first-order frame update (V . n_end dt for F_n,
// projection into the new plane) blows up or grows by a factor 20; 25 %
// separates the two with room for any build.
template <int D>
double soft_fiber_swing(std::uint64_t seed, double spin) {
  const double r = 0.5;
  DemSystem<D> sys;
  auto& p = sys.params;
  p.kn = 1.0;
  p.kt_over_kn = 2.0 / 7.0;
  p.restitution = 1.0;
  p.friction = 0.0;
  p.youngs_modulus = (D == 3 ? 1.0 / (kPi * r * r) : 1.0 / (2 * r)) * 2 * r;  // kbar_n A = 1
  p.kbar_star = 5.0;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Vec<D> dir;
  for (int d = 0; d < D; ++d) dir[d] = u(rng);
  dir.normalize();
  for (int a = 0; a < 4; ++a) {
    sys.add_particle((a - 1.5) * 2 * r * dir, r, 1.0, 0);
    if (a > 0) sys.add_bond(a - 1, a);
  }
  auto& ps = sys.particles;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (int d = 0; d < D; ++d) ps.v[i][d] = 0.24 * u(rng);
    for (int d = 0; d < ps.omega[i].size(); ++d) ps.omega[i][d] = spin * u(rng);
  }
  const double e0 = sys.kinetic_energy() + sys.elastic_energy();
  double swing = 0;
  for (int s = 0; s < 100000; ++s) {
    sys.step(0.05);
    swing = std::max(swing, std::abs((sys.kinetic_energy() + sys.elastic_energy()) / e0 - 1));
  }
  return swing;
}

template <int D>
void check_soft_fiber_energy() {
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
    for (double spin : {0.0, 0.5, 1.0}) worst = std::max(worst, soft_fiber_swing<D>(seed, spin));
  std::printf("energy D=%d soft tumbling fiber: largest |E/E0 - 1| %.2e over 1e5 steps\n", D,
              worst);
  EXPECT_LT(worst, 0.25);
}

TEST(DemEnergy, TumblingSoftFiberConservesEnergy2D) {
  check_soft_fiber_energy<2>();
}
TEST(DemEnergy, TumblingSoftFiberConservesEnergy3D) {
  check_soft_fiber_energy<3>();
}

}  // namespace
}  // namespace sphdem
