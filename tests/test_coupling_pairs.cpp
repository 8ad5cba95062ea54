// The coupling passes' pairs kept between passes (coupling_pairs.hpp): a
// list kept with a skin gives bitwise the results of a fresh search at
// every pass, is reused while the particles stay within the skin, and is
// searched afresh when they leave it or the caller's generation changes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sphdem/coupling/coupling_loops.hpp"

namespace sphdem {
namespace {

template <int D>
struct Scene {
  SphParticles<D> sph;
  DemParticles<D> dem;
};

template <int D>
Scene<D> random_scene(std::mt19937& gen, double dp) {
  const double L = 10 * dp;
  std::uniform_real_distribution<double> pos(0, L), vel(-1, 1), rho(850, 950), mass(0.8, 1.2);
  const auto rvec = [&](auto& dist) {
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = dist(gen);
    return v;
  };
  Scene<D> s;
  const int n_sph = D == 2 ? 600 : 2500;
  for (int r = 0; r < n_sph; ++r)
    s.sph.push_owned(r, Kind::Fluid, -1, mass(gen) * 900 * std::pow(dp, D), rvec(pos), rvec(vel),
                     rho(gen));
  for (int f = 0; f < 12; ++f) {
    const auto i = s.dem.push_owned(100 + 7 * f, f / 4, rvec(pos), 0.4 * dp, 2500, 1e-3);
    s.dem.v[i] = rvec(vel);
  }
  return s;
}

// One coupling pass (drag, then reaction) on a copy of `base` with `st`;
// the fields it sets, concatenated.
template <int D>
std::vector<double> pass(const Scene<D>& base, CouplingState<D>& st, const CouplingSettings& s) {
  Scene<D> c = base;
  for (std::size_t f = 0; f < c.dem.size(); ++f) c.dem.drag_impulse[f] = Vec<D>::Constant(1e-9);
  drag_on_fibers<D>(s, c.sph, c.dem, st, 1e-5);
  std::vector<double> eps;
  double rate = 0;
  const Vec<D> total = reaction_on_resin<D>(s, c.dem, c.sph, st, eps, rate);
  std::vector<double> out{rate};
  for (int a = 0; a < D; ++a) out.push_back(total[a]);
  for (std::size_t f = 0; f < c.dem.size(); ++f) {
    out.push_back(c.dem.shepard_sum[f]);
    out.push_back(c.dem.void_fraction[f]);
    out.push_back(c.dem.drag_coeff[f]);
    out.push_back(c.dem.torque_coeff[f]);
    // The parcel mass counts the DEM neighbours within the support: the
    // skin's candidates beyond it must not count.
    if (s.exponential_drag) out.push_back(c.dem.drag_parcel_mass[f]);
    for (int a = 0; a < D; ++a) out.push_back(c.dem.resin_velocity[f][a]);
  }
  for (std::size_t r = 0; r < c.sph.n_owned; ++r) {
    out.push_back(eps[r]);
    out.push_back(c.sph.drho[r]);
    for (int a = 0; a < D; ++a) out.push_back(c.sph.a[r][a]);
  }
  return out;
}

template <int D>
void check_kept_pairs(unsigned seed, bool exponential = false) {
  const double dp = 3e-4, h = 1.2 * dp, support = 2 * h;
  std::mt19937 gen(seed);
  Scene<D> scene = random_scene<D>(gen, dp);
  CouplingSettings s;
  s.drag.rho = 900;
  s.drag.mu = 0.1;
  s.h = h;
  s.thickness = 1e-3;
  s.exponential_drag = exponential;
  CouplingState<D> kept, fresh;
  kept.keep_pairs = true;
  kept.skin = 0.2 * support;
  // Each pass moves every particle by at most 0.03 support per axis: the
  // skin lasts a few passes.
  std::uniform_real_distribution<double> step(-0.03 * support, 0.03 * support);
  const int passes = 40;
  for (int k = 0; k < passes; ++k) {
    ASSERT_EQ(pass<D>(scene, kept, s), pass<D>(scene, fresh, s)) << "pass " << k;
    for (Vec<D>& x : scene.sph.x)
      for (int a = 0; a < D; ++a) x[a] += step(gen);
    for (Vec<D>& x : scene.dem.x)
      for (int a = 0; a < D; ++a) x[a] += step(gen);
  }
  // Fresh: one search per pass; kept: reused, and searched again as the
  // particles used up the skin.
  EXPECT_EQ(fresh.pairs.builds, passes);
  EXPECT_GT(kept.pairs.builds, 1);
  EXPECT_LT(kept.pairs.builds, passes / 2);
  // Unmoved: reused. A new generation (the caller's particles reordered)
  // searches afresh.
  pass<D>(scene, kept, s);
  const std::int64_t before = kept.pairs.builds;
  pass<D>(scene, kept, s);
  EXPECT_EQ(kept.pairs.builds, before);
  kept.generation += 1;
  EXPECT_EQ(pass<D>(scene, kept, s), pass<D>(scene, fresh, s));
  EXPECT_EQ(kept.pairs.builds, before + 1);
}

TEST(CouplingPairs, KeptPairsGiveTheFreshSearchResults2D) {
  check_kept_pairs<2>(11);
}
TEST(CouplingPairs, KeptPairsGiveTheFreshSearchResults3D) {
  check_kept_pairs<3>(12);
}
// With the exponential drag the DEM neighbours are counted (the parcel
// mass): it fails when the filter keeps a candidate beyond the support.
TEST(CouplingPairs, KeptPairsGiveTheFreshSearchResultsWithExponentialDrag2D) {
  check_kept_pairs<2>(14, true);
}
TEST(CouplingPairs, KeptPairsGiveTheFreshSearchResultsWithExponentialDrag3D) {
  check_kept_pairs<3>(15, true);
}

// The DEM particles reordered under the same generation and positions would
// go unseen (the caller must say so); a reordering that changes the counts
// is caught.
TEST(CouplingPairs, ChangedCountsSearchAfresh) {
  const double dp = 3e-4;
  std::mt19937 gen(13);
  Scene<2> scene = random_scene<2>(gen, dp);
  CouplingSettings s;
  s.h = 1.2 * dp;
  s.thickness = 1e-3;
  s.drag.rho = 900;
  s.drag.mu = 0.1;
  CouplingState<2> kept, fresh;
  kept.keep_pairs = true;
  kept.skin = 0.1 * dp;
  pass<2>(scene, kept, s);
  scene.dem.push_owned(999, 99, scene.dem.x[0] + Vec<2>(0.1 * dp, 0), 0.4 * dp, 2500, 1e-3);
  EXPECT_EQ(pass<2>(scene, kept, s), pass<2>(scene, fresh, s));
  EXPECT_EQ(kept.pairs.builds, 2);
}

}  // namespace
}  // namespace sphdem
