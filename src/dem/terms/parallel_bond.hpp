#pragma once
// Linear parallel bond of Potyondy & Cundall (2004), docs/validation.md section 6.
// Section of a bond of radius Rbar (eq. 12, 15):
//   2D (thickness t): A = 2 Rbar t, I = (2/3) Rbar^3 t   (no twisting)
//   3D:               A = pi Rbar^2, I = pi Rbar^4 / 4, J = pi Rbar^4 / 2
// Stiffness per unit area: kbar_n = E / (R1 + R2), kbar_s = kbar_n / kbar*.
// Incremental law per step (BondMotion: what the pair did over the step):
//   dF_n = -kbar_n A dL                  (F_n compression-positive)
//   dF_s = -kbar_s A dU_s                (dU_s: contact-point slip in the plane)
//   dM_t = -kbar_s J (dtheta . n)        (3D)
//   dM_b = -kbar_n I dtheta_s            (2D: the scalar dtheta)
// The update is objective and time-symmetric (docs/dem.md, "Parallel
// bonds"): the stored F_s and M_b are turned exactly with the pair from the
// start of the step to its middle, the increments are taken in the mid-step
// plane, and the totals are turned on to the end. dL is the exact change of
// the centre distance, so F_n = kbar_n A (L0 - L) up to round-off. The
// first-order variant (V . n_end dt, projection into the new plane) pumps
// energy into a fiber that tumbles and bends by O(0.1) rad per vibration:
// a free 4-sphere fiber of the DEM benchmark gained a factor 20 in energy
// over 1e5 steps and the 4800-fiber pile blew up after 15k steps.
// Stresses on the periphery and failure (P&C's signed variant: compression
// never breaks a bond, unlike LIGGGHTS's |F_n|):
//   sigma = -F_n/A + |M_b| Rbar/I,  tau = |F_s|/A (+ |M_t| Rbar/J in 3D)
//   broken for good when sigma >= sigma_c or tau >= tau_c.
#include <cmath>
#include <numbers>

#include "contact_linear.hpp"
#include "sphdem/particles/dem_particles.hpp"

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

// A bond's law as the update uses it: stiffness times section, and the
// stresses' factors as reciprocals, so that an update divides only where its
// motion asks. A fiber's bonds share one (evaluate_pair keeps the last:
// dem_kernels.hpp). The six divisions per update this saves (two building
// the law, four in the stresses) were about a fifteenth of the 4800-fiber
// deck's pair evaluation (docs/performance.md, "The DEM walls' pass and the
// bond's divisions").
struct PreparedBondLaw {
  double kn_area = 0, ks_area = 0;      // kbar_n A, kbar_s A
  double kn_inertia = 0, ks_polar = 0;  // kbar_n I, kbar_s J (3D)
  double inv_area = 0;                  // 1 / A
  double rbar_over_inertia = 0;         // Rbar / I
  double rbar_over_polar = 0;           // Rbar / J (3D; 0 in 2D)
  double sigma_c = 0, tau_c = 0;
  PreparedBondLaw() = default;
  PreparedBondLaw(const BondLaw& law, double rbar)
      : kn_area(law.kn * law.s.area),
        ks_area(law.ks * law.s.area),
        kn_inertia(law.kn * law.s.inertia),
        ks_polar(law.ks * law.s.polar),
        inv_area(1.0 / law.s.area),
        rbar_over_inertia(rbar / law.s.inertia),
        rbar_over_polar(law.s.polar > 0 ? rbar / law.s.polar : 0.0),
        sigma_c(law.sigma_c),
        tau_c(law.tau_c) {}
};

// The exact rotation that takes unit a to unit b (about a x b). Applied to
// vectors normal to a x b's plane it keeps their length to round-off.
template <int D>
struct PlaneTurn {
  double c = 1;               // cos of the angle: a . b
  double s = 0;               // 2D: its sine
  Vec<D> w = Vec<D>::Zero();  // 3D: a x b
  double k = 0.5;             // 3D: 1 / (1 + c)
  PlaneTurn() = default;
  PlaneTurn(const Vec<D>& a, const Vec<D>& b) : c(a.dot(b)) {
    if constexpr (D == 2) {
      s = a[0] * b[1] - a[1] * b[0];
    } else {
      w = a.cross(b);
      k = 1.0 / (1.0 + c);
    }
  }
  Vec<D> operator()(const Vec<D>& v) const {
    if constexpr (D == 2) {
      return Vec<D>(c * v[0] - s * v[1], s * v[0] + c * v[1]);
    } else {
      return c * v + w.cross(v) + (k * w.dot(v)) * w;
    }
  }
};

