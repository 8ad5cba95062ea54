// SPH-DEM coupling against hand computations: the drag law
// (include/sphdem/coupling/coupling.hpp), the pair kernels of src/coupling/terms/,
// and the reference solutions the validation tests compare against
// (docs/validation.md sections 4 and 5). docs/physics.md "Coupling" has the formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "../src/coupling/terms/continuity_void.hpp"
#include "../src/coupling/terms/reaction.hpp"
#include "../src/coupling/terms/shepard.hpp"
#include "../src/coupling/terms/void_fraction.hpp"
#include "sphdem/coupling/coupling.hpp"
#include "sphdem/sph/kernel.hpp"

namespace sphdem {
namespace {

constexpr double kPi = std::numbers::pi;

// The paper's resin and fibre particle (the paper's Table 1): 900 kg/m^3, 0.1 Pa s,
// d = 0.25 mm, h = 0.36 mm.
CouplingParams paper_resin() {
  CouplingParams c;
  c.rho = 900.0;
  c.mu = 0.1;
  return c;
}
constexpr double kD = 2.5e-4;
constexpr double kH = 3.6e-4;

// ---- Drag coefficient (paper Eq. 10)

// Re^0.687 by hand: 0.1^0.687 = 10^-0.687 = 0.2055890596, 10^0.687 =
// 4.864072057, 100^0.687 = 23.65919697, 1000^0.687 = 115.0800389.
//   Re = 0.1:  240 (1 + 0.15 * 0.2055890596) = 247.401206146
//   Re = 1:    24 (1 + 0.15) = 27.6
//   Re = 10:   2.4 (1 + 0.15 * 4.864072057) = 4.15106594049
//   Re = 100:  0.24 (1 + 0.15 * 23.65919697) = 1.09173109109
//   Re = 1000: 0.024 (1 + 0.15 * 115.0800389) = 0.43828814002 (still Schiller-Naumann)
//   Re = 2000: 0.44 (Newton regime)
TEST(CouplingDrag, DragCoefficientHandValues) {
  EXPECT_NEAR(drag_coefficient(0.1), 247.401206146, 1e-8);
  EXPECT_NEAR(drag_coefficient(1.0), 27.6, 1e-12);
  EXPECT_NEAR(drag_coefficient(10.0), 4.15106594049, 1e-10);
  EXPECT_NEAR(drag_coefficient(100.0), 1.09173109109, 1e-10);
  EXPECT_NEAR(drag_coefficient(1000.0), 0.43828814002, 1e-10);
  EXPECT_DOUBLE_EQ(drag_coefficient(1000.5), 0.44);
  EXPECT_DOUBLE_EQ(drag_coefficient(2000.0), 0.44);
  // C_d Re is finite at Re = 0 (Stokes: 24) and continuous in Re.
  EXPECT_EQ(drag_coefficient_times_re(0.0), 24.0);
  EXPECT_NEAR(drag_coefficient_times_re(1e-12), 24.0, 1e-7);
}

// ---- Momentum-exchange coefficient (paper Eq. 8 with the errata)

// rho 900, mu 0.1, d 2.5e-4 (d^2 = 6.25e-8), slip 0.1 m/s.
//  eps = 0.8 (Ergun, the boundary is Ergun's: paper "eps <= 0.8"):
//    150 (0.2)^2 0.1 / (0.8 * 6.25e-8) = 0.6 / 5e-8        = 1.2e7
//    1.75 (0.2) 900 0.1 / 2.5e-4        = 31.5 / 2.5e-4      = 1.26e5
//    beta = 12126000
//  eps = 0.79 (Ergun):
//    150 (0.21)^2 0.1 / (0.79 * 6.25e-8) = 0.6615 / 4.9375e-8 = 13397468.3544
//    1.75 (0.21) 900 0.1 / 2.5e-4       = 33.075 / 2.5e-4    = 132300
//    beta = 13529768.3544
//  eps = 0.81 (Wen & Yu): Re = 0.81 * 900 * 0.1 * 2.5e-4 / 0.1 = 0.18225,
//    C_d = 24/0.18225 (1 + 0.15 * 0.18225^0.687) = 137.820816126,
//    0.81^-2.65 = 1.74789242397,
//    beta = 0.75 * 137.820816126 * 0.81 * 0.19 * 900 * 0.1 / 2.5e-4 * 1.74789242397
//         = 10009949.8413
//  eps = 0.95 (Wen & Yu): Re = 0.21375, C_d = 118.115715509, 0.95^-2.65 = 1.1455985255,
//    beta = 0.75 * C_d * 0.95 * 0.05 * 900 * 0.1 / 2.5e-4 * 1.1455985255 = 1735391.65567
TEST(CouplingDrag, BetaHandValuesEitherSideOfTheSwitch) {
  const CouplingParams c = paper_resin();
  EXPECT_NEAR(drag_beta(c, 0.8, kD, 0.1) / 12126000.0, 1.0, 1e-12);
  EXPECT_NEAR(drag_beta(c, 0.79, kD, 0.1) / 13529768.3544, 1.0, 1e-11);
  EXPECT_NEAR(drag_beta(c, 0.81, kD, 0.1) / 10009949.8413, 1.0, 1e-10);
  EXPECT_NEAR(drag_beta(c, 0.95, kD, 0.1) / 1735391.65567, 1.0, 1e-10);
  // K = beta/(1-eps) stays finite at eps = 1, where beta vanishes.
  EXPECT_EQ(drag_beta(c, 1.0, kD, 0.1), 0.0);
  EXPECT_GT(drag_k(c, 1.0, kD, 0.1), 0.0);
  EXPECT_NEAR(drag_k(c, 0.95, kD, 0.1) * 0.05 / 1735391.65567, 1.0, 1e-10);
}

// Wen & Yu in the Newton regime: water-like rho 1000, mu 1e-3, d 1 mm,
// slip 2 m/s, eps 0.9: Re = 0.9 * 1000 * 2 * 1e-3 / 1e-3 = 1800 > 1000,
// C_d = 0.44, 0.9^-2.65 = 1.32207882668,
// beta = 0.75 * 0.44 * 0.9 * 0.1 * 1000 * 2 / 1e-3 * 1.32207882668 = 78531.482305.
TEST(CouplingDrag, BetaWenYuNewtonRegime) {
  CouplingParams c;
  c.rho = 1000.0;
  c.mu = 1e-3;
  EXPECT_NEAR(particle_reynolds(c, 0.9, 1e-3, 2.0), 1800.0, 1e-9);
  EXPECT_NEAR(drag_beta(c, 0.9, 1e-3, 2.0) / 78531.482305, 1.0, 1e-10);
}

// docs/validation.md section 5: OpenFOAM GidaspowErgunWenYu's K (= beta / (alpha_s alpha_f)),
// transcribed literally; alpha1 = solid, alpha2 = fluid. Re includes alpha2
// (our convention, GidaspowSchillerNaumann's). pos(0) = 1 in OpenFOAM, so
// the two codes differ only at eps = 0.8 exactly; the grid avoids it.
TEST(CouplingDrag, MatchesOpenFoamGidaspowErgunWenYu) {
  const CouplingParams c = paper_resin();
  const double nu2 = c.mu / c.rho, rho2 = c.rho, d = kD;
  for (double alpha2 : {0.4, 0.55, 0.7, 0.79, 0.81, 0.9, 0.99}) {
    for (double ur : {1e-4, 0.01, 0.3, 5.0, 400.0}) {
      const double alpha1 = 1.0 - alpha2;
      const double re = alpha2 * ur * d / nu2;
      const double cds = re <= 1000 ? 24.0 * (1.0 + 0.15 * std::pow(re, 0.687)) / re : 0.44;
      const double pos = alpha2 - 0.8 >= 0 ? 1.0 : 0.0;
      const double neg = 1.0 - pos;
      const double k_of = pos * (0.75 * cds * rho2 * ur * std::pow(alpha2, -2.65) / d) +
                          neg * (150 * alpha1 * nu2 * rho2 / ((alpha2 * d) * (alpha2 * d)) +
                                 1.75 * rho2 * ur / (alpha2 * d));
      const double beta_of = k_of * alpha1 * alpha2;
      EXPECT_NEAR(drag_beta(c, alpha2, d, ur) / beta_of, 1.0, 1e-12)
          << "eps " << alpha2 << " u_r " << ur;
    }
  }
}

// Stokes limit (slip -> 0, Re -> 0) in 3D: F_d = K V (u - v) with
// K = (3/4) 24 mu eps^-2.65 / d^2 and V = pi d^3/6, so
//   F_d = 3 pi mu d eps^-2.65 (u - v)      (Wen & Yu, eps > 0.8),
// Stokes' drag at eps = 1. The exponent is -2.65, not -1.65, because our Re
// contains eps (docs/physics.md "Coupling"): C_d |u_r| = 24 mu / (eps rho d). A code whose
// Re omits eps (older OpenFOAM WenYu) gets eps^-1.65; both agree at eps = 1.
TEST(CouplingDrag, StokesLimit3D) {
  const CouplingParams c = paper_resin();
  const Vec<3> u(3e-9, -1e-9, 2e-9), v(0, 0, 0);
  for (double eps : {1.0, 0.95, 0.85}) {
    const Vec<3> f = drag_force<3>(c, eps, kD, particle_volume<3>(kD), u, v);
    const Vec<3> stokes = 3 * kPi * c.mu * kD * std::pow(eps, -2.65) * (u - v);
    EXPECT_LT((f - stokes).norm() / stokes.norm(), 1e-6) << "eps " << eps;
  }
  // Direction: the resin drags the particle along the slip vbar - v_f.
  const Vec<2> f2 = drag_force<2>(c, 1.0, kD, particle_volume<2>(kD), Vec<2>(0, 0), Vec<2>(1, 0));
  EXPECT_LT(f2[0], 0.0);
  EXPECT_EQ(f2[1], 0.0);
  // 2D per unit depth: the same K times the disk area; at eps = 1 in the
  // Stokes limit 18 mu/d^2 * pi d^2/4 = 4.5 pi mu per unit slip (not Lamb's
  // cylinder drag: the law is the sphere's, applied per volume).
  const Vec<2> u2(1e-9, 0);
  const Vec<2> g2 = drag_force<2>(c, 1.0, kD, particle_volume<2>(kD), u2, Vec<2>::Zero());
  EXPECT_NEAR(g2[0] / (4.5 * kPi * c.mu * u2[0]), 1.0, 1e-6);
}

// ---- Void fraction

// One particle at its own position: eps = 1 - V W(0), W(0) = 16 C.
//  2D: V W(0) = pi d^2/4 * 16 * 7/(64 pi h^2) = 0.4375 (d/h)^2
//      paper (d/h = 0.25/0.36): 0.210985725309 -> eps = 0.789014274691 (Ergun side!)
//  3D: V W(0) = pi d^3/6 * 16 * 21/(256 pi h^3) = 0.21875 (d/h)^3 = 0.0732589323988
TEST(CouplingVoidFraction, OneParticleAtItsOwnPosition) {
  const WendlandC2<2> k2(kH);
  const WendlandC2<3> k3(kH);
  const double phi2 = terms::solid_fraction<2>(k2, particle_volume<2>(kD), 0.0);
  const double phi3 = terms::solid_fraction<3>(k3, particle_volume<3>(kD), 0.0);
  EXPECT_NEAR(phi2, 0.210985725309, 1e-11);
  EXPECT_NEAR(phi3, 0.0732589323988, 1e-12);
  EXPECT_NEAR(terms::void_fraction(phi2, 0.4), 0.789014274691, 1e-11);
  // Clipping: [eps_min, 1].
  EXPECT_EQ(terms::void_fraction(0.9, 0.4), 0.4);
  EXPECT_EQ(terms::void_fraction(0.0, 0.4), 1.0);
  EXPECT_EQ(terms::void_fraction(0.5, 0.4), 0.5);
}

// The solid fraction integrates to the particle's volume: sum over a fine
// lattice of sample points times the cell volume = V_f (midpoint rule on a
// C2 kernel: error far below 1e-6 at h/50 in 2D, h/16 in 3D).
TEST(CouplingVoidFraction, IntegratesToTheParticleVolume) {
  const double h = kH;
  {
    const WendlandC2<2> k(h);
    const double vol = particle_volume<2>(kD), dx = h / 50;
    const Vec<2> xf(0.3 * dx, -0.17 * dx);  // off the lattice
    double sum = 0;
    const int n = 110;
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j)
        sum += terms::solid_fraction<2>(k, vol, (Vec<2>(i * dx, j * dx) - xf).norm());
    EXPECT_NEAR(sum * dx * dx / vol, 1.0, 1e-6);
  }
  {
    const WendlandC2<3> k(h);
    const double vol = particle_volume<3>(kD), dx = h / 16;
    const Vec<3> xf(0.3 * dx, -0.17 * dx, 0.41 * dx);
    double sum = 0;
    const int n = 34;
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j)
        for (int l = -n; l <= n; ++l)
          sum += terms::solid_fraction<3>(k, vol, (Vec<3>(i * dx, j * dx, l * dx) - xf).norm());
    EXPECT_NEAR(sum * dx * dx * dx / vol, 1.0, 1e-6);
  }
}

