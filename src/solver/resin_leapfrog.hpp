#pragma once
// The resin's kick-drift-kick passes (ResinModule::predict and correct,
// docs/physics.md "Time integration"), eight particles at a time with
// AVX-512 (docs/performance.md, "The passes over particles"): GCC does not
// vectorize them itself (one-byte kinds beside D-double vectors). Each
// particle's update reads only its own fields; every product that feeds a
// sum is fused, in both forms, so the bits do not depend on the form or on
// the compiler's contraction choices.
#include <cmath>
#include <cstdint>

#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

namespace leapfrog_detail {

// The raw arrays of one pass; frozen, temperature, temp_half and dtemp may
// be null (the field not held or not wanted).
template <int D>
struct Arrays {
  const Kind* kind;
  const std::int32_t* frozen;
  double *x, *v, *v_half, *a, *rho, *rho_half, *drho;
  double *temperature, *temp_half, *dtemp;
};

template <int D>
Arrays<D> arrays(SphParticles<D>& ps, bool thermal) {
  return {ps.kind.data(),
          ps.frozen.empty() ? nullptr : ps.frozen.data(),
          ps.x.data()->data(),
          ps.v.data()->data(),
          ps.v_half.data()->data(),
          ps.a.data()->data(),
          ps.rho.data(),
          ps.rho_half.data(),
          ps.drho.data(),
          thermal ? ps.temperature.data() : nullptr,
          thermal ? ps.temp_half.data() : nullptr,
          thermal ? ps.dtemp.data() : nullptr};
}

// Particle i of the first kick and the drift.
template <int D>
void kick_drift_one(const Arrays<D>& p, std::size_t i, double dt, double half) {
  if (p.kind[i] != Kind::Fluid) return;
  const bool still = p.frozen != nullptr && p.frozen[i] != 0;
  for (int d = 0; d < D; ++d) {
    const std::size_t k = D * i + static_cast<std::size_t>(d);
    const double vh = still ? 0.0 : std::fma(half, p.a[k], p.v[k]);
    p.v_half[k] = vh;
    p.x[k] = std::fma(dt, vh, p.x[k]);
    p.v[k] = std::fma(half, p.a[k], vh);
  }
  p.rho_half[i] = std::fma(half, p.drho[i], p.rho[i]);
  p.rho[i] = std::fma(half, p.drho[i], p.rho_half[i]);
}

// Particle i of the second kick.
template <int D>
void kick_one(const Arrays<D>& p, std::size_t i, double half, bool density) {
  if (p.kind[i] != Kind::Fluid) return;
  const bool still = p.frozen != nullptr && p.frozen[i] != 0;
  for (int d = 0; d < D; ++d) {
    const std::size_t k = D * i + static_cast<std::size_t>(d);
    if (still) p.a[k] = 0.0;
    p.v[k] = std::fma(half, p.a[k], p.v_half[k]);
  }
  if (density) {
    p.rho[i] = std::fma(half, p.drho[i], p.rho_half[i]);
    if (p.temperature != nullptr) p.temperature[i] = std::fma(half, p.dtemp[i], p.temp_half[i]);
  }
}

}  // namespace leapfrog_detail

