// The resin's rates: the pair loop of pair_loop.hpp over the terms of
// sph_terms.hpp (docs/performance.md describes the loop's layout).
#include "pair_loop.hpp"
#include "sph_terms.hpp"

namespace sphdem {

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps);
}

template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