// d phi_i/dt = sum_f V_f F x_if . v_if is the exact time derivative of the
// kernel sum along the paths x_i + v_i t, x_f + v_f t (central difference).
TEST(CouplingVoidFraction, RateIsTheTimeDerivative) {
  const WendlandC2<3> k(kH);
  const double vol = particle_volume<3>(kD);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec<3> xi(0, 0, 0), vi(0.3, -0.1, 0.2);
  std::vector<Vec<3>> xf, vf;
  for (int f = 0; f < 6; ++f) {
    xf.emplace_back(u(gen) * kH, u(gen) * kH, u(gen) * kH);
    vf.emplace_back(u(gen), u(gen), u(gen));
  }
  const auto phi = [&](double t) {
    double s = 0;
    for (std::size_t f = 0; f < xf.size(); ++f)
      s += terms::solid_fraction<3>(k, vol, (xi + vi * t - xf[f] - vf[f] * t).norm());
    return s;
  };
  double rate = 0;
  for (std::size_t f = 0; f < xf.size(); ++f) {
    const Vec<3> x = xi - xf[f];
    rate += terms::solid_fraction_rate(vol, k.f(x.norm()), (vi - vf[f]).dot(x));
  }
  const double dt = 1e-8;
  EXPECT_NEAR(rate, (phi(dt) - phi(-dt)) / (2 * dt), 1e-6 * std::abs(rate));
  // The clipped eps does not change where the clip binds.
  EXPECT_EQ(terms::clipped_solid_fraction_rate(0.7, 5.0, 0.4), 0.0);
  EXPECT_EQ(terms::clipped_solid_fraction_rate(0.5, 5.0, 0.4), 5.0);
}