// The first kick of the velocity and the density and the drift of the
// owned resin particles; a frozen particle (resin.thermal) keeps its
// position at zero velocity.
template <int D>
void kick_drift_resin(SphParticles<D>& ps, double dt) {
  using namespace leapfrog_detail;
  const std::size_t n = ps.n_owned;
  if (n == 0) return;
  const double half = 0.5 * dt;
  const Arrays<D> p = arrays(ps, false);
  std::size_t i = 0;
#if defined(SPHDEM_PARTICLE_LANES)
  const __m512d h = _mm512_set1_pd(half), t = _mm512_set1_pd(dt);
  for (; i + 8 <= n; i += 8) {
    const __mmask8 fluid = lanes::resin(p.kind, i);
    if (fluid == 0) continue;
    const __mmask8 frozen = p.frozen != nullptr ? lanes::set(p.frozen, i) & fluid : 0;
    for (int q = 0; q < D; ++q) {
      const std::size_t k = D * i + 8 * static_cast<std::size_t>(q);
      const __mmask8 m = lanes::vector_mask<D>(fluid, q);
      const __m512d a = _mm512_maskz_loadu_pd(m, p.a + k);
      const __m512d vh =
          _mm512_maskz_mov_pd(static_cast<__mmask8>(~lanes::vector_mask<D>(frozen, q)),
                              _mm512_fmadd_pd(h, a, _mm512_maskz_loadu_pd(m, p.v + k)));
      _mm512_mask_storeu_pd(p.v_half + k, m, vh);
      _mm512_mask_storeu_pd(p.x + k, m, _mm512_fmadd_pd(t, vh, _mm512_maskz_loadu_pd(m, p.x + k)));
      _mm512_mask_storeu_pd(p.v + k, m, _mm512_fmadd_pd(h, a, vh));
    }
    const __m512d drho = _mm512_maskz_loadu_pd(fluid, p.drho + i);
    const __m512d rh = _mm512_fmadd_pd(h, drho, _mm512_maskz_loadu_pd(fluid, p.rho + i));
    _mm512_mask_storeu_pd(p.rho_half + i, fluid, rh);
    _mm512_mask_storeu_pd(p.rho + i, fluid, _mm512_fmadd_pd(h, drho, rh));
  }
#endif
  for (; i < n; ++i) kick_drift_one<D>(p, i, dt, half);
}

// The second kick of the owned resin particles' velocities (a frozen
// particle's acceleration is zeroed first) and, with `density`, of their
// densities (and, with `thermal`, temperatures).
template <int D>
void kick_resin(SphParticles<D>& ps, double dt, bool density, bool thermal) {
  using namespace leapfrog_detail;
  const std::size_t n = ps.n_owned;
  if (n == 0) return;
  const double half = 0.5 * dt;
  const Arrays<D> p = arrays(ps, thermal);
  std::size_t i = 0;
#if defined(SPHDEM_PARTICLE_LANES)
  const __m512d h = _mm512_set1_pd(half);
  for (; i + 8 <= n; i += 8) {
    const __mmask8 fluid = lanes::resin(p.kind, i);
    if (fluid == 0) continue;
    const __mmask8 frozen = p.frozen != nullptr ? lanes::set(p.frozen, i) & fluid : 0;
    for (int q = 0; q < D; ++q) {
      const std::size_t k = D * i + 8 * static_cast<std::size_t>(q);
      const __mmask8 m = lanes::vector_mask<D>(fluid, q), still = lanes::vector_mask<D>(frozen, q);
      if (still != 0) _mm512_mask_storeu_pd(p.a + k, still, _mm512_setzero_pd());
      const __m512d a = _mm512_maskz_loadu_pd(m, p.a + k);
      _mm512_mask_storeu_pd(p.v + k, m,
                            _mm512_fmadd_pd(h, a, _mm512_maskz_loadu_pd(m, p.v_half + k)));
    }
    if (density) {
      const __m512d rh = _mm512_maskz_loadu_pd(fluid, p.rho_half + i);
      _mm512_mask_storeu_pd(p.rho + i, fluid,
                            _mm512_fmadd_pd(h, _mm512_maskz_loadu_pd(fluid, p.drho + i), rh));
      if (p.temperature != nullptr) {
        const __m512d th = _mm512_maskz_loadu_pd(fluid, p.temp_half + i);
        _mm512_mask_storeu_pd(p.temperature + i, fluid,
                              _mm512_fmadd_pd(h, _mm512_maskz_loadu_pd(fluid, p.dtemp + i), th));
      }
    }
  }
#endif
  for (; i < n; ++i) kick_one<D>(p, i, half, density);
}

}  // namespace sphdem
