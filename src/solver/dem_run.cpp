// The fiber module (fiber_module.hpp): the case's fibers placed in the
// mold, alone (pushed by the piston) or coupled to the resin; and DemRun,
// a run of fibers alone.
#include "sphdem/solver/dem_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "dem_snapshot.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/clamped_cast.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/agreement.hpp"
#include "sphdem/parallel/timers.hpp"

namespace sphdem {

namespace {

template <int D>
DemParams<D> dem_params(const Case& c) {
  const FiberSettings& f = *c.fibers;
  DemParams<D> p;
  p.youngs_modulus = f.youngs_modulus;
  p.kbar_star = f.stiffness_ratio;
  p.tensile_strength = f.tensile_strength.value_or(std::numeric_limits<double>::infinity());
  p.shear_strength = f.shear_strength.value_or(std::numeric_limits<double>::infinity());
  p.restitution = f.restitution;
  p.friction = f.friction;
  p.dt_safety = f.dt_safety;
  p.subcycle_bonds = f.subcycle_bonds;
  p.implicit_bonds = f.implicit_bonds;
  p.exponential_drag = f.exponential_drag;
  p.chain_reach = implicit_chain_reach(c);
  p.gravity = to_vec<D>(c.body_force);
  p.kn = contact_stiffness_from_bond(p, 0.5 * f.diameter, f.contact_stiffness_fraction);
  return p;
}

template <int D>
FiberSpec<D> fiber_spec(const FiberSettings& f) {
  FiberSpec<D> s;
  s.count = f.count;
  s.fraction = f.area_fraction;
  s.particles_per_fiber = f.particles_per_fiber;
  s.radius = 0.5 * f.diameter;
  s.density = f.density;
  s.lo = to_vec<D>(f.region.lo);
  s.hi = to_vec<D>(f.region.hi);
  s.angle = f.angle;
  // 3D: the angle turns the fiber from +x in the x-y plane.
  if constexpr (D == 3)
    if (f.angle) s.direction = Vec<3>(std::cos(*f.angle), std::sin(*f.angle), 0.0);
  s.seed = f.seed;
  s.bend = f.initial_bend;
  return s;
}

}  // namespace

double implicit_chain_reach(const Case& c) {
  if (!c.fibers || !c.fibers->implicit_bonds) return 0.0;
  return 1.1 * (c.fibers->particles_per_fiber - 1) * c.fibers->diameter;
}

namespace {

// A fiber spec that cannot be placed: an input error at the key that sets
// the fibers' amount.
InputError fiber_input_error(const Case& c, const std::string& what) {
  const FiberSettings& f = *c.fibers;
  const bool from_set = f.amount_line == 0;
  return InputError(from_set ? "--set" : c.source_file, f.amount_line,
                    f.count > 0 ? "fibers.count" : "fibers.area_fraction", what);
}

}  // namespace

template <int D>
DemSystem<D> case_fibers(const Case& c, std::vector<int>& wall_owner, FiberPlacement& placement,
                         const FiberShare<D>* share) {
  DemSystem<D> all;
  all.walls = dem_walls_from_case<D>(c, wall_owner);
  all.params = dem_params<D>(c);
  const FiberSettings& f = *c.fibers;
  try {
    placement = place_fibers(fiber_spec<D>(f), all, share);
  } catch (const std::runtime_error& e) {
    throw fiber_input_error(c, e.what());
  }
  return all;
}

namespace {

// This rank's part of the fibers (place_fibers): the boxes of its top-level
// cells, the outer ones reaching to infinity as the grid clamps positions
// into them, and the owner of a fiber's centre.
template <int D>
FiberShare<D> rank_share(const Decomposition<D>& dec) {
  FiberShare<D> share;
  const CellGrid<D>& cells = dec.grid();
  const CellGrid<D>& blocks = dec.block_grid();
  const long edge = dec.block_edge();
  const std::vector<int>& owners = dec.block_owners();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (long b = 0; b < static_cast<long>(owners.size()); ++b) {
    if (owners[static_cast<std::size_t>(b)] != dec.comm().rank()) continue;
    const auto c = blocks.coords_of(b);
    Vec<D> lo, hi;
    for (int k = 0; k < D; ++k) {
      const long first = c[k] * edge, end = std::min((c[k] + 1) * edge, cells.dims()[k]);
      lo[k] = first == 0 ? -kInf : cells.lower(k, first);
      hi[k] = end == cells.dims()[k] ? kInf : cells.lower(k, end);
    }
    share.boxes.emplace_back(lo, hi);
  }
  share.owns = [&dec](const Vec<D>& x) { return dec.owner(x) == dec.comm().rank(); };
  return share;
}

}  // namespace

template <int D>
FiberModule<D>::FiberModule(const RunContext<D>& ctx, const FiberHost<D>* host) : ctx_(ctx) {
  const Case& c = ctx.case_data;
  if (!c.fibers) throw std::invalid_argument("sphdem: a fiber module needs a case with fibers");
  if (host) host_.emplace(*host);
  const Decomposition<D>* dec = host_ ? &host_->dec : nullptr;
  if (!host_) {
    std::vector<int> unused;
    const std::vector<DemWall<D>> walls = dem_walls_from_case<D>(c, unused);
    Box<D> box;
    box.lo = box.hi = walls.front().point;
    for (const DemWall<D>& w : walls) {
      box.lo = box.lo.cwiseMin(w.point).cwiseMin(w.end);
      box.hi = box.hi.cwiseMax(w.point).cwiseMax(w.end);
    }
    // The cells cover the mold and the health check's margin around it.
    const double margin = 0.1 * (box.hi - box.lo).maxCoeff();
    health_box_ = Box<D>{box.lo.array() - margin, box.hi.array() + margin};
    const double r = 0.5 * c.fibers->diameter;
    try {
      own_dec_ = std::make_unique<Decomposition<D>>(
          ctx.comm, health_box_, std::array<bool, 3>{false, false, false},
          std::max(DemDomain<D>::reach(r, r), implicit_chain_reach(c)));
    } catch (const std::length_error& e) {  // the mold far larger than the fibers
      throw input_error_at(c, "mold", e.what());
    }
    // Partitioned by where the fibers' first candidates lie (every rank
    // draws them, the same, without placing anything): nearly always
    // where the fibers end up.
    const FiberSpec<D> spec = fiber_spec<D>(*c.fibers);
    std::vector<std::int64_t> work(static_cast<std::size_t>(own_dec_->blocks()), 0);
    try {  // the same spec as place_fibers below: its errors, the same input errors
      for (int f = 0, n = fiber_target(spec); f < n; ++f)
        work[static_cast<std::size_t>(own_dec_->block_of(first_fiber_centre(spec, f)))] +=
            spec.particles_per_fiber;
    } catch (const std::runtime_error& e) {
      throw fiber_input_error(c, e.what());
    }
    own_dec_->partition(work, true);
    dec = own_dec_.get();
  } else {
    health_box_ = host_->domain;
  }
  // Each rank places the fibers whose centre lies in its cells (issue 14:
  // the same fibers at any rank count); a fiber that does not fit stops
  // every rank with the same error (the lowest failing rank's).
  const FiberShare<D> share = rank_share(*dec);
  DemSystem<D> mine;
  mine.walls = dem_walls_from_case<D>(c, wall_owner_);
  mine.params = dem_params<D>(c);
  const FiberSettings& f = *c.fibers;
  std::optional<std::string> error;
  try {
    placement_ = place_fibers(fiber_spec<D>(f), mine, &share);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  if (const std::optional<RankFailure> failed = first_failure(ctx.comm, error))
    throw fiber_input_error(c, failed->message);
  placement_.tries = ctx.comm.sum(placement_.tries);
  // The same step on every rank (a rank may hold no fiber).
  dem_dt_ = bond_dt_ = ctx.comm.min(mine.stable_dt());
  if (mine.params.subcycle_bonds) {  // bonds in inner steps, the step is the contacts'
    mine.params.bond_dt = dem_dt_;
    dem_dt_ = ctx.comm.min(stable_dem_outer_dt(mine.params, mine.particles));
  }
  if (host_) {
    dem_ = std::make_unique<DemDomain<D>>(host_->dec, mine.params, mine.walls,
                                          std::move(mine.particles), host_->halo_range,
                                          DemDomain<D>::Input::Share, host_->skin_limit);
    return;
  }
  dem_ = std::make_unique<DemDomain<D>>(*own_dec_, mine.params, mine.walls,
                                        std::move(mine.particles), 0.0, DemDomain<D>::Input::Share);
}

template <int D>
FiberModule<D>::~FiberModule() = default;

template <int D>
std::int64_t FiberModule<D>::counted_particles() const {
  return coupled() ? 0 : dem_->global_count();  // a coupled run counts its resin
}

template <int D>
std::optional<TimeStep> FiberModule<D>::stable_dt() {
  if (coupled()) return std::nullopt;  // sub-steps of the resin's step
  return TimeStep{dem_dt_, DtLimit::Dem};
}

// Rigid translation at the motions' velocity at t (mid-step): exact within
// a segment of the piecewise-linear table.
template <int D>
void FiberModule<D>::move_walls(double t) {
  std::vector<DemWall<D>>& walls = dem_->walls();
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const int w = wall_owner_[k];
    if (w >= 0) walls[k].velocity = to_vec<D>(ctx_.walls[static_cast<std::size_t>(w)].velocity(t));
  }
}

// Alone: one DEM step.
template <int D>
void FiberModule<D>::predict(double dt) {
  if (coupled()) return;
  ScopedPhase t(ctx_.timers, Phase::Dem);
  move_walls(ctx_.clock.time + 0.5 * dt);
  dem_->advance(1, dt);
}

// Coupled: the fibers follow the resin's decomposition (which may have
// changed). Alone, DemDomain rebuilds when its particles moved.
template <int D>
void FiberModule<D>::rebuild(bool /*restart*/) {
  if (coupled()) dem_->rebuild();
}

// Coupled: DEM sub-steps over the resin's step [t - dt, t], the drag of
// the last coupling pass held; the piston's DEM segments move at the SPH
// piston's mid-step speed.
template <int D>
void FiberModule<D>::substep(double dt) {
  if (!coupled()) return;
  ScopedPhase t(ctx_.timers, Phase::Dem);
  const double t0 = ctx_.clock.time - dt;
  move_walls(t0 + 0.5 * dt);
  // Sub-cycled bonds hold the drag over the outer step and correct it at
  // the end, stable below one drag time (docs/dem.md): half of it.
  const double drag_step = dem_->params().subcycle_bonds ? 0.5 * kFiberDragStep : kFiberDragStep;
  const double sub = drag_time_ > 0 ? std::min(dem_dt_, drag_step * drag_time_) : dem_dt_;
  substeps_ = substep_count(dt / sub * (1 - 1e-12), "fiber sub-steps per resin step");
  dem_->advance(substeps_, dt / static_cast<double>(substeps_));
  dem_->forward(DemGroup::State);
  coupled_dt_ = dt;
}

// A fiber through a wall (a step too large for an impact) ends the run.
template <int D>
void FiberModule<D>::check_health(std::string& problem) const {
  const DemParticles<D>& f = dem_->particles();
  for (std::size_t i = 0; i < f.n_owned && problem.empty(); ++i) {
    bool outside = false;
    for (int k = 0; k < D; ++k) {
      // Along a periodic axis a fiber crosses the face; the next rebuild wraps it.
      if (ctx_.case_data.periodic[static_cast<std::size_t>(k)]) continue;
      outside = outside || f.x[i][k] < health_box_.lo[k] || f.x[i][k] > health_box_.hi[k];
    }
    if (!f.x[i].allFinite() || outside) {
      problem = fmt::format("fiber particle {} (fiber {}) left the mold", f.gid[i], f.fiber[i]);
    }
  }
}

template <int D>
void add_fiber_work(const Decomposition<D>& dec, const DemParticles<D>& f, std::size_t n,
                    std::int64_t substeps, std::vector<std::int64_t>& work) {
  const std::int64_t per = fiber_particle_work(substeps);
  for (std::size_t i = 0; i < n; ++i) work[static_cast<std::size_t>(dec.block_of(f.x[i]))] += per;
}

// On the resin's decomposition: the owned fiber particles at the sub-steps
// of the last resin step (fiber_particle_work).
template <int D>
void FiberModule<D>::add_cell_work(const Decomposition<D>& dec,
                                   std::vector<std::int64_t>& work) const {
  if (!coupled()) return;
  const DemParticles<D>& f = dem_->particles();
  add_fiber_work<D>(dec, f, f.n_owned, substeps_, work);
}

template <int D>
void FiberModule<D>::snapshot(SnapshotParts& parts) {
  dem_->store_state();
  auto buf = std::make_shared<const DemSnapshotBuffers<D>>(dem_->particles(), ctx_.comm);
  parts.views.push_back(buf->view());
  parts.buffers.push_back(std::move(buf));
  // The next snapshot's interval peaks start now (a checkpoint of this step
  // is written after the snapshot, so a restart resumes the same interval).
  for (BondPeakSlots& slots : dem_->particles().bond_peaks)
    for (BondPeak& peak : slots) peak.start_interval();
}

// Alone: the piston's speed (a coupled run reports the resin's piston).
template <int D>
void FiberModule<D>::progress(std::string& line) const {
  if (coupled()) return;
  for (std::size_t k = 0; k < dem_->walls().size(); ++k) {
    if (wall_owner_[k] < 0) continue;
    const WallMotion& m = ctx_.walls[static_cast<std::size_t>(wall_owner_[k])];
    line += fmt::format("  {} v={:.3g} m/s", m.name, dem_->walls()[k].velocity.norm());
    return;
  }
}

template <int D>
DemRun<D>::DemRun(const Case& c, const Comm& comm, RunOptions opt)
    : Run<D>((!c.fibers || !c.fill.empty())
                 ? throw std::invalid_argument("sphdem: DemRun needs a case with fibers, no resin")
                 : c,
             comm, std::move(opt)) {}

template DemSystem<2> case_fibers<2>(const Case&, std::vector<int>&, FiberPlacement&,
                                     const FiberShare<2>*);
template DemSystem<3> case_fibers<3>(const Case&, std::vector<int>&, FiberPlacement&,
                                     const FiberShare<3>*);
template void add_fiber_work<2>(const Decomposition<2>&, const DemParticles<2>&, std::size_t,
                                std::int64_t, std::vector<std::int64_t>&);
template void add_fiber_work<3>(const Decomposition<3>&, const DemParticles<3>&, std::size_t,
                                std::int64_t, std::vector<std::int64_t>&);
template class FiberModule<2>;
template class FiberModule<3>;
template class DemRun<2>;
template class DemRun<3>;

}  // namespace sphdem