// ---- Continuity with the void fraction

// With no DEM particle near (eps = 1, rate 0) it is paper Eq. 3. It keeps the
// superficial density eps rho on the plain continuity rate:
//   d(eps rho)/dt = eps drho/dt + rho deps/dt = fluid_sum   (deps/dt = -phi_rate).
// Hand value: fluid_sum 3, rho 900, phi_rate 0.02, eps 0.6: (3 + 18)/0.6 = 35.
TEST(CouplingContinuity, VoidFractionForm) {
  EXPECT_EQ(terms::continuity_void_fraction(3.0, 900.0, 0.0, 1.0), 3.0);
  EXPECT_NEAR(terms::continuity_void_fraction(3.0, 900.0, 0.02, 0.6), 35.0, 1e-12);
  const double rho = 912.0, eps = 0.73, phi_rate = -0.4, fluid_sum = 17.0;
  const double drho = terms::continuity_void_fraction(fluid_sum, rho, phi_rate, eps);
  EXPECT_NEAR(eps * drho + rho * (-phi_rate), fluid_sum, 1e-11);
}

// ---- Shepard filter (paper Eq. 9)

template <int D>
std::vector<Vec<D>> lattice_around(double dp, int n) {
  std::vector<Vec<D>> xs;
  const int nz = D == 3 ? n : 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int l = -nz; l <= nz; ++l) {
        Vec<D> x;
        x[0] = i * dp;
        x[1] = j * dp;
        if constexpr (D == 3) x[2] = l * dp;
        xs.push_back(x);
      }
  return xs;
}

