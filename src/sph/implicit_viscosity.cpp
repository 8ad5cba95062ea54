// Implicit laminar viscosity: the operator and the Jacobi-preconditioned
// conjugate-gradient solve (include/sphdem/sph/implicit_viscosity.hpp,
// docs/physics.md "Implicit viscosity").
#include "sphdem/sph/implicit_viscosity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "terms/viscosity_variable.hpp"

namespace sphdem {

template <int D>
void ViscousOperator<D>::build(const SphParams& sp, const NeighborList<D>& nl,
                               const SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  coeff.assign(nl.total_pairs(), 0.0);
  row_sum.assign(ps.n_owned, 0.0);
  const std::int32_t* nb = nl.indices();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double mu_i = sp.variable_viscosity ? ps.viscosity[i] : sp.mu;
    const double scale_i = sp.mu_scale / ps.rho[i];
    double s = 0.0;
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const auto j = static_cast<std::size_t>(nb[n]);
      const double r2 = (ps.x[i] - ps.x[j]).squaredNorm();
      const double mu_j =
          ps.kind[j] == Kind::Fluid && sp.variable_viscosity ? ps.viscosity[j] : mu_i;
      const double two_mu = 2.0 * terms::harmonic_mean(mu_i, mu_j);
      const double k =
          two_mu * scale_i * ps.mass[j] / ps.rho[j] * kernel.f(std::sqrt(r2)) * r2 / (r2 + sp.eta2);
      coeff[n] = k;
      s += k;
    }
    row_sum[i] = s;
  }
}

template <int D>
void ViscousOperator<D>::apply(const NeighborList<D>& nl, const SphParticles<D>& ps,
                               const std::vector<Vec<D>>& u, std::vector<Vec<D>>& out) const {
  out.assign(ps.n_owned, Vec<D>::Zero());
  const std::int32_t* nb = nl.indices();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    Vec<D> a = Vec<D>::Zero();
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n)
      a += coeff[n] * (u[i] - u[static_cast<std::size_t>(nb[n])]);
    out[i] = a;
  }
}

namespace {

// The conjugate-gradient state over the owned unknowns (rows of the owned
// resin particles; other rows stay 0). B = M (I - dt L) restricted to the
// unknowns: B_ii = m_i (1 - dt S_i), B_ij = dt m_i K_ij for an unknown j.
template <int D>
class ViscousCg {
 public:
  ViscousCg(const SphParams& sp, double dt, const NeighborList<D>& nl, SphParticles<D>& ps,
            const ViscousSolveHooks& hooks)
      : dt_(dt), nl_(nl), ps_(ps), hooks_(hooks) {
    op_.build(sp, nl, ps);
    const std::size_t n = ps.n_owned;
    diag_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      if (ps.visc_free[i] > 0.5) diag_[i] = ps.mass[i] * (1.0 - dt * op_.row_sum[i]);
  }

  // visc_u and visc_free are current on the ghosts: visc_u the known values
  // (walls, frozen) and the start velocities (unknowns). Returns b and B x0.
  void rhs_and_product(std::vector<Vec<D>>& b, std::vector<Vec<D>>& bx) const {
    const std::size_t n = ps_.n_owned;
    b.assign(n, Vec<D>::Zero());
    bx.assign(n, Vec<D>::Zero());
    const std::int32_t* nb = nl_.indices();
    for (std::size_t i = 0; i < n; ++i) {
      if (!(ps_.visc_free[i] > 0.5)) continue;
      Vec<D> known = Vec<D>::Zero(), unknown = Vec<D>::Zero();
      for (std::size_t k = nl_.begin(i), e = nl_.end(i); k < e; ++k) {
        const auto j = static_cast<std::size_t>(nb[k]);
        const double f = ps_.visc_free[j];
        unknown += (op_.coeff[k] * f) * ps_.visc_u[j];
        known += (op_.coeff[k] * (1.0 - f)) * ps_.visc_u[j];
      }
      const double dm = dt_ * ps_.mass[i];
      b[i] = ps_.mass[i] * ps_.visc_u[i] - dm * known;
      bx[i] = diag_[i] * ps_.visc_u[i] + dm * unknown;
    }
  }

  // q = B p, p in visc_u (current on the ghosts; known entries ignored).
  void product(std::vector<Vec<D>>& q) const {
    const std::size_t n = ps_.n_owned;
    q.assign(n, Vec<D>::Zero());
    const std::int32_t* nb = nl_.indices();
    for (std::size_t i = 0; i < n; ++i) {
      if (!(ps_.visc_free[i] > 0.5)) continue;
      Vec<D> s = Vec<D>::Zero();
      for (std::size_t k = nl_.begin(i), e = nl_.end(i); k < e; ++k) {
        const auto j = static_cast<std::size_t>(nb[k]);
        s += (op_.coeff[k] * ps_.visc_free[j]) * ps_.visc_u[j];
      }
      q[i] = diag_[i] * ps_.visc_u[i] + (dt_ * ps_.mass[i]) * s;
    }
  }

  double inverse_diag(std::size_t i) const { return diag_[i] > 0 ? 1.0 / diag_[i] : 0.0; }

