// DEM core against hand computations: the pair kernels of
// src/dem/terms/, the owner rule for pair state, conservation by the loops,
// and the fiber generator.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "../src/dem/dem_kernels.hpp"
#include "../src/dem/terms/contact_linear.hpp"
#include "../src/dem/terms/parallel_bond.hpp"
#include "../src/dem/terms/restitution_damping.hpp"
#include "sphdem/core/clamped_cast.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/dem/cell_list.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/dem/dem_fibers.hpp"

namespace sphdem {
namespace {

// The pair-list build's gid lookup (dem_kernels.hpp): the table of a dense
// gid range and the binary search of a sparse one give what a scan gives,
// the copy nearest to x among periodic images (the first in local order on
// a tie) and -1 for an absent gid.
TEST(DemPairs, GidIndexAgreesWithAScan) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const bool sparse : {false, true}) {
    DemParticles<3> ps;
    const std::size_t n = 300;
    ps.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      // gids 1000..1199, some twice (images); sparse: spread past 4 n + 64
      const auto g = static_cast<std::int64_t>(1000 + (i * 7) % 200);
      ps.gid[i] = sparse ? g * 1000003 : g;
      ps.x[i] = Vec<3>(u(rng), u(rng), u(rng));
    }
    ps.x[5] = ps.x[205];  // a tie between two images of one gid
    ASSERT_EQ(ps.gid[5], ps.gid[205]);
    const GidIndex<3> index(ps);
    for (std::int64_t g0 = 990; g0 < 1210; ++g0) {
      const std::int64_t g = sparse ? g0 * 1000003 : g0;
      const Vec<3> x(u(rng), u(rng), u(rng));
      std::int32_t first = -1, nearest = -1;
      double best = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (ps.gid[i] != g) continue;
        if (first < 0) first = static_cast<std::int32_t>(i);
        const double d2 = (ps.x[i] - x).squaredNorm();
        if (nearest < 0 || d2 < best) {
          nearest = static_cast<std::int32_t>(i);
          best = d2;
        }
      }
      EXPECT_EQ(index.find(g), first) << g;
      EXPECT_EQ(index.find_nearest(g, x, ps), nearest) << g;
    }
    EXPECT_EQ(index.find_nearest(ps.gid[5], ps.x[5], ps), 5);  // the tie: local order
  }
}

// The cell list's half stencil (for_each_pair) finds every pair that
// for_each_near finds from either end, each once, in 2D and 3D, with
// particles outside the box's cells clamped into the edge cells.
template <int D>
void check_half_stencil() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec<D>> x(400);
  for (auto& p : x)
    for (int d = 0; d < D; ++d) p[d] = u(rng);
  std::vector<std::int32_t> start, items;
  for (const double cell : {0.15, 0.4, 0.0}) {
    // The last round: cells of 0.01 asked, one particle far away, so the
    // cell budget (16 per particle) doubles the cells until they fit.
    if (cell == 0.0) x[0] = Vec<D>::Constant(4.5);
    dem_detail::CellList<D> cells;
    cells.build(x, x.size(), cell == 0.0 ? 0.01 : cell, start, items);
    std::set<std::pair<int, int>> near, half;
    for (std::size_t i = 0; i < x.size(); ++i)
      cells.for_each_near(x[i], [&](std::int32_t j) {
        if (static_cast<std::size_t>(j) != i)
          near.insert(
              {std::min<int>(static_cast<int>(i), j), std::max<int>(static_cast<int>(i), j)});
      });
    std::size_t calls = 0;
    cells.for_each_pair([&](std::int32_t a, std::int32_t b) {
      ++calls;
      EXPECT_NE(a, b);
      half.insert({std::min(a, b), std::max(a, b)});
    });
    EXPECT_EQ(calls, half.size());  // each pair once
    EXPECT_EQ(half, near);
    EXPECT_GT(near.size(), x.size());
  }
}

TEST(DemPairs, HalfStencilFindsEveryPairOnce2D) {
  check_half_stencil<2>();
}
TEST(DemPairs, HalfStencilFindsEveryPairOnce3D) {
  check_half_stencil<3>();
}

TEST(DemRotation, TwoDIsTheZComponentOfThreeD) {
  const Vec<3> r(0.3, -1.2, 0), f(2.0, 0.7, 0);
  const Vec<3> w3(0, 0, 1.7);
  Rot<2> w2;
  w2[0] = 1.7;
  const Vec<2> v2 = cross<2>(w2, Vec<2>(r[0], r[1]));
  const Vec<3> v3 = cross<3>(w3, r);
  EXPECT_DOUBLE_EQ(v2[0], v3[0]);
  EXPECT_DOUBLE_EQ(v2[1], v3[1]);
  EXPECT_DOUBLE_EQ(moment<2>(Vec<2>(r[0], r[1]), Vec<2>(f[0], f[1]))[0], moment<3>(r, f)[2]);
}

// docs/validation.md section 2 lists zeta(e): 0.5 -> 0.215454, 0.8 -> 0.070850 (6 digits).
TEST(DemContact, DampingFromRestitution) {
  const double m = 2.0, k = 50.0;
  EXPECT_NEAR(terms::restitution_damping(0.5, m, k) / (2 * std::sqrt(m * k)), 0.215454, 1e-6);
  EXPECT_NEAR(terms::restitution_damping(0.8, m, k) / (2 * std::sqrt(m * k)), 0.070850, 1e-6);
  EXPECT_EQ(terms::restitution_damping(1.0, m, k), 0.0);
}

