#pragma once
// The distributed set-up (docs/parallel.md, "Distributed set-up"): every
// rank fills only the particles of its own top-level cells, numbered as
// one rank numbers them (build_initial_particles), so the ids and every
// result do not depend on the rank count.
#include "sphdem/config/case.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Collective. Counts the lattice (each rank a 1/P share of its rows),
// partitions `dec` by the work per top-level cell, then fills `out` (empty)
// with this rank's owned particles, resin first, each in id order. Returns
// the global counts. Throws InputError on every rank for a bad fill region
// or initial-field expression.
template <int D>
InitialCounts fill_distributed(const Case& c, Decomposition<D>& dec, SphParticles<D>& out);

}  // namespace sphdem