  // Exact, rank-count independent dot products of pairs of owned vectors.
  template <std::size_t K>
  std::array<double, K> dots(const std::array<const std::vector<Vec<D>>*, 2 * K>& v) const {
    std::array<double, K> max{};
    const std::size_t n = ps_.n_owned;
    for (std::size_t k = 0; k < K; ++k) {
      bool finite = true;
      for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < D; ++d) {
          const double t = std::abs((*v[2 * k])[i][d] * (*v[2 * k + 1])[i][d]);
          finite = finite && std::isfinite(t);
          max[k] = std::max(max[k], t);
        }
      // A NaN would slip through max: report it as infinite (every rank sees it).
      if (!finite) max[k] = std::numeric_limits<double>::infinity();
    }
    hooks_.max(max);
    std::array<double, K> out{};
    for (std::size_t k = 0; k < K; ++k)
      if (!std::isfinite(max[k])) out[k] = max[k];
    std::array<Int128, K> sum{};
    std::array<int, K> scale{};
    for (std::size_t k = 0; k < K; ++k) scale[k] = exact_sum_scale(max[k]);
    for (std::size_t k = 0; k < K; ++k) {
      if (!std::isfinite(max[k])) continue;
      for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < D; ++d)
          sum[k] += exact_term((*v[2 * k])[i][d] * (*v[2 * k + 1])[i][d], scale[k]);
    }
    hooks_.exact_sum(sum);
    for (std::size_t k = 0; k < K; ++k)
      if (std::isfinite(max[k])) out[k] = exact_value(sum[k], scale[k]);
    return out;
  }

 private:
  double dt_;
  const NeighborList<D>& nl_;
  SphParticles<D>& ps_;
  const ViscousSolveHooks& hooks_;
  ViscousOperator<D> op_;
  std::vector<double> diag_;
};

}  // namespace

template <int D>
ViscousSolveStats solve_implicit_viscosity(const SphParams& sp, double dt, double tolerance,
                                           int max_iterations, const NeighborList<D>& nl,
                                           SphParticles<D>& ps, const ViscousSolveHooks& hooks) {
  const std::size_t n = ps.n_owned;
  // Unknowns, known values and start values, then to the ghosts.
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = ps.kind[i] == Kind::Fluid;
    const bool free = fluid && !ps.is_frozen(i);
    ps.visc_free[i] = free ? 1.0 : 0.0;
    ps.visc_u[i] = fluid ? ps.v[i] : ps.vwall[i];
  }
  hooks.forward(SphGroup::Viscous);
  ViscousCg<D> cg(sp, dt, nl, ps, hooks);

  std::vector<Vec<D>> x(n), b, r, z(n, Vec<D>::Zero()), p(n), q;
  for (std::size_t i = 0; i < n; ++i) x[i] = ps.visc_u[i];
  cg.rhs_and_product(b, r);
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = b[i] - r[i];
    z[i] = cg.inverse_diag(i) * r[i];
    p[i] = z[i];
  }
  const auto [bb, rr0, rz0] = cg.template dots<3>({&b, &b, &r, &r, &r, &z});
  double rr = rr0, rz = rz0;
  const double target = tolerance * tolerance * bb;
  ViscousSolveStats stats;
  if (bb == 0.0) {  // the solution is 0
    for (std::size_t i = 0; i < n; ++i) x[i].setZero();
    rr = 0.0;
  }
  auto finish = [&] {
    stats.residual = bb > 0 ? std::sqrt(rr / bb) : 0.0;
    stats.converged = rr <= target && std::isfinite(rr);
  };
  while (!(rr <= target) && stats.iterations < max_iterations && std::isfinite(rr)) {
    for (std::size_t i = 0; i < n; ++i) ps.visc_u[i] = p[i];
    hooks.forward(SphGroup::Viscous);
    cg.product(q);
    const double pq = cg.template dots<1>({&p, &q})[0];
    const double alpha = pq > 0 ? rz / pq : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
      z[i] = cg.inverse_diag(i) * r[i];
    }
    const auto [rr_new, rz_new] = cg.template dots<2>({&r, &r, &r, &z});
    const double beta = rz > 0 ? rz_new / rz : 0.0;
    rr = rr_new;
    rz = rz_new;
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    ++stats.iterations;
    if (!(pq > 0)) break;  // a zero search direction: nothing left to reduce
  }
  finish();
  for (std::size_t i = 0; i < n; ++i)
    if (ps.visc_free[i] > 0.5) ps.v[i] = x[i];
  return stats;
}

template struct ViscousOperator<2>;
template struct ViscousOperator<3>;
template ViscousSolveStats solve_implicit_viscosity<2>(const SphParams&, double, double, int,
                                                       const NeighborList<2>&, SphParticles<2>&,
                                                       const ViscousSolveHooks&);
template ViscousSolveStats solve_implicit_viscosity<3>(const SphParams&, double, double, int,
                                                       const NeighborList<3>&, SphParticles<3>&,
                                                       const ViscousSolveHooks&);

}  // namespace sphdem
