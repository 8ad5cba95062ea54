// The resin's hydrodynamic torque on fiber particles (docs/physics.md
// "Hydrodynamic torque"): its kernels against hand values (the resin spin
// of a linear field, the Stokes rotational friction), the exact return of
// angular momentum to the resin, and Jeffery orbits (Jeffery 1922) of rigid
// bead chains in simple shear, 2D and 3D, 4, 8 and 16 particles, with the
// equivalent aspect ratio of the bead model's torque balance.
//
// The Jeffery cases are one-way: the resin is a lattice sampling the simple
// shear u = G y e_x (Jeffery's undisturbed flow), the fibers are the DEM's
// bonded chains, and the coupling pass (coupling_loops.hpp) runs every few
// DEM sub-steps as in a coupled run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "../src/coupling/terms/rotation.hpp"
#include "sphdem/coupling/coupling_loops.hpp"
#include "sphdem/dem/dem.hpp"

namespace sphdem {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- Kernels

// The fit recovers the rotation of any linear field, whatever the weights.
template <int D>
void check_spin_of_linear_field(unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  terms::Mat<D> l;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) l(a, b) = u(gen);
  std::vector<Vec<D>> x(40);
  std::vector<double> w(40);
  Vec<D> xbar = Vec<D>::Zero();
  double s = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    for (int a = 0; a < D; ++a) x[k][a] = u(gen);
    w[k] = 1.0 + u(gen) * 0.5;
    xbar += w[k] * x[k];
    s += w[k];
  }
  xbar /= s;
  terms::RotationFit<D> fit;
  for (std::size_t k = 0; k < x.size(); ++k) fit.add(w[k], x[k] - xbar, Vec<D>(l * (x[k] - xbar)));
  ASSERT_TRUE(fit.solvable());
  const Rot<D> spin = fit.spin();
  if constexpr (D == 2) {
    EXPECT_NEAR(spin[0], 0.5 * (l(1, 0) - l(0, 1)), 1e-13);
  } else {
    EXPECT_NEAR(spin[0], 0.5 * (l(2, 1) - l(1, 2)), 1e-13);
    EXPECT_NEAR(spin[1], 0.5 * (l(0, 2) - l(2, 0)), 1e-13);
    EXPECT_NEAR(spin[2], 0.5 * (l(1, 0) - l(0, 1)), 1e-13);
  }
}

TEST(HydrodynamicTorque, SpinOfALinearFieldIsHalfItsVorticity) {
  check_spin_of_linear_field<2>(1);
  check_spin_of_linear_field<3>(2);
}

// Neighbours on one line do not span the plane: no rotation is measured.
TEST(HydrodynamicTorque, CollinearNeighboursAreNotSolvable) {
  terms::RotationFit<2> fit;
  for (int k = -3; k <= 3; ++k) fit.add(1.0, Vec<2>(k, 0), Vec<2>(0, k));
  EXPECT_FALSE(fit.solvable());
}

// At eps = 1 and zero slip the drag law is Stokes' (coupling.hpp); the
// rotational friction is then 8 pi mu a^3 (sphere) and 4 pi mu a^2 per
// unit depth (circular cylinder, Lamb).
TEST(HydrodynamicTorque, StokesRotationalFriction) {
  CouplingParams c;
  c.rho = 900;
  c.mu = 0.7;
  const double a = 1.3e-4, d = 2 * a;
  const double k = drag_k(c, 1.0, d, 0.0);
  EXPECT_NEAR(terms::rotational_friction<3>(k * particle_volume<3>(d), a),
              8 * kPi * c.mu * a * a * a, 1e-12 * 8 * kPi * c.mu * a * a * a);
  EXPECT_NEAR(terms::rotational_friction<2>(k * particle_volume<2>(d), a), 4 * kPi * c.mu * a * a,
              1e-12 * 4 * kPi * c.mu * a * a);
}