TEST(DemContact, HandValuesAndCoulombCap) {
  const terms::LinearContact c{100.0, 50.0, 2.0, 0.0, 0.5};
  const Vec<2> n(1, 0);
  Vec<2> xi = Vec<2>::Zero();
  // Approaching at 0.5 with a tangential slide of 0.1: F_n = 100*0.01 + 2*0.5 = 2,
  // xi = 0.1*0.01, F_t = -50 xi = -0.05 (under the cap 1).
  Vec<2> f = terms::linear_contact<2>(c, n, 0.01, Vec<2>(-0.5, 0.1), 0.01, xi);
  EXPECT_NEAR(f[0], 2.0, 1e-14);
  EXPECT_NEAR(f[1], -0.05, 1e-14);
  EXPECT_NEAR(xi[1], 1e-3, 1e-16);
  // A fast slide: capped at mu F_n = 1, spring reset to F_t / -k_t.
  f = terms::linear_contact<2>(c, n, 0.01, Vec<2>(-0.5, 10.0), 0.01, xi);
  EXPECT_NEAR(f[1], -1.0, 1e-14);
  EXPECT_NEAR(xi[1], 1.0 / 50.0, 1e-15);
  // Pulling apart (F_n < 0): no friction.
  f = terms::linear_contact<2>(c, n, 0.001, Vec<2>(1.0, 10.0), 0.01, xi);
  EXPECT_NEAR(f[0], 0.1 - 2.0, 1e-14);
  EXPECT_EQ(f[1], 0.0);
}

TEST(DemContact, HistoryTurnsWithTheContactPlane) {
  Vec<3> xi(0.0, 2.0, 0.0);
  const Vec<3> n = Vec<3>(0.1, 1.0, 0.3).normalized();
  terms::rotate_into_plane<3>(xi, n);
  EXPECT_NEAR(xi.dot(n), 0.0, 1e-14);  // round-off of the projection, magnified by the rescale
  EXPECT_NEAR(xi.norm(), 2.0, 1e-15);
}

TEST(DemBond, Sections) {
  const double r = 0.3;
  const auto s2 = terms::bond_section<2>(r, 1.0);
  EXPECT_DOUBLE_EQ(s2.area, 0.6);
  EXPECT_DOUBLE_EQ(s2.inertia, std::pow(2 * r, 3) / 12);  // rectangle 2r x 1
  const auto s3 = terms::bond_section<3>(r, 1.0);
  EXPECT_DOUBLE_EQ(s3.area, std::numbers::pi * r * r);
  EXPECT_DOUBLE_EQ(s3.inertia, std::numbers::pi * std::pow(r, 4) / 4);
  EXPECT_DOUBLE_EQ(s3.polar, 2 * s3.inertia);
}

// The motion of a pair whose normal n stays put: relative contact-point
// displacement du and relative rotation dtheta over the step.
template <int D>
terms::BondMotion<D> still_motion(const Vec<D>& n, const Vec<D>& du, const Rot<D>& dtheta) {
  terms::BondMotion<D> m;
  m.n1 = m.nm = n;
  m.dlen = du.dot(n);
  m.du = du;
  m.dtheta = dtheta;
  return m;
}

// One increment each of stretch, shear, bending and twisting against the
// incremental law of docs/validation.md section 6, and breakage at the strengths.
TEST(DemBond, IncrementsStressesAndBreakage) {
  const double rbar = 0.5, dt = 0.01;
  terms::BondLaw law{terms::bond_section<3>(rbar, 1.0), 1e3, 4e3, 1e9, 1e9};
  const Vec<3> n(1, 0, 0);
  DemBond<3> b;
  b.partner = 1;
  // Stretch at 0.1 and shear at 0.2 (y): dF_n = -kn A 1e-3, dF_s = -ks A 2e-3.
  ASSERT_TRUE(terms::parallel_bond_update<3>(
      law, rbar, still_motion<3>(n, (Vec<3>(0.1, 0.2, 0)) * dt, Rot<3>::Zero()), b));
  const double A = law.s.area;
  EXPECT_NEAR(b.fn, -1e3 * A * 1e-3, 1e-15);
  EXPECT_NEAR(b.fs[1], -4e3 * A * 2e-3, 1e-15);
  EXPECT_NEAR(b.sigma, 1e3 * 1e-3, 1e-12);  // -F_n/A
  EXPECT_NEAR(b.tau, 4e3 * 2e-3, 1e-12);    // |F_s|/A
  // Bend about z by 0.01 and twist about n by 0.02.
  DemBond<3> m;
  ASSERT_TRUE(terms::parallel_bond_update<3>(
      law, rbar, still_motion<3>(n, (Vec<3>::Zero()) * dt, Rot<3>(0.02, 0, 0.01)), m));
  EXPECT_NEAR(m.mb[2], -1e3 * law.s.inertia * 0.01, 1e-15);
  EXPECT_NEAR(m.mt, -4e3 * law.s.polar * 0.02, 1e-15);
  EXPECT_NEAR(m.sigma, 1e3 * 0.01 * rbar, 1e-12);  // |M_b| Rbar / I
  EXPECT_NEAR(m.tau, 4e3 * 0.02 * rbar, 1e-12);    // |M_t| Rbar / J
  // Compression never breaks (P&C's signed criterion); tension does.
  law.sigma_c = 5.0;
  DemBond<3> c;
  EXPECT_TRUE(terms::parallel_bond_update<3>(
      law, rbar, still_motion<3>(n, (Vec<3>(-10, 0, 0)) * dt, Rot<3>::Zero()), c));
  DemBond<3> t;
  EXPECT_TRUE(terms::parallel_bond_update<3>(
      law, rbar, still_motion<3>(n, (Vec<3>(0.4, 0, 0)) * dt, Rot<3>::Zero()), t));  // sigma = 4
  EXPECT_FALSE(terms::parallel_bond_update<3>(
      law, rbar, still_motion<3>(n, (Vec<3>(0.2, 0, 0)) * dt, Rot<3>::Zero()), t));  // sigma = 6
  EXPECT_TRUE(t.broken);
  EXPECT_EQ(t.fn, 0.0);
  EXPECT_NEAR(t.sigma, 6.0, 1e-12);  // the stress that broke it is kept
}