// A uniform field is reproduced to round-off on any cloud; a linear field
// exactly where the neighbourhood is symmetric (first moment zero), and to
// the lattice error elsewhere.
TEST(CouplingShepard, UniformAndLinearFields) {
  const double dp = 3e-4, h = 1.2 * dp;
  const WendlandC2<2> k(h);
  const Vec<2> u0(0.7, -0.2), grad(3.0, 5.0);  // v(x) = u0 + (grad . x) e_x
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> jitter(-0.3 * dp, 0.3 * dp), rho(880, 920);
  // Uniform on a jittered cloud with scattered masses and densities.
  {
    terms::ShepardSum<2> s;
    const Vec<2> xf(0.1 * dp, 0.2 * dp);
    for (const Vec<2>& x : lattice_around<2>(dp, 4)) {
      const Vec<2> xr = x + Vec<2>(jitter(gen), jitter(gen));
      s.add(900 * dp * dp / rho(gen), k.w((xf - xr).norm()), u0);
    }
    ASSERT_TRUE(s.has_resin());
    EXPECT_LT((s.mean() - u0).norm(), 1e-15);
  }
  const auto field = [&](const Vec<2>& x) { return Vec<2>(u0 + grad.dot(x) * Vec<2>::UnitX()); };
  // Linear, DEM particle on a lattice node and midway between nodes.
  for (const Vec<2>& xf : {Vec<2>(0, 0), Vec<2>(0.5 * dp, 0.5 * dp)}) {
    terms::ShepardSum<2> s;
    for (const Vec<2>& xr : lattice_around<2>(dp, 4))
      s.add(dp * dp, k.w((xf - xr).norm()), field(xr));
    EXPECT_LT((s.mean() - field(xf)).norm(), 1e-14);
  }
  // Linear, generic offset: the error is grad * (first moment / S), well
  // below a percent of grad * dp.
  {
    const Vec<2> xf(0.23 * dp, -0.31 * dp);
    terms::ShepardSum<2> s;
    for (const Vec<2>& xr : lattice_around<2>(dp, 4))
      s.add(dp * dp, k.w((xf - xr).norm()), field(xr));
    EXPECT_LT((s.mean() - field(xf)).norm(), 1e-2 * grad.norm() * dp);
  }
  // No resin in reach: no velocity (and the caller applies no drag).
  terms::ShepardSum<3> empty;
  empty.add(1e-9, 0.0, Vec<3>(1, 2, 3));
  EXPECT_FALSE(empty.has_resin());
  EXPECT_EQ(empty.mean(), Vec<3>::Zero());
}