// ---- Angular momentum: the torques and drags the fibers took over a
// step, returned to the resin by reaction_on_resin, leave the total linear
// and angular momentum unchanged to round-off.
template <int D>
void check_angular_momentum(unsigned seed) {
  std::mt19937 gen(seed);
  const double dp = 1e-3, h = 1.3 * dp, box = 8 * dp, thickness = D == 2 ? 0.01 : 1.0;
  std::uniform_real_distribution<double> pos(0, box), inner(2 * h, box - 2 * h), vel(-1, 1),
      rho(850, 950), mass(0.8, 1.2);
  const auto rvec = [&](auto& dist) {
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = dist(gen);
    return v;
  };
  SphParticles<D> sph;
  const int n_sph = D == 2 ? 400 : 2000;
  for (int r = 0; r < n_sph; ++r) {
    const double m = mass(gen) * 900 * std::pow(dp, D);
    const Vec<D> x = rvec(pos), v = rvec(vel);
    sph.push_owned(r, Kind::Fluid, -1, m, x, v, rho(gen));
  }
  DemParticles<D> dem;
  const double dt = 1e-3;
  std::vector<Rot<D>> torque;  // the mean torque of the step on each
  for (int f = 0; f < 10; ++f) {
    const auto i = dem.push_owned(f, f / 5, rvec(inner), 0.3 * dp, 1200, thickness);
    dem.v[i] = rvec(vel);
    dem.drag_impulse[i] = 1e-6 * rvec(vel);
    Rot<D> t;
    for (int a = 0; a < t.size(); ++a) t[a] = 1e-9 * vel(gen);
    dem.torque_impulse[i] = t;
    torque.push_back(t / dt);
  }
  CouplingSettings s;
  s.drag.rho = 900;
  s.drag.mu = 0.1;
  s.h = h;
  s.thickness = thickness;
  CouplingState<D> st;
  drag_on_fibers<D>(s, sph, dem, st, dt);
  std::vector<double> eps;
  double rate = 0;
  reaction_on_resin<D>(s, dem, sph, st, eps, rate);
  Vec<D> p = Vec<D>::Zero();
  Rot<D> l = Rot<D>::Zero();
  double p_scale = 0, l_scale = 0;
  for (std::size_t f = 0; f < dem.size(); ++f) {
    ASSERT_GT(dem.torque_coeff[f], 0.0) << "fiber particle " << f << " has resin around it";
    p += dem.mean_drag[f];
    l += torque[f] + moment<D>(dem.x[f], dem.mean_drag[f]);
    p_scale = std::max(p_scale, dem.mean_drag[f].norm());
    l_scale = std::max({l_scale, torque[f].norm(), box * dem.mean_drag[f].norm()});
  }
  Rot<D> l_resin = Rot<D>::Zero();
  for (std::size_t r = 0; r < sph.size(); ++r) {
    const Vec<D> fr = thickness * sph.mass[r] * sph.a[r];
    p += fr;
    l_resin += moment<D>(sph.x[r], fr);
  }
  EXPECT_LT(p.norm() / p_scale, 1e-12);
  EXPECT_LT((l + l_resin).norm() / l_scale, 1e-12)
      << "fibers took " << l.transpose() << ", the resin got " << l_resin.transpose();
}

TEST(HydrodynamicTorque, ReactionConservesAngularMomentum2D) {
  check_angular_momentum<2>(7);
}
TEST(HydrodynamicTorque, ReactionConservesAngularMomentum3D) {
  check_angular_momentum<3>(8);
}

// ---- Jeffery orbits

constexpr double kG = 1.0;      // shear rate [1/s]
constexpr double kMu = 1.0;     // resin viscosity [Pa s]
constexpr double kA = 1e-3;     // fiber particle radius [m]
constexpr double kRho = 9.0e4;  // fiber density: m / (6 pi mu a) = 0.02 / G, inertia negligible

