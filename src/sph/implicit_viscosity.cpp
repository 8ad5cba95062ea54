// Implicit laminar viscosity: the operator and the Jacobi-preconditioned
// BiCGSTAB solve, the walls' dummy values implicit (include/sphdem/sph/implicit_viscosity.hpp,
// docs/physics.md "Implicit viscosity").
#include "sphdem/sph/implicit_viscosity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "sphdem/sph/surface_traction.hpp"
#include "terms/viscosity_variable.hpp"

namespace sphdem {

template <int D>
void ViscousOperator<D>::build(const SphParams& sp, const NeighborList<D>& nl,
                               const SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  coeff.assign(nl.total_pairs(), 0.0);
  row_sum.assign(ps.n_owned, 0.0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    const double mu_i = sp.variable_viscosity ? ps.viscosity[i] : sp.mu;
    const double scale_i = sp.mu_scale / ps.rho[i];
    double s = 0.0;
    const NeighborRow nb = nl.row(i);
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
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    Vec<D> a = Vec<D>::Zero();
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n)
      a += coeff[n] * (u[i] - u[static_cast<std::size_t>(nb[n])]);
    out[i] = a;
  }
}

namespace {

// The linear system over the owned unknowns (rows of the owned resin
// particles that are not frozen; other rows stay 0):
//   (B u)_i = m_i (1 - dt S_i) u_i + dt m_i sum_j K_ij u_j - dt m_i T_i(u),
// T_i the free surface's traction at the surface rows (surface_traction.hpp,
// with sp.free_surface_traction; linear in u like the Morris part),
// u_j for a wall neighbour its dummy value from the resin's u (affine: the
// wall's own velocity and the frozen resin give the constant part, moved to
// the right-hand side b).
template <int D>
class ViscousSystem {
 public:
  ViscousSystem(const SphParams& sp, double dt, const NeighborList<D>& nl, SphParticles<D>& ps,
                std::span<const WallSlipLaw> wall_slip, const ViscousSolveHooks& hooks)
      : sp_(sp), dt_(dt), nl_(nl), ps_(ps), wall_slip_(wall_slip), hooks_(hooks) {
    op_.build(sp, nl, ps);
    traction_.build(sp, nl, ps);
    const std::size_t n = ps.n_owned;
    diag_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      if (ps.visc_free[i] > 0.5) diag_[i] = ps.mass[i] * (1.0 - dt * op_.row_sum[i]);
    // The walls' Shepard weights, as compute_wall_state takes them.
    const WendlandC2<D> kernel(sp.h);
    shepard_.assign(nl.total_pairs(), 0.0);
    wall_sum_.assign(n, 0.0);
    for (std::size_t w = 0; w < n; ++w) {
      if (ps.kind[w] != Kind::Wall) continue;
      double sum = 0.0;
      const NeighborRow nb = nl.row(w);
      for (std::size_t k = nl.begin(w), e = nl.end(w); k < e; ++k) {
        const double W = kernel.w((ps.x[w] - ps.x[static_cast<std::size_t>(nb[k])]).norm());
        shepard_[k] = W;
        sum += W;
      }
      wall_sum_[w] = sum;
      if (sum > 0.0)
        for (std::size_t k = nl.begin(w), e = nl.end(w); k < e; ++k) shepard_[k] /= sum;
    }
  }

