// The resin's rate loop: one gather pass over each owned resin particle's
// neighbors (resin and wall, owned and ghost) that sums every term of
// src/sph/terms/. The switches are template parameters so that the
// pair loop carries no branch for terms that are off.
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

struct Scratch {
  std::vector<double> por2;  // P / rho^2
  std::vector<double> rac;   // anti-clump R_a
};

template <int D, bool kVisc, bool kArtVisc, bool kAntiClump, bool kDelta>
void rates_loop(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                const Scratch& s) {
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  const double two_mu = 2.0 * sp.mu * sp.mu_scale / sp.grad_scale;  // F carries grad_scale
  const double alpha_c0_h = sp.alpha * sp.c0 * sp.h;
  const double delta_h_c0 = sp.delta * sp.h * sp.c0;
  const double inv_w_dp = 1.0 / kernel.w(sp.spacing);
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
  const std::int32_t* nb = nl.indices();

  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const Vec<D> xi = ps.x[i];
    const Vec<D> vi = ps.v[i];
    const double rho_i = ps.rho[i];
    const double por2_i = s.por2[i];
    Vec<D> acc = Vec<D>::Zero();
    double drho = 0.0;
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      const Vec<D> x_ij = xi - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (r2 >= support2) continue;
      const double r = std::sqrt(r2);
      const double F = kernel.f(r) * sp.grad_scale;
      const double m_j = ps.mass[j];
      const double rho_j = ps.rho[j];
      drho += terms::continuity<D>(m_j, F, vi - ps.v[j], x_ij);
      if constexpr (kDelta) {
        if (ps.kind[j] == Kind::Fluid) drho += terms::delta_sph(delta_h_c0, rho_i, rho_j, m_j, F);
      }
      double bracket = por2_i + s.por2[j];
      const Vec<D> v_ij = vi - ps.vwall[j];
      if constexpr (kArtVisc) {
        bracket +=
            terms::artificial_viscosity(alpha_c0_h, v_ij.dot(x_ij), r2, sp.eta2, rho_i, rho_j);
      }
      if constexpr (kAntiClump) {
        bracket += terms::anti_clump(s.rac[i], s.rac[j], por2_i, s.por2[j],
                                     kernel.w(r) * inv_w_dp, sp.anti_clump_n);
      }
      acc -= (m_j * bracket * F) * x_ij;
      if constexpr (kVisc) {
        acc += terms::morris_viscosity(m_j, two_mu, rho_i, rho_j, F, r2, sp.eta2) * v_ij;
      }
    }
    ps.a[i] = acc + g;
    ps.drho[i] = drho;
  }
}

template <int D, bool V, bool A, bool C>
void dispatch_delta(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    const Scratch& s) {
  if (sp.delta > 0) rates_loop<D, V, A, C, true>(sp, nl, ps, s);
  else rates_loop<D, V, A, C, false>(sp, nl, ps, s);
}

template <int D, bool V, bool A>
void dispatch_clump(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                    const Scratch& s) {
  if (sp.anti_clump) dispatch_delta<D, V, A, true>(sp, nl, ps, s);
  else dispatch_delta<D, V, A, false>(sp, nl, ps, s);
}

template <int D, bool V>
void dispatch_art(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                  const Scratch& s) {
  if (sp.alpha > 0) dispatch_clump<D, V, true>(sp, nl, ps, s);
  else dispatch_clump<D, V, false>(sp, nl, ps, s);
}

}  // namespace

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  thread_local Scratch s;
  const std::size_t n = ps.size();
  s.por2.resize(n);
  s.rac.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.por2[i] = terms::pressure_over_rho2(ps.p[i], ps.rho[i]);
    s.rac[i] = terms::anti_clump_r(sp.anti_clump_eps, s.por2[i]);
  }
  if (sp.mu > 0) dispatch_art<D, true>(sp, nl, ps, s);
  else dispatch_art<D, false>(sp, nl, ps, s);
}

template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
