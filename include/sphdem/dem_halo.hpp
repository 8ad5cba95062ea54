#pragma once
// Ghost DEM particles (docs/parallel.md, "DEM particles"): the same plan as
// the SPH halo (halo.hpp), over DEM particles. The build copies every ghost
// field once, bond and contact slots included, so a rank evaluates a pair
// whose smaller gid is a ghost from the same state as the ghost's owner.
// Between DEM sub-steps only position, velocity and spin travel.
#include <cstdint>
#include <vector>

#include "sphdem/decomposition.hpp"
#include "sphdem/dem_particles.hpp"

namespace sphdem {

template <int D>
class DemHalo {
 public:
  // Collective. Drops old ghosts and appends copies of every owned particle
  // within `range` of another rank's cell. Call after migration.
  void build(const Decomposition<D>& dec, DemParticles<D>& ps, double range);

  // Collective. Position, velocity and angular velocity of every ghost.
  void update_state(DemParticles<D>& ps);

  // Collective. The coupling's mean drag and Shepard sum of every ghost
  // (both indexed like the particles).
  void update_coupling(std::vector<Vec<D>>& drag, std::vector<double>& shepard_sum);

  std::size_t size() const { return recv_.total(); }       // ghosts received
  std::size_t sent() const { return send_index_.size(); }  // copies sent

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  MessageRoute send_, recv_;
  std::vector<std::size_t> send_index_;
  std::vector<Vec<D>> send_shift_;
  std::vector<double> send_buf_, recv_buf_;
};

}  // namespace sphdem
