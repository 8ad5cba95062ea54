#pragma once
// The resin's hydrodynamic torque on a DEM particle and its reaction
// (docs/physics.md "Hydrodynamic torque").
//
// Resin rotation at x_f: the weighted least-squares linear fit of the resin
// velocities v_r of f's neighbours, with the Shepard filter's weights
// w_r = V_r W_fr (shepard.hpp), about their weighted centroid xbar:
//   C = sum_r w_r d_r d_r^T,  G = sum_r w_r (v_r - vbar) d_r^T,  d_r = x_r - xbar,
//   L = G C^-1 (the velocity gradient, exact for a linear velocity field),
// and the resin spin is half its vorticity, Omega = (curl v) / 2 (the
// antisymmetric part of L). The torque on f is T = zeta_r (Omega - omega_f).
//
// Rotational friction: the bead model's Stokes torque on a sphere,
// 8 pi mu a^3, and per unit length on a circular cylinder in 2D,
// 4 pi mu a^2 (Lamb), scaled like the drag law's K (void fraction,
// Reynolds number) so that both follow the same correction:
//   zeta_r = c_D a^2 K V_f,   c_3 = 4/3, c_2 = 8/9,
// since the drag law's Stokes limit at eps = 1 is K V_f = 6 pi mu a (3D)
// and 4.5 pi mu per unit depth (2D) (coupling.hpp).
//
// Reaction: resin neighbour r receives F_r = w_r A x d_r, with the lever A
// solving J A = -M, J = sum_r w_r (|d_r|^2 I - d_r d_r^T) (2D: sum_r
// w_r |d_r|^2). Then sum_r F_r = 0 (sum_r w_r d_r = 0 about the centroid)
// and sum_r d_r x F_r = -M. With M = T_f - (xbar - x_f) x F_f the resin
// gets back exactly the angular momentum the particle's torque and drag
// took (the drag's reaction acts at xbar, not at x_f).
#include <Eigen/Dense>
#include <cmath>

#include "sphdem/particles/dem_particles.hpp"

namespace sphdem::terms {

// zeta_r / (a^2 K V_f): the ratio of the Stokes rotational friction to the
// drag law's Stokes translational friction, times 1/a^2 (see above).
template <int D>
inline constexpr double kRotationalFriction = D == 2 ? 8.0 / 9.0 : 4.0 / 3.0;

// zeta_r [N m s] of a particle of radius a whose drag coefficient is K V_f
// (drag_coeff [kg/s], 2D: with the depth already in it).
template <int D>
inline double rotational_friction(double drag_coeff, double a) {
  return kRotationalFriction<D> * a * a * drag_coeff;
}

template <int D>
using Mat = Eigen::Matrix<double, D, D>;

// The weighted fit about the centroid: add every neighbour with its
// offset from the centroid d and its velocity relative to vbar.
template <int D>
struct RotationFit {
  Mat<D> c = Mat<D>::Zero();  // sum w d d^T [m^5] (2D: m^4)
  Mat<D> g = Mat<D>::Zero();  // sum w (v - vbar) d^T

  void add(double w, const Vec<D>& d, const Vec<D>& dv) {
    c.noalias() += w * d * d.transpose();
    g.noalias() += w * dv * d.transpose();
  }
  // The neighbours span the space (not all on a line or a plane): the
  // smallest eigenvalue of C above 1e-8 of the mean one.
  bool solvable() const {
    const double mean = c.trace() / D;
    if (!(mean > 0.0)) return false;
    return c.determinant() > 1e-8 * std::pow(mean, D);
  }
  // L = G C^-1, its antisymmetric part as a spin (half the vorticity).
  Rot<D> spin() const {
    const Mat<D> l = g * c.inverse();
    Rot<D> s;
    if constexpr (D == 2) {
      s[0] = 0.5 * (l(1, 0) - l(0, 1));
    } else {
      s = 0.5 * Vec<3>(l(2, 1) - l(1, 2), l(0, 2) - l(2, 0), l(1, 0) - l(0, 1));
    }
    return s;
  }
  // A with J A = -m.
  Rot<D> lever(const Rot<D>& m) const {
    if constexpr (D == 2) {
      Rot<D> a;
      a[0] = -m[0] / c.trace();
      return a;
    } else {
      const Mat<3> j = c.trace() * Mat<3>::Identity() - c;
      return Rot<D>(-j.inverse() * m);
    }
  }
};

// The moment the resin must get back from particle f: its mean torque
// plus the moment of its mean drag about the centroid (offset = xbar - x_f).
template <int D>
inline Rot<D> torque_to_return(const Rot<D>& mean_torque, const Vec<D>& offset,
                               const Vec<D>& mean_drag) {
  return mean_torque - moment<D>(offset, mean_drag);
}

// The force on resin neighbour r (weight w = V_r W_fr, d = x_r - xbar).
template <int D>
inline Vec<D> torque_reaction_force(double w, const Rot<D>& lever, const Vec<D>& d) {
  return w * cross<D>(lever, d);
}

}  // namespace sphdem::terms
