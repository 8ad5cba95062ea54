// The SPH pair terms (src/sph/terms/) and the resin's rate loop
// (compute_fluid_rates) against hand computations (docs/physics.md):
//  - each term with small numbers worked out by hand, and against the
//    published form it rewrites (delta-SPH's psi_ij, Morris's
//    (mu_i + mu_j) / (rho_i rho_j) x_ij . grad W / (r^2 + eta^2));
//  - compute_fluid_rates on a few resin particles and a wall particle,
//    against the equations summed pair by pair in this file: continuity
//    (paper Eq. 3) with delta-SPH, momentum (paper Eq. 5, sign corrected)
//    with artificial viscosity, anti-clump (the n = 4 fast path and the
//    general exponent), Morris viscosity with the lattice corrections, and
//    the body force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../src/sph/terms/anti_clump.hpp"
#include "../src/sph/terms/artificial_viscosity.hpp"
#include "../src/sph/terms/continuity.hpp"
#include "../src/sph/terms/delta_sph.hpp"
#include "../src/sph/terms/pressure.hpp"
#include "../src/sph/terms/viscosity_morris.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/sph/kernel.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {
namespace {

// ------------------------------------------------------ each pair term

TEST(SphTerms, ContinuityHandValue) {
  // m_j F (v_ij . x_ij) = 2 * (-3) * 0.5.
  EXPECT_DOUBLE_EQ(terms::continuity(2.0, -3.0, 0.5), -3.0);
  EXPECT_EQ(terms::continuity(2.0, 0.0, 0.5), 0.0) << "beyond the support F = 0";
}

TEST(SphTerms, PressureOverRhoSquared) {
  EXPECT_DOUBLE_EQ(terms::pressure_over_rho2(2000.0, 1000.0), 2e-3);
  EXPECT_DOUBLE_EQ(terms::pressure_over_rho2(-500.0, 500.0), -2e-3);
}

TEST(SphTerms, DeltaSphHandValueAndPsiForm) {
  // -2 delta h c0 (rho_j - rho_i) F V_j = -2 * 0.5 * 2 * (-4) * 1e-3.
  EXPECT_DOUBLE_EQ(terms::delta_sph(0.5, 1000.0, 1002.0, 1e-3, -4.0), 8e-3);
  // Molteni & Colagrossi (2009): delta h c0 V_j psi_ij . grad_i W_ij with
  // psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / r^2 and grad_i W_ij = F x_ij.
  const Vec<2> xi(0.3, -0.1), xj(-0.2, 0.4);
  const Vec<2> xij = xi - xj;
  const double rho_i = 998, rho_j = 1003, vol_j = 2e-6, F = -7.5, dhc = 0.04;
  const Vec<2> psi = 2 * (rho_j - rho_i) * (xj - xi) / xij.squaredNorm();
  const double published = dhc * vol_j * psi.dot(F * xij);
  EXPECT_NEAR(terms::delta_sph(dhc, rho_i, rho_j, vol_j, F), published,
              1e-15 * std::abs(published));
  EXPECT_EQ(terms::delta_sph(dhc, rho_i, rho_i, vol_j, F), 0.0) << "equal densities";
}

TEST(SphTerms, ArtificialViscosityActsOnApproachingPairsOnly) {
  // -alpha c0 h mu_ij / rho_bar with mu_ij = -2 / (0.9 + 0.1), rho_bar = 1000.
  EXPECT_DOUBLE_EQ(terms::artificial_viscosity(0.3, -2.0, 0.9, 0.1, 999.0, 1001.0), 6e-4);
  EXPECT_EQ(terms::artificial_viscosity(0.3, 2.0, 0.9, 0.1, 999.0, 1001.0), 0.0) << "receding";
  EXPECT_EQ(terms::artificial_viscosity(0.3, 0.0, 0.9, 0.1, 999.0, 1001.0), 0.0) << "sliding";
}

TEST(SphTerms, MorrisViscosityHandValueAndPublishedForm) {
  // (2 mu / rho_i) V_j F r^2 / (r^2 + eta^2) = 0.004 * 0.5 * (-2) * 0.09 / 0.1.
  EXPECT_DOUBLE_EQ(terms::morris_viscosity(0.004, 0.5, -2.0, 0.09, 0.01), -3.6e-3);
  // Morris, Fox & Zhu (1997): m_j (mu_i + mu_j) / (rho_i rho_j)
  // x_ij . grad_i W_ij / (r^2 + eta^2), with x_ij . grad_i W_ij = F r^2.
  const double mu = 0.7, rho_i = 1010, rho_j = 990, m_j = 3e-4, F = -12.0, r2 = 4e-6,
               eta2 = 1.44e-8;
  const double published = m_j * (mu + mu) / (rho_i * rho_j) * (F * r2) / (r2 + eta2);
  EXPECT_NEAR(terms::morris_viscosity(2 * mu / rho_i, m_j / rho_j, F, r2, eta2), published,
              1e-15 * std::abs(published));
}

TEST(SphTerms, AntiClumpParts) {
  // R_a = eps |P_a| / rho_a^2 where P_a < 0, else 0.
  EXPECT_DOUBLE_EQ(terms::anti_clump_r(0.2, -3e-3), 6e-4);
  EXPECT_EQ(terms::anti_clump_r(0.2, 3e-3), 0.0);
  EXPECT_EQ(terms::anti_clump_r(0.2, 0.0), 0.0);
  // Both pressures positive: 0.01 (P_i/rho_i^2 + P_j/rho_j^2); else R_i + R_j.
  EXPECT_DOUBLE_EQ(terms::anti_clump_coefficient(0.1, 0.2, 0.5, 0.7), 0.012);
  EXPECT_DOUBLE_EQ(terms::anti_clump_coefficient(0.1, 0.2, -0.5, 0.7), 0.3);
  EXPECT_DOUBLE_EQ(terms::anti_clump_coefficient(0.0, 0.2, 0.0, -0.7), 0.2);
  // f^n for the default and other exponents.
  EXPECT_EQ(terms::anti_clump_power(0.5, 0), 1.0);
  EXPECT_EQ(terms::anti_clump_power(0.5, 1), 0.5);
  EXPECT_EQ(terms::anti_clump_power(0.5, 3), 0.125);
  EXPECT_EQ(terms::anti_clump_power(0.5, 4), 0.0625);
  EXPECT_DOUBLE_EQ(terms::anti_clump_power(0.9, 6), 0.531441);
  EXPECT_DOUBLE_EQ(terms::anti_clump(0.1, 0.2, -0.5, 0.7, 0.5, 3), 0.3 * 0.125);
}

// ------------------------------------------- the rate loop, pair by pair

// One owned particle (no ghosts, so every particle is owned).
template <int D>
void add(SphParticles<D>& ps, Kind kind, const Vec<D>& x, const Vec<D>& v, double rho, double p,
         const Vec<D>& vwall) {
  const std::int64_t gid = static_cast<std::int64_t>(ps.size());
  const double mass = kind == Kind::Fluid ? 1.0e-3 * (1 + 0.01 * static_cast<double>(gid)) : 1e-3;
  ps.push_owned(gid, kind, -1, mass, x, v, rho);
  ps.p.back() = p;
  ps.vwall.back() = vwall;
}

SphParams params(int clump_n) {
  SphParams sp;
  sp.spacing = 1e-3;
  sp.h = 1.2e-3;
  sp.rho0 = 1000;
  sp.c0 = 10;
  sp.mu = 0.05;
  sp.mu_scale = 1.05;  // off 1 so that a misplaced lattice factor shows
  sp.grad_scale = 1.03;
  sp.alpha = 0.1;
  sp.delta = 0.1;
  sp.anti_clump = true;
  sp.anti_clump_eps = 0.2;
  sp.anti_clump_n = clump_n;
  sp.eta2 = 0.01 * sp.h * sp.h;
  sp.body_force = {0.5, -9.81, 0.25};
  return sp;
}

struct Expected {
  std::vector<std::vector<double>> a;
  std::vector<double> drho, scale;  // scale: the sum of the terms' magnitudes
};

// The equations, summed over every other particle within the support 2h,
// in whatever order: continuity (paper Eq. 3) + delta-SPH between resin
// particles; momentum (paper Eq. 5) -m_j (P_i/rho_i^2 + P_j/rho_j^2 + Pi_ij
// + R_ij f_ij^n) grad_i W_ij + Morris viscosity + body force. The lattice
// corrections scale grad W by grad_scale and the viscous Laplacian by
// mu_scale. A wall particle is seen with its own velocity in continuity and
// its no-slip velocity (vwall) in the viscous terms (docs/physics.md).
template <int D>
Expected by_hand(const SphParams& sp, const SphParticles<D>& ps) {
  const WendlandC2<D> k(sp.h);
  Expected e;
  const std::size_t n = ps.size();
  e.a.assign(n, std::vector<double>(D, 0.0));
  e.drho.assign(n, 0.0);
  e.scale.assign(n, 0.0);
  const auto por2 = [&](std::size_t a) { return ps.p[a] / (ps.rho[a] * ps.rho[a]); };
  const auto clump_r = [&](std::size_t a) {
    return ps.p[a] < 0 ? sp.anti_clump_eps * std::abs(ps.p[a]) / (ps.rho[a] * ps.rho[a]) : 0.0;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    for (int d = 0; d < D; ++d) e.a[i][d] = sp.body_force[d];
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Vec<D> xij = ps.x[i] - ps.x[j];
      const double r = xij.norm(), r2 = r * r;
      if (r >= 2 * sp.h) continue;
      const Vec<D> grad = sp.grad_scale * k.f(r) * xij;
      const Vec<D> vij = ps.v[i] - ps.v[j];
      const Vec<D> wij = ps.v[i] - ps.vwall[j];
      const double rho_i = ps.rho[i], rho_j = ps.rho[j], m_j = ps.mass[j];
      double drho = m_j * vij.dot(grad);
      if (sp.delta > 0 && ps.kind[j] == Kind::Fluid) {
        const Vec<D> psi = 2 * (rho_j - rho_i) * (ps.x[j] - ps.x[i]) / r2;
        drho += sp.delta * sp.h * sp.c0 * (m_j / rho_j) * psi.dot(grad);
      }
      e.drho[i] += drho;
      e.scale[i] += std::abs(drho);
      double pi_ij = 0;
      if (sp.alpha > 0 && wij.dot(xij) < 0) {
        const double mu_ij = wij.dot(xij) / (r2 + sp.eta2);
        pi_ij = -sp.alpha * sp.c0 * sp.h * mu_ij / (0.5 * (rho_i + rho_j));
      }
      double clump = 0;
      if (sp.anti_clump) {
        const double r_ij =
            ps.p[i] > 0 && ps.p[j] > 0 ? 0.01 * (por2(i) + por2(j)) : clump_r(i) + clump_r(j);
        clump = r_ij * std::pow(k.w(r) / k.w(sp.spacing), sp.anti_clump_n);
      }
      const Vec<D> pressure = -m_j * (por2(i) + por2(j) + pi_ij + clump) * grad;
      const Vec<D> raw_grad = k.f(r) * xij;
      const Vec<D> viscous = m_j * (sp.mu + sp.mu) / (rho_i * rho_j) * sp.mu_scale *
                             xij.dot(raw_grad) / (r2 + sp.eta2) * wij;
      for (int d = 0; d < D; ++d) e.a[i][d] += pressure[d] + viscous[d];
      e.scale[i] += pressure.norm() + viscous.norm();
    }
  }
  return e;
}

