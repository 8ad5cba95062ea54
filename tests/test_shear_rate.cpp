// The shear-rate pass (src/sph/terms/shear_rate.hpp) on a Cartesian lattice
// with an imposed linear velocity field v = A x: the lattice-corrected SPH
// gradient of a linear field is exact on the full lattice (the correction
// divides by the lattice's own second moment, docs/physics.md), so interior
// particles give gamma_dot = sqrt(2 D:D) of A to round-off. A support
// holds ~30 (2D) or ~170 (3D) neighbours, each contributing a term of size
// ~|A| with a relative rounding of 1e-16, and the off-diagonal moments
// cancel exactly by symmetry up to that rounding; 1e-12 |A| leaves two
// orders of margin and still fails for a missing lattice correction (3.6 %
// in 2D, 1.5 % in 3D), a wrong sign or a wall seen with its own velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {
namespace {

constexpr double kDp = 1.0e-3, kHOverDp = 1.2;

SphParams lattice_params(int dimension, bool requested) {
  SphParams sp;
  sp.spacing = kDp;
  sp.h = kHOverDp * kDp;
  sp.rho0 = 1000;
  sp.c0 = 10;
  sp.grad_scale = gradient_lattice_correction(dimension, kHOverDp);
  sp.anti_clump = false;
  if (requested) sp.output_fields = {"velocity", "shear_rate"};
  return sp;
}

// An n^D lattice; rows y < 0 are walls whose own velocity is zero and whose
// no-slip velocity (vwall) continues the field, as the Adami extrapolation
// does for a linear profile.
template <int D>
SphParticles<D> lattice(int n, const Eigen::Matrix<double, D, D>& A) {
  SphParticles<D> ps;
  std::int64_t id = 0;
  const int nz = D == 3 ? n : 1;
  for (int i = 0; i < n; ++i)
    for (int j = -3; j < n; ++j)
      for (int k = 0; k < nz; ++k) {
        Vec<D> x;
        x[0] = i * kDp;
        x[1] = j * kDp;
        if constexpr (D == 3) x[2] = k * kDp;
        const bool wall = j < 0;
        const Vec<D> v = A * x;
        ps.push_owned(id++, wall ? Kind::Wall : Kind::Fluid, -1, 1000 * std::pow(kDp, D), x,
                      wall ? Vec<D>(Vec<D>::Zero()) : v, 1000);
        ps.vwall.back() = v;
        ps.shear_rate.back() = -1.0;  // must be overwritten (owned) or left (not run)
      }
  return ps;
}

template <int D>
double expected(const Eigen::Matrix<double, D, D>& A) {
  const Eigen::Matrix<double, D, D> S = 0.5 * (A + A.transpose());
  return std::sqrt(2.0 * S.cwiseProduct(S).sum());
}

// Runs the pass on the lattice and checks every particle at least 2h from
// the lattice's open sides (the walls close y = 0). Returns how many.
template <int D>
int check_lattice(const Eigen::Matrix<double, D, D>& A, double scale) {
  const int n = 9;
  SphParticles<D> ps = lattice<D>(n, A);
  const SphParams sp = lattice_params(D, true);
  NeighborList<D> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  std::vector<SphGroup> forwarded;
  compute_fluid_passes<D>(sp, nl, ps, [&](SphGroup g) { forwarded.push_back(g); });
  EXPECT_EQ(forwarded, std::vector<SphGroup>{SphGroup::ShearRate});
  const double want = expected<D>(A);
  const double margin = 2.0 * sp.h + 1e-9;
  const double hi = (n - 1) * kDp - margin;
  int checked = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] == Kind::Wall) {
      EXPECT_EQ(ps.shear_rate[i], 0.0);
      continue;
    }
    bool interior = ps.x[i][1] <= hi;
    for (int d = 0; d < D; ++d)
      if (d != 1) interior = interior && ps.x[i][d] >= margin && ps.x[i][d] <= hi;
    if (!interior) continue;
    EXPECT_NEAR(ps.shear_rate[i], want, 1e-12 * scale) << "particle at " << ps.x[i].transpose();
    ++checked;
  }
  return checked;
}

TEST(ShearRate, ExactForLinearFieldsOnTheLattice2D) {
  using M = Eigen::Matrix2d;
  const double G = 3.0;
  M shear, rotation, extension;
  shear << 0, G, 0, 0;       // v_x = G y: gamma_dot = G
  rotation << 0, -G, G, 0;   // rigid rotation: 0
  extension << G, 0, 0, -G;  // planar extension: 2 G
  EXPECT_DOUBLE_EQ(expected<2>(shear), G);
  EXPECT_DOUBLE_EQ(expected<2>(extension), 2 * G);
  EXPECT_GT(check_lattice<2>(shear, G), 5);
  EXPECT_GT(check_lattice<2>(rotation, G), 5);
  EXPECT_GT(check_lattice<2>(extension, G), 5);
}

TEST(ShearRate, ExactForLinearFieldsOnTheLattice3D) {
  using M = Eigen::Matrix3d;
  const double G = 3.0;
  M shear = M::Zero(), rotation = M::Zero(), extension = M::Zero();
  shear(0, 1) = G;                                // v_x = G y
  rotation << 0, -G, 0, G, 0, 0, 0, 0, 0;         // about z
  extension.diagonal() << G, -0.5 * G, -0.5 * G;  // uniaxial: sqrt(3) G
  EXPECT_DOUBLE_EQ(expected<3>(shear), G);
  EXPECT_NEAR(expected<3>(extension), std::sqrt(3.0) * G, 1e-15 * G);
  EXPECT_GT(check_lattice<3>(shear, G), 5);
  EXPECT_GT(check_lattice<3>(rotation, G), 5);
  EXPECT_GT(check_lattice<3>(extension, G), 5);
}

// Near the wall too: the walls' no-slip velocity, not their own (zero), is
// what the gradient sees.
TEST(ShearRate, WallNeighboursUseTheirNoSlipVelocity) {
  Eigen::Matrix2d shear;
  shear << 0, 2.0, 0, 0;
  SphParticles<2> ps = lattice<2>(9, shear);
  const SphParams sp = lattice_params(2, true);
  NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  compute_fluid_passes<2>(sp, nl, ps, [](SphGroup) {});
  int checked = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const Vec<2> x = ps.x[i];
    if (ps.kind[i] != Kind::Fluid || std::abs(x[1]) > 1e-12 || x[0] < 3 * kDp || x[0] > 5 * kDp)
      continue;
    EXPECT_NEAR(ps.shear_rate[i], 2.0, 1e-12 * 2.0);
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

// Not requested and read by no active term: the pass does not run (results
// of existing cases stay bitwise unchanged) and nothing is forwarded.
TEST(ShearRate, DoesNotRunUnlessRequested) {
  Eigen::Matrix2d shear;
  shear << 0, 1.0, 0, 0;
  SphParticles<2> ps = lattice<2>(6, shear);
  SphParams sp = lattice_params(2, false);
  sp.mu = 0.1;  // every term the library has switched on
  sp.alpha = 0.1;
  sp.delta = 0.1;
  sp.anti_clump = true;
  NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  int calls = 0;
  // Anti-clump reads the free-surface flag (docs/physics.md), so that pass
  // may run; the shear-rate pass must not.
  compute_fluid_passes<2>(sp, nl, ps, [&](SphGroup g) { calls += g == SphGroup::ShearRate; });
  EXPECT_EQ(calls, 0);
  for (std::size_t i = 0; i < ps.size(); ++i) EXPECT_EQ(ps.shear_rate[i], -1.0);
}

}  // namespace
}  // namespace sphdem
