#pragma once
// The two coupling passes (docs/physics.md "Coupling"),
// over the particles present on a rank (owned and ghosts). No MPI: between
// the passes the solver sends each DEM ghost its owner's drag and Shepard
// sum (DemHalo::forward(DemGroup::Coupling)).
//   1. drag_on_fibers: for every owned DEM particle f, the mean drag of the
//      step that just ended (its impulse over the sub-steps / dt: the
//      momentum the resin must get back), then the void fraction at x_f,
//      the Shepard resin velocity vbar and the normaliser S_f, and the new
//      drag law F = K V_f (vbar - v_f) held over the next sub-steps
//      (drag_coeff = K V_f with K at the current slip, drag_velocity = vbar);
//      with hydrodynamic_torque, the same for the rotation: the mean
//      torque of the step, the resin spin (half the vorticity of the
//      weighted linear fit of the neighbours' velocities) and the
//      rotational friction held over the next sub-steps, and the lever
//      that returns the angular impulse to the resin (terms/rotation.hpp).
//   2. reaction_on_resin: for every owned resin particle r, the reaction
//      -(V_r W_fr / S_f) F_mean,f of every DEM neighbour f (into a; returns
//      the sum of these forces over the rank's resin), with
//      hydrodynamic_torque the torque's reaction V_r W_fr A_f x d_r (zero
//      net force; its moment returns the torque and the drag's moment), and with
//      void_fraction_in_continuity the continuity rate with the void
//      fraction (into drho).
// Every sum runs over neighbours in increasing global id, so results are
// bitwise the same on any number of ranks; the reactions of one DEM
// particle sum to -F_d exactly up to round-off.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "sphdem/coupling/coupling.hpp"
#include "sphdem/coupling/coupling_pairs.hpp"
#include "sphdem/particles/dem_particles.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/kernel.hpp"

namespace sphdem {

struct CouplingSettings {
  CouplingParams drag;                      // resin rho, mu, eps_min, eps_switch
  double h = 0;                             // smoothing length of the averaging kernel [m]
  double thickness = 1.0;                   // 2D depth of the DEM particles [m]
  bool void_fraction_in_continuity = true;  // the "local averaging" continuity form
  bool hydrodynamic_torque = true;          // the resin's torque on the fibers and its reaction
  // fibers.drag_integration: exponential: the sub-steps relax each fiber
  // particle with its resin parcel (drag_exchange.hpp); drag_on_fibers sets
  // the parcel's mass and no drag force or torque.
  bool exponential_drag = false;
};

// The resin mass a fiber particle exchanges momentum with under
// exponential drag [kg] (docs/physics.md "Exponential drag"). An impulse J
// spread over the resin as w_r J (w_r = V_r W_fr / S_f) moves the Shepard
// velocity by J sum_r w_r^2 / m_r: the parcel's mass is 1 / sum_r w_r^2 / m_r
// (`inverse_sum`). Other fiber particles within the kernel pull on the same
// resin: the mass is shared among the `sharing` DEM particles there, and
// halved, since an exchange is stable only while the parcel's mass is not
// overestimated (the resin receives the impulse a step late).
inline double drag_parcel_mass(double inverse_sum, int sharing) {
  return inverse_sum > 0 ? 0.5 / (inverse_sum * std::max(sharing, 1)) : 0.0;
}

// What the passes keep between calls: the candidate pairs
// (coupling_pairs.hpp) and scratch. The passes' results per DEM particle
// are fields of DemParticles (dem_particles.hpp): shepard_sum, mean_drag,
// void_fraction, resin_velocity.
template <int D>
struct CouplingState {
  CouplingPairs<D> pairs;
  // keep_pairs: the pairs live across passes, with a skin [m] (the caller
  // sets `generation` anew whenever either side's particles may have been
  // reordered, or invalidates the pairs). Otherwise every drag pass
  // searches afresh (the reaction always uses the drag pass's pairs).
  bool keep_pairs = false;
  double skin = 0;
  std::int64_t generation = 0;
  // The reaction's accumulators, one record per slot
  // (CouplingPairs::slot_resin): a pair reads and writes one cache line
  // instead of one in each of six arrays (docs/performance.md, "The
  // plate's loop kept inline; the coupling's walks").
  struct ReactionSlot {
    Vec<D> force = Vec<D>::Zero();
    double phi = 0, phi_rate = 0, held = 0;
    double vol = 0;  // V_r = m_r / rho_r
    bool touched = false;
  };
  std::vector<ReactionSlot> slots;
};

// dt: the SPH step that just ended (0 at the start: no impulse yet).
template <int D>
void drag_on_fibers(const CouplingSettings& s, const SphParticles<D>& sph, DemParticles<D>& dem,
                    CouplingState<D>& st, double dt);

// Reads the DEM particles' mean_drag, shepard_sum and drag_coeff, ghosts'
// included, and walks the pairs of the drag pass before it (`st`). resin_drag_rate: the largest,
// over the owned resin, of sum_f (V_r W_fr / S_f) K_f V_f / m_r [1/s], the rate at which the
// reaction relaxes a resin particle's velocity towards the fibers' (the
// resin side of the exchange is explicit: docs/physics.md "The stable
// window").
// impulse_dt > 0 (exponential drag): the reaction is not an acceleration
// but the impulse F_mean impulse_dt itself, added to the half-step velocity
// v_half that the second kick starts from (and to v): the resin gets the
// fibers' impulse in the step it was exchanged, not through its leapfrog a
// step late; frozen resin keeps its rest (the impulse goes to the mold, as
// at a wall).
template <int D>
Vec<D> reaction_on_resin(const CouplingSettings& s, const DemParticles<D>& dem,
                         SphParticles<D>& sph, CouplingState<D>& st,
                         std::vector<double>& resin_void_fraction, double& resin_drag_rate,
                         double impulse_dt = 0.0);

}  // namespace sphdem
