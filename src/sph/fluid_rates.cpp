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

// Per-pair lane arrays for one particle's list (structure of arrays, so the
// pair-term loop runs on contiguous doubles).
template <int D>
struct Lanes {
  enum Field { kX = 0, kV = D, kW = 2 * D, kM = 3 * D, kRho, kVol, kPor2, kRac, kFluid, kA, kDrho = kA + D, kCount };
  std::size_t cap = 0;
  std::vector<double> buf;
  void reserve(std::size_t n) {
    if (n <= cap) return;
    cap = (n + 7) & ~std::size_t{7};
    buf.assign(cap * kCount, 0.0);
  }
  double* operator()(int field) { return buf.data() + static_cast<std::size_t>(field) * cap; }
};

template <int D>
struct Scratch {
  std::vector<NeighborRecord<D>> rec;
  Lanes<D> lanes;
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
  const double kw = kernel.w(0.0) / 16.0, kf = -10.0 * kw;
  const int clump_n = sp.anti_clump_n;
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
  const std::int32_t* nb = nl.indices();
  const NeighborRecord<D>* rec = s.rec.data();
  using L = Lanes<D>;

  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const NeighborRecord<D>& ri = rec[i];
    const double rho_i = ri.rho, por2_i = ri.por2, rac_i = ri.rac;
    const double two_mu_over_rho_i = two_mu / rho_i;
    const std::size_t b = nl.begin(i), cnt = nl.end(i) - b;
    s.lanes.reserve(cnt);
    double* __restrict xl[D];
    double* __restrict vl[D];
    double* __restrict wl[D];
    double* __restrict al[D];
    for (int d = 0; d < D; ++d) {
      xl[d] = s.lanes(L::kX + d);
      vl[d] = s.lanes(L::kV + d);
      wl[d] = s.lanes(L::kW + d);
      al[d] = s.lanes(L::kA + d);
    }
    double* __restrict ml = s.lanes(L::kM);
    double* __restrict rhol = s.lanes(L::kRho);
    double* __restrict voll = s.lanes(L::kVol);
    double* __restrict por2l = s.lanes(L::kPor2);
    double* __restrict racl = s.lanes(L::kRac);
    double* __restrict fluidl = s.lanes(L::kFluid);
    double* __restrict drhol = s.lanes(L::kDrho);

    // 1. Gather (x_ij, v_ij, and the neighbor's scalars).
    for (std::size_t k = 0; k < cnt; ++k) {
      const NeighborRecord<D>& rj = rec[nb[b + k]];
      for (int d = 0; d < D; ++d) {
        xl[d][k] = ri.x[d] - rj.x[d];
        vl[d][k] = ri.v[d] - rj.v[d];
        wl[d][k] = ri.v[d] - rj.vw[d];
      }
      ml[k] = rj.m;
      rhol[k] = rj.rho;
      voll[k] = rj.vol;
      por2l[k] = rj.por2;
      racl[k] = rj.rac;
      fluidl[k] = rj.fluid;
    }

    // 2. Pair terms, branch-free (vectorized).
    for (std::size_t k = 0; k < cnt; ++k) {
      double r2 = 0.0, vx = 0.0;
      for (int d = 0; d < D; ++d) r2 += xl[d][k] * xl[d][k];
      for (int d = 0; d < D; ++d) vx += vl[d][k] * xl[d][k];
      const bool inside = r2 < support2;
      const double r = std::sqrt(r2);
      const double q = r * inv_h;
      const double t = inside ? 2.0 - q : 0.0;
      const double F = kf * t * t * t * inv_h * inv_h * grad_scale;
      const double m_j = ml[k];
      double drho = terms::continuity(m_j, F, vx);
      if constexpr (kDelta) {
        drho += fluidl[k] * terms::delta_sph(delta_h_c0, rho_i, rhol[k], voll[k], F);
      }
      double bracket = por2_i + por2l[k];
      if constexpr (kArtVisc) {
        double wx = 0.0;
        for (int d = 0; d < D; ++d) wx += wl[d][k] * xl[d][k];
        bracket += terms::artificial_viscosity(alpha_c0_h, wx, r2, eta2, rho_i, rhol[k]);
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
        bracket += terms::anti_clump_coefficient(rac_i, racl[k], por2_i, por2l[k]) * f;
      }
      const double pf = m_j * bracket * F;
      double visc = 0.0;
      if constexpr (kVisc) {
        visc = terms::morris_viscosity(two_mu_over_rho_i, voll[k], F, r2, eta2);
      }
      for (int d = 0; d < D; ++d) al[d][k] = visc * wl[d][k] - pf * xl[d][k];
      drhol[k] = drho;
    }

    // 3. Sum in list (global-id) order.
    Vec<D> acc = Vec<D>::Zero();
    double drho = 0.0;
    for (std::size_t k = 0; k < cnt; ++k) {
      for (int d = 0; d < D; ++d) acc[d] += al[d][k];
      drho += drhol[k];
    }
    ps.a[i] = acc + g;
    ps.drho[i] = drho;
  }
}

template <int D, bool V, bool A, Clump C>
void dispatch_delta(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    Scratch<D>& s) {
  if (sp.delta > 0) rates_loop<D, V, A, C, true>(sp, nl, ps, s);
  else rates_loop<D, V, A, C, false>(sp, nl, ps, s);
}

template <int D, bool V, bool A>
void dispatch_clump(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    Scratch<D>& s) {
  if (!sp.anti_clump) dispatch_delta<D, V, A, Clump::Off>(sp, nl, ps, s);
  else if (sp.anti_clump_n == 4) dispatch_delta<D, V, A, Clump::N4>(sp, nl, ps, s);
  else dispatch_delta<D, V, A, Clump::General>(sp, nl, ps, s);
}

template <int D, bool V>
void dispatch_art(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                  Scratch<D>& s) {
  if (sp.alpha > 0) dispatch_clump<D, V, true>(sp, nl, ps, s);
  else dispatch_clump<D, V, false>(sp, nl, ps, s);
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
  if (sp.mu > 0) dispatch_art<D, true>(sp, nl, ps, s);
  else dispatch_art<D, false>(sp, nl, ps, s);
}

template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
