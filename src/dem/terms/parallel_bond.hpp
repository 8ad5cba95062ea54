#pragma once
// Linear parallel bond of Potyondy & Cundall (2004), ANALYTIC.md 6.
// Section of a bond of radius Rbar (eq. 12, 15):
//   2D (thickness t): A = 2 Rbar t, I = (2/3) Rbar^3 t   (no twisting)
//   3D:               A = pi Rbar^2, I = pi Rbar^4 / 4, J = pi Rbar^4 / 2
// Stiffness per unit area: kbar_n = E / (R1 + R2), kbar_s = kbar_n / kbar*.
// Incremental law per step, with V the velocity of the partner's contact
// point relative to the owner's and dtheta = (omega_partner - omega_owner) dt:
//   dF_n = -kbar_n A (V . n) dt          (F_n compression-positive)
//   dF_s = -kbar_s A V_s dt              (V_s: V in the contact plane)
//   dM_t = -kbar_s J (dtheta . n)        (3D)
//   dM_b = -kbar_n I dtheta_s            (2D: the scalar dtheta)
// The accumulated F_s (and M_b in 3D) are first turned with the contact
// plane; in 3D F_s and M_b also turn with the pair's mean spin about n
// (an exact, length-preserving rotation).
// Stresses on the periphery and failure (P&C's signed variant: compression
// never breaks a bond, unlike LIGGGHTS's |F_n|):
//   sigma = -F_n/A + |M_b| Rbar/I,  tau = |F_s|/A (+ |M_t| Rbar/J in 3D)
//   broken for good when sigma >= sigma_c or tau >= tau_c.
#include <cmath>
#include <numbers>

#include "contact_linear.hpp"
#include "sphdem/dem_particles.hpp"

namespace sphdem::terms {

struct BondSection {
  double area = 0, inertia = 0, polar = 0;  // A [m^2], I, J [m^4] (2D: per depth)
};

template <int D>
inline BondSection bond_section(double rbar, double thickness) {
  if constexpr (D == 2) {
    return {2.0 * rbar * thickness, 2.0 / 3.0 * rbar * rbar * rbar * thickness, 0.0};
  } else {
    const double r2 = rbar * rbar;
    return {std::numbers::pi * r2, std::numbers::pi * r2 * r2 / 4.0,
            std::numbers::pi * r2 * r2 / 2.0};
  }
}

struct BondLaw {
  BondSection s;
  double kn = 0, ks = 0;  // kbar_n, kbar_s [Pa/m]
  double sigma_c = 0, tau_c = 0;
};

// Advances the bond by one step. mean_spin_n: (omega_o + omega_p)/2 . n
// (3D). Returns false when the bond breaks now (its forces are zeroed).
template <int D>
inline bool parallel_bond_update(const BondLaw& law, double rbar, const Vec<D>& n,
                                 const Vec<D>& v_rel, const Rot<D>& dtheta, double mean_spin_n,
                                 double dt, DemBond<D>& b) {
  rotate_into_plane<D>(b.fs, n);
  if constexpr (D == 3) {
    // Turn F_s and M_b with the pair's mean spin about n by the exact
    // rotation of angle theta = spin dt. (The first-order update
    // v += theta n x v lengthens v by sqrt(1 + theta^2) each step: a fiber
    // spinning about its axis then pumps energy into its own bonds until
    // it blows up, which the 4800-fiber benchmark did after ~15k steps.)
    rotate_into_plane<D>(b.mb, n);
    const double theta = mean_spin_n * dt, c = std::cos(theta), sn = std::sin(theta);
    b.fs = c * b.fs + sn * n.cross(b.fs);
    b.mb = c * b.mb + sn * n.cross(b.mb);
  }
  const double vn = v_rel.dot(n);
  const Vec<D> vs = v_rel - vn * n;
  b.fn -= law.kn * law.s.area * vn * dt;
  b.fs -= law.ks * law.s.area * dt * vs;
  if constexpr (D == 3) {
    const double twist = dtheta.dot(n);
    b.mt -= law.ks * law.s.polar * twist;
    b.mb -= law.kn * law.s.inertia * (dtheta - twist * n);
  } else {
    b.mb -= law.kn * law.s.inertia * dtheta;
  }
  b.sigma = -b.fn / law.s.area + b.mb.norm() * rbar / law.s.inertia;
  b.tau = b.fs.norm() / law.s.area;
  if constexpr (D == 3) b.tau += std::abs(b.mt) * rbar / law.s.polar;
  if (b.sigma >= law.sigma_c || b.tau >= law.tau_c) {
    b.broken = true;
    b.fn = 0;
    b.fs.setZero();
    b.mb.setZero();
    b.mt = 0;
    return false;
  }
  return true;
}

// Elastic energy stored in the bond's springs.
template <int D>
inline double parallel_bond_energy(const BondLaw& law, const DemBond<D>& b) {
  double e = b.fn * b.fn / (2 * law.kn * law.s.area) +
             b.fs.squaredNorm() / (2 * law.ks * law.s.area) +
             b.mb.squaredNorm() / (2 * law.kn * law.s.inertia);
  if constexpr (D == 3) e += b.mt * b.mt / (2 * law.ks * law.s.polar);
  return e;
}

}  // namespace sphdem::terms
