#pragma once
// Ghost particles (forward communication, docs/parallel.md). A ghost is a
// copy of another rank's owned particle, or a periodic image of any owned
// particle (a rank's own included: one rank with periodic axes sends to
// itself, so there is one code path). Every owned particle within `range`
// of a cell of another rank - or of a cell across a periodic face - goes to
// that cell's owner, shifted by the period when it crosses a face.
//
// The plan (per destination: local indices and shifts; per source: counts)
// is built with the neighbor lists and reused every step until the next
// rebuild. Ghosts are never written by the physics (gather
// formulation), so there is no reverse communication. What travels is read
// from the field registry (particles.hpp): every kGhost field at the build,
// the fields of one exchange group at each forward(group).
#include <cstdint>
#include <vector>

#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Who sends which owned particle to whom, and where the copies land; shared
// by the SPH and DEM halos (src/parallel/ghost_fields.hpp sends along it).
template <int D>
struct GhostPlan {
  MessageRoute send, recv;
  std::vector<std::size_t> send_index;  // owned source of each copy sent, grouped by rank
  std::vector<Vec<D>> send_shift;       // periodic shift of each copy (kShifted fields)
  // Ghost slot of each copy received, grouped by source rank; empty: the
  // ghosts in order from n_owned.
  std::vector<std::size_t> recv_slot;
};

template <int D>
class Halo {
 public:
  // Collective. Drops old ghosts and appends the new ones after the owned
  // particles, ordered by source rank, then by the source's local order, with
  // every kGhost field (gid, kind, wall, mass and the state; positions
  // shifted). Call after migration: every owned particle must lie in this
  // rank's cells.
  void build(const Decomposition<D>& dec, SphParticles<D>& ps, double range);

  // Collective. The fields of `group` (SphGroup, particles.hpp) from their
  // owners: State to every ghost before the rates (position plus the
  // shift, velocity, density), WallState to the wall ghosts after the wall
  // extrapolation (pressure, density, no-slip velocity).
  void forward(SphParticles<D>& ps, SphGroup group);

  std::size_t size() const { return plan_.recv.total(); }       // ghosts received
  std::size_t sent() const { return plan_.send_index.size(); }  // copies sent

 private:
  void build_wall_plan(const SphParticles<D>& ps, std::size_t ranks);

  MPI_Comm comm_ = MPI_COMM_NULL;
  GhostPlan<D> plan_;       // every ghost
  GhostPlan<D> wall_plan_;  // the wall ghosts only
  std::vector<char> send_buf_, recv_buf_;
};

}  // namespace sphdem