// The resin: a lattice of spacing dp sampling u = G y e_x over the disk the
// fibers sweep (|x|, |y| <= half), and |z| <= half_z in 3D.
template <int D>
SphParticles<D> shear_lattice(double dp, double half, double half_z) {
  SphParticles<D> sph;
  const int n = static_cast<int>(std::ceil(half / dp)),
            nz = static_cast<int>(std::ceil(half_z / dp));
  std::int64_t id = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = D == 3 ? -nz : 0; k <= (D == 3 ? nz : 0); ++k) {
        Vec<D> x, v = Vec<D>::Zero();
        x[0] = i * dp;
        x[1] = j * dp;
        if constexpr (D == 3) x[2] = k * dp;
        v[0] = kG * x[1];
        sph.push_owned(id++, Kind::Fluid, -1, 1000 * std::pow(dp, D), x, v, 1000);
      }
  return sph;
}

struct Fiber {
  Vec<3> centre;
  double angle;  // from +x in the x-y plane [rad]
};

// Straight chains of n touching particles, bonded, in the x-y plane.
template <int D>
DemSystem<D> make_fibers(const std::vector<Fiber>& fibers, int n) {
  DemSystem<D> sys;
  for (std::size_t f = 0; f < fibers.size(); ++f) {
    for (int k = 0; k < n; ++k) {
      const double s = (2 * k - (n - 1)) * kA;
      Vec<D> x = fibers[f].centre.template head<D>();
      x[0] += s * std::cos(fibers[f].angle);
      x[1] += s * std::sin(fibers[f].angle);
      const std::int64_t id = sys.add_particle(x, kA, kRho, static_cast<std::int32_t>(f));
      if (k > 0) sys.add_bond(id - 1, id);
    }
  }
  return sys;
}

// The equivalent aspect ratio of a rigid chain of the bead model, from its
// torque balance in simple shear (docs/physics.md "Hydrodynamic torque"):
//   r_e^2 = 1 + 2 sum_i zeta_t,i s_i^2 / sum_i zeta_r,i,
// s_i the particles' distances from the chain's centre; with equal
// particles 1 + 2 (N^2 - 1) / (3 c_D), c_D of terms/rotation.hpp.
template <int D>
double chain_aspect_ratio(const DemParticles<D>& dem, std::size_t first, int n) {
  Vec<D> c = Vec<D>::Zero();
  for (int k = 0; k < n; ++k) c += dem.x[first + static_cast<std::size_t>(k)];
  c /= n;
  double num = 0, den = 0;
  for (int k = 0; k < n; ++k) {
    const std::size_t i = first + static_cast<std::size_t>(k);
    num += dem.drag_coeff[i] * (dem.x[i] - c).squaredNorm();
    den += dem.torque_coeff[i];
  }
  return std::sqrt(1.0 + 2.0 * num / den);
}

template <int D>
double closed_form_aspect_ratio(int n) {
  return std::sqrt(1.0 + 2.0 * (n * n - 1) / (3.0 * terms::kRotationalFriction<D>));
}

template <int D>
double orientation(const DemParticles<D>& dem, std::size_t first, int n) {
  const Vec<D> p = dem.x[first + static_cast<std::size_t>(n - 1)] - dem.x[first];
  return std::atan2(p[1], p[0]);
}

struct Orbit {
  double re = 0;                         // the chain's r_e (first fiber), at the first pass
  std::vector<double> t;                 // pass times [s]
  std::vector<std::vector<double>> phi;  // per fiber, unwrapped [rad]
};