// A loaded bond carried by a rigid motion of its pair over one step (a
// turn by 0.3 rad, then a spin about the bond by 0.3 rad) keeps F_n and
// M_t, and its F_s and M_b turn with the pair: exactly for the frame, up
// to the O(angle^3) of the mid-step increments (a chord against its arc:
// ks A L (theta - 2 sin(theta/2))) and of the Cayley spin (|v| phi^3/48).
TEST(DemBond, RigidMotionTurnsTheLoads) {
  const double rbar = 0.5, L = 1.0, theta = 0.3;
  terms::BondLaw law{terms::bond_section<3>(rbar, 1.0), 1e3, 4e3, 1e9, 1e9};
  const Vec<3> n0 = Vec<3>(1, 2, 2) / 3.0;
  const Vec<3> axis_perp = n0.cross(Vec<3>(0, 0, 1)).normalized();
  auto loaded = [&] {
    DemBond<3> b;
    b.partner = 1;
    b.fn = 0.7;
    b.fs = 0.3 * n0.cross(Vec<3>(1, 0, 0)).normalized();
    b.mb = 0.2 * axis_perp;
    b.mt = -0.1;
    return b;
  };
  // Turn about an axis normal to the bond (both particles spin with it).
  {
    DemBond<3> b = loaded();
    const DemBond<3> b0 = b;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, axis_perp).toRotationMatrix();
    const Vec<3> d = R * (L * n0);
    const Rot<3> w_dt = theta * axis_perp;
    const auto m = terms::bond_motion<3>(d, L, d - L * n0, w_dt, w_dt, 0.5 * L, 0.5 * L);
    EXPECT_NEAR(m.dlen, 0.0, 1e-15);
    ASSERT_TRUE(terms::parallel_bond_update<3>(law, rbar, m, b));
    EXPECT_NEAR(b.fn, b0.fn, 1e-15);
    EXPECT_NEAR(b.mt, b0.mt, 1e-15);
    const double chord = law.ks * law.s.area * L * (theta - 2 * std::sin(theta / 2));
    EXPECT_LT((b.fs - R * b0.fs).norm(), 1.01 * chord);
    EXPECT_GT((b.fs - R * b0.fs).norm(), 0.99 * chord);  // the bound is the error, not slack
    EXPECT_LT((b.mb - R * b0.mb).norm(), 1e-14);
  }
  // Spin about the bond itself: the normal stays, F_s and M_b spin.
  {
    DemBond<3> b = loaded();
    const DemBond<3> b0 = b;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, n0).toRotationMatrix();
    const Rot<3> w_dt = theta * n0;
    const auto m = terms::bond_motion<3>(L * n0, L, Vec<3>::Zero(), w_dt, w_dt, 0.5 * L, 0.5 * L);
    ASSERT_TRUE(terms::parallel_bond_update<3>(law, rbar, m, b));
    EXPECT_NEAR(b.fn, b0.fn, 1e-15);
    EXPECT_NEAR(b.mt, b0.mt, 1e-15);
    EXPECT_NEAR(b.fs.norm(), b0.fs.norm(), 1e-14);  // a few ulps over the four turns
    EXPECT_NEAR(b.mb.norm(), b0.mb.norm(), 1e-14);
    const double cayley = std::pow(theta, 3) / 48;
    EXPECT_LT((b.fs - R * b0.fs).norm(), 1.05 * cayley * b0.fs.norm());
    EXPECT_LT((b.mb - R * b0.mb).norm(), 1.05 * cayley * b0.mb.norm());
  }
}

// 2D: the bending moment is the scalar -kn I dtheta; no twisting.
TEST(DemBond, TwoDBending) {
  const double rbar = 0.5;
  const terms::BondLaw law{terms::bond_section<2>(rbar, 1.0), 1e3, 4e3, 1e9, 1e9};
  DemBond<2> b;
  Rot<2> dth;
  dth[0] = 0.01;
  terms::parallel_bond_update<2>(law, rbar,
                                 still_motion<2>(Vec<2>(0, 1), (Vec<2>::Zero()) * 1e-3, dth), b);
  EXPECT_NEAR(b.mb[0], -1e3 * law.s.inertia * 0.01, 1e-15);
  EXPECT_NEAR(b.sigma, 1e3 * 0.01 * rbar, 1e-12);
}

