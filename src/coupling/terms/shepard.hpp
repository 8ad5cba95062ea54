#pragma once
// Resin velocity at a DEM particle by a Shepard filter over its SPH
// neighbours r (paper Eq. 9):
//   vbar_f = sum_r v_r V_r W_fr / S_f,   S_f = sum_r V_r W_fr,   V_r = m_r / rho_r.
// S_f is also the normaliser of the reaction (paper Eq. 12, reaction.hpp).
// No resin within the support (S_f = 0): no resin velocity, and the caller
// applies no drag (a fibre in air or in a void is not dragged).
// Only resin particles count, not wall particles.
#include "sphdem/particles/particles.hpp"

namespace sphdem::terms {

template <int D>
struct ShepardSum {
  double s = 0.0;              // S_f = sum_r V_r W_fr [-]
  Vec<D> sv = Vec<D>::Zero();  // sum_r V_r W_fr v_r [m/s]

  // One SPH neighbour r: vol_r = m_r / rho_r, w = W(|x_f - x_r|).
  void add(double vol_r, double w, const Vec<D>& v_r) {
    const double a = vol_r * w;
    s += a;
    sv += a * v_r;
  }
  bool has_resin() const { return s > 0.0; }
  // vbar; zero when there is no resin (has_resin() false).
  Vec<D> mean() const { return s > 0.0 ? Vec<D>(sv / s) : Vec<D>::Zero(); }
};

}  // namespace sphdem::terms
