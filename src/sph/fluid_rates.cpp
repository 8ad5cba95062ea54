// The resin's rates: the neighbour-sum passes of pass_loop.hpp, then the pair loop of pair_loop.hpp
// over the terms of sph_terms.hpp (docs/performance.md describes the loop's layout).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "pair_loop.hpp"
#include "pass_loop.hpp"
#include "sph_terms.hpp"
#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/sph/fluid_rates.hpp"

namespace sphdem {

namespace {

// Whether the pair loop computes the free-surface flag on the side: the pass
// would run as its Lite (only the anti-clump term reads the flag) and the
// case's loop gathers the flag's lanes (x, m/rho) anyway.
template <int D>
bool flag_in_pair_loop(const SphParams& sp) {
  return terms::pass_run<terms::FreeSurfacePass>(sp, terms::SphTerms{}) == terms::PassRun::Lite &&
         terms::pair_loop_computes<D, terms::SphTerms, terms::FreeSurfacePass::Lite>(sp);
}

template <int D>
void run_fluid_passes(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                      const std::function<void(SphGroup)>& forward, bool flag_in_loop) {
  terms::run_passes<D, terms::SphTerms>(sp, nl, ps, forward, terms::SphPasses{}, flag_in_loop);
  // The viscosity of a law, or asked for as output (a Newtonian resin's mu).
  const auto& out = sp.output_fields;
  if (sp.variable_viscosity || std::find(out.begin(), out.end(), "viscosity") != out.end())
    terms::compute_particle_viscosity(sp, ps);
}

// The owned resin particles whose record is in `refill` or whose list holds
// one of `refill` (sorted by index): what the second run of the loop
// computes again. Lists are symmetric (a pair is listed by both sides when
// both have lists: the same cell test and the same distance, whose square is
// the same bits either way round) and only resin particles are flagged, so
// an owned flagged particle's own list names the owned resin particles that
// list it: no walk of every list (that walk was 4-5 % of the plate's run).
// A flagged ghost has no list: the particles listing it are found by
// walking only the lists that hold a ghost (NeighborList::ghost_listers,
// found at the build: walking every list for its largest index at every
// step was 3 % of a 2-rank plate's CPU).
template <int D>
void particles_near_flags(const NeighborList<D>& nl, const SphParticles<D>& ps,
                          const std::vector<double>& flag, const std::vector<std::uint32_t>& refill,
                          std::vector<std::uint32_t>& redo) {
  const std::size_t n_owned = ps.n_owned;
  thread_local std::vector<std::uint8_t> mark;
  mark.assign(n_owned, 0);
  const auto mark_resin = [&](std::size_t i) {
    if (ps.kind[i] == Kind::Fluid) mark[i] = 1;
  };
  bool flagged_ghost = false;
  for (const std::uint32_t j : refill) {
    if (j >= n_owned) {
      flagged_ghost = true;
      continue;
    }
    mark_resin(j);
    const NeighborRow nb = nl.row(j);
    for (std::size_t b = nl.begin(j), e = nl.end(j); b < e; ++b) {
      const auto k = static_cast<std::size_t>(nb[b]);
      if (k < n_owned) mark_resin(k);
    }
  }
  if (flagged_ghost) {
    for (const std::uint32_t i : nl.ghost_listers()) {
      if (mark[i] || ps.kind[i] != Kind::Fluid) continue;
      const std::size_t b0 = nl.begin(i), e = nl.end(i);
      const NeighborRow nb = nl.row(i);
      for (std::size_t b = b0; b < e && !mark[i]; ++b) {
        const auto k = static_cast<std::size_t>(nb[b]);
        if (k >= n_owned && flag[k] != 0.0) mark[i] = 1;
      }
    }
  }
  for (std::size_t i = 0; i < n_owned; ++i)
    if (mark[i]) redo.push_back(static_cast<std::uint32_t>(i));
}

// The pair loop with the free-surface flag computed on the side
// (docs/performance.md, "The free-surface flag inside the pair loop"). The
// records read the flag (anti-clump's R_a is 0 where it is 1), so the loop
// runs on flags of 0 everywhere, then the flags are forwarded to the ghosts,
// and where some flag is 1 (a resin particle on the surface with P < 0: the
// only places the flag is set) those records are filled again and every
// list that holds one of them is computed again, with the same operations in
// the same order as a loop that had the flags from the start: the same bits
// as the flag pass followed by the loop.
template <int D>
void pair_loop_with_flag(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                         terms::CloseNeighbours& close,
                         const std::function<void(SphGroup)>& forward) {
  std::vector<double>& flag = terms::FreeSurfacePass::output(ps);
  std::fill(flag.begin(), flag.end(), 0.0);
  terms::PairLoopRun run;
  run.close = &close;
  run.side = true;
  terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps, run);
  forward(terms::FreeSurfacePass::group);

  thread_local std::vector<std::uint32_t> refill, redo;
  refill.clear();
  redo.clear();
  lanes::for_each_nonzero(flag.data(), ps.size(),
                          [&](std::size_t j) { refill.push_back(static_cast<std::uint32_t>(j)); });
  if (refill.empty()) return;
  particles_near_flags<D>(nl, ps, flag, refill, redo);
  run.side = false;
  run.redo = &redo;
  run.refill = &refill;
  terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps, run);
}

template <int D>
void run_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                     const std::function<void(SphGroup)>* flag_forward) {
  // The pair loop lists the particles close enough to a neighbour for the
  // wall repulsion, which then walks only their lists.
  thread_local terms::CloseNeighbours close;
  close.within2 = wall_repulsion_range2<D>(sp);
  if (flag_forward != nullptr)
    pair_loop_with_flag<D>(sp, nl, ps, close, *flag_forward);
  else
    terms::run_pair_loop<D, terms::SphTerms>(sp, nl, ps, &close);
  add_wall_repulsion<D>(sp, nl, ps, close.particles);
  // With implicit viscosity the traction is in the solve (implicit_viscosity.cpp).
  if (!sp.implicit_viscosity) add_free_surface_traction<D>(sp, nl, ps);
}

}  // namespace

template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps) {
  run_fluid_rates<D>(sp, nl, ps, nullptr);
}

template <int D>
void compute_fluid_passes(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                          const std::function<void(SphGroup)>& forward) {
  run_fluid_passes<D>(sp, nl, ps, forward, false);
}

template <int D>
void compute_fluid_passes_and_rates(const SphParams& sp, const NeighborList<D>& nl,
                                    SphParticles<D>& ps,
                                    const std::function<void(SphGroup)>& forward) {
  const bool flag_in_loop = flag_in_pair_loop<D>(sp);
  run_fluid_passes<D>(sp, nl, ps, forward, flag_in_loop);
  run_fluid_rates<D>(sp, nl, ps, flag_in_loop ? &forward : nullptr);
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
template void compute_fluid_passes_and_rates<2>(const SphParams&, const NeighborList<2>&,
                                                SphParticles<2>&,
                                                const std::function<void(SphGroup)>&);
template void compute_fluid_passes_and_rates<3>(const SphParams&, const NeighborList<3>&,
                                                SphParticles<3>&,
                                                const std::function<void(SphGroup)>&);
template void compute_fluid_rates<2>(const SphParams&, const NeighborList<2>&, SphParticles<2>&);
template void compute_fluid_rates<3>(const SphParams&, const NeighborList<3>&, SphParticles<3>&);

}  // namespace sphdem
