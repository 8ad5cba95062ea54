#pragma once
// local_extremes' maxima eight particles at a time (AVX-512; with AVX2,
// ExtremesOneByOne below, four at a time in 2D), kept in registers group by
// group: local_extremes runs it over every owned
// particle, and the second kick over each group it has just written
// (kick_resin_and_extremes, src/solver/resin_leapfrog.hpp), so a step
// reads the velocities and accelerations once for both.
#include <cmath>

#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

#if defined(SPHDEM_PARTICLE_LANES)
template <int D>
class ExtremeLanes {
 public:
  // Particles i .. i + 7 (`valid` of them): |v|^2 of every one, |a|^2 and
  // the viscosity of the resin that is not frozen. |u|^2 is x x + y y with
  // each product rounded, then fma(z, z, .) in 3D (the one-particle form's
  // operations, time_step.cpp); a NaN never replaces a maximum.
  void add(const SphParticles<D>& ps, std::size_t i, __mmask8 valid) {
    __m512d r[D];
    lanes::load_vectors<D>(ps.v.data()->data(), i, valid, r);
    v2_ = lanes::max(squared_norms(r), v2_);
    __mmask8 moving = lanes::of_kind(ps.kind.data(), i, valid, Kind::Fluid);
    if (!ps.frozen.empty())
      moving &= static_cast<__mmask8>(~lanes::set(ps.frozen.data(), i, valid));
    if (moving == 0) return;
    lanes::load_vectors<D>(ps.a.data()->data(), i, moving, r);
    a2_ = _mm512_mask_max_pd(a2_, moving, squared_norms(r), a2_);
    if (!ps.viscosity.empty())
      mu_ = _mm512_mask_max_pd(mu_, moving, _mm512_maskz_loadu_pd(moving, ps.viscosity.data() + i),
                               mu_);
  }
  // The largest speed, acceleration and viscosity of the particles added.
  LocalExtremes result() const {
    return {std::sqrt(lanes::largest(v2_)), std::sqrt(lanes::largest(a2_)), lanes::largest(mu_)};
  }

 private:
  static __m512d squared_norms(const __m512d (&r)[D]) {
    const __m512d x = lanes::component<D>(r, 0), y = lanes::component<D>(r, 1);
    __m512d n2 = lanes::add(lanes::mul(x, x), lanes::mul(y, y));  // not fused
    if constexpr (D == 3) {
      const __m512d z = lanes::component<D>(r, 2);
      n2 = _mm512_fmadd_pd(z, z, n2);
    }
    return n2;
  }
  __m512d v2_ = _mm512_setzero_pd(), a2_ = _mm512_setzero_pd(), mu_ = _mm512_setzero_pd();
};
#endif

#if defined(SPHDEM_PARTICLE_LANES4)
// local_extremes' maxima particle by particle over ranges, for the second
// kick of four particles at a time (kick_resin_and_extremes): the
// operations of local_extremes' one-particle form (time_step.cpp), each
// product rounded on its own (an empty asm hides it from GCC's fusion into
// the sum, as that form's fp-contract=off does).
template <int D>
class ExtremesOneByOne {
 public:
  // Particles i .. i + 3: in 2D four at a time (AVX2), with the same
  // operations, each lane's sums rounded as the one-particle form's.
  void add4(const SphParticles<D>& ps, std::size_t i) {
    if constexpr (D == 2) {
      const double* const v = ps.v[i].data();
      v2_lanes_ = _mm256_max_pd(squared_norms(_mm256_loadu_pd(v)), v2_lanes_);
      v2_lanes_ = _mm256_max_pd(squared_norms(_mm256_loadu_pd(v + 4)), v2_lanes_);
      unsigned moving = lanes::resin4(ps.kind.data(), i);
      if (!ps.frozen.empty()) moving &= ~lanes::set4(ps.frozen.data(), i);
      if (moving == 0) return;
      // Lanes of other particles read +0, which no maximum (from +0 up) takes.
      const double* const a = ps.a[i].data();
      for (int q = 0; q < 2; ++q) {
        const __m256d a2 = squared_norms(_mm256_loadu_pd(a + 4 * q));
        a2_lanes_ = _mm256_max_pd(_mm256_and_pd(lanes::vector_mask4<2>(moving, q), a2), a2_lanes_);
      }
      if (!ps.viscosity.empty()) {
        const __m256d mu = _mm256_loadu_pd(ps.viscosity.data() + i);
        mu_lanes_ = _mm256_max_pd(_mm256_and_pd(lanes::vector_mask4<1>(moving, 0), mu), mu_lanes_);
      }
    } else {
      add(ps, i, i + 4);
    }
  }
  // Particles [begin, end).
  void add(const SphParticles<D>& ps, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double vi = squared_norm(ps.v[i].data());
      v2_ = vi > v2_ ? vi : v2_;  // a NaN keeps the maximum
      if (ps.kind[i] != Kind::Fluid || (!ps.frozen.empty() && ps.frozen[i] != 0)) continue;
      const double ai = squared_norm(ps.a[i].data());
      a2_ = ai > a2_ ? ai : a2_;
      if (!ps.viscosity.empty()) mu_ = ps.viscosity[i] > mu_ ? ps.viscosity[i] : mu_;
    }
  }
  LocalExtremes result() const {
    return {std::sqrt(largest(v2_lanes_, v2_)), std::sqrt(largest(a2_lanes_, a2_)),
            largest(mu_lanes_, mu_)};
  }

 private:
  // Lane 2 l and 2 l + 1: |u|^2 of the two particles' 2D vectors u (x x +
  // y y, each product rounded, in both lanes: a sum does not depend on its
  // order). max(new, old) keeps old where new is a NaN.
  static __m256d squared_norms(__m256d u) {
    __m256d p = _mm256_mul_pd(u, u);
    __asm__("" : "+x"(p));  // no fusion of a product into the sum
    return _mm256_add_pd(p, _mm256_permute_pd(p, 0b0101));
  }
  // The largest of the lanes and of m (none NaN).
  static double largest(__m256d lanes, double m) {
    alignas(32) double l[4];
    _mm256_store_pd(l, lanes);
    for (const double x : l) m = x > m ? x : m;
    return m;
  }
  __m256d v2_lanes_ = _mm256_setzero_pd(), a2_lanes_ = _mm256_setzero_pd(),
          mu_lanes_ = _mm256_setzero_pd();
  static double rounded_product(double a, double b) {
    double p = a * b;
    __asm__("" : "+x"(p));
    return p;
  }
  static double squared_norm(const double* u) {
    double n2 = rounded_product(u[0], u[0]) + rounded_product(u[1], u[1]);
    if constexpr (D == 3) n2 = lanes::mul_add(u[2], u[2], n2);
    return n2;
  }
  double v2_ = 0.0, a2_ = 0.0, mu_ = 0.0;
};
#endif

}  // namespace sphdem
