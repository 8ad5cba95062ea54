// The passes over particles that take eight (or 64) particles at a time with
// AVX-512 (include/sphdem/particles/particle_lanes.hpp, docs/performance.md
// "The passes over particles"): each must give the bits of the one-particle
// form, whatever the mix of kinds and the tail after the last whole group.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {
namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

const std::size_t kSizes[] = {0, 1, 5, 8, 63, 64, 65, 130, 203};

// n particles of random kinds (about a third walls), frozen flags and
// viscosities, velocities and accelerations over several decades.
template <int D>
SphParticles<D> cloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SphParticles<D> ps;
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> x, v;
    for (int d = 0; d < D; ++d) {
      x[d] = u(rng);
      v[d] = std::ldexp(u(rng), static_cast<int>(8 * u(rng)));
    }
    const Kind kind = u(rng) < -0.3 ? Kind::Wall : Kind::Fluid;
    ps.push_owned(static_cast<std::int64_t>(i), kind, -1, 1.0, x, v, 1000.0);
  }
  ps.frozen.assign(n, 0);
  ps.viscosity.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < D; ++d) ps.a[i][d] = std::ldexp(u(rng), static_cast<int>(8 * u(rng)));
    ps.frozen[i] = u(rng) < -0.6 ? 1 : 0;
    ps.viscosity[i] = 1.0 + u(rng);
  }
  return ps;
}

// |v|^2 with the operations of Eigen's squaredNorm as GCC compiles it in
// local_extremes' one-particle form: products rounded, x x + y y, then
// fma(z, z, .) in 3D (volatile keeps the test's own compiler from fusing).
template <int D>
double squared_norm(const Vec<D>& v) {
  volatile double xx = v[0] * v[0], yy = v[1] * v[1];
  const double n2 = xx + yy;
  if constexpr (D == 3) return lanes::mul_add(v[2], v[2], n2);
  return n2;
}

template <int D>
LocalExtremes by_hand(const SphParticles<D>& ps) {
  double v2 = 0.0, a2 = 0.0, mu = 0.0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    v2 = std::max(v2, squared_norm<D>(ps.v[i]));
    if (ps.kind[i] != Kind::Fluid || ps.frozen[i] != 0) continue;
    a2 = std::max(a2, squared_norm<D>(ps.a[i]));
    mu = std::max(mu, ps.viscosity[i]);
  }
  return {std::sqrt(v2), std::sqrt(a2), mu};
}

TEST(ParticleLanes, ForEachOfKindVisitsEachInOrder) {
  for (const std::size_t n : kSizes) {
    const SphParticles<2> ps = cloud<2>(n, 7 + static_cast<unsigned>(n));
    for (const Kind k : {Kind::Wall, Kind::Fluid}) {
      std::vector<std::size_t> want, got;
      for (std::size_t i = 0; i < n; ++i)
        if (ps.kind[i] == k) want.push_back(i);
      lanes::for_each_of_kind(ps.kind.data(), n, k, [&](std::size_t i) { got.push_back(i); });
      EXPECT_EQ(got, want) << n << " particles";
    }
  }
}

// Every size around whole groups, and the values the flags' scan can meet:
// +0 and -0 are skipped; a NaN, infinities, a denormal, 1 and -1 are visited.
TEST(ParticleLanes, ForEachNonzeroVisitsEachInOrder) {
  const double kinds[] = {0.0,
                          -0.0,
                          1.0,
                          -1.0,
                          std::nan(""),
                          std::numeric_limits<double>::infinity(),
                          -std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::denorm_min(),
                          0.0,
                          0.0,
                          -0.0};
  for (std::size_t n = 0; n <= 40; ++n) {
    for (std::size_t shift = 0; shift < 11; ++shift) {
      std::vector<double> v(n);
      for (std::size_t i = 0; i < n; ++i) v[i] = kinds[(i * 7 + shift) % 11];
      std::vector<std::size_t> want, got;
      for (std::size_t i = 0; i < n; ++i)
        if (!(v[i] == 0.0)) want.push_back(i);
      lanes::for_each_nonzero(v.data(), n, [&](std::size_t i) { got.push_back(i); });
      EXPECT_EQ(got, want) << n << " values, shift " << shift;
    }
  }
}

#if defined(SPHDEM_PARTICLE_LANES)
template <int D>
void check_components() {
  std::vector<double> p(D * 24);
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = 1.0 + static_cast<double>(k);
  std::vector<float> f(p.begin(), p.end());
  for (const std::size_t i : {std::size_t{0}, std::size_t{8}, std::size_t{13}}) {
    const __mmask8 valid = lanes::first(i == 13 ? 5 : 8);
    __m512d r[D], rf[D];
    lanes::load_vectors<D>(p.data(), i, valid, r);
    lanes::load_vectors<D>(f.data(), i, valid, rf);
    for (int d = 0; d < D; ++d) {
      alignas(64) double c[8], cf[8];
      _mm512_store_pd(c, lanes::component<D>(r, d));
      _mm512_store_pd(cf, lanes::component<D>(rf, d));
      for (int l = 0; l < 8; ++l) {
        const double want = (valid >> l) & 1 ? p[D * (i + l) + d] : 0.0;
        EXPECT_EQ(c[l], want) << "D " << D << " group at " << i << " component " << d;
        EXPECT_EQ(cf[l], want) << "floats, D " << D << " group at " << i << " component " << d;
      }
    }
  }
}

TEST(ParticleLanes, ComponentsOfEightVectors) {
  check_components<2>();
  check_components<3>();
}