// ---- Reaction (paper Eqs. 11-12): momentum conservation to round-off

// A random configuration: DEM particles among SPH particles with scattered
// masses, densities and velocities. Each DEM particle's drag plus the
// reactions it spreads over its SPH neighbours sums to zero; so does the
// total, and the weights of each DEM particle sum to 1.
template <int D>
void check_reactions_cancel(unsigned seed) {
  const CouplingParams c = paper_resin();
  const double dp = 3e-4, h = 1.2 * dp, L = 8 * dp;
  const WendlandC2<D> k(h);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> pos(0, L), vel(-1, 1), rho(850, 950), mass(0.8, 1.2);
  const auto rvec = [&](auto& dist) {
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = dist(gen);
    return v;
  };
  const int n_sph = D == 2 ? 700 : 2500, n_dem = 12;
  std::vector<Vec<D>> xr(n_sph), vr(n_sph);
  std::vector<double> volr(n_sph);
  for (int r = 0; r < n_sph; ++r) {
    xr[r] = rvec(pos);
    vr[r] = rvec(vel);
    const double m = mass(gen) * 900 * std::pow(dp, D);
    volr[r] = m / rho(gen);
  }
  std::vector<Vec<D>> reaction(n_sph, Vec<D>::Zero());
  Vec<D> total_drag = Vec<D>::Zero();
  double scale = 0;
  for (int f = 0; f < n_dem; ++f) {
    const Vec<D> xf = rvec(pos), vf = rvec(vel);
    terms::ShepardSum<D> s;
    for (int r = 0; r < n_sph; ++r) s.add(volr[r], k.w((xf - xr[r]).norm()), vr[r]);
    if (!s.has_resin()) continue;
    const Vec<D> fd = drag_force<D>(c, 0.7 + 0.02 * f, kD, particle_volume<D>(kD), s.mean(), vf);
    Vec<D> sum_f = fd;
    double wsum = 0;
    for (int r = 0; r < n_sph; ++r) {
      const double w = k.w((xf - xr[r]).norm());
      if (w == 0.0) continue;
      const Vec<D> fr = terms::reaction_force<D>(volr[r], w, s.s, fd);
      reaction[r] += fr;
      sum_f += fr;
      wsum += terms::reaction_weight(volr[r], w, s.s);
    }
    // A few ulps of a sum of O(10-100) terms.
    EXPECT_LT(sum_f.norm() / fd.norm(), 4e-15) << "DEM particle " << f;
    EXPECT_NEAR(wsum, 1.0, 4e-15);
    total_drag += fd;
    scale = std::max(scale, fd.norm());
  }
  Vec<D> total = total_drag;
  for (const Vec<D>& fr : reaction) total += fr;
  EXPECT_LT(total.norm() / scale, 4e-15 * n_dem);
}

