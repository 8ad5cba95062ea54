#pragma once
// Free-surface detection, a neighbour-sum pass (pass_loop.hpp), per resin
// particle i over every neighbour j (resin and wall), V_j = m_j / rho_j,
// grad W_ij = F_ij x_ij (lattice-corrected):
//   div r_i = -sum_j V_j F_ij |x_ij|^2                 (D inside the resin)
//   grad C_i = sum_j V_j grad W_ij                      (0 inside, points inward at the surface)
//   grad C~_i = sum_j V_j (1 + 0.2 (W_ij / W(dp))^4) grad W_ij
// i is on the free surface when div r_i < 1.5 (2D) or 2.4 (3D) (Lee et al.
// 2008, JCP 227:8417; Lind et al. 2012, JCP 231:1499), with the outward
// unit normal n_i = -grad C_i / |grad C_i|; grad C~ (with Lind's tensile
// correction) drives particle shifting (src/sph/particle_shifting.cpp).
// docs/physics.md, "Free surface". output.fields: free_surface,
// surface_normal, position_divergence.
//
// When only the anti-clump term reads the flag (no shifting, no front
// events, none of the three fields in output.fields) the pass runs as its
// Lite, FreeSurfaceFlag: div r alone (no normal, no gradient), and only at
// the particles where the term reads the flag, those with P < 0 (R_a = 0 at
// P >= 0 whatever the flag). The flag there is the same bits as the full
// pass's; elsewhere it is 0 and nothing reads it (docs/performance.md,
// "The free-surface pass for the anti-clump term"; tests/test_free_surface.cpp,
// FreeSurfaceFlag.*).
#include <cmath>
#include <cstddef>
#include <vector>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "../record_fields.hpp"
#include "anti_clump.hpp"
#include "pressure.hpp"

namespace sphdem::terms {

// The divergence of position below which a particle is on the surface.
template <int D>
inline constexpr double kFreeSurfaceThreshold = D == 2 ? 1.5 : 2.4;

namespace field {
struct FreeSurface : ScalarField {
  static constexpr const char* name = "free_surface";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.free_surface[i];
  }
};
}  // namespace field

// This pair's part of div r_i = -sum_j V_j F_ij |x_ij|^2 (one expression for both passes).
template <class P>
auto position_divergence_part(const P& p) {
  const auto vf = p.lane(field::Vol{}) * p.F;
  return -vf * p.r2;
}

// The anti-clump term reads the flag (numerics.anti_clump_at_surface off).
inline bool anti_clump_reads_surface(const SphParams& sp) {
  return sp.anti_clump && sp.anti_clump_eps > 0.0 && !sp.anti_clump_at_surface;
}

// The flag alone, where the anti-clump term reads it: FreeSurfacePass's Lite
// (pass_loop.hpp), run when nothing else needs the free-surface pass.
struct FreeSurfaceFlag {
  using Reads = Fields<field::Pos, field::Vol>;
  static constexpr bool kVectorPair = true;
  template <int D>
  static constexpr std::size_t kSums = 1;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.free_surface;
  }
  static bool needed(const SphParams& sp) { return anti_clump_reads_surface(sp); }
  // R_a (field::AntiClumpR) is 0 whatever the flag unless P < 0: the flag is
  // computed exactly where it changes R_a.
  template <int D>
  static bool wanted(const SphParams& sp, const SphParticles<D>& ps, std::size_t i) {
    return wanted_from(sp, pressure_over_rho2(ps.p[i], ps.rho[i]));
  }
  // The same from P_i / rho_i^2 as particle i's record holds it (field::PoR2
  // is pressure_over_rho2, the same bits): the pair loop asks its records,
  // with no division per particle.
  using WantedFrom = field::PoR2;
  static bool wanted_from(const SphParams& sp, double p_over_rho2) {
    return anti_clump_r(sp.anti_clump_eps, p_over_rho2) != 0.0;
  }
  template <class P, class V>
  void pair(const P& p, V* s) const {
    s[0] = position_divergence_part(p);
  }
  template <int D>
  double finish(const double* sums) const {
    return sums[0] < kFreeSurfaceThreshold<D> ? 1.0 : 0.0;
  }