// What a bonded pair did over one step, owner i to partner j.
template <int D>
struct BondMotion {
  Vec<D> n1 = Vec<D>::Zero();      // unit normal at the end of the step
  Vec<D> nm = Vec<D>::Zero();      // mid-step normal, (n0 + n1) normalised
  PlaneTurn<D> half;               // n0 to nm, which is also nm to n1
  double dlen = 0;                 // change of the centre distance
  Vec<D> du = Vec<D>::Zero();      // displacement of j's contact point relative to i's
  Rot<D> dtheta = Rot<D>::Zero();  // relative rotation (omega_j - omega_i) dt
  double spin = 0;                 // 3D: the pair's mean rotation about nm over the step
};

// The motion from the end-of-step centre vector d = x_j - x_i and its length,
// the centres' relative displacement dx over the step (the drift moved each
// particle by v dt, so x_old = x - v dt exactly), the spins over the step
// and the contact arms' lengths a_i, a_j (from each centre to the contact
// point).
template <int D>
[[gnu::always_inline]] inline BondMotion<D> bond_motion(const Vec<D>& d, double len,
                                                        const Vec<D>& dx, const Rot<D>& wi_dt,
                                                        const Rot<D>& wj_dt, double a_i,
                                                        double a_j) {
  BondMotion<D> m;
  const Vec<D> d0 = d - dx;
  const double len0 = d0.norm();
  m.n1 = d / len;
  const Vec<D> n0 = len0 > 0.0 ? Vec<D>(d0 / len0) : m.n1;
  m.nm = (n0 + m.n1).normalized();
  m.half = PlaneTurn<D>(n0, m.nm);
  m.dlen = len - len0;
  m.du = dx + cross<D>(wj_dt, -a_j * m.nm) - cross<D>(wi_dt, a_i * m.nm);
  m.dtheta = wj_dt - wi_dt;
  if constexpr (D == 3) m.spin = 0.5 * (wi_dt + wj_dt).dot(m.nm);
  return m;
}

// Advances the bond by one step. Returns false when the bond breaks now
// (its forces are zeroed).
template <int D>
[[gnu::always_inline]] inline bool parallel_bond_update(const PreparedBondLaw& k,
                                                        const BondMotion<D>& m, DemBond<D>& b) {
  // Half the turn, the increments in the mid-step plane, the other half.
  // In 3D each half also spins F_s and M_b about nm by half the pair's spin.
  // The spin turn is the Cayley rotation of t = tan(angle / 2) = spin / 4:
  // orthogonal, and its angle 2 atan(spin / 4) is spin / 2 to O(spin^3).
  double cs = 1, ss = 0;
  if constexpr (D == 3) {
    const double t = 0.25 * m.spin, inv = 1.0 / (1.0 + t * t);
    cs = (1.0 - t * t) * inv;
    ss = 2.0 * t * inv;
  }
  auto spin = [&](Vec<D>& v) {
    if constexpr (D == 3) v = cs * v + ss * m.nm.cross(v);
  };
  b.fs = m.half(b.fs);
  spin(b.fs);
  const Vec<D> us = m.du - m.du.dot(m.nm) * m.nm;
  b.fn -= k.kn_area * m.dlen;
  b.fs -= k.ks_area * us;
  spin(b.fs);
  b.fs = m.half(b.fs);
  if constexpr (D == 3) {
    b.mb = m.half(b.mb);
    spin(b.mb);
    const double twist = m.dtheta.dot(m.nm);
    b.mt -= k.ks_polar * twist;
    b.mb -= k.kn_inertia * (m.dtheta - twist * m.nm);
    spin(b.mb);
    b.mb = m.half(b.mb);
    b.mb -= b.mb.dot(m.n1) * m.n1;  // only round-off leaves the plane
  } else {
    b.mb -= k.kn_inertia * m.dtheta;
  }
  b.fs -= b.fs.dot(m.n1) * m.n1;
  b.sigma = -b.fn * k.inv_area + b.mb.norm() * k.rbar_over_inertia;
  b.tau = b.fs.norm() * k.inv_area;
  if constexpr (D == 3) b.tau += std::abs(b.mt) * k.rbar_over_polar;
  if (b.sigma >= k.sigma_c || b.tau >= k.tau_c) {
    b.broken = true;
    b.fn = 0;
    b.fs.setZero();
    b.mb.setZero();
    b.mt = 0;
    return false;
  }
  return true;
}

// The same from the law and the bond's radius.
template <int D>
inline bool parallel_bond_update(const BondLaw& law, double rbar, const BondMotion<D>& m,
                                 DemBond<D>& b) {
  return parallel_bond_update<D>(PreparedBondLaw(law, rbar), m, b);
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
