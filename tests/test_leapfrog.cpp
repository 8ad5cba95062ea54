// The resin's kick-drift-kick passes (src/solver/resin_leapfrog.hpp): with
// AVX-512 they take eight particles at a time, with AVX2 four; every
// particle must get the bits of the one-particle form, whatever the mix of
// resin, wall and frozen particles in its group and the tail after the last
// whole group;
// the one-particle form is the scheme of docs/physics.md by hand; and the
// passes that also run the rebuild check and the time step's maxima give
// what the separate passes give (docs/performance.md, "The streaming
// passes").
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>

#include "../src/solver/resin_leapfrog.hpp"

namespace sphdem {
namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// n particles, every kind and frozen flag mixed at random, random fields.
template <int D>
SphParticles<D> cloud(std::size_t n, unsigned seed, bool frozen) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SphParticles<D> ps;
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> x, v;
    for (int d = 0; d < D; ++d) {
      x[d] = u(rng);
      v[d] = u(rng);
    }
    const Kind kind = u(rng) < -0.4 ? Kind::Wall : Kind::Fluid;
    ps.push_owned(static_cast<std::int64_t>(i), kind, -1, 1.0, x, v, 1000.0 + u(rng));
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < D; ++d) {
      ps.a[i][d] = 1e3 * u(rng);
      ps.v_half[i][d] = u(rng);
    }
    ps.drho[i] = 1e2 * u(rng);
    ps.rho_half[i] = 1000.0 + u(rng);
    ps.temperature[i] = 500.0 + u(rng);
    ps.temp_half[i] = 500.0 + u(rng);
    ps.dtemp[i] = 10.0 * u(rng);
  }
  if (frozen) {
    ps.frozen.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) ps.frozen[i] = u(rng) < 0.0 ? 1 : 0;
  } else {
    ps.frozen.clear();
  }
  return ps;
}

template <int D>
void expect_same_bits(const SphParticles<D>& a, const SphParticles<D>& b) {
  for (std::size_t i = 0; i < a.n_owned; ++i) {
    for (int d = 0; d < D; ++d) {
      EXPECT_TRUE(same_bits(a.x[i][d], b.x[i][d])) << i;
      EXPECT_TRUE(same_bits(a.v[i][d], b.v[i][d])) << i;
      EXPECT_TRUE(same_bits(a.v_half[i][d], b.v_half[i][d])) << i;
      EXPECT_TRUE(same_bits(a.a[i][d], b.a[i][d])) << i;
    }
    EXPECT_TRUE(same_bits(a.rho[i], b.rho[i])) << i;
    EXPECT_TRUE(same_bits(a.rho_half[i], b.rho_half[i])) << i;
    EXPECT_TRUE(same_bits(a.temperature[i], b.temperature[i])) << i;
  }
}

template <int D>
void eight_at_a_time_equals_one_at_a_time() {
  const double dt = 1.3e-5;
  for (const std::size_t n : {std::size_t{5}, std::size_t{64}, std::size_t{203}}) {
    for (const bool frozen : {false, true}) {
      SCOPED_TRACE(testing::Message() << "n " << n << " frozen " << frozen);
      const SphParticles<D> start = cloud<D>(n, static_cast<unsigned>(n), frozen);
      SphParticles<D> eight = start, one = start;
      kick_drift_resin<D>(eight, dt);
      const auto p = leapfrog_detail::arrays(one, dt, false);
      for (std::size_t i = 0; i < n; ++i) leapfrog_detail::kick_drift_one<D>(p, i);
      expect_same_bits(eight, one);
      for (const bool density : {false, true}) {
        SphParticles<D> eight2 = start, one2 = start;
        kick_resin<D>(eight2, dt, density, true);
        const auto q = leapfrog_detail::arrays(one2, dt, true);
        for (std::size_t i = 0; i < n; ++i) leapfrog_detail::kick_one<D>(q, i, density);
        expect_same_bits(eight2, one2);
      }
    }
  }
}

TEST(Leapfrog, EightParticlesAtATimeGiveTheBitsOfOneAtATime2D) {
  eight_at_a_time_equals_one_at_a_time<2>();
}

TEST(Leapfrog, EightParticlesAtATimeGiveTheBitsOfOneAtATime3D) {
  eight_at_a_time_equals_one_at_a_time<3>();
}

