#pragma once
// The resin's kick-drift-kick passes (ResinModule::predict and correct,
// docs/physics.md "Time integration"), eight particles at a time with
// AVX-512 and four with AVX2 (docs/performance.md, "The passes over
// particles", "The streaming passes with AVX2"): GCC does not
// vectorize them itself (one-byte kinds beside D-double vectors). Each
// particle's update reads only its own fields; every product that feeds a
// sum is fused, in both forms (lanes::mul_add: where the build has FMA, as
// every AVX-512 build does), so the bits do not depend on the form or on
// the compiler's contraction choices.
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/extreme_lanes.hpp"

namespace sphdem {

namespace leapfrog_detail {

// One pass's step and particle count and the fields' raw arrays; frozen,
// temperature, temp_half and dtemp may be null (the field not held or not
// wanted).
template <int D>
struct Arrays {
  double dt, half;
  std::size_t n;
  const Kind* kind;
  const std::int32_t* frozen;
  double *x, *v, *v_half, *a, *rho, *rho_half, *drho;
  double *temperature, *temp_half, *dtemp;
};

// A vector field's doubles (null when it holds none).
template <int D>
double* doubles(std::vector<Vec<D>>& field) {
  return field.empty() ? nullptr : field.data()->data();
}

template <int D>
Arrays<D> arrays(SphParticles<D>& ps, double dt, bool thermal) {
  return {dt,
          0.5 * dt,
          ps.n_owned,
          ps.kind.data(),
          ps.frozen.empty() ? nullptr : ps.frozen.data(),
          doubles<D>(ps.x),
          doubles<D>(ps.v),
          doubles<D>(ps.v_half),
          doubles<D>(ps.a),
          ps.rho.data(),
          ps.rho_half.data(),
          ps.drho.data(),
          thermal ? ps.temperature.data() : nullptr,
          thermal ? ps.temp_half.data() : nullptr,
          thermal ? ps.dtemp.data() : nullptr};
}

// Particle i of the first kick and the drift.
template <int D>
void kick_drift_one(const Arrays<D>& p, std::size_t i) {
  const double dt = p.dt, half = p.half;
  if (p.kind[i] != Kind::Fluid) return;
  const bool still = p.frozen != nullptr && p.frozen[i] != 0;
  for (int d = 0; d < D; ++d) {
    const std::size_t k = D * i + static_cast<std::size_t>(d);
    const double vh = still ? 0.0 : lanes::mul_add(half, p.a[k], p.v[k]);
    p.v_half[k] = vh;
    p.x[k] = lanes::mul_add(dt, vh, p.x[k]);
    p.v[k] = lanes::mul_add(half, p.a[k], vh);
  }
  p.rho_half[i] = lanes::mul_add(half, p.drho[i], p.rho[i]);
  p.rho[i] = lanes::mul_add(half, p.drho[i], p.rho_half[i]);
}

// Particle i's density (and temperature) kick.
template <int D>
void kick_density_one(const Arrays<D>& p, std::size_t i) {
  p.rho[i] = lanes::mul_add(p.half, p.drho[i], p.rho_half[i]);
  if (p.temperature != nullptr)
    p.temperature[i] = lanes::mul_add(p.half, p.dtemp[i], p.temp_half[i]);
}

// Particle i of the second kick.
template <int D>
void kick_one(const Arrays<D>& p, std::size_t i, bool density) {
  const double half = p.half;
  if (p.kind[i] != Kind::Fluid) return;
  const bool still = p.frozen != nullptr && p.frozen[i] != 0;
  for (int d = 0; d < D; ++d) {
    const std::size_t k = D * i + static_cast<std::size_t>(d);
    if (still) p.a[k] = 0.0;
    p.v[k] = lanes::mul_add(half, p.a[k], p.v_half[k]);
  }
  if (density) kick_density_one<D>(p, i);
}

#if defined(SPHDEM_PARTICLE_LANES)
// Calls group(i, resin, frozen) for each whole group of eight particles
// i .. i + 7 that holds some resin (bit l: particle i + l is resin, is
// frozen resin); returns the first particle after the last whole group.
template <int D, class Group>
std::size_t resin_groups(const Arrays<D>& p, Group&& group) {
  std::size_t i = 0;
  for (; i + 8 <= p.n; i += 8) {
    const __mmask8 fluid = lanes::resin(p.kind, i);
    if (fluid == 0) continue;
    group(i, fluid, p.frozen != nullptr ? lanes::set(p.frozen, i) & fluid : __mmask8{0});
  }
  return i;
}
#endif

#if defined(SPHDEM_PARTICLE_LANES4)
// Without AVX-512, four particles at a time (AVX2): each register's doubles
// are computed for all four and blended into what was there, so a wall's
// or a frozen particle's values are stored back as they were read (the
// one-particle form's results, bit for bit: the same fused operations).

// The first kick and the drift of the resin among particles i .. i + 3
// (bits of `fluid`, `frozen` of them frozen).
template <int D>
[[gnu::always_inline]] inline void kick_drift_group4(const Arrays<D>& p, std::size_t i,
                                                     unsigned fluid, unsigned frozen) {
  const __m256d h = _mm256_set1_pd(p.half), t = _mm256_set1_pd(p.dt);
  for (int q = 0; q < D; ++q) {
    const std::size_t k = D * i + 4 * static_cast<std::size_t>(q);
    const __m256d m = lanes::vector_mask4<D>(fluid, q);
    const __m256d a = _mm256_loadu_pd(p.a + k), x = _mm256_loadu_pd(p.x + k);
    const __m256d v = _mm256_loadu_pd(p.v + k);
    // A frozen particle's half-step velocity is +0, as the one-particle form's.
    const __m256d vh =
        _mm256_andnot_pd(lanes::vector_mask4<D>(frozen, q), _mm256_fmadd_pd(h, a, v));
    _mm256_storeu_pd(p.v_half + k, _mm256_blendv_pd(_mm256_loadu_pd(p.v_half + k), vh, m));
    _mm256_storeu_pd(p.x + k, _mm256_blendv_pd(x, _mm256_fmadd_pd(t, vh, x), m));
    _mm256_storeu_pd(p.v + k, _mm256_blendv_pd(v, _mm256_fmadd_pd(h, a, vh), m));
  }
  const __m256d m = lanes::vector_mask4<1>(fluid, 0);
  const __m256d drho = _mm256_loadu_pd(p.drho + i), rho = _mm256_loadu_pd(p.rho + i);
  const __m256d rh = _mm256_fmadd_pd(h, drho, rho);
  _mm256_storeu_pd(p.rho_half + i, _mm256_blendv_pd(_mm256_loadu_pd(p.rho_half + i), rh, m));
  _mm256_storeu_pd(p.rho + i, _mm256_blendv_pd(rho, _mm256_fmadd_pd(h, drho, rh), m));
}

// The second kick of the resin among particles i .. i + 3 (bits of
// `fluid`, `frozen` of them frozen).
template <int D>
[[gnu::always_inline]] inline void kick_group4(const Arrays<D>& p, std::size_t i, unsigned fluid,
                                               unsigned frozen, bool density) {
  const __m256d h = _mm256_set1_pd(p.half);
  for (int q = 0; q < D; ++q) {
    const std::size_t k = D * i + 4 * static_cast<std::size_t>(q);
    const __m256d m = lanes::vector_mask4<D>(fluid, q);
    __m256d a = _mm256_loadu_pd(p.a + k);
    if (frozen != 0) {
      a = _mm256_andnot_pd(lanes::vector_mask4<D>(frozen, q), a);
      _mm256_storeu_pd(p.a + k, a);
    }
    _mm256_storeu_pd(p.v + k,
                     _mm256_blendv_pd(_mm256_loadu_pd(p.v + k),
                                      _mm256_fmadd_pd(h, a, _mm256_loadu_pd(p.v_half + k)), m));
  }
  if (!density) return;
  const __m256d m = lanes::vector_mask4<1>(fluid, 0);
  const __m256d rho =
      _mm256_fmadd_pd(h, _mm256_loadu_pd(p.drho + i), _mm256_loadu_pd(p.rho_half + i));
  _mm256_storeu_pd(p.rho + i, _mm256_blendv_pd(_mm256_loadu_pd(p.rho + i), rho, m));
  if (p.temperature != nullptr) {
    const __m256d temp =
        _mm256_fmadd_pd(h, _mm256_loadu_pd(p.dtemp + i), _mm256_loadu_pd(p.temp_half + i));
    _mm256_storeu_pd(p.temperature + i,
                     _mm256_blendv_pd(_mm256_loadu_pd(p.temperature + i), temp, m));
  }
}

// Calls group(i, resin, frozen) for each whole group of four particles
// i .. i + 3 that holds some resin; returns the first particle after the
// last whole group.
template <int D, class Group>
std::size_t resin_groups4(const Arrays<D>& p, Group&& group) {
  std::size_t i = 0;
  for (; i + 4 <= p.n; i += 4) {
    const unsigned fluid = lanes::resin4(p.kind, i);
    if (fluid == 0) continue;
    group(i, fluid, p.frozen != nullptr ? lanes::set4(p.frozen, i) & fluid : 0u);
  }
  return i;
}
#endif

}  // namespace leapfrog_detail

#if defined(SPHDEM_PARTICLE_LANES)
namespace leapfrog_detail {

// The first kick and the drift of the resin among particles i .. i + 7
// (bits of `fluid`, `frozen` of them frozen).
template <int D>
[[gnu::always_inline]] inline void kick_drift_group(const Arrays<D>& p, std::size_t i,
                                                    __mmask8 fluid, __mmask8 frozen) {
  const __m512d h = _mm512_set1_pd(p.half), t = _mm512_set1_pd(p.dt);
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

}  // namespace leapfrog_detail
#endif

// The first kick of the velocity and the density and the drift of the
// owned resin particles; a frozen particle (resin.thermal) keeps its
// position at zero velocity.
template <int D>
void kick_drift_resin(SphParticles<D>& ps, double dt) {
  using namespace leapfrog_detail;
  const Arrays<D> p = arrays(ps, dt, false);
  std::size_t at = 0;  // the first particle left to the one-particle form
#if defined(SPHDEM_PARTICLE_LANES)
  at = resin_groups<D>(p, [&](std::size_t i, __mmask8 fluid, __mmask8 frozen) {
    kick_drift_group<D>(p, i, fluid, frozen);
  });
#elif defined(SPHDEM_PARTICLE_LANES4)
  at = resin_groups4<D>(p, [&](std::size_t i, unsigned fluid, unsigned frozen) {
    kick_drift_group4<D>(p, i, fluid, frozen);
  });
#endif
  for (; at < p.n; ++at) kick_drift_one<D>(p, at);
}

// kick_drift_resin, then nl.needs_rebuild(ps): with AVX-512 the check of
// every owned particle runs on the positions just written, group by group
// while they are in cache (the same test, NeighborList::moved_too_far), so
// the step reads the positions once for both. With `box` (AVX-512 only;
// other forms leave it empty), the pass also gives nl.move_box(ps).
template <int D>
bool kick_drift_resin_and_check(
    SphParticles<D>& ps, double dt, const NeighborList<D>& nl,
    [[maybe_unused]] std::optional<typename NeighborList<D>::MoveBox>* box = nullptr) {
#if defined(SPHDEM_PARTICLE_LANES)
  using namespace leapfrog_detail;
  if (nl.positions_at_build() != ps.n_owned) {  // needs_rebuild's first answer
    kick_drift_resin<D>(ps, dt);
    // An infinite box: every rank that asked gets one, so every rank joins
    // the same reduction in ResinModule::moved.
    if (box != nullptr) *box = nl.move_box(ps);
    return true;
  }
  const Arrays<D> p = arrays(ps, dt, false);
  bool moved = false;
  typename NeighborList<D>::MoveLanes moves;
  std::size_t i = 0;
  for (; i + 8 <= p.n; i += 8) {
    const __mmask8 fluid = lanes::resin(p.kind, i);
    if (fluid != 0)
      kick_drift_group<D>(p, i, fluid,
                          p.frozen != nullptr ? lanes::set(p.frozen, i) & fluid : __mmask8{0});
    if (box != nullptr)
      moved = nl.add_moves(p.x, i, lanes::first(8), !moved, moves) || moved;
    else
      moved = moved || nl.moved_too_far(p.x, i, lanes::first(8));
  }
  if (i < p.n) {
    for (std::size_t j = i; j < p.n; ++j) kick_drift_one<D>(p, j);
    if (box != nullptr)
      moved = nl.add_moves(p.x, i, lanes::first(p.n - i), !moved, moves) || moved;
    else
      moved = moved || nl.moved_too_far(p.x, i, lanes::first(p.n - i));
  }
  if (box != nullptr) *box = moves.box();
  return moved;
#elif defined(SPHDEM_PARTICLE_LANES4)
  using namespace leapfrog_detail;
  if (nl.positions_at_build() != ps.n_owned) {  // needs_rebuild's first answer
    kick_drift_resin<D>(ps, dt);
    return true;
  }
  const Arrays<D> p = arrays(ps, dt, false);
  bool moved = false;
  std::size_t i = 0;
  for (; i + 4 <= p.n; i += 4) {
    const unsigned fluid = lanes::resin4(p.kind, i);
    if (fluid != 0)
      kick_drift_group4<D>(p, i, fluid,
                           p.frozen != nullptr ? lanes::set4(p.frozen, i) & fluid : 0u);
    moved = moved || nl.moved_too_far4(p.x, i);
  }
  if (i < p.n) {
    for (std::size_t j = i; j < p.n; ++j) kick_drift_one<D>(p, j);
    moved = moved || nl.moved_too_far(p.x, i, p.n - i);
  }
  return moved;
#else
  kick_drift_resin<D>(ps, dt);
  return nl.needs_rebuild(ps);
#endif
}

#if defined(SPHDEM_PARTICLE_LANES)
namespace leapfrog_detail {

// The second kick of the resin among particles i .. i + 7 (bits of
// `fluid`, `frozen` of them frozen).
template <int D>
[[gnu::always_inline]] inline void kick_group(const Arrays<D>& p, std::size_t i, __mmask8 fluid,
                                              __mmask8 frozen, bool density) {
  const __m512d h = _mm512_set1_pd(p.half);
  for (int q = 0; q < D; ++q) {
    const std::size_t k = D * i + 8 * static_cast<std::size_t>(q);
    const __mmask8 m = lanes::vector_mask<D>(fluid, q), still = lanes::vector_mask<D>(frozen, q);
    if (still != 0) _mm512_mask_storeu_pd(p.a + k, still, _mm512_setzero_pd());
    const __m512d a = _mm512_maskz_loadu_pd(m, p.a + k);
    _mm512_mask_storeu_pd(p.v + k, m,
                          _mm512_fmadd_pd(h, a, _mm512_maskz_loadu_pd(m, p.v_half + k)));
  }
  if (!density) return;
  const __m512d rh = _mm512_maskz_loadu_pd(fluid, p.rho_half + i);
  _mm512_mask_storeu_pd(p.rho + i, fluid,
                        _mm512_fmadd_pd(h, _mm512_maskz_loadu_pd(fluid, p.drho + i), rh));
  if (p.temperature != nullptr) {
    const __m512d th = _mm512_maskz_loadu_pd(fluid, p.temp_half + i);
    _mm512_mask_storeu_pd(p.temperature + i, fluid,
                          _mm512_fmadd_pd(h, _mm512_maskz_loadu_pd(fluid, p.dtemp + i), th));
  }
}

}  // namespace leapfrog_detail
#endif

// The second kick of the owned resin particles' velocities (a frozen
// particle's acceleration is zeroed first) and, with `density`, of their
// densities (and, with `thermal`, temperatures).
template <int D>
void kick_resin(SphParticles<D>& ps, double dt, bool density, bool thermal) {
  using namespace leapfrog_detail;
  const Arrays<D> p = arrays(ps, dt, thermal);
  std::size_t at = 0;  // the first particle left to the one-particle form
#if defined(SPHDEM_PARTICLE_LANES)
  at = resin_groups<D>(p, [&](std::size_t i, __mmask8 fluid, __mmask8 frozen) {
    kick_group<D>(p, i, fluid, frozen, density);
  });
#elif defined(SPHDEM_PARTICLE_LANES4)
  at = resin_groups4<D>(p, [&](std::size_t i, unsigned fluid, unsigned frozen) {
    kick_group4<D>(p, i, fluid, frozen, density);
  });
#endif
  for (; at < p.n; ++at) kick_one<D>(p, at, density);
}

// kick_resin, then local_extremes(ps): with AVX-512 the maxima of every
// owned particle are taken on the velocities and accelerations just
// written, group by group while they are in cache (the same operations,
// ExtremeLanes), so the step reads them once for the kick and the next
// step's time step (ResinModule::correct).
template <int D>
LocalExtremes kick_resin_and_extremes(SphParticles<D>& ps, double dt, bool density, bool thermal) {
#if defined(SPHDEM_PARTICLE_LANES)
  using namespace leapfrog_detail;
  const Arrays<D> p = arrays(ps, dt, thermal);
  ExtremeLanes<D> ex;
  std::size_t i = 0;
  for (; i + 8 <= p.n; i += 8) {
    const __mmask8 fluid = lanes::resin(p.kind, i);
    if (fluid != 0)
      kick_group<D>(p, i, fluid,
                    p.frozen != nullptr ? lanes::set(p.frozen, i) & fluid : __mmask8{0}, density);
    ex.add(ps, i, lanes::first(8));
  }
  if (i < p.n) {
    for (std::size_t j = i; j < p.n; ++j) kick_one<D>(p, j, density);
    ex.add(ps, i, lanes::first(p.n - i));
  }
  return ex.result();
#elif defined(SPHDEM_PARTICLE_LANES4)
  using namespace leapfrog_detail;
  const Arrays<D> p = arrays(ps, dt, thermal);
  ExtremesOneByOne<D> ex;
  std::size_t i = 0;
  for (; i + 4 <= p.n; i += 4) {
    const unsigned fluid = lanes::resin4(p.kind, i);
    if (fluid != 0)
      kick_group4<D>(p, i, fluid, p.frozen != nullptr ? lanes::set4(p.frozen, i) & fluid : 0u,
                     density);
    ex.add4(ps, i);
  }
  for (std::size_t j = i; j < p.n; ++j) kick_one<D>(p, j, density);
  ex.add(ps, i, p.n);
  return ex.result();
#else
  kick_resin<D>(ps, dt, density, thermal);
  return local_extremes<D>(ps);
#endif
}

// The density (and, with `thermal`, temperature) kick alone, after an
// implicit viscous solve (ResinModule::correct).
template <int D>
void kick_density_resin(SphParticles<D>& ps, double dt, bool thermal) {
  const leapfrog_detail::Arrays<D> p = leapfrog_detail::arrays(ps, dt, thermal);
  for (std::size_t i = 0; i < p.n; ++i)
    if (p.kind[i] == Kind::Fluid) leapfrog_detail::kick_density_one<D>(p, i);
}

}  // namespace sphdem
