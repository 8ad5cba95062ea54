// The resin's rates: the neighbour-sum passes of pass_loop.hpp, then the pair loop of pair_loop.hpp
// over the terms of sph_terms.hpp (docs/performance.md describes the loop's layout).
#include <algorithm>

#include "pair_loop.hpp"
#include "pass_loop.hpp"
#include "sph_terms.hpp"

namespace sphdem {

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps);
  add_wall_repulsion<D>(sp, nl, ps);
}

template <int D>
void compute_fluid_passes(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                          const std::function<void(SphGroup)>& forward) {
  terms::run_passes<D, terms::SphTerms>(sp, nl, ps, forward, terms::SphPasses{});
  // The viscosity of a law, or asked for as output (a Newtonian resin's mu).
  const auto& out = sp.output_fields;
  if (sp.variable_viscosity || std::find(out.begin(), out.end(), "viscosity") != out.end())
    terms::compute_particle_viscosity(sp, ps);
}

template void compute_fluid_passes<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&,
                                      const std::function<void(SphGroup)>&);
template void compute_fluid_passes<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&,
                                      const std::function<void(SphGroup)>&);
template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
