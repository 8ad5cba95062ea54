// The resin's rates: the neighbour-sum passes of pass_loop.hpp, then the pair loop of pair_loop.hpp
// over the terms of sph_terms.hpp (docs/performance.md describes the loop's layout).
#include <algorithm>
#include <string_view>

#include "pair_loop.hpp"
#include "pass_loop.hpp"
#include "sph_terms.hpp"

namespace sphdem {

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  // The pair loop lists the particles close enough to a neighbour for the
  // wall repulsion, which then walks only their lists.
  thread_local terms::CloseNeighbours close;
  close.within2 = wall_repulsion_range2<D>(sp);
  terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps, &close);
  add_wall_repulsion<D>(sp, nl, ps, close.particles);
  // With implicit viscosity the traction is in the solve (implicit_viscosity.cpp).
  if (!sp.implicit_viscosity) add_free_surface_traction<D>(sp, nl, ps);
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

// Each optional field with the options that read or write it; the passes'
// fields follow pass_needed (src/sph/pass_loop.hpp), so a field is held
// exactly when something touches it (tests/test_field_use.cpp).
template <int D>
void drop_unused_fields(const SphParams& sp, bool slip_walls, SphParticles<D>& ps) {
  const std::vector<std::string> passes =
      terms::needed_passes<terms::SphTerms>(sp, terms::SphPasses{});
  const auto in = [](const std::vector<std::string>& names, std::string_view n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  const auto named = [&](std::string_view n) { return in(sp.output_fields, n); };
  const auto runs = [&](std::string_view n) { return in(passes, n); };
  const bool tension = runs("colour") || runs("curvature");  // the curvature reads the normals
  const bool surface_normal = sp.shifting > 0.0 || sp.front_events || named("surface_normal");
  struct Use {
    const char* field;
    bool used;
  };
  const Use uses[] = {
      // the slip walls' dummy velocity, the thermal walls' distance, the contact angle
      {"wall_to_surface", slip_walls || sp.thermal || tension},
      {"temperature", sp.thermal || named("temperature")},
      {"dtemp", sp.thermal},
      {"temp_half", sp.thermal},
      {"frozen", sp.thermal || named("frozen")},
      {"weld_line", sp.front_events || named("weld_line")},
      {"shear_rate", runs("shear_rate")},
      // a law's particle viscosity (also the coupling's local viscosity), or its output
      {"viscosity", sp.melt.law != ViscosityLaw::Newtonian || named("viscosity")},
      // the anti-clump term reads the flag even when its pass does not run (epsilon 0)
      {"free_surface", runs("free_surface") || sp.anti_clump},
      {"surface_normal", surface_normal},
      {"position_divergence", named("position_divergence")},
      {"shifting_gradient", sp.shifting > 0.0},
      {"shift", sp.shifting_continuity},
      {"colour", tension},
      {"csf_normal", tension},
      {"curvature", runs("curvature")},
      {"visc_u", sp.implicit_viscosity},
      {"visc_free", sp.implicit_viscosity},
      {"visc_acc", sp.implicit_viscosity},
  };
  for (const Use& u : uses)
    if (!u.used) ps.drop_field(u.field);
}

template void drop_unused_fields<2>(const SphParams&, bool, SphParticles<2>&);
template void drop_unused_fields<3>(const SphParams&, bool, SphParticles<3>&);

template void compute_fluid_passes<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&,
                                      const std::function<void(SphGroup)>&);
template void compute_fluid_passes<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&,
                                      const std::function<void(SphGroup)>&);
template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
