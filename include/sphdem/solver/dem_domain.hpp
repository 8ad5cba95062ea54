#pragma once
// The decomposed DEM particles of a run (docs/parallel.md, "DEM
// particles"): each rank owns the DEM particles in its cells of a
// Decomposition (its own in a fibers-only run, the resin's in a coupled
// run) plus ghosts within the halo range, and advances them by velocity-
// Verlet sub-steps. Between sub-steps only the ghosts' position, velocity
// and spin travel (DemGroup::State); a rebuild (migration, ghosts with their slots, pair
// list) happens when some particle has moved half the pair-list skin, or
// when the decomposition changes. Results are bitwise the same on any
// number of ranks (gather formulation, dem.hpp).
#include <cstdint>
#include <limits>
#include <vector>

#include "sphdem/dem/dem.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/dem_halo.hpp"

namespace sphdem {

template <int D>
class DemDomain {
 public:
  // What each rank passes to the constructor: every DEM particle, the same
  // on every rank (as the generator makes them), each rank keeping those in
  // its cells; or a share, every particle on exactly one rank (a restart's
  // slice of the checkpoint, docs/checkpoint.md "At scale"), which one
  // migration takes to the owners.
  enum class Input { Replicated, Share };
  // Collective. halo_range: how far other ranks must see a particle (at
  // least the DEM pair reach 2 R_max + skin, which is added here; a coupled
  // run passes the resin's cut-off). Either input gives the owned
  // particles in the same (gid) order. skin_limit: the largest pair-list
  // skin (a coupled run's, coupled_skins.hpp).
  DemDomain(const Decomposition<D>& dec, const DemParams<D>& params, std::vector<DemWall<D>> walls,
            DemParticles<D> particles, double halo_range = 0, Input input = Input::Replicated,
            double skin_limit = std::numeric_limits<double>::infinity());

  // The pair-list skin and the pair reach 2 R_max + skin for particle radii
  // in [r_min, r_max]: the smallest cell a DEM-only decomposition may use.
  static double skin(double r_min) { return 0.25 * r_min; }
  static double reach(double r_min, double r_max) { return 2.0 * r_max + skin(r_min); }
  // The pair-list skin this domain chose (the same on every rank).
  double list_skin() const { return ws_.skin; }

  // Collective. n velocity-Verlet sub-steps of dt, f_ext held constant.
  void advance(std::int64_t n, double dt);
  // Collective. Migration, ghosts, pair list (after a re-partition).
  void rebuild();
  // Take the particles' force and torque as those of the current state
  // (a restart: they come from the checkpoint), so the first sub-step does
  // not evaluate them again.
  void adopt_forces() { ws_.forces_valid = true; }
  // The contact history back into the owners' slots (before output).
  void store_state() { dem_store_pair_state(ps_, ws_); }

  // Collective: the stable sub-step over all ranks.
  double stable_dt() const;
  std::int64_t global_count() const { return n_global_; }
  std::int64_t rebuilds() const { return rebuilds_; }

  DemParticles<D>& particles() { return ps_; }
  const DemParticles<D>& particles() const { return ps_; }
  std::vector<DemWall<D>>& walls() { return walls_; }
  const std::vector<DemWall<D>>& walls() const { return walls_; }
  const DemParams<D>& params() const { return params_; }
  double halo_range() const { return range_; }
  // Collective: the fields of an exchange group to the ghosts (DemHalo::
  // forward). advance() leaves the ghosts at the last sub-step's half-step
  // velocity (the final kick comes after their update): the coupling,
  // which reads full-step values, forwards State first; and Coupling after
  // its drag pass, for the reaction on the resin of other ranks.
  void forward(DemGroup group) { halo_.forward(ps_, group); }

 private:
  void advance_subcycled(std::int64_t n, double dt);
  // Collective: the ghosts' State forwarded and whether any rank's particle
  // (or wall) moved more than sqrt(limit2) since the last rebuild, or any
  // rank forces a rebuild.
  bool vote_and_forward(double limit2, bool force);
  const Decomposition<D>& dec_;
  DemParams<D> params_;
  std::vector<DemWall<D>> walls_;
  DemParticles<D> ps_;
  DemWorkspace<D> ws_;
  DemHalo<D> halo_;
  double range_ = 0;
  std::int64_t n_global_ = 0, rebuilds_ = 0;
};

}  // namespace sphdem