// compute_fluid_rates on `ps` with lists of support 2h and a skin of 0.5 h
// (a pair in the skin contributes exactly nothing).
template <int D>
void rates(const SphParams& sp, SphParticles<D>& ps) {
  NeighborList<D> nl(2 * sp.h, 0.5 * sp.h);
  nl.build(ps);
  compute_fluid_rates<D>(sp, nl, ps);
}

template <int D>
void expect_rates_match(const SphParams& sp, SphParticles<D>& ps) {
  rates<D>(sp, ps);
  const Expected e = by_hand<D>(sp, ps);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double tol = 1e-13 * e.scale[i];
    EXPECT_NEAR(ps.drho[i], e.drho[i], tol) << "particle " << i;
    for (int d = 0; d < D; ++d) EXPECT_NEAR(ps.a[i][d], e.a[i][d], tol) << "particle " << i;
  }
}

// Two resin particles (0 at positive pressure, 1 at negative) and a wall
// particle within each other's support, and resin particle 3 in the skin of
// particle 0 only (2.6 mm away, support 2.4 mm). The pairs cover both
// branches of the anti-clump coefficient (0-wall both positive, 0-1 not)
// and of the artificial viscosity (1 leaves the wall's no-slip velocity).
SphParticles<2> configuration_2d() {
  SphParticles<2> ps;
  add<2>(ps, Kind::Fluid, {0, 0}, {0.1, 0}, 1010, 500, {0.1, 0});
  add<2>(ps, Kind::Fluid, {1.0e-3, 0.3e-3}, {-0.05, 0.02}, 995, -300, {-0.05, 0.02});
  add<2>(ps, Kind::Wall, {0.2e-3, -1.0e-3}, {0, 0}, 1000, 200, {-0.1, 0});
  add<2>(ps, Kind::Fluid, {-2.6e-3, 0}, {0.3, -0.2}, 1002, 100, {0.3, -0.2});
  return ps;
}