TEST(CouplingReaction, DragPlusReactionsSumToZero2D) {
  check_reactions_cancel<2>(3);
}
TEST(CouplingReaction, DragPlusReactionsSumToZero3D) {
  check_reactions_cancel<3>(5);
}

// ---- Reference solutions for the validation tests

// docs/validation.md section 4, glass (2500) in water (1000, 1e-3 Pa s), g = 9.81, with
// buoyancy. At eps = 1 the Wen & Yu law is exactly Schiller-Naumann:
// K V U = (3/4) C_d rho U^2 / d * pi d^3/6 = C_d (pi d^2/8) rho U^2.
// Below eps = 1 the settling speed carries the hindrance factor: in the
// Stokes limit U = U_St eps^2.65 (Wen & Yu; eps^1.65 if Re omitted eps).
TEST(CouplingReference, TerminalVelocityMatchesSchillerNaumannTable) {
  CouplingParams c;
  c.rho = 1000.0;
  c.mu = 1e-3;
  const double rho_p = 2500.0, g = 9.81;
  // The table's digits, each with half a unit of its last printed digit.
  struct Row {
    double d, re, re_tol, u, u_tol;
  };
  for (const Row& row :
       {Row{1e-4, 0.7294, 5e-5, 7.294e-3, 5e-7}, Row{5e-4, 36.72, 5e-3, 7.344e-2, 5e-6},
        Row{1e-3, 145.95, 5e-3, 0.1459, 5e-5}}) {
    const double u3 = terminal_velocity<3>(c, rho_p, row.d, g, 1.0, true);
    const double u2 = terminal_velocity<2>(c, rho_p, row.d, g, 1.0, true);
    EXPECT_NEAR(u3, row.u, row.u_tol) << "d " << row.d;
    EXPECT_NEAR(particle_reynolds(c, 1.0, row.d, u3), row.re, row.re_tol) << "d " << row.d;
    // Per unit depth in 2D the volume cancels the same way: the same speed.
    EXPECT_NEAR(u2 / u3, 1.0, 1e-14);
  }
  // Stokes limit (tiny d): U_St = (rho_p - rho_f) g d^2 / (18 mu), times
  // eps^2.65 for eps > 0.8.
  const double d = 1e-6;
  const double ust = (rho_p - c.rho) * g * d * d / (18 * c.mu);
  EXPECT_NEAR(terminal_velocity<3>(c, rho_p, d, g, 1.0, true) / ust, 1.0, 1e-4);
  EXPECT_NEAR(terminal_velocity<3>(c, rho_p, d, g, 0.9, true) / (ust * std::pow(0.9, 2.65)), 1.0,
              1e-4);
  // Without buoyancy (the paper's model has no pressure-gradient force).
  EXPECT_NEAR(terminal_velocity<3>(c, rho_p, d, g, 1.0, false) / (ust * rho_p / (rho_p - c.rho)),
              1.0, 1e-4);
  // No net weight: no settling.
  EXPECT_EQ(terminal_velocity<3>(c, 900.0, 1e-4, g, 1.0, true), 0.0);
}

