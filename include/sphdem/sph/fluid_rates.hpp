#pragma once
// The passes and the rates of one rate evaluation, as the solver runs them
// (src/sph/fluid_rates.cpp).
#include <functional>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

// compute_fluid_passes then compute_fluid_rates, the same bits, with one walk
// over the lists less when only the anti-clump term reads the free-surface
// flag: the pair loop then computes the flag on the side and forwards its
// group itself (docs/performance.md, "The free-surface flag inside the pair
// loop").
template <int D>
void compute_fluid_passes_and_rates(const SphParams& sp, const NeighborList<D>& nl,
                                    SphParticles<D>& ps,
                                    const std::function<void(SphGroup)>& forward);

}  // namespace sphdem