// store_vectors is component's inverse: eight particles' D-vectors written
// from their component rows, and nothing before or after them touched.
template <int D>
void check_store_vectors() {
  for (const std::size_t i : {std::size_t{0}, std::size_t{5}}) {
    std::vector<double> p(D * 16, -1.0);
    __m512d rows[D];
    for (int d = 0; d < D; ++d) {
      alignas(64) double c[8];
      for (int l = 0; l < 8; ++l) c[l] = 10.0 * l + d + 0.5;
      rows[d] = _mm512_load_pd(c);
    }
    lanes::store_vectors<D>(p.data(), i, rows);
    for (std::size_t k = 0; k < p.size(); ++k) {
      const bool ours = k >= D * i && k < D * (i + 8);
      const double want = ours ? 10.0 * static_cast<double>((k - D * i) / D) +
                                     static_cast<double>((k - D * i) % D) + 0.5
                               : -1.0;
      EXPECT_EQ(p[k], want) << "D " << D << " group at " << i << " double " << k;
    }
    __m512d back[D];
    lanes::load_vectors<D>(p.data(), i, 0xff, back);
    for (int d = 0; d < D; ++d) {
      alignas(64) double got[8], want[8];
      _mm512_store_pd(got, lanes::component<D>(back, d));
      _mm512_store_pd(want, rows[d]);
      for (int l = 0; l < 8; ++l) EXPECT_EQ(got[l], want[l]) << "D " << D << " lane " << l;
    }
  }
}

TEST(ParticleLanes, StoreVectorsIsComponentsInverse) {
  check_store_vectors<2>();
  check_store_vectors<3>();
}

TEST(ParticleLanes, LargestLane) {
  for (int l = 0; l < 8; ++l) {
    alignas(64) double x[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    x[l] = 100.0 + l;
    EXPECT_EQ(lanes::largest(_mm512_load_pd(x)), 100.0 + l);
  }
}
#endif

// The largest speed, acceleration and viscosity: the largest of each in the
// last particle of a tail (where a group of eight reads past the end if
// its mask is wrong) and anywhere else, frozen and wall particles' own
// accelerations left out.
template <int D>
void check_extremes() {
  for (const std::size_t n : kSizes) {
    for (unsigned seed = 0; seed < 4; ++seed) {
      SphParticles<D> ps = cloud<D>(n, 100 * seed + static_cast<unsigned>(n));
      if (seed == 1 && n > 0) {  // the largest in the last particle
        ps.kind[n - 1] = Kind::Fluid;
        ps.frozen[n - 1] = 0;
        ps.v[n - 1] *= 1e6;
        ps.a[n - 1] *= 1e6;
        ps.viscosity[n - 1] = 1e6;
      }
      if (seed == 2) {  // a huge acceleration on every frozen or wall particle
        for (std::size_t i = 0; i < n; ++i)
          if (ps.kind[i] != Kind::Fluid || ps.frozen[i] != 0) ps.a[i] *= 1e9;
      }
      const LocalExtremes got = local_extremes<D>(ps), want = by_hand<D>(ps);
      EXPECT_TRUE(same_bits(got.v_max, want.v_max)) << n << " " << got.v_max << " " << want.v_max;
      EXPECT_TRUE(same_bits(got.a_max, want.a_max)) << n << " " << got.a_max << " " << want.a_max;
      EXPECT_TRUE(same_bits(got.mu_max, want.mu_max)) << n;
    }
  }
}

TEST(LocalExtremes, EightAtATimeGiveTheOneParticleBits2D) {
  check_extremes<2>();
}
TEST(LocalExtremes, EightAtATimeGiveTheOneParticleBits3D) {
  check_extremes<3>();
}

// A rebuild is asked for when any one particle has moved beyond half the
// skin, the first, one in a whole group or the last of a tail, and not when
// every particle moved less.
template <int D>
void check_one_mover() {
  constexpr double kSkin = 1e-3;
  for (const std::size_t n : {std::size_t{1}, std::size_t{8}, std::size_t{13}, std::size_t{203}}) {
    SphParticles<D> ps;
    for (std::size_t i = 0; i < n; ++i) {
      Vec<D> x = Vec<D>::Zero();
      x[0] = 0.01 * static_cast<double>(i % 17);
      x[1] = 0.01 * static_cast<double>(i / 17);
      ps.push_owned(static_cast<std::int64_t>(i), Kind::Fluid, -1, 1.0, x, Vec<D>::Zero(), 1000.0);
    }
    NeighborList<D> nl(0.012, kSkin);
    nl.build(ps);
    for (const std::size_t who : {std::size_t{0}, n / 2, n - 1}) {
      const Vec<D> at = ps.x[who];
      for (std::size_t i = 0; i < n; ++i) ps.x[i][D - 1] += 0.3 * kSkin;  // everyone a little
      EXPECT_FALSE(nl.needs_rebuild(ps)) << n << " particles";
      ps.x[who][D - 1] = at[D - 1] + 0.501 * kSkin;
      EXPECT_TRUE(nl.needs_rebuild(ps)) << n << " particles, particle " << who;
      for (std::size_t i = 0; i < n; ++i) ps.x[i][D - 1] -= 0.3 * kSkin;
      ps.x[who] = at;
    }
  }
}

TEST(NeighborSkin, AnyOneParticleBeyondHalfTheSkin2D) {
  check_one_mover<2>();
}
TEST(NeighborSkin, AnyOneParticleBeyondHalfTheSkin3D) {
  check_one_mover<3>();
}

}  // namespace
}  // namespace sphdem