// Runs the fibers in the lattice's shear to t_end: a coupling pass every
// two drag or spin relaxation times, DEM sub-steps in between.
template <int D>
Orbit run_shear(const std::vector<Fiber>& fibers, int n, double t_end, bool torque) {
  const double dp = (D == 2 ? 6 : 4) * kA, h = 1.2 * dp;
  double reach = 0;
  for (const Fiber& f : fibers) reach = std::max(reach, std::abs(f.centre[0]));
  const SphParticles<D> sph = shear_lattice<D>(dp, reach + n * kA + 2.5 * h, 2.5 * h);
  DemSystem<D> sys = make_fibers<D>(fibers, n);
  CouplingSettings s;
  s.drag.rho = 1000;
  s.drag.mu = kMu;
  s.h = h;
  s.hydrodynamic_torque = torque;
  CouplingState<D> st;
  DemParticles<D>& dem = sys.particles;
  drag_on_fibers<D>(s, sph, dem, st, 0.0);
  double relax = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < dem.size(); ++i) {
    relax = std::min(relax, dem.mass[i] / dem.drag_coeff[i]);
    if (torque) relax = std::min(relax, dem.inertia[i] / dem.torque_coeff[i]);
  }
  // Bonds stiff enough for a rigid chain: 200 times the Forgacs-Mason
  // buckling modulus of a fiber of aspect ratio n in this shear,
  // E_c = 2 r_p^4 mu G / (ln(2 r_p) - 1.75) (Forgacs & Mason 1959), so the
  // chain bends by well under a percent; the DEM's stable step, and a
  // coupling pass every two relaxation times.
  const double rp = n;
  sys.params.youngs_modulus = 200 * 2 * std::pow(rp, 4) * kMu * kG / (std::log(2 * rp) - 1.75);
  sys.params.kn = contact_stiffness_from_bond(sys.params, kA);
  sys.invalidate_forces();
  const double dt = std::min(0.5 * relax, sys.stable_dt());
  const int per_pass = std::max(1, static_cast<int>(std::ceil(2 * relax / dt)));
  Orbit o;
  o.re = torque ? chain_aspect_ratio(dem, 0, n) : 0.0;
  o.phi.resize(fibers.size());
  const auto record = [&](double t) {
    o.t.push_back(t);
    for (std::size_t f = 0; f < fibers.size(); ++f) {
      const double a = orientation(dem, f * static_cast<std::size_t>(n), n);
      std::vector<double>& phi = o.phi[f];
      double u = a;
      if (!phi.empty()) u = phi.back() + std::remainder(a - phi.back(), 2 * kPi);
      phi.push_back(u);
    }
  };
  record(0.0);
  double t = 0;
  while (t < t_end) {
    for (int k = 0; k < per_pass; ++k) sys.step(dt);
    t += per_pass * dt;
    drag_on_fibers<D>(s, sph, dem, st, per_pass * dt);
    record(t);
  }
  return o;
}

// Jeffery's closed form (Jeffery 1922; the same in-plane kinematics for an
// elliptic cylinder in 2D): tan phi = tan(kappa - omega t) / r_e,
// omega = G / (r_e + 1/r_e), tan kappa = r_e tan phi0. The phase
// theta = atan2(r_e sin phi, cos phi) then falls linearly, kappa - omega t.
double jeffery_phase(double phi, double re) {
  return std::atan2(re * std::sin(phi), std::cos(phi));
}

