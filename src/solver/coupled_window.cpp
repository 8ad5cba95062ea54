// The coupled model's stable window for `sphdem check` (coupled_window.hpp,
// docs/physics.md "The stable window").
#include "sphdem/solver/coupled_window.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ostream>

#include "sphdem/coupling/coupling.hpp"
#include "sphdem/solver/coupling_module.hpp"
#include "sphdem/sph/kernel.hpp"

namespace sphdem {

template <int D>
double lone_fiber_void_fraction(double h, double d, int n) {
  const WendlandC2<D> kernel(h);
  double phi = 0;
  for (int j = 0; j < n; ++j) phi += kernel.w(std::abs(j - n / 2) * d);
  return 1.0 - particle_volume<D>(d) * phi;
}

template <int D>
CoupledWindow coupled_window(const Case& c, const Simulation<D>& sim, double resin_dt) {
  CoupledWindow w;
  const CouplingModule<D>* coupling = sim.coupling();
  w.fiber_drag_time = coupling->fiber_drag_time();
  w.resin_drag_time = coupling->resin_drag_rate() > 0 ? 1.0 / coupling->resin_drag_rate() : 0.0;
  w.dem_dt = sim.dem_dt();
  w.resin_dt = resin_dt;
  const FiberSettings& f = *c.fibers;
  const double ratio = c.numerics.h_over_spacing;
  const auto eps_at = [&](double spacing) {
    return lone_fiber_void_fraction<D>(ratio * spacing, f.diameter, f.particles_per_fiber);
  };
  w.fiber_void_fraction = eps_at(c.numerics.spacing);
  // The void fraction grows with the spacing (a wider kernel dilutes the
  // fiber's volume): bisect for the clip between d/100 and 100 d.
  double lo = 0.01 * f.diameter, hi = 100.0 * f.diameter;
  for (int it = 0; it < 100; ++it) {
    const double mid = std::sqrt(lo * hi);
    (eps_at(mid) < f.void_fraction_min ? lo : hi) = mid;
  }
  w.spacing_at_clip = hi;
  return w;
}

void print_coupled_window(const CoupledWindow& w, const Case& c, std::ostream& out) {
  const FiberSettings& f = *c.fibers;
  out << "  coupled window (docs/physics.md \"The stable window\"):\n";
  if (f.exponential_drag) {
    // No limit from the drag (docs/physics.md "Exponential drag").
    out << fmt::format(
        "    fibers.drag_integration: exponential: fiber drag time {:.3g} s, resin drag time "
        "{:.3g} s, neither limits a step; DEM sub-step {:.3g} s (the fibers' own), resin step "
        "{:.3g} s ({:.3g} fiber drag times)\n",
        w.fiber_drag_time, w.resin_drag_time, w.dem_dt, w.resin_dt,
        w.fiber_drag_time > 0 ? w.resin_dt / w.fiber_drag_time : 0.0);
  } else if (w.fiber_drag_time > 0) {
    const double sub = std::min(w.dem_dt, kFiberDragStep * w.fiber_drag_time);
    out << fmt::format(
        "    fiber drag time m_f/(K V_f) {:.3g} s; DEM sub-step {:.3g} s ({}, explicit drag "
        "stable below 2 drag times)\n",
        w.fiber_drag_time, sub, sub < w.dem_dt ? "limited by the drag time" : "the fibers' own");
  }
  if (w.resin_drag_time > 0 && !f.exponential_drag) {
    const double dt = std::min(w.resin_dt, kResinDragStep * w.resin_drag_time);
    out << fmt::format(
        "    resin drag time m_r/sum_f (V_r W_fr/S_f) K_f V_f {:.3g} s; resin step {:.3g} s\n",
        w.resin_drag_time, dt);
    if (dt < w.resin_dt) {
      out << fmt::format(
          "  warning: the drag limits the resin's step to {:.3g} s, {:.3g} times below its own "
          "{:.3g} s: the run takes as many times the steps (light resin particles near the "
          "fibers: numerics.spacing {:.3g} m against fibers.diameter {:.3g} m, "
          "resin.viscosity {:.3g} Pa s)\n",
          dt, w.resin_dt / dt, w.resin_dt, c.numerics.spacing, f.diameter, c.resin.viscosity);
    }
  }
  out << fmt::format(
      "    void fraction at a lone fiber's middle particle {:.3f} (h {:.3g} m, fiber diameter "
      "{:.3g} m), clip fibers.void_fraction_min {:.3g}\n",
      w.fiber_void_fraction, c.h(), f.diameter, f.void_fraction_min);
  if (w.fiber_void_fraction < f.void_fraction_min) {
    out << fmt::format(
        "  warning: the fibers' own volume fills the averaging kernel (void fraction {:.3f} below "
        "fibers.void_fraction_min {:.3g}): the drag is the clip's Ergun value, not a measured "
        "one; numerics.spacing above {:.3g} m keeps a lone fiber above the clip\n",
        w.fiber_void_fraction, f.void_fraction_min, w.spacing_at_clip);
  }
}

template double lone_fiber_void_fraction<2>(double, double, int);
template double lone_fiber_void_fraction<3>(double, double, int);
template CoupledWindow coupled_window<2>(const Case&, const Simulation<2>&, double);
template CoupledWindow coupled_window<3>(const Case&, const Simulation<3>&, double);

}  // namespace sphdem