// The drift with the rebuild check: the same fields as kick_drift_resin and
// the verdict of needs_rebuild after it, for particles moved by the drift
// and for particles moved by hand since the build (a wall in a group with
// no resin, the tail after the last whole group), both verdicts reached.
template <int D>
void drift_and_check_equals_drift_then_check() {
  int moved = 0, still = 0;
  for (const std::size_t n : {std::size_t{5}, std::size_t{64}, std::size_t{203}}) {
    for (const bool frozen : {false, true}) {
      SphParticles<D> start = cloud<D>(n, static_cast<unsigned>(n) + 7, frozen);
      for (std::size_t i = 8; i < 16 && i < n; ++i) start.kind[i] = Kind::Wall;
      NeighborList<D> nl(0.3, 0.04);  // moves beyond about 0.02 call for a rebuild
      nl.build(start);
      // dt 1e-3: nobody moves far enough; 0.01 and more: fast particles do.
      for (const double dt : {1e-3, 0.01, 0.02, 0.05}) {
        // -1: as built; else that particle moved by hand (0.03) first.
        for (const std::size_t shifted : {std::size_t(-1), std::size_t{12}, n - 1}) {
          if (shifted != std::size_t(-1) && shifted >= n) continue;
          SCOPED_TRACE(testing::Message() << "n " << n << " frozen " << frozen << " dt " << dt
                                          << " shifted " << static_cast<long>(shifted));
          SphParticles<D> fused = start;
          if (shifted != std::size_t(-1)) fused.x[shifted][0] += 0.03;
          SphParticles<D> apart = fused;
          SphParticles<D> boxed = fused;
          const bool verdict = kick_drift_resin_and_check<D>(fused, dt, nl);
          kick_drift_resin<D>(apart, dt);
          EXPECT_EQ(verdict, nl.needs_rebuild(apart));
          expect_same_bits(fused, apart);
          (verdict ? moved : still)++;
          // With the box of all moves (AVX-512 builds fill it): the same
          // verdict and fields, and the bits of move_box.
          std::optional<typename NeighborList<D>::MoveBox> box;
          EXPECT_EQ(kick_drift_resin_and_check<D>(boxed, dt, nl, &box), verdict);
          expect_same_bits(boxed, apart);
#if defined(SPHDEM_PARTICLE_LANES)
          ASSERT_TRUE(box.has_value());
          const typename NeighborList<D>::MoveBox by_one = nl.move_box(apart);
          EXPECT_EQ(std::memcmp(box->data(), by_one.data(), sizeof(by_one)), 0);
          // A position that is not finite: an infinite box in both forms.
          SphParticles<D> broken = apart;
          broken.x[n - 1][D - 1] = std::numeric_limits<double>::quiet_NaN();
          const typename NeighborList<D>::MoveBox nan_box = nl.move_box(broken);
          SphParticles<D> broken_fused = fused;
          broken_fused.x[n - 1][D - 1] = std::numeric_limits<double>::quiet_NaN();
          std::optional<typename NeighborList<D>::MoveBox> nan_fused;
          kick_drift_resin_and_check<D>(broken_fused, 0.0, nl, &nan_fused);
          ASSERT_TRUE(nan_fused.has_value());
          for (std::size_t k = 0; k < nan_box.size(); ++k) {
            EXPECT_EQ(nan_box[k], std::numeric_limits<double>::infinity());
            EXPECT_EQ((*nan_fused)[k], std::numeric_limits<double>::infinity());
          }
#else
          EXPECT_FALSE(box.has_value());
#endif
        }
      }
    }
  }
  EXPECT_GT(moved, 10);
  EXPECT_GT(still, 3);
  // Lists of another particle count: needs_rebuild's answer (rebuild).
  SphParticles<D> other = cloud<D>(9, 3, false);
  NeighborList<D> nl(0.3, 0.04);
  nl.build(other);
  other.push_owned(9, Kind::Fluid, -1, 1.0, Vec<D>::Zero(), Vec<D>::Zero(), 1000.0);
  EXPECT_TRUE(kick_drift_resin_and_check<D>(other, 1e-9, nl));
  // With the box asked for: an infinite one (AVX-512 builds), so a rank
  // whose count changed joins the same reduction as the others.
  std::optional<typename NeighborList<D>::MoveBox> box;
  EXPECT_TRUE(kick_drift_resin_and_check<D>(other, 1e-9, nl, &box));
#if defined(SPHDEM_PARTICLE_LANES)
  ASSERT_TRUE(box.has_value());
  for (const double v : *box) EXPECT_EQ(v, std::numeric_limits<double>::infinity());
#endif
}

TEST(Leapfrog, DriftWithTheRebuildCheckGivesNeedsRebuildsVerdict2D) {
  drift_and_check_equals_drift_then_check<2>();
}

TEST(Leapfrog, DriftWithTheRebuildCheckGivesNeedsRebuildsVerdict3D) {
  drift_and_check_equals_drift_then_check<3>();
}

