#pragma once
// Monaghan (2000) tensile-instability ("anti-clump") term:
//   R_ij f_ij^n with f_ij = W(r_ij) / W(dp), n = 4 by default,
//   R_ij = R_i + R_j, R_a = eps |P_a| / rho_a^2 when P_a < 0, else 0;
//   when both pressures are positive R_ij = 0.01 (P_i/rho_i^2 + P_j/rho_j^2).
// It adds a short-range repulsion that stops particles pairing up where
// the pressure is negative.
// Not at the free surface (numerics.anti_clump_at_surface off, the
// default): R_a = 0 at a particle the free-surface pass flags. A thinning
// front or splash goes into tension only because its continuity density
// falls (a real surface is at the ambient pressure); there R grows as the
// pair stretches and pushes it further apart, a runaway that nothing
// outside the resin contains: impacts blew up (docs/physics.md,
// "Momentum"; tests/test_front.cpp, AntiClumpAtImpacts).
// Written with selects instead of branches so that the pair loop vectorizes.
// Case-file switches: numerics.anti_clump, anti_clump_epsilon,
// anti_clump_exponent (n = 4 is a compile-time fast path, f^4 = (f^2)^2).
#include <cstddef>

#include "../record_fields.hpp"
#include "pressure.hpp"

namespace sphdem::terms {

struct FreeSurfaceFlag;  // terms/free_surface.hpp

// Per-particle part R_a (0 for non-negative pressure).
inline double anti_clump_r(double eps, double p_over_rho2) {
  return p_over_rho2 < 0.0 ? -eps * p_over_rho2 : 0.0;
}

// R_ij.
inline auto anti_clump_coefficient(auto r_i, auto r_j, auto por2_i, auto por2_j) {
  return (por2_i > 0.0 && por2_j > 0.0) ? 0.01 * (por2_i + por2_j) : r_i + r_j;
}

// f^n for any n >= 0 (a loop: the term has a fast path for n = 4).
inline auto anti_clump_power(auto w_ratio, int n) {
  decltype(w_ratio) f = splat<decltype(w_ratio)>(1.0);
  for (int k = 0; k < n; ++k) f *= w_ratio;
  return f;
}

inline auto anti_clump(auto r_i, auto r_j, auto por2_i, auto por2_j, auto w_ratio, int n) {
  return anti_clump_coefficient(r_i, r_j, por2_i, por2_j) * anti_clump_power(w_ratio, n);
}

namespace field {
// R_a, prepared once per particle (0 on the free surface unless asked).
struct AntiClumpR : ScalarField {
  static constexpr const char* name = "anti_clump_r";
  template <int D>
  static void fill(const SphParams& sp, const SphParticles<D>& ps, std::size_t i, double* out) {
    const bool off = !sp.anti_clump_at_surface && ps.free_surface[i] != 0.0;
    out[0] = off ? 0.0 : anti_clump_r(sp.anti_clump_eps, pressure_over_rho2(ps.p[i], ps.rho[i]));
  }
};
}  // namespace field

struct AntiClump {
  static constexpr const char* name = "anti_clump";
  using Reads = Fields<field::PoR2, field::AntiClumpR>;
  static constexpr unsigned writes = kBracket;
  static constexpr bool kVectorPair = true;
  static bool active(const SphParams& sp) { return sp.anti_clump; }
  // Variant 0: n = 4, f^4 = (f^2)^2. Variant 1: any n.
  static constexpr int variants = 2;
  static int variant(const SphParams& sp) { return sp.anti_clump_n == 4 ? 0 : 1; }
  // R_a reads the free-surface flag, which the pair loop computes on the side
  // when only this term reads it (pair_loop.hpp, PairLoopRun::side).
  using SidePass = FreeSurfaceFlag;

  double kw_over_w_dp;  // W = kw t^4 (1 + 2q), over W(dp): one constant, one product fewer
  int n;
  template <int D>
  explicit AntiClump(const TermContext<D>& c)
      : kw_over_w_dp(c.kw / c.kernel.w(c.sp.spacing)), n(c.sp.anti_clump_n) {}

  template <int V, class P, class Sums>
  void pair(const P& p, Sums& s) const {
    // WendlandC2::w (kernel.hpp) over W(dp), the same operations without the branch.
    const auto t2 = p.t * p.t;
    const auto w_ratio = kw_over_w_dp * t2 * t2 * (1.0 + 2.0 * p.q);
    std::remove_const_t<decltype(w_ratio)> f;
    if constexpr (V == 0) {
      const auto w2 = w_ratio * w_ratio;
      f = w2 * w2;
    } else {
      f = anti_clump_power(w_ratio, n);
    }
    s.bracket +=
        anti_clump_coefficient(p.own_value(field::AntiClumpR{}), p.lane(field::AntiClumpR{}),
                               p.own_value(field::PoR2{}), p.lane(field::PoR2{})) *
        f;
  }
};

}  // namespace sphdem::terms