// In the Ergun regime the balance is a quadratic in U:
//   (1.75 rho / d) U^2 + (150 (1-eps) mu / (eps d^2)) U - (rho_p - rho_f) g = 0.
TEST(CouplingReference, TerminalVelocityErgunQuadratic) {
  const CouplingParams c = paper_resin();
  const double rho_p = 2540.0, g = 9.81, eps = 0.6;
  const double a = 1.75 * c.rho / kD, b = 150 * (1 - eps) * c.mu / (eps * kD * kD),
               q = (rho_p - c.rho) * g;
  const double u = 2 * q / (b + std::sqrt(b * b + 4 * a * q));
  EXPECT_NEAR(terminal_velocity<2>(c, rho_p, kD, g, eps, true) / u, 1.0, 1e-13);
}

// tau = rho_p / K(eps, d, 0): at eps = 1, rho_p d^2 / (18 mu) (paper fibre:
// 2540 * 6.25e-8 / 1.8 = 8.81944e-5 s); eps^2.65 times that for eps > 0.8.
// A particle at rest in a uniform flow reaches u (1 - 1/e) at t = tau
// (RK4 on m dv/dt = F_d at a slip small enough for Stokes).
TEST(CouplingReference, StokesRelaxationTime) {
  const CouplingParams c = paper_resin();
  const double rho_p = 2540.0;
  EXPECT_NEAR(stokes_relaxation_time(c, rho_p, kD, 1.0), 2540 * 6.25e-8 / 1.8, 1e-17);
  EXPECT_NEAR(stokes_relaxation_time(c, rho_p, kD, 0.9) / (2540 * 6.25e-8 / 1.8),
              std::pow(0.9, 2.65), 1e-12);
  for (double eps : {1.0, 0.9, 0.6}) {
    const double tau = stokes_relaxation_time(c, rho_p, kD, eps);
    const double vol = particle_volume<2>(kD), m = rho_p * vol;
    const Vec<2> u(1e-7, 0);
    const auto acc = [&](const Vec<2>& v) {
      return Vec<2>(drag_force<2>(c, eps, kD, vol, u, v) / m);
    };
    Vec<2> v = Vec<2>::Zero();
    const int n = 1000;
    const double dt = tau / n;
    for (int s = 0; s < n; ++s) {
      const Vec<2> k1 = acc(v), k2 = acc(v + 0.5 * dt * k1), k3 = acc(v + 0.5 * dt * k2),
                   k4 = acc(v + dt * k3);
      v += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    EXPECT_NEAR(v[0] / u[0], 1 - std::exp(-1.0), 1e-5) << "eps " << eps;
  }
  // Two-way, uniform resin of mass M: tau M / (M + m).
  EXPECT_DOUBLE_EQ(two_way_relaxation_time(2.0, 1.0, 3.0), 1.5);
}

}  // namespace
}  // namespace sphdem
