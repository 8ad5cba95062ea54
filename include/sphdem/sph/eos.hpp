#pragma once
// Tait equation of state (docs/physics.md): P = B ((rho/rho0)^gamma - 1),
// B = c0^2 rho0 / gamma, a gauge pressure: relative to the ambient (air)
// pressure Pa, which acts at the free surface and the wall floors
// (resin.ambient_pressure, docs/physics.md "Ambient pressure"), never in the
// bulk. gamma = 7 takes a fast path.
#include <cmath>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace sphdem {

class TaitEos {
 public:
  TaitEos(double rho0, double c0, double gamma = 7.0)
      : rho0_(rho0), c0_(c0), gamma_(gamma), b_(c0 * c0 * rho0 / gamma) {}

  double pressure(double rho) const {
    const double s = rho / rho0_;
    if (gamma_ == 7.0) {
      const double s2 = s * s;
      return b_ * (s2 * s2 * s2 * s - 1.0);
    }
    return b_ * (std::pow(s, gamma_) - 1.0);
  }

  // Inverse: the density at which the pressure is p. Pressures below -B
  // map to a tiny positive density instead of NaN.
  // At zero pressure (a wall held at its floor: often most of them) the
  // answer is rho0 without pow: pow(1, y) is exactly 1.
  double density(double p) const {
    if (p == 0.0) return rho0_;
    const double base = p / b_ + 1.0;
    return rho0_ * std::pow(base > 1e-12 ? base : 1e-12, 1.0 / gamma_);
  }

  double rho0() const { return rho0_; }
  double c0() const { return c0_; }
  double gamma() const { return gamma_; }
  double b() const { return b_; }

 private:
  double rho0_, c0_, gamma_, b_;
};

#if defined(__AVX512F__)
// TaitEos::pressure of eight densities on its gamma = 7 path (the caller
// checks gamma()), with its operations in its order: each lane has its bits.
inline __m512d tait_pressure7(const TaitEos& eos, __m512d rho) {
  const __m512d s = _mm512_div_pd(rho, _mm512_set1_pd(eos.rho0()));
  const __m512d s2 = _mm512_mul_pd(s, s);
  const __m512d s7 = _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(s2, s2), s2), s);
  return _mm512_mul_pd(_mm512_set1_pd(eos.b()), _mm512_sub_pd(s7, _mm512_set1_pd(1.0)));
}
#endif
#if defined(__AVX__)
// The same for four densities (AVX).
inline __m256d tait_pressure7(const TaitEos& eos, __m256d rho) {
  const __m256d s = _mm256_div_pd(rho, _mm256_set1_pd(eos.rho0()));
  const __m256d s2 = _mm256_mul_pd(s, s);
  const __m256d s7 = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(s2, s2), s2), s);
  return _mm256_mul_pd(_mm256_set1_pd(eos.b()), _mm256_sub_pd(s7, _mm256_set1_pd(1.0)));
}
#endif

}  // namespace sphdem
