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
// rebuild (STYLE habit 2). Ghosts are never written by the physics (gather
// formulation), so there is no reverse communication.
#include <cstdint>
#include <vector>

#include "sphdem/decomposition.hpp"
#include "sphdem/particles.hpp"

namespace sphdem {

template <int D>
class Halo {
 public:
  // Collective. Drops old ghosts and appends the new ones after the owned
  // particles, ordered by source rank, then by the source's local order, with
  // every field of FieldPolicy.ghost (gid, kind, wall, mass and the state).
  // Call after migration: every owned particle must lie in this rank's cells.
  void build(const Decomposition<D>& dec, SphParticles<D>& ps, double range);

  // Collective. Before the rates: position (plus the shift), velocity and
  // density of every ghost.
  void update_state(SphParticles<D>& ps);

  // Collective. After the wall extrapolation: pressure, density and no-slip
  // velocity of the wall ghosts.
  void update_wall_state(SphParticles<D>& ps);

  std::size_t size() const { return recv_.total(); }       // ghosts received
  std::size_t sent() const { return send_index_.size(); }  // copies sent

 private:
  void build_wall_plan(const SphParticles<D>& ps, std::size_t ranks);

  MPI_Comm comm_ = MPI_COMM_NULL;
  // Who sends to whom; offsets count ghosts (state) or wall ghosts.
  MessageRoute send_, recv_;                  // every ghost
  std::vector<std::size_t> send_index_;       // owned source of each copy sent, grouped by rank
  std::vector<Vec<D>> send_shift_;            // periodic shift added to its position
  MessageRoute wall_send_, wall_recv_;        // the wall ghosts only
  std::vector<std::size_t> wall_send_index_;  // owned sources of wall copies, grouped by rank
  std::vector<std::size_t> wall_recv_slot_;   // their ghost slots, grouped by source
  std::vector<double> send_buf_, recv_buf_;
};

}  // namespace sphdem
