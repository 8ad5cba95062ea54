// The coupling module (coupling_module.hpp).
#include "sphdem/solver/coupling_module.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "sphdem/io/checkpoint.hpp"

namespace sphdem {

template <int D>
CouplingModule<D>::CouplingModule(const RunContext<D>& ctx, ResinModule<D>& resin,
                                  FiberModule<D>& fibers)
    : ctx_(ctx), resin_(resin), fibers_(fibers) {
  const Case& c = ctx.case_data;
  coupling_.drag.rho = c.resin.density;
  coupling_.drag.mu = c.resin.viscosity;
  coupling_.drag.local_viscosity = c.resin.melt.law != ViscosityLaw::Newtonian &&
                                   c.numerics.viscosity_model != ViscosityModel::None;
  coupling_.drag.eps_min = c.fibers->void_fraction_min;
  coupling_.h = c.h();
  coupling_.thickness = fibers.dem().params().thickness;
  coupling_.void_fraction_in_continuity = c.fibers->void_fraction_in_continuity;
  coupling_.hydrodynamic_torque = c.fibers->hydrodynamic_torque;
  coupling_.exponential_drag = c.fibers->exponential_drag;
  // The pairs live between passes with the resin's Verlet skin: a new
  // search at every rebuild of the fibers' lists (a new
  // DemDomain::rebuilds(); every resin rebuild is one), or once a fiber and
  // a resin particle may have moved the skin towards each other
  // (update_coupling_pairs). Their partners are owned or ghosts by
  // coupled_skins.hpp's rule.
  cstate_.keep_pairs = true;
  cstate_.skin = c.numerics.neighbor_skin * WendlandC2<D>(coupling_.h).support();
}

template <int D>
void CouplingModule<D>::rebuild(bool /*restart*/) {
  cstate_.pairs.invalidate();
}

// Drag on the fibers, then its reaction on the resin (coupling_loops.hpp);
// the DEM ghosts get their owners' drag and S_f in between.
template <int D>
void CouplingModule<D>::rates() {
  ScopedPhase t(ctx_.timers, Phase::Coupling);
  SphParticles<D>& ps = resin_.particles();
  DemDomain<D>& domain = fibers_.dem();
  DemParticles<D>& dem = domain.particles();
  cstate_.generation = domain.rebuilds();
  drag_on_fibers<D>(coupling_, ps, dem, cstate_, fibers_.coupled_dt());
  domain.forward(DemGroup::Coupling);
  double rate = 0;
  const Vec<D> reaction =
      reaction_on_resin<D>(coupling_, dem, ps, cstate_, resin_eps_, rate,
                           coupling_.exponential_drag ? fibers_.coupled_dt() : 0.0);
  double drag_time = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    if (dem.drag_coeff[f] > 0) drag_time = std::min(drag_time, dem.mass[f] / dem.drag_coeff[f]);
    // The spin relaxes under the torque the same way (explicit too).
    if (dem.torque_coeff[f] > 0)
      drag_time = std::min(drag_time, dem.inertia[f] / dem.torque_coeff[f]);
  }
  // Diagnostics: total drag + total reaction, which must vanish.
  std::array<double, 2 * D + 1> sums{};
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    for (int k = 0; k < D; ++k) sums[static_cast<std::size_t>(k)] += dem.mean_drag[f][k];
    sums[2 * D] += dem.mean_drag[f].norm();
  }
  for (int k = 0; k < D; ++k) sums[static_cast<std::size_t>(D + k)] = reaction[k];
  // One collective per pass: the largest rate, the smallest drag time and the sums.
  std::array<double, 2> maxes{rate, -drag_time};
  ctx_.comm.sum_max(sums, maxes);
  resin_drag_rate_ = maxes[0];
  drag_time = -maxes[1];
  fiber_drag_time_ = std::isfinite(drag_time) ? drag_time : 0.0;
  // Exponential drag is stable at any sub-step and resin step.
  fibers_.limit_substep(coupling_.exponential_drag ? 0.0 : fiber_drag_time_);
  double residual = 0;
  for (int k = 0; k < D; ++k)
    residual +=
        std::pow(sums[static_cast<std::size_t>(k)] + sums[static_cast<std::size_t>(D + k)], 2);
  momentum_residual_ = sums[2 * D] > 0 ? std::sqrt(residual) / sums[2 * D] : 0.0;
}

template <int D>
std::optional<TimeStep> CouplingModule<D>::stable_dt() {
  if (!(resin_drag_rate_ > 0) || coupling_.exponential_drag) return std::nullopt;
  return TimeStep{kResinDragStep / resin_drag_rate_, DtLimit::Drag};
}

// The limit of the next step comes from the last pass, which a restart
// does not repeat.
template <int D>
void CouplingModule<D>::write_checkpoint(CheckpointWriter& w) {
  w.attribute("resin_drag_rate", resin_drag_rate_);
  w.attribute("fiber_drag_time", fiber_drag_time_);
}

template <int D>
std::function<void()> CouplingModule<D>::read_checkpoint(CheckpointReader& r,
                                                         const std::string& /*path*/) {
  const double rate = r.real("resin_drag_rate");
  const double drag_time = r.real("fiber_drag_time");
  return [this, rate, drag_time] {
    resin_drag_rate_ = rate;
    fiber_drag_time_ = drag_time;
    fibers_.limit_substep(coupling_.exponential_drag ? 0.0 : drag_time);
  };
}

template class CouplingModule<2>;
template class CouplingModule<3>;

}  // namespace sphdem
