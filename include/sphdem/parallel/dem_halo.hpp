#pragma once
// Ghost DEM particles (docs/parallel.md, "DEM particles"): the same plan as
// the SPH halo (halo.hpp), over DEM particles. The build copies every
// kGhost field once, bond and contact slots included, so a rank evaluates a
// pair whose smaller gid is a ghost from the same state as the ghost's
// owner. Afterwards only the fields of one exchange group travel at a time
// (DemGroup, dem_particles.hpp).
#include <cstdint>
#include <vector>

#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/halo.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

template <int D>
class DemHalo {
 public:
  // Collective. Drops old ghosts and appends copies of every owned particle
  // within `range` of another rank's cell. Call after migration.
  void build(const Decomposition<D>& dec, DemParticles<D>& ps, double range);

  // Collective. The fields of `group` from their owners to every ghost:
  // State between sub-steps (position plus the shift, velocity, angular
  // velocity), Coupling at the coupling pass (mean drag, Shepard sum).
  void forward(DemParticles<D>& ps, DemGroup group);
  // Collective over every rank: forward(ps, group) and the largest `value`
  // over the ranks, in one synchronisation for a few ranks (a DEM sub-step's
  // ghost update and rebuild vote together).
  double forward_max(DemParticles<D>& ps, DemGroup group, double value);

  std::size_t size() const { return plan_.recv.total(); }       // ghosts received
  std::size_t sent() const { return plan_.send_index.size(); }  // copies sent

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  GhostPlan<D> plan_;
  std::vector<char> send_buf_, recv_buf_;
};

}  // namespace sphdem