template <int D>
void check_jeffery(int n) {
  const double re_closed = closed_form_aspect_ratio<D>(n);
  const double half_turn = kPi * (re_closed + 1 / re_closed) / kG;
  const Orbit o = run_shear<D>({{Vec<3>::Zero(), 0.0}}, n, 2.1 * half_turn, true);
  const double re = o.re, t_half = kPi * (re + 1 / re) / kG, omega = kG / (re + 1 / re);
  const std::vector<double>& phi = o.phi[0];
  // The time to turn by pi from phi = 0 (phi falls: u = G y turns it clockwise).
  double t_flip = -1;
  for (std::size_t k = 1; k < phi.size(); ++k) {
    if (phi[k] <= -kPi && phi[k - 1] > -kPi) {
      const double f = (-kPi - phi[k - 1]) / (phi[k] - phi[k - 1]);
      t_flip = o.t[k - 1] + f * (o.t[k] - o.t[k - 1]);
      break;
    }
  }
  // Over two flips, the phase stays within 10 % of a half turn of the closed form's.
  double worst = 0, theta = 0;
  for (std::size_t k = 0; k < phi.size() && o.t[k] <= 2 * t_half; ++k) {
    const double raw = jeffery_phase(phi[k], re);
    theta = k == 0 ? raw : theta + std::remainder(raw - theta, 2 * kPi);
    worst = std::max(worst, std::abs(theta - (-omega * o.t[k])));
  }
  std::printf(
      "%dD, %2d particles: r_e %.3f (equal particles: %.3f); turn by pi in %.3f s, "
      "pi (r_e + 1/r_e)/G = %.3f s (%+.1f %%); largest phase lag %.3f pi over two flips\n",
      D, n, re, re_closed, t_flip, t_half, 100 * (t_flip / t_half - 1), worst / kPi);
  EXPECT_NEAR(t_flip, t_half, 0.1 * t_half);
  EXPECT_LT(worst, 0.1 * kPi);
  // The chain's void fraction is not uniform (the ends see fewer
  // neighbours); the equal-particle mapping is still within 10 %.
  EXPECT_NEAR(re, re_closed, 0.1 * re_closed);
}

TEST(Jeffery, Chains2D) {
  for (int n : {4, 8}) check_jeffery<2>(n);
}
TEST(Jeffery, Chains3D) {
  for (int n : {4, 8}) check_jeffery<3>(n);
}
// 16 particles: the rigid chain needs bonds 16 times stiffer than 8 (the
// buckling modulus goes as r_p^4), a minute or more; ctest label `long`.
TEST(JefferyLong, Chains16) {
  check_jeffery<2>(16);
  check_jeffery<3>(16);
}

// Without the torque, a chain aligned with the flow never turns (drag
// alone: dphi/dt = -G sin^2 phi, the symptom).
TEST(Jeffery, WithoutTorqueAnAlignedChainNeverTurns) {
  const Orbit o = run_shear<2>({{Vec<3>::Zero(), 0.0}}, 4, 20.0, false);
  EXPECT_LT(std::abs(o.phi[0].back()), 1e-3);
}

// A cloud of five non-touching 4-particle chains, nearly aligned at the
// start (0 to 4 degrees, turning towards the flow): with the torque the orientation tensor's a_xx
// keeps oscillating (below 0.3 and above 0.9 in the last half turn of three); with drag only it
// locks near 1.
double a_xx(const Orbit& o, std::size_t k) {
  double sum = 0;
  for (const std::vector<double>& phi : o.phi) sum += std::pow(std::cos(phi[k]), 2);
  return sum / static_cast<double>(o.phi.size());
}

TEST(Jeffery, CloudKeepsFlipping) {
  std::vector<Fiber> cloud;
  const double deg = kPi / 180;
  const double angles[] = {0.0, 1 * deg, 2 * deg, 3 * deg, 4 * deg};
  for (int f = 0; f < 5; ++f) cloud.push_back({Vec<3>((f - 2) * 12 * kA, 0, 0), angles[f]});
  const double re = closed_form_aspect_ratio<2>(4), half_turn = kPi * (re + 1 / re) / kG;
  for (bool torque : {true, false}) {
    const Orbit o = run_shear<2>(cloud, 4, 3 * half_turn, torque);
    double lo = 1, hi = 0;
    for (std::size_t k = 0; k < o.t.size(); ++k) {
      if (o.t[k] < 2 * half_turn) continue;
      lo = std::min(lo, a_xx(o, k));
      hi = std::max(hi, a_xx(o, k));
    }
    std::printf("cloud, torque %s: a_xx in [%.3f, %.3f] over the last half turn\n",
                torque ? "on" : "off", lo, hi);
    if (torque) {
      EXPECT_LT(lo, 0.3);
      EXPECT_GT(hi, 0.9);
    } else {
      EXPECT_GT(lo, 0.9);
    }
  }
}

}  // namespace
}  // namespace sphdem
