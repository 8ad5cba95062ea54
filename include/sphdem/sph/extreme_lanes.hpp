#pragma once
// local_extremes' maxima eight particles at a time (AVX-512), kept in
// registers group by group: local_extremes runs it over every owned
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

}  // namespace sphdem
