#pragma once
// Reaction of the drag on the resin (paper Eqs. 11-12 as docs/physics.md "Coupling" reads
// them): SPH neighbour r of DEM particle f receives
//   F_r = - (V_r W_fr / S_f) F_d,f,   S_f = sum_r V_r W_fr (shepard.hpp),
// and its acceleration is F_r / m_r (paper Eq. 5's F_ext / m_r; Eq. 13
// drops the 1/m_r). The weights of f's neighbours sum to 1, so the
// reactions sum to -F_d,f and the total momentum is conserved to round-off.
// Use the same S_f, neighbour set and V_r as the Shepard filter.
#include "sphdem/particles/particles.hpp"

namespace sphdem::terms {

// r's share of f's drag: V_r W_fr / S_f (S_f > 0).
inline double reaction_weight(double vol_r, double w_fr, double s_f) {
  return vol_r * w_fr / s_f;
}

// The force on SPH particle r from DEM particle f's drag f_drag.
template <int D>
inline Vec<D> reaction_force(double vol_r, double w_fr, double s_f, const Vec<D>& f_drag) {
  return -reaction_weight(vol_r, w_fr, s_f) * f_drag;
}

// The same factored for the loop over DEM particles: -F_d,f / S_f once per
// DEM particle (zero without resin), times V_r W_fr per neighbour r.
template <int D>
inline Vec<D> reaction_per_weight(double s_f, const Vec<D>& f_drag) {
  return s_f > 0.0 ? Vec<D>(-f_drag / s_f) : Vec<D>::Zero();
}

}  // namespace sphdem::terms