  // Loads into visc_u, owned and ghosts, the value every particle shows the
  // rows: x for an unknown, the known velocity of frozen resin, a wall's
  // dummy value from those. homogeneous: the linear part only (frozen resin
  // and the walls' own velocities 0).
  void load(const std::vector<Vec<D>>& x, bool homogeneous) const {
    const std::size_t n = ps_.n_owned;
    for (std::size_t i = 0; i < n; ++i) {
      if (ps_.kind[i] != Kind::Fluid) continue;
      if (ps_.visc_free[i] > 0.5)
        ps_.visc_u[i] = x[i];
      else
        ps_.visc_u[i] = homogeneous ? Vec<D>::Zero() : ps_.v[i];
    }
    hooks_.forward(SphGroup::Viscous);
    for (std::size_t w = 0; w < n; ++w) {
      if (ps_.kind[w] != Kind::Wall) continue;
      const Vec<D> vw = homogeneous ? Vec<D>::Zero() : ps_.v[w];
      if (!(wall_sum_[w] > 0.0)) {  // no resin neighbour: its own velocity
        ps_.visc_u[w] = vw;
        continue;
      }
      Vec<D> mean = Vec<D>::Zero();
      const NeighborRow nb = nl_.row(w);
      for (std::size_t k = nl_.begin(w), e = nl_.end(w); k < e; ++k)
        mean += shepard_[k] * ps_.visc_u[static_cast<std::size_t>(nb[k])];
      const std::int32_t index = ps_.wall[w];
      const WallSlipLaw& law = index >= 0 && static_cast<std::size_t>(index) < wall_slip_.size()
                                   ? wall_slip_[static_cast<std::size_t>(index)]
                                   : sp_.mold_wall;
      const Vec<D> to_surface =
          ps_.wall_to_surface.empty() ? Vec<D>::Zero() : Vec<D>(ps_.wall_to_surface[w]);
      ps_.visc_u[w] = dummy_velocity<D>(law, vw, mean, to_surface);
    }
    hooks_.forward(SphGroup::Viscous);
  }

  // out = B x over the unknowns from the values load() left in visc_u.
  void rows(std::vector<Vec<D>>& out) const {
    const std::size_t n = ps_.n_owned;
    out.assign(n, Vec<D>::Zero());
    for (std::size_t i = 0; i < n; ++i) {
      if (!(ps_.visc_free[i] > 0.5)) continue;
      Vec<D> s = Vec<D>::Zero();
      const NeighborRow nb = nl_.row(i);
      for (std::size_t k = nl_.begin(i), e = nl_.end(i); k < e; ++k)
        s += op_.coeff[k] * ps_.visc_u[static_cast<std::size_t>(nb[k])];
      out[i] = diag_[i] * ps_.visc_u[i] + (dt_ * ps_.mass[i]) * s;
    }
    for (std::size_t r = 0; r < traction_.rows.size(); ++r) {
      const std::size_t i = traction_.rows[r];
      if (ps_.visc_free[i] > 0.5) out[i] -= (dt_ * ps_.mass[i]) * traction_.row(r, nl_, ps_.visc_u);
    }
  }

  // q = B x (linear).
  void product(const std::vector<Vec<D>>& x, std::vector<Vec<D>>& q) const {
    load(x, /*homogeneous=*/true);
    rows(q);
  }

  // b = M v - (the known values' part of the rows), v the start velocities.
  void rhs(const std::vector<Vec<D>>& v, std::vector<Vec<D>>& b) const {
    const std::size_t n = ps_.n_owned;
    const std::vector<Vec<D>> zero(n, Vec<D>::Zero());
    load(zero, /*homogeneous=*/false);
    rows(b);
    for (std::size_t i = 0; i < n; ++i)
      b[i] = ps_.visc_free[i] > 0.5 ? Vec<D>(ps_.mass[i] * v[i] - b[i]) : Vec<D>::Zero();
  }

  double inverse_diag(std::size_t i) const { return diag_[i] > 0 ? 1.0 / diag_[i] : 0.0; }

  // Exact, rank-count independent dot products of pairs of owned vectors:
  // one max and one integer sum over the ranks for all K together.
  template <std::size_t K>
  std::array<double, K> dots(const std::array<const std::vector<Vec<D>>*, 2 * K>& v) const {
    static_assert(sizeof(Vec<D>) == D * sizeof(double),
                  "a vector of Vec<D> is a flat double array");
    const std::size_t m = ps_.n_owned * static_cast<std::size_t>(D);
    const auto flat = [](const std::vector<Vec<D>>& x) {
      return x.empty() ? nullptr : x[0].data();
    };
    std::array<double, K> max{};
    if (m > 0)
      for (std::size_t k = 0; k < K; ++k)
        max[k] = exact_dot_max(flat(*v[2 * k]), flat(*v[2 * k + 1]), m);
    hooks_.max(max);
    std::array<double, K> out{};
    std::array<Int128, K> sum{};
    std::array<int, K> scale{};
    for (std::size_t k = 0; k < K; ++k) {
      if (!std::isfinite(max[k])) {  // a NaN or inf somewhere: every rank reports it
        out[k] = max[k];
        continue;
      }
      scale[k] = exact_sum_scale(max[k]);
      if (m == 0) continue;
      const double* a = flat(*v[2 * k]);
      const double* b = flat(*v[2 * k + 1]);
      const double power = exact_power(scale[k]);
      if (power > 0.0) {
        sum[k] = exact_dot_scaled(a, b, m, power);
      } else {
        for (std::size_t i = 0; i < m; ++i) sum[k] += exact_term(a[i] * b[i], scale[k]);
      }
    }
    hooks_.exact_sum(sum);
    for (std::size_t k = 0; k < K; ++k)
      if (std::isfinite(max[k])) out[k] = exact_value(sum[k], scale[k]);
    return out;
  }

