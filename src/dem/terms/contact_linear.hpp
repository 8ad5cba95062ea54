#pragma once
// Linear spring-dashpot contact (Cundall & Strack 1979; docs/dem.md):
//   normal      F_n = k_n delta - c_n v_n            (along n, on the partner)
//   tangential  xi += v_t dt,  F_t = -k_t xi - c_t v_t,  |F_t| <= mu max(F_n, 0)
// n is the unit vector from the owner to the partner (or the wall), delta
// the overlap, v = v_partner - v_owner at the contact point, v_n = v . n
// (> 0 separating). The normal force is not clipped at zero, so restitution
// and contact time follow docs/validation.md section 2 exactly (a slight pull at the end of
// an impact). The spring xi is the pair's history: it is turned into the
// current tangent plane keeping its length (the contact plane rotates), and
// when the Coulomb cap binds it is reset to the length that gives the capped
// force, so the contact slips with no stored excess.
#include <algorithm>
#include <cmath>

#include "sphdem/particles/dem_particles.hpp"

namespace sphdem::terms {

struct LinearContact {
  double kn, kt;  // [N/m]
  double cn, ct;  // [N s/m]
  double mu;
};

// Turns a history vector into the plane normal to n, keeping its length.
template <int D>
inline void rotate_into_plane(Vec<D>& s, const Vec<D>& n) {
  const double len = s.norm();
  s -= s.dot(n) * n;
  const double len_new = s.norm();
  if (len_new > 0.0) s *= len / len_new;
}

// Force on the partner; the owner receives its opposite. Updates xi.
template <int D>
inline Vec<D> linear_contact(const LinearContact& c, const Vec<D>& n, double delta,
                             const Vec<D>& v_rel, double dt, Vec<D>& xi) {
  const double vn = v_rel.dot(n);
  const double fn = c.kn * delta - c.cn * vn;
  const Vec<D> vt = v_rel - vn * n;
  rotate_into_plane<D>(xi, n);
  xi += vt * dt;
  Vec<D> ft = -c.kt * xi - c.ct * vt;
  const double cap = c.mu * std::max(fn, 0.0);
  const double ft_norm = ft.norm();
  if (ft_norm > cap) {
    ft *= ft_norm > 0.0 ? cap / ft_norm : 0.0;
    if (c.kt > 0.0) xi = -(ft + c.ct * vt) / c.kt;
  }
  return fn * n + ft;
}

// Elastic energy of the contact's springs (energy diagnostics).
template <int D>
inline double linear_contact_energy(const LinearContact& c, double delta, const Vec<D>& xi) {
  return 0.5 * c.kn * delta * delta + 0.5 * c.kt * xi.squaredNorm();
}

}  // namespace sphdem::terms