// The second kick with the maxima: the same fields as kick_resin and the
// bits of local_extremes after it, with walls, frozen resin, a viscosity
// field, the tail, and a NaN acceleration (which no maximum takes).
template <int D>
void kick_and_extremes_equals_kick_then_extremes() {
  for (const std::size_t n : {std::size_t{5}, std::size_t{64}, std::size_t{203}}) {
    for (const bool frozen : {false, true}) {
      for (const bool density : {false, true}) {
        SCOPED_TRACE(testing::Message()
                     << "n " << n << " frozen " << frozen << " density " << density);
        SphParticles<D> fused = cloud<D>(n, static_cast<unsigned>(n) + 11, frozen);
        fused.viscosity.assign(n, 0.0);
        for (std::size_t i = 0; i < n; ++i) fused.viscosity[i] = 0.1 + 1e-3 * fused.rho_half[i];
        // The fastest wall and the largest acceleration sit in the tail
        // (n = 5, 203) or the last whole group (n = 64), with components
        // whose squares round (so a product fused into the sum shows).
        fused.v[n - 1] = Vec<D>::Constant(40.0 + 1.0 / 3.0);
        fused.v[n - 1][1] = 40.0 - 1.0 / 3.0;
        fused.kind[n - 1] = Kind::Wall;
        fused.a[n - 2] = Vec<D>::Constant(5e4 + 1.0 / 3.0);
        fused.a[n - 2][1] = 5e4 - 1.0 / 6.0;
        if (!fused.frozen.empty()) fused.frozen[n - 2] = 0;
        fused.kind[n - 2] = Kind::Fluid;
        fused.a[0][0] = std::nan("");
        SphParticles<D> apart = fused;
        const LocalExtremes got = kick_resin_and_extremes<D>(fused, 1.3e-5, density, true);
        kick_resin<D>(apart, 1.3e-5, density, true);
        const LocalExtremes want = local_extremes<D>(apart);
        expect_same_bits(fused, apart);
        EXPECT_TRUE(same_bits(got.v_max, want.v_max)) << got.v_max << " " << want.v_max;
        EXPECT_TRUE(same_bits(got.a_max, want.a_max)) << got.a_max << " " << want.a_max;
        EXPECT_TRUE(same_bits(got.mu_max, want.mu_max)) << got.mu_max << " " << want.mu_max;
        EXPECT_NEAR(got.v_max, 40.0 * std::sqrt(static_cast<double>(D)), 0.3);
        EXPECT_GE(got.a_max, (5e4 - 1.0) * std::sqrt(static_cast<double>(D)));
        EXPECT_GT(got.mu_max, 1.0);
      }
    }
  }
}

TEST(Leapfrog, KickWithTheMaximaGivesLocalExtremes2D) {
  kick_and_extremes_equals_kick_then_extremes<2>();
}

TEST(Leapfrog, KickWithTheMaximaGivesLocalExtremes3D) {
  kick_and_extremes_equals_kick_then_extremes<3>();
}

// By hand: v_half = v + dt/2 a, x += dt v_half, v = v_half + dt/2 a (the
// prediction for the rates), rho likewise; walls and frozen resin stay put.
TEST(Leapfrog, KickDriftKickByHand) {
  SphParticles<2> ps;
  ps.push_owned(0, Kind::Fluid, -1, 1.0, Vec<2>(1.0, 2.0), Vec<2>(3.0, -1.0), 1000.0);
  ps.push_owned(1, Kind::Wall, -1, 1.0, Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.0), 1000.0);
  ps.push_owned(2, Kind::Fluid, -1, 1.0, Vec<2>(5.0, 5.0), Vec<2>(1.0, 1.0), 1000.0);
  ps.a[0] = Vec<2>(4.0, 8.0);
  ps.drho[0] = 20.0;
  ps.frozen.assign(3, 0);
  ps.frozen[2] = 1;
  ps.a[2] = Vec<2>(0.0, 0.0);
  kick_drift_resin<2>(ps, 0.5);
  EXPECT_EQ(ps.v_half[0], Vec<2>(4.0, 1.0));
  EXPECT_EQ(ps.x[0], Vec<2>(3.0, 2.5));
  EXPECT_EQ(ps.v[0], Vec<2>(5.0, 3.0));
  EXPECT_EQ(ps.rho_half[0], 1005.0);
  EXPECT_EQ(ps.rho[0], 1010.0);
  EXPECT_EQ(ps.x[1], Vec<2>(0.0, 0.0));
  EXPECT_EQ(ps.v[1], Vec<2>(0.5, 0.0));
  EXPECT_EQ(ps.x[2], Vec<2>(5.0, 5.0));
  EXPECT_EQ(ps.v[2], Vec<2>(0.0, 0.0));
  // The second kick with new rates: v = v_half + dt/2 a.
  ps.a[0] = Vec<2>(-4.0, 0.0);
  ps.a[2] = Vec<2>(7.0, 7.0);  // frozen: zeroed
  ps.drho[0] = -40.0;
  kick_resin<2>(ps, 0.5, true, false);
  EXPECT_EQ(ps.v[0], Vec<2>(3.0, 1.0));
  EXPECT_EQ(ps.rho[0], 995.0);
  EXPECT_EQ(ps.a[2], Vec<2>(0.0, 0.0));
  EXPECT_EQ(ps.v[2], Vec<2>(0.0, 0.0));
  // A rank with no particles (every field empty) passes through.
  SphParticles<2> none;
  kick_drift_resin<2>(none, 0.5);
  kick_resin<2>(none, 0.5, true, true);
  EXPECT_EQ(none.n_owned, 0u);
}

}  // namespace
}  // namespace sphdem