 private:
  const SphParams& sp_;
  double dt_;
  const NeighborList<D>& nl_;
  SphParticles<D>& ps_;
  std::span<const WallSlipLaw> wall_slip_;
  const ViscousSolveHooks& hooks_;
  ViscousOperator<D> op_;
  SurfaceTractionOperator<D> traction_;
  std::vector<double> diag_;
  std::vector<double> shepard_;   // per neighbour-list entry of a wall row: W / sum W
  std::vector<double> wall_sum_;  // per owned wall: sum W over its resin neighbours
};

}  // namespace

template <int D>
ViscousSolveStats solve_implicit_viscosity(const SphParams& sp, double dt, double tolerance,
                                           int max_iterations, const NeighborList<D>& nl,
                                           SphParticles<D>& ps,
                                           std::span<const WallSlipLaw> wall_slip,
                                           const ViscousSolveHooks& hooks) {
  const std::size_t n = ps.n_owned;
  // The unknowns (owned rows; load() forwards the values they show).
  for (std::size_t i = 0; i < n; ++i) {
    const bool free = ps.kind[i] == Kind::Fluid && !ps.is_frozen(i);
    ps.visc_free[i] = free ? 1.0 : 0.0;
  }
  ViscousSystem<D> sys(sp, dt, nl, ps, wall_slip, hooks);

  // Preconditioned BiCGSTAB (right Jacobi preconditioner), from
  // x = v + dt a_visc, a_visc the particle's viscous acceleration of the
  // last solve (0 at the start): the viscous correction changes little from
  // one step to the next, so the first residual is a fraction of that of
  // x = v (docs/performance.md "Implicit viscosity").
  const bool guess = ps.visc_acc.size() >= n;
  std::vector<Vec<D>> x(n, Vec<D>::Zero()), b, r(n), rhat, p(n, Vec<D>::Zero()),
      v(n, Vec<D>::Zero()), y(n), s(n), z(n), t;
  for (std::size_t i = 0; i < n; ++i)
    if (ps.visc_free[i] > 0.5) x[i] = guess ? Vec<D>(ps.v[i] + dt * ps.visc_acc[i]) : ps.v[i];
  sys.rhs(ps.v, b);
  sys.product(x, r);
  for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - r[i];
  rhat = r;
  const auto [bb, rr0] = sys.template dots<2>({&b, &b, &r, &r});
  double rr = rr0, rho = rr0;  // rho = (rhat, r) = (r, r) at the start
  const double target = tolerance * tolerance * bb;
  ViscousSolveStats stats;
  if (bb == 0.0) {  // the solution is 0
    for (std::size_t i = 0; i < n; ++i) x[i].setZero();
    rr = 0.0;
  }
  double rho_prev = 1.0, alpha = 1.0, omega = 1.0;
  bool first = true;
  while (!(rr <= target) && stats.iterations < max_iterations && std::isfinite(rr)) {
    if (!(rho != 0.0)) break;  // breakdown: (rhat, r) = 0 before convergence
    const double beta = first ? 0.0 : (rho / rho_prev) * (alpha / omega);
    first = false;
    for (std::size_t i = 0; i < n; ++i) {
      p[i] = r[i] + beta * (p[i] - omega * v[i]);
      y[i] = sys.inverse_diag(i) * p[i];
    }
    sys.product(y, v);
    const double rv = sys.template dots<1>({&rhat, &v})[0];
    ++stats.iterations;
    if (!(rv != 0.0)) break;  // breakdown
    alpha = rho / rv;
    for (std::size_t i = 0; i < n; ++i) {
      s[i] = r[i] - alpha * v[i];
      z[i] = sys.inverse_diag(i) * s[i];
    }
    sys.product(z, t);
    // One reduction for the rest of the iteration (two, not three, per
    // iteration): with r = s - omega t,
    //   (r, r) = (s, s) - omega (2 (t, s) - omega (t, t)),
    //   (rhat, r) = (rhat, s) - omega (rhat, t).
    // The first loses a few eps (s, s) to cancellation (omega (t, s) and
    // omega^2 (t, t) are at most (s, s)), far below the target tol^2 |b|^2
    // unless (s, s) > 1e3 |b|^2 at tol = 1e-6; a residual it puts under the
    // target is confirmed by the exact (r, r) before the solve stops.
    const auto [ss, ts, tt, rs, rt] =
        sys.template dots<5>({&s, &s, &t, &s, &t, &t, &rhat, &s, &rhat, &t});
    omega = tt > 0.0 ? ts / tt : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * y[i] + omega * z[i];
      r[i] = s[i] - omega * t[i];
    }
    rr = ss - omega * (2.0 * ts - omega * tt);
    if (rr <= target || !std::isfinite(rr)) rr = sys.template dots<1>({&r, &r})[0];
    rho_prev = rho;
    rho = rs - omega * rt;
    if (!(omega != 0.0)) break;  // stagnation: the next beta is undefined
  }
  stats.residual = bb > 0 ? std::sqrt(rr / bb) : 0.0;
  stats.converged = rr <= target && std::isfinite(rr);
  for (std::size_t i = 0; i < n; ++i) {
    const bool free = ps.visc_free[i] > 0.5;
    if (guess) ps.visc_acc[i] = free ? Vec<D>((x[i] - ps.v[i]) / dt) : Vec<D>::Zero();
    if (free) ps.v[i] = x[i];
  }
  return stats;
}