TEST(FluidRates, ConfigurationIsWhatTheCommentsSay) {
  const SphParticles<2> ps = configuration_2d();
  const double support = 2.4e-3, cutoff = 3.0e-3;
  EXPECT_LT((ps.x[0] - ps.x[1]).norm(), support);
  EXPECT_LT((ps.x[0] - ps.x[2]).norm(), support);
  EXPECT_LT((ps.x[1] - ps.x[2]).norm(), support);
  EXPECT_GT((ps.x[0] - ps.x[3]).norm(), support);
  EXPECT_LT((ps.x[0] - ps.x[3]).norm(), cutoff) << "in the skin";
  // 1 recedes from the wall's no-slip velocity; 0 approaches 1 and the wall.
  EXPECT_GT((ps.v[1] - ps.vwall[2]).dot(ps.x[1] - ps.x[2]), 0);
  EXPECT_LT((ps.v[0] - ps.vwall[1]).dot(ps.x[0] - ps.x[1]), 0);
  EXPECT_LT((ps.v[0] - ps.vwall[2]).dot(ps.x[0] - ps.x[2]), 0);
}

TEST(FluidRates, EveryTermTwoDimensions) {
  SphParticles<2> ps = configuration_2d();
  expect_rates_match<2>(params(4), ps);
  // Particle 3 has no neighbor within the support: body force only.
  EXPECT_EQ(ps.a[3][0], 0.5);
  EXPECT_EQ(ps.a[3][1], -9.81);
  EXPECT_EQ(ps.drho[3], 0.0);
}

