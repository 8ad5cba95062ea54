#pragma once
// The candidate pairs of the coupling passes (coupling_loops.hpp): one
// search serves the drag on the fibers and the reaction on the resin, and
// is kept between passes like the resin's Verlet list. Candidates lie
// within the kernel support plus a skin; each pass keeps the pairs within
// the support, in the order of the old per-pass search (increasing global
// id), so the results do not depend on when the list was built.
//
// The list indexes the particles present on the rank: it is built afresh
// when either side's particles may have been reordered (a rebuild of the
// resin's or of the DEM's lists: `generation` changes, or the caller
// invalidates it), or when a DEM particle and a resin particle (or two DEM
// particles) may together have moved more than the skin since the build.
// The decision is rank-local: no vote, the results are the same either way.
#include <cstdint>
#include <vector>

#include "sphdem/particles/dem_particles.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

template <int D>
struct CouplingPairs {
  // Per DEM particle f (owned and ghosts): the fluid particles (owned and
  // ghosts) within support + skin, [resin_start[f], resin_start[f + 1]) of
  // resin_items (SPH indices), by increasing gid; resin_slot: the owned
  // one's slot (below), -1 for a ghost.
  std::vector<std::int32_t> resin_start, resin_items, resin_slot;
  // Per owned DEM particle f: the DEM particles (owned and ghosts) within
  // support + skin, f itself included, by increasing gid.
  std::vector<std::int32_t> dem_start, dem_items;
  // Every DEM particle, by increasing gid (the reaction's order).
  std::vector<std::int32_t> dem_order;
  // The owned fluid particles in some list, by increasing SPH index: the
  // reaction's accumulators.
  std::vector<std::int32_t> slot_resin;

  // The build: positions, sizes and the caller's generation.
  std::vector<Vec<D>> resin_x0, dem_x0;
  std::size_t n_sph = 0, n_sph_owned = 0, n_dem = 0, n_dem_owned = 0;
  std::int64_t generation = 0;
  bool valid = false;
  double support = 0, skin = 0;

  std::int64_t builds = 0;  // a counter, for the timings

  void invalidate() { valid = false; }
  // Whether the list was built over these particles (their counts; the
  // positions are update_coupling_pairs's check).
  bool built_for(const SphParticles<D>& sph, const DemParticles<D>& dem) const {
    return valid && n_sph == sph.size() && n_sph_owned == sph.n_owned && n_dem == dem.size() &&
           n_dem_owned == dem.n_owned;
  }
};

// Rebuilds `pairs` unless they still hold every pair within `support` of
// the current positions (see above). Returns true when it rebuilt.
template <int D>
bool update_coupling_pairs(CouplingPairs<D>& pairs, const SphParticles<D>& sph,
                           const DemParticles<D>& dem, double support, double skin,
                           std::int64_t generation);

}  // namespace sphdem