// A random cluster of bonded and touching particles, no walls or gravity:
// the loops apply every pair force and couple to both sides, so linear and
// angular momentum (about the origin, with spin) are conserved to round-off.
template <int D>
void check_conservation() {
  DemSystem<D> sys;
  sys.params.kn = 1e4;
  sys.params.youngs_modulus = 1e5;
  sys.params.restitution = 0.7;
  sys.params.friction = 0.4;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 30; ++i) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = 1.5 * u(rng);
    sys.add_particle(x, 0.2 + 0.05 * u(rng), 1000);
  }
  for (int i = 0; i + 1 < 30; i += 3) sys.add_bond(i, i + 1);
  auto& ps = sys.particles;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (int d = 0; d < D; ++d) ps.v[i][d] = u(rng);
    for (int d = 0; d < ps.omega[i].size(); ++d) ps.omega[i][d] = 5 * u(rng);
  }
  auto momenta = [&] {
    Vec<D> p = Vec<D>::Zero();
    Rot<D> l = Rot<D>::Zero();
    for (std::size_t i = 0; i < ps.size(); ++i) {
      p += ps.mass[i] * ps.v[i];
      l += moment<D>(ps.x[i], ps.mass[i] * ps.v[i]) + ps.inertia[i] * ps.omega[i];
    }
    return std::pair{p, l};
  };
  const auto [p0, l0] = momenta();
  const double dt = sys.stable_dt();
  int contacts = 0;
  for (int s = 0; s < 2000; ++s) {
    sys.step(dt);
    for (std::size_t i = 0; i < ps.size(); ++i)
      for (const auto& c : ps.contacts[i]) contacts += c.partner >= 0;
  }
  EXPECT_GT(contacts, 100);  // the test exercised contacts
  const auto [p1, l1] = momenta();
  double scale = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) scale += ps.mass[i];
  EXPECT_LT((p1 - p0).norm() / scale, 1e-13);
  EXPECT_LT((l1 - l0).norm() / scale, 1e-12);
}
TEST(DemLoops, MomentumConserved2D) {
  check_conservation<2>();
}
TEST(DemLoops, MomentumConserved3D) {
  check_conservation<3>();
}

// Owner rule: the pair's history sits on the smaller gid, keyed by the
// larger; it survives while in contact and is dropped at separation.
TEST(DemLoops, ContactHistoryOnOwnerDroppedAtSeparation) {
  DemSystem<2> sys;
  sys.params.kn = 1e3;
  sys.params.friction = 0.5;
  sys.add_particle(Vec<2>(0.19, 0), 0.1, 1000);  // gid 0
  sys.add_particle(Vec<2>(0, 0), 0.1, 1000);     // gid 1
  auto& ps = sys.particles;
  ps.v[1] = Vec<2>(0, 0.01);
  const double dt = 1e-4;
  sys.step(dt);
  EXPECT_EQ(ps.contacts[0][0].partner, 1);
  EXPECT_EQ(ps.contacts[1][0].partner, DemContact<2>::kNone);
  EXPECT_GT(ps.contacts[0][0].xi.norm(), 0.0);
  const double xi1 = ps.contacts[0][0].xi.norm();
  sys.step(dt);
  EXPECT_GT(ps.contacts[0][0].xi.norm(), xi1);  // accumulated across steps
  ps.x[1] = Vec<2>(-0.5, 0);
  sys.step(dt);
  EXPECT_EQ(ps.contacts[0][0].partner, DemContact<2>::kNone);
}

// A bonded pair gets no contact force: set overlapping, the unstressed bond
// leaves both at rest. Once broken, the contact pushes them apart.
TEST(DemLoops, BondedPairsGetNoContactForce) {
  DemSystem<2> sys;
  sys.params.kn = 1e3;
  sys.params.youngs_modulus = 1e4;
  sys.params.tensile_strength = 1.0;
  sys.add_particle(Vec<2>(0, 0), 0.1, 1000);
  sys.add_particle(Vec<2>(0.15, 0), 0.1, 1000);
  sys.add_bond(1, 0);  // stored on gid 0 whatever the order given
  EXPECT_EQ(sys.particles.bonds[0][0].partner, 1);
  EXPECT_EQ(sys.particles.bonds[1][0].partner, -1);
  for (int s = 0; s < 10; ++s) sys.step(1e-4);
  EXPECT_EQ(sys.particles.v[0].norm(), 0.0);
  EXPECT_EQ(sys.particles.contacts[0][0].partner, DemContact<2>::kNone);
  sys.particles.bonds[0][0].broken = true;
  sys.invalidate_forces();
  sys.step(1e-4);
  EXPECT_LT(sys.particles.v[0][0], 0.0);
  EXPECT_EQ(sys.particles.contacts[0][0].partner, 1);
}

