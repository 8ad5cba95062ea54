// The resin's rate loop: one gather pass over each owned resin particle's
// neighbors (resin and wall, owned and ghost) that sums every term of
// src/sph/terms/. The switches are template parameters so that the
// pair loop carries no branch for terms that are off.
//
// Performance layout (docs/performance.md). Per owned resin particle i:
//   1. gather: copy what the pair terms read about each neighbor j from a
//      packed per-particle record (built once per rate evaluation, two
//      cache lines per particle) into short contiguous lane arrays;
//   2. pair terms: one branch-free loop over those lanes that the compiler
//      vectorizes (pairs beyond the support get F = 0, a select instead of
//      a `continue`, and contribute exact zeros);
//   3. sum: add the per-pair contributions in list order.
// The neighbor list is sorted by global id, and step 3 is a plain
// sequential sum in that order, so the result still does not depend on
// the particle layout or the rank count.
#include <algorithm>
#include <cmath>

#include "sphdem/sph.hpp"
#include "terms/anti_clump.hpp"
#include "terms/artificial_viscosity.hpp"
#include "terms/continuity.hpp"
#include "terms/delta_sph.hpp"
#include "terms/pressure.hpp"
#include "terms/viscosity_morris.hpp"

namespace sphdem {

namespace {

// What the pair loop reads about neighbor j. 12 (2D) or 15 (3D) doubles,
// padded to 128 bytes: a neighbor costs two cache lines instead of one line
// in each of eight particle arrays.
template <int D>
struct alignas(64) NeighborRecord {
  double x[D];
  double v[D];   // own velocity (continuity)
  double vw[D];  // velocity seen by the viscous terms (no-slip value for walls)
  double m;
  double rho;
  double vol;    // m / rho
  double por2;   // P / rho^2
  double rac;    // anti-clump R_a
  double fluid;  // 1 for resin, 0 for wall (delta-SPH acts between resin only)
};

// Per-pair lane arrays for a chunk of one particle's list (structure of
// arrays with fixed size, so the pair-term loop runs on contiguous doubles
// at addresses the compiler can see).
constexpr std::size_t kChunk = 64;
template <int D>
struct alignas(64) Lanes {
  double x[D][kChunk];  // x_ij
  double v[D][kChunk];  // v_i - v_j (continuity)
  double w[D][kChunk];  // v_i - vw_j (viscous terms)
  double m[kChunk], rho[kChunk], vol[kChunk], por2[kChunk], rac[kChunk], fluid[kChunk];
  double a[D][kChunk];  // out: acceleration contribution
  double drho[kChunk];  // out: density-rate contribution
};

template <int D>
struct Scratch {
  std::vector<NeighborRecord<D>> rec;
};

enum class Clump { Off, N4, General };

template <int D, bool kVisc, bool kArtVisc, Clump kClump, bool kDelta>
void rates_loop(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                Scratch<D>& s) {
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  const double two_mu = 2.0 * sp.mu * sp.mu_scale / sp.grad_scale;  // F carries grad_scale
  const double grad_scale = sp.grad_scale, eta2 = sp.eta2;
  const double alpha_c0_h = sp.alpha * sp.c0 * sp.h;
  const double delta_h_c0 = sp.delta * sp.h * sp.c0;
  const double inv_w_dp = 1.0 / kernel.w(sp.spacing);
  const double inv_h = 1.0 / sp.h;
  // Wendland C2 normalisation C: W(0) = 16 C exactly (a power of two).
  const double kw = kernel.w(0.0) / 16.0, kf = -10.0 * kw;
  const int clump_n = sp.anti_clump_n;
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
  const std::int32_t* nb = nl.indices();
  const NeighborRecord<D>* rec = s.rec.data();
  Lanes<D> l;

  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const NeighborRecord<D>& ri = rec[i];
    const double rho_i = ri.rho, por2_i = ri.por2, rac_i = ri.rac;
    const double two_mu_over_rho_i = two_mu / rho_i;
    Vec<D> acc = Vec<D>::Zero();
    double drho_sum = 0.0;
    for (std::size_t b = nl.begin(i), e = nl.end(i); b < e; b += kChunk) {
      const std::size_t cnt = std::min(kChunk, e - b);

      // 1. Gather (x_ij, v_ij, and the neighbor's scalars).
      for (std::size_t k = 0; k < cnt; ++k) {
        const NeighborRecord<D>& rj = rec[nb[b + k]];
        for (int d = 0; d < D; ++d) {
          l.x[d][k] = ri.x[d] - rj.x[d];
          l.v[d][k] = ri.v[d] - rj.v[d];
          l.w[d][k] = ri.v[d] - rj.vw[d];
        }
        l.m[k] = rj.m;
        l.rho[k] = rj.rho;
        l.vol[k] = rj.vol;
        l.por2[k] = rj.por2;
        l.rac[k] = rj.rac;
        l.fluid[k] = rj.fluid;
      }

      // 2. Pair terms, branch-free (vectorized). Pairs beyond the support
      // get t = 0, hence F = 0 and W = 0, and contribute exact zeros.
      for (std::size_t k = 0; k < cnt; ++k) {
        double r2 = 0.0, vx = 0.0;
        for (int d = 0; d < D; ++d) r2 += l.x[d][k] * l.x[d][k];
        for (int d = 0; d < D; ++d) vx += l.v[d][k] * l.x[d][k];
        const bool inside = r2 < support2;
        const double r = std::sqrt(r2);
        const double q = r * inv_h;
        const double t = inside ? 2.0 - q : 0.0;
        // WendlandC2::f and ::w (kernel.hpp), same operations, without the branch.
        const double F = kf * t * t * t * inv_h * inv_h * grad_scale;
        const double m_j = l.m[k];
        double drho = terms::continuity(m_j, F, vx);
        if constexpr (kDelta) {
          drho += l.fluid[k] * terms::delta_sph(delta_h_c0, rho_i, l.rho[k], l.vol[k], F);
        }
        double bracket = por2_i + l.por2[k];
        if constexpr (kArtVisc) {
          double wx = 0.0;
          for (int d = 0; d < D; ++d) wx += l.w[d][k] * l.x[d][k];
          bracket += terms::artificial_viscosity(alpha_c0_h, wx, r2, eta2, rho_i, l.rho[k]);
        }
        if constexpr (kClump != Clump::Off) {
          const double t2 = t * t;
          const double w_ratio = kw * t2 * t2 * (1.0 + 2.0 * q) * inv_w_dp;
          double f;
          if constexpr (kClump == Clump::N4) {
            const double w2 = w_ratio * w_ratio;
            f = w2 * w2;
          } else {
            f = terms::anti_clump_power(w_ratio, clump_n);
          }
          bracket += terms::anti_clump_coefficient(rac_i, l.rac[k], por2_i, l.por2[k]) * f;
        }
        const double pf = m_j * bracket * F;
        double visc = 0.0;
        if constexpr (kVisc) {
          visc = terms::morris_viscosity(two_mu_over_rho_i, l.vol[k], F, r2, eta2);
        }
        for (int d = 0; d < D; ++d) l.a[d][k] = visc * l.w[d][k] - pf * l.x[d][k];
        l.drho[k] = drho;
      }

      // 3. Sum in list (global-id) order.
      for (std::size_t k = 0; k < cnt; ++k) {
        for (int d = 0; d < D; ++d) acc[d] += l.a[d][k];
        drho_sum += l.drho[k];
      }
    }
    ps.a[i] = acc + g;
    ps.drho[i] = drho_sum;
  }
}

template <int D, bool V, bool A, Clump C>
void dispatch_delta(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    Scratch<D>& s) {
  if (sp.delta > 0)
    rates_loop<D, V, A, C, true>(sp, nl, ps, s);
  else
    rates_loop<D, V, A, C, false>(sp, nl, ps, s);
}

template <int D, bool V, bool A>
void dispatch_clump(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    Scratch<D>& s) {
  if (!sp.anti_clump)
    dispatch_delta<D, V, A, Clump::Off>(sp, nl, ps, s);
  else if (sp.anti_clump_n == 4)
    dispatch_delta<D, V, A, Clump::N4>(sp, nl, ps, s);
  else
    dispatch_delta<D, V, A, Clump::General>(sp, nl, ps, s);
}

template <int D, bool V>
void dispatch_art(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                  Scratch<D>& s) {
  if (sp.alpha > 0)
    dispatch_clump<D, V, true>(sp, nl, ps, s);
  else
    dispatch_clump<D, V, false>(sp, nl, ps, s);
}

}  // namespace

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  thread_local Scratch<D> s;
  const std::size_t n = ps.size();
  s.rec.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    NeighborRecord<D>& r = s.rec[i];
    for (int d = 0; d < D; ++d) {
      r.x[d] = ps.x[i][d];
      r.v[d] = ps.v[i][d];
      r.vw[d] = ps.vwall[i][d];
    }
    r.m = ps.mass[i];
    r.rho = ps.rho[i];
    r.vol = ps.mass[i] / ps.rho[i];
    r.por2 = terms::pressure_over_rho2(ps.p[i], ps.rho[i]);
    r.rac = terms::anti_clump_r(sp.anti_clump_eps, r.por2);
    r.fluid = ps.kind[i] == Kind::Fluid ? 1.0 : 0.0;
  }
  if (sp.mu > 0)
    dispatch_art<D, true>(sp, nl, ps, s);
  else
    dispatch_art<D, false>(sp, nl, ps, s);
}

template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