template <int D>
void add_viscous_density(const SphParams& sp, double dt, const NeighborList<D>& nl,
                         SphParticles<D>& ps, const std::function<void(SphGroup)>& forward) {
  const std::size_t n = ps.n_owned;
  for (std::size_t i = 0; i < n; ++i) {
    const bool free = ps.kind[i] == Kind::Fluid && !ps.is_frozen(i);
    ps.visc_u[i] = free ? Vec<D>((0.5 * dt * dt) * ps.visc_acc[i]) : Vec<D>::Zero();
  }
  forward(SphGroup::Viscous);
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  for (std::size_t i = 0; i < n; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    double drho = 0.0;
    const NeighborRow nb = nl.row(i);
    for (std::size_t k = nl.begin(i), e = nl.end(i); k < e; ++k) {
      const auto j = static_cast<std::size_t>(nb[k]);
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) continue;
      const double F = kernel.f(std::sqrt(r2)) * sp.grad_scale;
      drho += ps.mass[j] * F * (ps.visc_u[i] - ps.visc_u[j]).dot(x_ij);
    }
    ps.rho[i] += drho;
  }
}

template struct ViscousOperator<2>;
template struct ViscousOperator<3>;
template ViscousSolveStats solve_implicit_viscosity<2>(const SphParams&, double, double, int,
                                                       const NeighborList<2>&, SphParticles<2>&,
                                                       std::span<const WallSlipLaw>,
                                                       const ViscousSolveHooks&);
template ViscousSolveStats solve_implicit_viscosity<3>(const SphParams&, double, double, int,
                                                       const NeighborList<3>&, SphParticles<3>&,
                                                       std::span<const WallSlipLaw>,
                                                       const ViscousSolveHooks&);

template void add_viscous_density<2>(const SphParams&, double, const NeighborList<2>&,
                                     SphParticles<2>&, const std::function<void(SphGroup)>&);
template void add_viscous_density<3>(const SphParams&, double, const NeighborList<3>&,
                                     SphParticles<3>&, const std::function<void(SphGroup)>&);

}  // namespace sphdem