// Walls: the contact point of a segment end, the wall's history key.
TEST(DemLoops, SegmentEndAndPlaneWalls) {
  DemSystem<2> sys;
  sys.params.kn = 1e3;
  sys.walls.push_back(DemWall<2>::segment(Vec<2>(-1, 0), Vec<2>(0, 0)));
  sys.walls.push_back(DemWall<2>::plane(Vec<2>(0, -1), Vec<2>(0, 1)));
  // Beyond the segment's end a, at 45 degrees: pushed along (1, 1)/sqrt 2.
  sys.add_particle(Vec<2>(0.06, 0.06), 0.1, 1000);
  sys.step(1e-5);
  const Vec<2> f = sys.particles.force[0];
  EXPECT_NEAR(f[0], f[1], 1e-12 * f.norm());
  EXPECT_NEAR(f.norm(), 1e3 * (0.1 - std::sqrt(2) * 0.06), 1e-3 * f.norm());
  EXPECT_EQ(sys.particles.wall_contacts[0][0].partner, wall_key(0));
}

// dt = 0.2 sqrt(m/k_n) for a loose disk (rotation: I/(k_t R^2) = 1.75 m/k_n).
TEST(DemStep, StableTimeStepOfALooseDisk) {
  DemSystem<2> sys;
  sys.params.kn = 1e3;
  sys.add_particle(Vec<2>::Zero(), 0.1, 1000);
  EXPECT_DOUBLE_EQ(sys.stable_dt(), 0.2 * std::sqrt(sys.particles.mass[0] / 1e3));
}

// The paper's bath (docs/paper-comparison.md): 30 x 30 mm, fibers of 4 particles of
// d = 0.25 mm. Checked by brute force over all pairs.
template <int D>
void check_placement(const DemSystem<D>& sys, const FiberSpec<D>& s, int fibers) {
  const auto& ps = sys.particles;
  ASSERT_EQ(ps.size(), static_cast<std::size_t>(fibers * s.particles_per_fiber));
  const double r = s.radius;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (int d = 0; d < D; ++d) {
      EXPECT_GE(ps.x[i][d] - r, s.lo[d] - 1e-15);
      EXPECT_LE(ps.x[i][d] + r, s.hi[d] + 1e-15);
    }
    for (std::size_t j = i + 1; j < ps.size(); ++j) {
      const double dist = (ps.x[j] - ps.x[i]).norm();
      if (ps.fiber[i] == ps.fiber[j]) continue;
      ASSERT_GE(dist, 2 * r * (1 - 1e-12)) << i << " " << j;
    }
  }
  // Chains: consecutive particles touch and are bonded on the smaller gid.
  for (std::size_t i = 0; i + 1 < ps.size(); ++i) {
    if (ps.fiber[i] != ps.fiber[i + 1]) {
      EXPECT_EQ(ps.bonds[i][0].partner, -1);
      continue;
    }
    EXPECT_EQ(ps.bonds[i][0].partner, ps.gid[i + 1]);
    EXPECT_NEAR((ps.x[i + 1] - ps.x[i]).norm(), 2 * r, 1e-15);
  }
}

FiberSpec<2> bath(int count, std::uint64_t seed) {
  FiberSpec<2> s;
  s.count = count;
  s.radius = 0.125e-3;
  s.lo = Vec<2>(-15e-3, 30e-3);
  s.hi = Vec<2>(15e-3, 60e-3);
  s.angle = 0.0;  // perpendicular to the injection (-y)
  s.seed = seed;
  return s;
}

TEST(DemFibers, PaperBath175And375) {
  for (const auto& [n, frac] : {std::pair{175, 0.0382}, std::pair{375, 0.0818}}) {
    DemSystem<2> sys;
    const FiberSpec<2> s = bath(n, 3);
    const FiberPlacement p = place_fibers(s, sys);
    EXPECT_EQ(p.fibers, n);
    EXPECT_NEAR(p.fraction, frac, 5e-5);  // 175*4*pi*0.125^2/900 = 3.818 %
    check_placement(sys, s, n);
  }
}

TEST(DemFibers, FractionGivesTheSmallestCountReachingIt) {
  DemSystem<2> sys;
  FiberSpec<2> s = bath(0, 3);
  s.fraction = 0.038;
  s.angle.reset();                              // random orientation
  EXPECT_EQ(place_fibers(s, sys).fibers, 175);  // 0.038*900/(4 pi 0.125^2) = 174.2
  check_placement(sys, s, 175);
}

TEST(DemFibers, DeterministicForASeed) {
  DemSystem<2> a, b, c;
  place_fibers(bath(175, 11), a);
  place_fibers(bath(175, 11), b);
  place_fibers(bath(175, 12), c);
  EXPECT_EQ(a.particles.x, b.particles.x);
  EXPECT_NE(a.particles.x, c.particles.x);
}

TEST(DemFibers, ThreeDRandomOrientation) {
  DemSystem<3> sys;
  FiberSpec<3> s;
  s.count = 300;
  s.lo = Vec<3>(0, 0, 0);
  s.hi = Vec<3>(5e-3, 5e-3, 5e-3);
  s.seed = 5;
  place_fibers(s, sys);
  check_placement(sys, s, 300);
}