// anti_clump_exponent != 4 runs the general path of the loop.
TEST(FluidRates, GeneralAntiClumpExponent) {
  for (int n : {1, 3, 6}) {
    SCOPED_TRACE(n);
    SphParticles<2> ps = configuration_2d();
    expect_rates_match<2>(params(n), ps);
  }
  // The exponent matters here: the anti-clump term is not negligible.
  SphParticles<2> four = configuration_2d(), three = configuration_2d();
  rates<2>(params(4), four);
  rates<2>(params(3), three);
  EXPECT_GT(std::abs(four.a[0][0] - three.a[0][0]), 1e-9 * std::abs(four.a[0][0]));
  EXPECT_GT(std::abs(four.a[1][1] - three.a[1][1]), 1e-9 * std::abs(four.a[1][1]));
}

// Each switch off in turn, then only pressure, continuity and gravity.
// Each term weighs here: switching it off changes particle 0's or 1's rates
// by far more than the tolerance of the comparisons above.
TEST(FluidRates, TermsSwitchedOff) {
  SphParticles<2> all = configuration_2d();
  rates<2>(params(4), all);
  const Expected e = by_hand<2>(params(4), all);
  const auto check = [&](const char* what, auto edit) {
    SCOPED_TRACE(what);
    SphParams sp = params(4);
    edit(sp);
    SphParticles<2> ps = configuration_2d();
    expect_rates_match<2>(sp, ps);
    double change = 0;
    for (std::size_t i = 0; i < 2; ++i) {
      const double rel = 1.0 / e.scale[i];
      change = std::max(change, std::abs(ps.drho[i] - all.drho[i]) * rel);
      for (int d = 0; d < 2; ++d)
        change = std::max(change, std::abs(ps.a[i][d] - all.a[i][d]) * rel);
    }
    EXPECT_GT(change, 1e-6) << "the term is negligible in this configuration";
  };
  check("no viscosity", [](SphParams& sp) { sp.mu = 0; });
  check("no artificial viscosity", [](SphParams& sp) { sp.alpha = 0; });
  check("no delta-SPH", [](SphParams& sp) { sp.delta = 0; });
  check("no anti-clump", [](SphParams& sp) { sp.anti_clump = false; });
  check("no lattice correction", [](SphParams& sp) {
    sp.grad_scale = 1;
    sp.mu_scale = 1;
  });
  check("pressure only", [](SphParams& sp) {
    sp.mu = 0;
    sp.alpha = 0;
    sp.delta = 0;
    sp.anti_clump = false;
  });
}

