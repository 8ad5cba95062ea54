#pragma once
// Ghost particles (forward communication). Built with the neighbor lists and
// reused every step until the next rebuild (STYLE habit 2): a ghost is a
// copy of an owned particle - here the periodic image of one within
// `range` of a periodic face; with several ranks the same plan also lists
// the particles other ranks need. Ghosts are never written by the physics
// (gather formulation), so there is no reverse communication.
#include <array>
#include <vector>

#include "sphdem/geometry.hpp"
#include "sphdem/particles.hpp"

namespace sphdem {

template <int D>
class Halo {
 public:
  // Drops old ghosts, wraps owned positions back into the periodic box and
  // appends a ghost for every image within `range` of the box.
  void build(SphParticles<D>& ps, const Box<D>& domain, const std::array<bool, 3>& periodic,
             double range);

  // Before the rates: position, velocity, density (and the constant fields
  // kind, wall, mass, gid, copied at build).
  void update_state(SphParticles<D>& ps) const;

  // After the wall extrapolation: the wall particles' pressure, density and
  // no-slip velocity.
  void update_wall_state(SphParticles<D>& ps) const;

  std::size_t size() const { return src_.size(); }

 private:
  std::vector<std::size_t> src_;  // owned source of ghost k (slot n_owned + k)
  std::vector<Vec<D>> shift_;     // periodic shift added to the source position
};

}  // namespace sphdem