#if defined(__AVX512F__)
  // Eight particles' flags, wanted_from ? finish : 0 lane by lane, from
  // their P / rho^2 and their sums (the pair loop's eight particles in a
  // row, pair_loop.hpp): the same comparisons and the same product.
  template <int D>
  static __m512d flags8(const SphParams& sp, __m512d p_over_rho2, __m512d sums) {
    const __m512d zero = _mm512_setzero_pd();
    const __mmask8 negative = _mm512_cmp_pd_mask(p_over_rho2, zero, _CMP_LT_OQ);
    const __m512d r =
        _mm512_maskz_mul_round_pd(negative, _mm512_set1_pd(-sp.anti_clump_eps), p_over_rho2,
                                  _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    const __mmask8 wanted = _mm512_cmp_pd_mask(r, zero, _CMP_NEQ_UQ);
    const __mmask8 surface =
        _mm512_mask_cmp_pd_mask(wanted, sums, _mm512_set1_pd(kFreeSurfaceThreshold<D>), _CMP_LT_OQ);
    return _mm512_maskz_mov_pd(surface, _mm512_set1_pd(1.0));
  }
#endif
  // With every V_j > 0 each part -V_j F r^2 is >= 0 (F <= 0; a t rounded
  // just below 0 at the support's edge gives a part some 1e-40 of the
  // threshold, below its rounding), so a sum in list order never falls
  // back: once it reaches the threshold the flag is 0, as after the whole
  // list (a NaN part would give 0 too). The pass stops there: the same bits.
  using SettledIfPositive = field::Vol;
  template <int D>
  static bool settled(const double* sums) {
    return sums[0] >= kFreeSurfaceThreshold<D>;
  }
};

struct FreeSurfacePass {
  static constexpr const char* name = "free_surface";
  // Its other snapshot fields: asking for one of them runs the pass too.
  static constexpr const char* also_outputs[] = {"surface_normal", "position_divergence"};
  using Reads = Fields<field::Pos, field::Vol>;
  using Output = field::FreeSurface;
  static constexpr SphGroup group = SphGroup::FreeSurface;
  template <int D>
  static constexpr std::size_t kSums = 1 + 2 * D;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.free_surface;
  }
  // Particle shifting, the weld-line detection and the surface's viscous
  // traction need it even when no term reads it; the anti-clump term (off at
  // the surface) needs only its Lite.
  static bool needed(const SphParams& sp) {
    return sp.shifting > 0.0 || sp.front_events || sp.free_surface_traction;
  }
  using Lite = FreeSurfaceFlag;

  double kw, inv_w_dp;  // W = kw t^4 (1 + 2q); 1 / W(dp)
  template <int D>
  explicit FreeSurfacePass(const TermContext<D>& c)
      : kw(c.kw), inv_w_dp(1.0 / c.kernel.w(c.sp.spacing)) {}

  // s[0] = div r, s[1..D] = grad C, s[1+D..2D] = grad C~.
  template <class P>
  void pair(const P& p, double* s) const {
    constexpr int D = P::kDim;
    const double vf = p.lane(field::Vol{}) * p.F;
    s[0] = position_divergence_part(p);
    const double t2 = p.t * p.t;
    const double w_ratio = kw * t2 * t2 * (1.0 + 2.0 * p.q) * inv_w_dp;
    const double w2 = w_ratio * w_ratio;
    const double tensile = 1.0 + 0.2 * w2 * w2;
    for (int d = 0; d < D; ++d) {
      const double g = vf * p.lane(field::Pos{}, d);
      s[1 + d] = g;
      s[1 + D + d] = tensile * g;
    }
  }
  template <int D>
  double finish(const double* sums) const {
    return sums[0] < kFreeSurfaceThreshold<D> ? 1.0 : 0.0;
  }
  // The rest of the particle's result (the flag is finish's).
  template <int D>
  void store(const double* sums, SphParticles<D>& ps, std::size_t i) const {
    // Each of these only when an option uses it (drop_unused_fields).
    if (!ps.position_divergence.empty()) ps.position_divergence[i] = sums[0];
    Vec<D> grad_c, grad_ct;
    for (int d = 0; d < D; ++d) {
      grad_c[d] = sums[1 + d];
      grad_ct[d] = sums[1 + D + d];
    }
    const double norm = grad_c.norm();
    const bool surface = sums[0] < kFreeSurfaceThreshold<D> && norm > 0.0;
    if (!ps.surface_normal.empty())
      ps.surface_normal[i] = surface ? Vec<D>(-grad_c / norm) : Vec<D>::Zero();
    if (!ps.shifting_gradient.empty()) ps.shifting_gradient[i] = grad_ct;
  }
  template <int D>
  void clear(SphParticles<D>& ps, std::size_t i) const {
    if (!ps.position_divergence.empty()) ps.position_divergence[i] = 0.0;
    if (!ps.surface_normal.empty()) ps.surface_normal[i] = Vec<D>::Zero();
    if (!ps.shifting_gradient.empty()) ps.shifting_gradient[i] = Vec<D>::Zero();
  }
};

}  // namespace sphdem::terms