TEST(DemFibers, ImpossibleFractionIsAClearError) {
  DemSystem<2> sys;
  FiberSpec<2> s = bath(0, 3);
  s.fraction = 0.6;  // above what random sequential placement of rods can reach
  s.attempts_per_fiber = 2000;
  try {
    place_fibers(s, sys);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("could not place fiber"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sys.particles.size(), 0u);  // left unchanged
  s.fraction = 0;
  s.count = 1;
  s.hi = Vec<2>(-14.5e-3, 60e-3);  // 0.5 mm wide: a 1 mm fiber along x cannot fit
  EXPECT_THROW(place_fibers(s, sys), std::runtime_error);
}

// The overlap test's bucket of a far, infinite or NaN position: clamped as
// a double before the cast (main cast it as it was: INT64_MIN on x86).
TEST(DemFibers, BucketOfARunawayPositionIsClamped) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(fiber_bucket_coord(2.5e-3, 0.0, 1e-3), 2);
  EXPECT_EQ(fiber_bucket_coord(-0.5e-3, 0.0, 1e-3), -1);
  EXPECT_EQ(fiber_bucket_coord(1e300, 0.0, 1e-3), kMaxBucketCoord);
  EXPECT_EQ(fiber_bucket_coord(1e19, 0.0, 1e-3), kMaxBucketCoord);
  EXPECT_EQ(fiber_bucket_coord(inf, 0.0, 1e-3), kMaxBucketCoord);
  EXPECT_EQ(fiber_bucket_coord(-1e300, 0.0, 1e-3), -kMaxBucketCoord);
  EXPECT_EQ(fiber_bucket_coord(-inf, 0.0, 1e-3), -kMaxBucketCoord);
  EXPECT_EQ(fiber_bucket_coord(std::numeric_limits<double>::quiet_NaN(), 0.0, 1e-3),
            -kMaxBucketCoord);
  // Runaway particles already in the system: the same fibers around them.
  DemSystem<2> clean, runaway;
  for (const double far : {1e300, -1e300, inf, std::numeric_limits<double>::quiet_NaN()})
    runaway.add_particle(Vec<2>(far, far), 0.125e-3, 2540, 0);
  const std::size_t before = runaway.particles.size();
  place_fibers(bath(175, 3), clean);
  place_fibers(bath(175, 3), runaway);
  ASSERT_EQ(runaway.particles.size(), before + clean.particles.size());
  for (std::size_t i = 0; i < clean.particles.size(); ++i)
    EXPECT_EQ(runaway.particles.x[before + i], clean.particles.x[i]) << i;
}