// Between two resin particles every term is antisymmetric: m_i a_i + m_j a_j
// is the body force's share alone (momentum is conserved).
TEST(FluidRates, PairForcesCancel) {
  SphParticles<2> ps;
  add<2>(ps, Kind::Fluid, {0, 0}, {0.1, 0}, 1010, 500, {0.1, 0});
  add<2>(ps, Kind::Fluid, {1.0e-3, 0.3e-3}, {-0.05, 0.02}, 995, -300, {-0.05, 0.02});
  const SphParams sp = params(3);
  rates<2>(sp, ps);
  for (int d = 0; d < 2; ++d) {
    const double net =
        ps.mass[0] * (ps.a[0][d] - sp.body_force[d]) + ps.mass[1] * (ps.a[1][d] - sp.body_force[d]);
    EXPECT_NEAR(net, 0.0, 1e-15 * ps.mass[0] * std::abs(ps.a[0][d] - sp.body_force[d]));
  }
  EXPECT_NE(ps.a[0][0], sp.body_force[0]) << "the pair interacts";
}

// 3D: four resin particles and two wall particles off any lattice.
TEST(FluidRates, EveryTermThreeDimensions) {
  SphParticles<3> ps;
  add<3>(ps, Kind::Fluid, {0, 0, 0}, {0.1, 0, -0.02}, 1010, 500, {0.1, 0, -0.02});
  add<3>(ps, Kind::Fluid, {1.0e-3, 0.3e-3, 0.2e-3}, {-0.05, 0.02, 0}, 995, -300, {-0.05, 0.02, 0});
  add<3>(ps, Kind::Fluid, {0.4e-3, 1.1e-3, -0.5e-3}, {0, 0.04, 0.01}, 1004, -50, {0, 0.04, 0.01});
  add<3>(ps, Kind::Wall, {0.2e-3, -1.0e-3, 0}, {0, 0, 0}, 1000, 200, {-0.1, 0, 0.03});
  add<3>(ps, Kind::Wall, {1.2e-3, -0.9e-3, 0.3e-3}, {0, 0, 0}, 1001, -20, {0.02, 0, 0});
  add<3>(ps, Kind::Fluid, {-1.5e-3, -1.5e-3, 1.5e-3}, {0.3, -0.2, 0}, 1002, 100, {0.3, -0.2, 0});
  for (int n : {4, 3}) {
    SCOPED_TRACE(n);
    SphParticles<3> copy = ps;
    expect_rates_match<3>(params(n), copy);
  }
}

}  // namespace
}  // namespace sphdem
