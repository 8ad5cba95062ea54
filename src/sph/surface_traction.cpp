// The viscous traction at the free surface (numerics.free_surface_traction,
// docs/physics.md "Viscous traction at the free surface"). The Morris term
// (terms/viscosity_morris.hpp) of a particle whose kernel support is cut by
// the free surface acts, for a velocity field with gradient G_ab =
// dv_a/dx_b, as a_i = (2 mu / rho_i) G g_i with
//   g_i = (mu_scale / grad_scale) sum_j V_j F_ij x_ij r^2 / (r^2 + eta^2),
// the Morris weight's colour gradient: zero inside the resin, pointing into
// it at the surface. It drives the normal derivative of the velocity, G n,
// to zero (tests/test_fountain.cpp, SurfaceTraction.*, by hand).
// The stress-free surface of a Newtonian liquid needs the traction
// mu (G + G^T) n to vanish instead; the symmetric stress form
// sum_j m_j (tau_i / rho_i^2 + tau_j / rho_j^2) . grad W_ij, which the
// pressure term uses for -P I, gives (2 mu / rho_i) (G + G^T) g_i there.
// The missing part,
//   a_i += (2 mu_i / rho_i) G_i^T g_i,
// is added at the particles the free-surface pass flags, with G_i the
// renormalised velocity gradient (Bonet & Lok 1999, Comput. Methods Appl.
// Mech. Eng. 180:97), exact for a linear field whatever part of the
// support is missing:
//   L_i = sum_j V_j (v~_j - v_i) (x) grad W_ij,   B_i = -sum_j V_j F_ij x_ij (x) x_ij,
//   G_i = L_i B_i^-1,
// over every neighbour (walls with the velocity the viscous term sees,
// v~_j). A rigid rotation, stress-free, then feels no viscous force at the
// surface (the Morris term alone brakes it), and a sheared front (a
// Poiseuille profile reaching a free surface across the flow) is turned
// outward (the fountain). Resin in the bulk is untouched. Neighbours in
// list (global-id) order: rank-count independent.
// With implicit viscosity the same term, written as a linear operator of
// the velocity (SurfaceTractionOperator, include/sphdem/sph/
// surface_traction.hpp), enters the backward-Euler solve instead.
#include "sphdem/sph/surface_traction.hpp"

#include <Eigen/LU>
#include <cmath>

#include "sphdem/sph/kernel.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
void add_free_surface_traction(const SphParams& sp, const NeighborList<D>& nl,
                               SphParticles<D>& ps) {
  if (!sp.free_surface_traction || !(sp.mu > 0.0) || ps.free_surface.empty()) return;
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  const double morris_scale = sp.mu_scale / sp.grad_scale;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid || ps.free_surface[i] == 0.0) continue;
    Eigen::Matrix<double, D, D> L = Eigen::Matrix<double, D, D>::Zero();
    Eigen::Matrix<double, D, D> B = Eigen::Matrix<double, D, D>::Zero();
    Vec<D> g = Vec<D>::Zero();
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) continue;
      const double F = kernel.f(std::sqrt(r2)) * sp.grad_scale;
      const double vf = ps.mass[j] / ps.rho[j] * F;
      const Vec<D> dv = ps.vwall[j] - ps.v[i];  // v~_j - v_i
      L += (vf * dv) * x_ij.transpose();
      B -= (vf * x_ij) * x_ij.transpose();
      g += (vf * morris_scale * r2 / (r2 + sp.eta2)) * x_ij;
    }
    const double det = B.determinant();
    if (!(std::abs(det) > 1e-6 * std::pow(B.trace() / D, D))) continue;  // too few neighbours
    const Eigen::Matrix<double, D, D> G = L * B.inverse();
    const double mu = sp.variable_viscosity ? ps.viscosity[i] : sp.mu;
    ps.a[i] += (2.0 * mu / ps.rho[i]) * (G.transpose() * g);
  }
}

template <int D>
void SurfaceTractionOperator<D>::build(const SphParams& sp, const NeighborList<D>& nl,
                                       const SphParticles<D>& ps) {
  rows.clear();
  offset.clear();
  g.clear();
  q.clear();
  if (!sp.free_surface_traction || !(sp.mu > 0.0) || ps.free_surface.empty()) return;
  const WendlandC2<D> kernel(sp.h);
  const double support2 = 4.0 * sp.h * sp.h;
  const double morris_scale = sp.mu_scale / sp.grad_scale;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid || ps.free_surface[i] == 0.0) continue;
    Eigen::Matrix<double, D, D> B = Eigen::Matrix<double, D, D>::Zero();
    Vec<D> gi = Vec<D>::Zero();
    const std::size_t first = q.size();
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i), e = nl.end(i); n < e; ++n) {
      const std::int32_t j = nb[n];
      const Vec<D> x_ij = ps.x[i] - ps.x[j];
      const double r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) {
        q.push_back(Vec<D>::Zero());
        continue;
      }
      const double vf = ps.mass[j] / ps.rho[j] * kernel.f(std::sqrt(r2)) * sp.grad_scale;
      B -= (vf * x_ij) * x_ij.transpose();
      gi += (vf * morris_scale * r2 / (r2 + sp.eta2)) * x_ij;
      q.push_back(vf * x_ij);  // w_ij x_ij, scaled below
    }
    const double det = B.determinant();
    if (!(std::abs(det) > 1e-6 * std::pow(B.trace() / D, D))) {  // as the explicit term
      q.resize(first);
      continue;
    }
    const double mu = sp.variable_viscosity ? ps.viscosity[i] : sp.mu;
    const Eigen::Matrix<double, D, D> C = (2.0 * mu / ps.rho[i]) * B.inverse().transpose();
    for (std::size_t k = first; k < q.size(); ++k) q[k] = C * q[k];
    rows.push_back(i);
    offset.push_back(first);
    g.push_back(gi);
  }
}

template struct SurfaceTractionOperator<2>;
template struct SurfaceTractionOperator<3>;

template void add_free_surface_traction<2>(const SphParams&, const NeighborList<2>&,
                                           SphParticles<2>&);
template void add_free_surface_traction<3>(const SphParams&, const NeighborList<3>&,
                                           SphParticles<3>&);

}  // namespace sphdem