// A region of absurd extent is a clear error, not an out-of-range cast:
// by fraction, a fiber count past int (main: cast to INT_MIN), by count,
// tiles past 2^31 (main: cast to INT64_MIN, then one tile, no error).
TEST(DemFibers, AnAbsurdRegionIsAClearError) {
  const auto message = [](const FiberSpec<2>& s) -> std::string {
    DemSystem<2> sys;
    try {
      place_fibers(s, sys);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  FiberSpec<2> s = bath(0, 3);
  s.fraction = 0.01;
  s.hi = Vec<2>(1e200, 1e200);
  EXPECT_NE(message(s).find("more than 2^31 - 1"), std::string::npos) << message(s);
  s = bath(10, 3);
  s.hi = Vec<2>(1e300, 60e-3);
  EXPECT_NE(message(s).find("more than 2^31 tiles"), std::string::npos) << message(s);
}

// Sub-steps from a step ratio: at least 1, and past 2^31 (a ratio that
// overflowed, a NaN) a SimulationError rather than an out-of-range cast
// (main returned INT64_MIN for the bond sub-steps below).
TEST(DemStep, SubstepCountsPast2To31AreAnError) {
  EXPECT_EQ(substep_count(0.3, "steps"), 1);
  EXPECT_EQ(substep_count(2.5, "steps"), 3);
  EXPECT_EQ(substep_count(static_cast<double>(kMaxSubsteps), "steps"), kMaxSubsteps);
  EXPECT_THROW(substep_count(1e300, "steps"), SimulationError);
  EXPECT_THROW(substep_count(std::numeric_limits<double>::quiet_NaN(), "steps"), SimulationError);
  DemParams<2> p;
  p.bond_dt = 1e-6;
  EXPECT_EQ(dem_bond_substeps(p, 2.5e-6), 3);
  p.bond_dt = 1e-300;
  EXPECT_THROW(dem_bond_substeps(p, 1.0), SimulationError);
}

// Fibers placed by shares (issue 14 part 1): shares of the region, each
// placing the fibers whose centre it owns, together give the whole
// placement bit for bit (positions, fiber ids, bonds and their ids),
// whatever the split; random orientations at a fraction where overlaps
// are frequent, in 2D and 3D.
template <int D>
void expect_shares_give_the_whole(const FiberSpec<D>& s, const std::array<int, 3>& split) {
  DemSystem<D> whole;
  whole.params.youngs_modulus = 1e8;  // a seeded bend preloads the bonds' moments
  const FiberPlacement all = place_fibers(s, whole);
  const DemParticles<D>& w = whole.particles;
  ASSERT_EQ(w.size(), static_cast<std::size_t>(all.fibers * s.particles_per_fiber));
  std::size_t seen = 0;
  std::int64_t tries = 0;
  Vec<D> step;
  for (int d = 0; d < D; ++d) step[d] = (s.hi[d] - s.lo[d]) / split[static_cast<std::size_t>(d)];
  for (int k = 0; k < split[0] * split[1] * split[2]; ++k) {
    const std::array<int, 3> c{k % split[0], (k / split[0]) % split[1], k / (split[0] * split[1])};
    Vec<D> lo, hi;
    for (int d = 0; d < D; ++d) {
      lo[d] = c[d] == 0 ? -1.0 : s.lo[d] + c[d] * step[d];
      hi[d] = c[d] + 1 == split[d] ? 1.0 : s.lo[d] + (c[d] + 1) * step[d];
    }
    FiberShare<D> share;
    share.boxes.emplace_back(lo, hi);
    share.owns = [&](const Vec<D>& x) {
      return (x.array() >= lo.array()).all() && (x.array() < hi.array()).all();
    };
    DemSystem<D> part;
    part.params.youngs_modulus = whole.params.youngs_modulus;
    const FiberPlacement p = place_fibers(s, part, &share);
    EXPECT_EQ(p.fibers, all.fibers);
    tries += p.tries;
    const DemParticles<D>& m = part.particles;
    for (std::size_t i = 0; i < m.size(); ++i) {
      const auto j = static_cast<std::size_t>(m.gid[i]);
      ASSERT_LT(j, w.size());
      EXPECT_EQ(w.gid[j], m.gid[i]);
      EXPECT_EQ(w.fiber[j], m.fiber[i]);
      EXPECT_TRUE(w.x[j] == m.x[i]) << "gid " << m.gid[i];
      EXPECT_EQ(w.mass[j], m.mass[i]);
      for (std::size_t b = 0; b < w.bonds[j].size(); ++b) {
        EXPECT_EQ(w.bonds[j][b].partner, m.bonds[i][b].partner);
        EXPECT_EQ(w.bonds[j][b].id, m.bonds[i][b].id);
        EXPECT_EQ(w.bonds[j][b].rbar, m.bonds[i][b].rbar);
        EXPECT_EQ(w.bonds[j][b].length0, m.bonds[i][b].length0);
        EXPECT_EQ(w.bonds[j][b].fn, m.bonds[i][b].fn);
        EXPECT_TRUE(w.bonds[j][b].fs == m.bonds[i][b].fs);
        EXPECT_TRUE(w.bonds[j][b].mb == m.bonds[i][b].mb);
      }
    }
    seen += m.size();
  }
  EXPECT_EQ(seen, w.size());  // each fiber on exactly one share
  EXPECT_EQ(tries, all.tries);
}

TEST(DemFibers, SharesPlaceTheWholePlacementBitwise) {
  FiberSpec<2> s = bath(375, 4);  // 8.2 %: many candidates overlap
  s.angle.reset();
  expect_shares_give_the_whole(s, {3, 2, 1});
  expect_shares_give_the_whole(s, {1, 5, 1});
  FiberSpec<3> t;
  t.count = 300;
  t.lo = Vec<3>(0, 0, 0);
  t.hi = Vec<3>(5e-3, 5e-3, 5e-3);
  t.seed = 5;
  expect_shares_give_the_whole(t, {2, 2, 2});
  // With a seeded bend (fibers.initial_bend): the arcs and the bonds' preloads too.
  s.bend = 0.1;
  expect_shares_give_the_whole(s, {3, 2, 1});
  t.bend = 0.2;
  t.particles_per_fiber = 6;
  t.count = 150;
  expect_shares_give_the_whole(t, {2, 2, 2});
}

// The seeded bend (fibers.initial_bend, docs/dem.md "Seeded bend"): one 3D
// fiber of 20 particles along phi = -10 deg in the x-y plane. Its centres
// have the requested sagitta over the length 2 r n, bulge along e_z x u (in
// the x-y plane), keep the pitch 2 r and the end-to-end direction u; the
// middle bond holds the moment of the straight fiber bent to the arc's
// curvature, E I theta0 pi / L_c with theta0 = pi W / L_c for a small
// half-sine of sagitta W over the centres' arc length L_c = 2 r (n - 1).
TEST(DemFibers, SeededBendIsAStressedHalfSine) {
  constexpr double kPi = std::numbers::pi;
  for (const double bend : {1e-3, 0.05, 0.2}) {
    FiberSpec<3> s;
    s.count = 1;
    s.particles_per_fiber = 20;
    s.lo = Vec<3>(0, 0, 0);
    s.hi = Vec<3>(8e-3, 4e-3, 1e-3);
    s.direction = Vec<3>(std::cos(-kPi / 18), std::sin(-kPi / 18), 0);
    s.bend = bend;
    DemSystem<3> sys;
    sys.params.youngs_modulus = 1e6;
    place_fibers(s, sys);
    check_placement(sys, s, 1);
    const DemParticles<3>& ps = sys.particles;
    const double r = s.radius, length = 2 * r * 20;
    const Vec<3> e = ps.x[19] - ps.x[0], u = *s.direction;
    const Vec<3> v = Vec<3>(0, 0, 1).cross(u).normalized();
    EXPECT_NEAR(e.normalized().dot(u), 1.0, 1e-14) << bend;
    double sagitta = 0;
    for (std::size_t k = 0; k < 20; ++k) {
      EXPECT_NEAR((ps.x[k] - ps.x[0]).dot(Vec<3>(0, 0, 1)), 0.0, 1e-18);
      sagitta = std::max(sagitta, (ps.x[k] - ps.x[0]).dot(v));
    }
    EXPECT_NEAR(sagitta / length, bend, 1e-12 * bend);
    if (bend > 1e-3) continue;
    const double lc = 2 * r * 19, theta0 = kPi * sagitta / lc;
    const double ei = 1e6 * kPi * std::pow(r, 4) / 4;
    const Vec<3> mb = ps.bonds[9][0].mb;  // the middle bond (particles 9 and 10)
    EXPECT_NEAR(mb.norm(), ei * theta0 * kPi / lc, 2e-3 * ei * theta0 * kPi / lc);
    EXPECT_NEAR(mb.normalized().dot(Vec<3>(0, 0, 1)), 1.0, 1e-12);  // u x v
    EXPECT_EQ(ps.bonds[9][0].fn, 0.0);
    EXPECT_EQ(ps.bonds[9][0].fs.norm(), 0.0);
  }
}

// The seed is a stressed perturbation: the rest shape stays straight. A
// free bent fiber (no drag, no damping) swings through straight to the
// other side within a period of its first free-free bending mode,
// omega = 22.37 sqrt(E I / (m_l L^4)); the same arc with its bonds' moments
// cleared (a bent rest shape) stays where it was.
TEST(DemFibers, SeededBendSpringsBackThroughStraight) {
  constexpr double kPi = std::numbers::pi;
  const auto swing = [](bool preloaded) {
    FiberSpec<3> s;
    s.count = 1;
    s.particles_per_fiber = 10;
    s.lo = Vec<3>(0, 0, 0);
    s.hi = Vec<3>(4e-3, 4e-3, 1e-3);
    s.direction = Vec<3>(1, 0, 0);
    s.bend = 0.02;
    DemSystem<3> sys;
    sys.params.youngs_modulus = 1e8;
    sys.params.kn = contact_stiffness_from_bond(sys.params, s.radius);
    place_fibers(s, sys);
    DemParticles<3>& ps = sys.particles;
    if (!preloaded)
      for (auto& slots : ps.bonds) slots[0].mb.setZero();
    sys.invalidate_forces();
    const double r = s.radius, length = 2 * r * 10;
    const double ei = 1e8 * kPi * std::pow(r, 4) / 4;
    const double m_l = ps.mass[0] / (2 * r);
    const double period = 2 * kPi / (22.37 * std::sqrt(ei / (m_l * std::pow(length, 4))));
    const double dt = sys.stable_dt();
    const auto offset = [&] {  // the middle's signed distance from the end-to-end line, along y
      return 0.5 * (ps.x[4][1] + ps.x[5][1]) - 0.5 * (ps.x[0][1] + ps.x[9][1]);
    };
    const double start = offset();
    double least = start;
    for (double t = 0; t < period; t += dt) {
      sys.step(dt);
      least = std::min(least, offset());
    }
    return least / start;
  };
  const double stressed = swing(true), rest_bent = swing(false);
  std::printf("least middle offset over one period / the seed's: %.3f stressed, %.3f rest-bent\n",
              stressed, rest_bent);
  EXPECT_LT(stressed, -0.5);
  EXPECT_GT(rest_bent, 0.9);
}

// Long fibers (issue 12 part 5): aspect ratio 20 to 50 in the paper's bath,
// at random orientations (2D) and on the sphere (3D), placed without
// overlaps, touching and bonded.
TEST(DemFibers, LongFibersAspectRatio20To50) {
  for (int n : {20, 35, 50}) {
    DemSystem<2> sys;
    FiberSpec<2> s = bath(40, 7);
    s.particles_per_fiber = n;
    s.angle.reset();
    place_fibers(s, sys);
    check_placement(sys, s, 40);
  }
  DemSystem<3> sys;
  FiberSpec<3> s;
  s.count = 30;
  s.particles_per_fiber = 50;
  s.lo = Vec<3>(0, 0, 0);
  s.hi = Vec<3>(15e-3, 15e-3, 15e-3);
  s.seed = 9;
  place_fibers(s, sys);
  check_placement(sys, s, 30);
}

// A fiber longer than its region can hold is refused at once, naming the
// key, whether its orientation is fixed or random (no direction fits).
TEST(DemFibers, TooLongFiberIsAClearError) {
  const auto expect_refused = [](const FiberSpec<2>& s) {
    DemSystem<2> sys;
    try {
      place_fibers(s, sys);
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("cannot lie in the region"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("particles_per_fiber"), std::string::npos) << e.what();
    }
    EXPECT_EQ(sys.particles.size(), 0u);
  };
  FiberSpec<2> s = bath(1, 3);
  s.particles_per_fiber = 121;  // 30.25 mm along x in a 30 mm wide bath
  expect_refused(s);
  s.particles_per_fiber = 110;  // 27.5 mm: fits
  DemSystem<2> sys;
  EXPECT_EQ(place_fibers(s, sys).fibers, 1);
  s.angle.reset();
  s.particles_per_fiber = 171;  // centres 42.5 mm apart; the diagonal left to them is 42.1 mm
  expect_refused(s);
}

}  // namespace
}  // namespace sphdem
