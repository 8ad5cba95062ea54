#include <fmt/format.h>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "dem_snapshot.hpp"
#include "run_loop.hpp"
#include "snapshot_fields.hpp"
#include "sphdem/checkpoint.hpp"
#include "sphdem/dem_run.hpp"
#include "sphdem/errors.hpp"
#include "sphdem/geometry.hpp"
#include "sphdem/io.hpp"
#include "sphdem/ordered_sum.hpp"
#include "sphdem/output_cadence.hpp"
#include "sphdem/solver.hpp"

namespace sphdem {

template <int D>
Simulation<D>::Simulation(const Case& c, const Comm& comm, RunOptions opt)
    : case_(c),
      comm_(comm),
      opt_(std::move(opt)),
      sp_(make_sph_params(c)),
      eos_(c.resin.density, c.resin.sound_speed, c.resin.gamma),
      domain_(simulation_domain<D>(c)),
      nl_(2.0 * c.h(), c.numerics.neighbor_skin * 2.0 * c.h()),
      walls_(make_wall_motions(c)),
      dec_(comm, domain_, c.periodic, nl_.cutoff()) {
  const InitialCounts counts = build_initial_particles<D>(c, ps_);
  n_fluid_global_ = static_cast<std::int64_t>(counts.fluid);
  n_wall_global_ = static_cast<std::int64_t>(counts.wall);
  if (opt_.output_dir.empty()) opt_.output_dir = c.output.directory;
  // Every rank built every particle: partition their work, keep our share.
  dec_.partition(dec_.cell_work(ps_, ps_.n_owned), /*replicated=*/true);
  dec_.keep_owned(ps_);
  last_imbalance_ = dec_.imbalance(ps_);
  set_wall_velocities(0.0);
  rebuild_neighbors();
  if (c.fibers) init_fibers();
  compute_rates();
}

// The case's fibers on the resin's decomposition; their ghosts reach as
// far as the coupling kernel (the SPH neighbor cut-off).
template <int D>
void Simulation<D>::init_fibers() {
  DemSystem<D> all = case_fibers<D>(case_, dem_wall_owner_, placement_);
  coupling_.drag.rho = case_.resin.density;
  coupling_.drag.mu = case_.resin.viscosity;
  coupling_.drag.eps_min = case_.fibers->void_fraction_min;
  coupling_.h = case_.h();
  coupling_.thickness = all.params.thickness;
  coupling_.void_fraction_in_continuity = case_.fibers->void_fraction_in_continuity;
  dem_dt_ = all.stable_dt();
  dem_ = std::make_unique<DemDomain<D>>(dec_, all.params, all.walls, std::move(all.particles),
                                        nl_.cutoff());
}

// DEM sub-steps over [t0, t0 + dt], the drag of the last coupling pass
// held; the piston's DEM segments move at the SPH piston's mid-step speed.
template <int D>
void Simulation<D>::advance_fibers(double t0, double dt) {
  ScopedPhase t(timers_, Phase::Dem);
  std::vector<DemWall<D>>& walls = dem_->walls();
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const int w = dem_wall_owner_[k];
    if (w >= 0)
      walls[k].velocity = to_vec<D>(walls_[static_cast<std::size_t>(w)].velocity(t0 + 0.5 * dt));
  }
  substeps_ = static_cast<std::int64_t>(std::ceil(dt / dem_dt_ * (1 - 1e-12)));
  substeps_ = std::max<std::int64_t>(substeps_, 1);
  dem_->advance(substeps_, dt / static_cast<double>(substeps_));
  dem_->update_ghosts();
  coupled_dt_ = dt;
}

// Drag on the fibers, then its reaction on the resin (coupling_loops.hpp);
// the DEM ghosts get their owners' drag and S_f in between.
template <int D>
void Simulation<D>::couple() {
  ScopedPhase t(timers_, Phase::Coupling);
  DemParticles<D>& dem = dem_->particles();
  drag_on_fibers<D>(coupling_, ps_, dem, cstate_, coupled_dt_);
  dem_->update_coupling(cstate_.mean_drag, cstate_.shepard_sum);
  const Vec<D> reaction =
      reaction_on_resin<D>(coupling_, dem, cstate_.mean_drag, cstate_.shepard_sum, ps_, resin_eps_);
  // Diagnostics: total drag + total reaction, which must vanish.
  std::vector<double> sums(2 * D + 1, 0.0);
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    for (int k = 0; k < D; ++k) sums[static_cast<std::size_t>(k)] += cstate_.mean_drag[f][k];
    sums[2 * D] += cstate_.mean_drag[f].norm();
  }
  for (int k = 0; k < D; ++k) sums[static_cast<std::size_t>(D + k)] = reaction[k];
  comm_.sum(sums);
  double residual = 0;
  for (int k = 0; k < D; ++k)
    residual +=
        std::pow(sums[static_cast<std::size_t>(k)] + sums[static_cast<std::size_t>(D + k)], 2);
  momentum_residual_ = sums[2 * D] > 0 ? std::sqrt(residual) / sums[2 * D] : 0.0;
}

template <int D>
Simulation<D>::~Simulation() = default;

template <int D>
void Simulation<D>::set_wall_velocities(double t) {
  std::vector<Vec<D>> v(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) v[k] = to_vec<D>(walls_[k].velocity(t));
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    if (ps_.kind[i] != Kind::Wall) continue;
    const std::int32_t k = ps_.wall[i];
    ps_.v[i] = k >= 0 ? v[static_cast<std::size_t>(k)] : Vec<D>::Zero();
  }
}

// Migration, halo and lists are rebuilt together: the halo plan and the
// lists index the particles that migration rearranges.
template <int D>
void Simulation<D>::rebuild_neighbors(bool restart) {
  // Wrap first: a particle's owner is the owner of the cell it lies in.
  if (!restart) wrap_periodic<D>(ps_, domain_, case_.periodic);
  {
    ScopedPhase t(timers_, Phase::Migration);
    migrate<D>(dec_, ps_);
  }
  if (!restart) maybe_rebalance();
  sort_by_cell<D>(ps_, nl_.cutoff());
  {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.build(dec_, ps_, nl_.cutoff());
  }
  nl_.build(ps_);
  // The fibers follow the resin's decomposition (which may have changed).
  if (dem_) dem_->rebuild();
  check_health();
}

// The work per rank changes only when particles migrate, so the imbalance is
// measured right after a migration, at most once per balance_every steps.
// Re-partitioning only at a rebuild the step needs anyway (never forcing an
// extra one) keeps the rebuild steps, where periodic positions wrap, the
// same at every rank count; the gather in global-id order does the rest.
template <int D>
void Simulation<D>::maybe_rebalance() {
  const int every = case_.parallel.balance_every;
  if (every <= 0 || step_ - last_balance_step_ < every) return;
  ScopedPhase t(timers_, Phase::Rebalance);
  last_balance_step_ = step_;
  const std::vector<std::int64_t> work = cell_work();
  const double before = dec_.imbalance(work);
  last_imbalance_ = before;
  if (!(before > case_.parallel.imbalance_threshold)) return;
  dec_.partition(work, /*replicated=*/false);
  const MigrationCounts moved = migrate<D>(dec_, ps_);
  last_imbalance_ = dec_.imbalance(work);
  ++repartitions_;
  const std::int64_t total_moved = comm_.sum(static_cast<std::int64_t>(moved.sent));
  if (opt_.log && comm_.root()) {
    *opt_.log << fmt::format(
                     "step {}: re-partitioned over {} ranks: imbalance {:.1f} % -> {:.1f} %, {} "
                     "particles moved\n",
                     step_, comm_.size(), 100 * before, 100 * last_imbalance_, total_moved)
              << std::flush;
  }
}

// Work per cell of this rank's particles: the resin's (decomposition.hpp)
// plus, for each fiber particle, its sub-steps at kDemSubstepWork each
// (a DEM particle-step costs about half a resin particle-step, measured on
// the plate: 3 pairs against 20 neighbours).
template <int D>
std::vector<std::int64_t> Simulation<D>::cell_work() const {
  std::vector<std::int64_t> work = dec_.cell_work(ps_, ps_.n_owned);
  if (!dem_) return work;
  constexpr std::int64_t kDemSubstepWork = kFluidWork / 2;
  const std::int64_t per = kDemSubstepWork * std::max<std::int64_t>(substeps_, 1);
  const DemParticles<D>& f = dem_->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i)
    work[static_cast<std::size_t>(dec_.grid().cell_of(f.x[i]))] += per;
  return work;
}

// Mean face pressure per wall over all ranks (NaN for a wall touching no
// resin), summed in global-id order: bitwise the same at every rank count.
template <int D>
std::vector<double> Simulation<D>::face_means(const std::vector<WallFaceSample>& face) {
  if (walls_.empty()) return {};
  ScopedPhase t(timers_, Phase::Wait);
  std::vector<OrderedTerm> terms;
  terms.reserve(face.size());
  for (const WallFaceSample& f : face) terms.push_back({f.gid, f.wall, f.p});
  const std::vector<KeySum> sums = ordered_sums(comm_, terms, walls_.size());
  std::vector<double> mean(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) {
    mean[k] = sums[k].count > 0 ? sums[k].sum / static_cast<double>(sums[k].count) : std::nan("");
  }
  return mean;
}

template <int D>
void Simulation<D>::compute_rates() {
  {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.update_state(ps_);
  }
  compute_fluid_pressure<D>(eos_, ps_);
  std::vector<WallKinematics<D>> kin(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    kin[k].accel = to_vec<D>(walls_[k].acceleration(time_));
    kin[k].pressure_floor = -walls_[k].adhesion_pressure;
  }
  const std::vector<WallFaceSample> face = compute_wall_state<D>(sp_, eos_, nl_, kin, ps_);
  update_wall_controllers(walls_, face_means(face), dt_.dt);
  {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.update_wall_state(ps_);
  }
  compute_fluid_rates<D>(sp_, nl_, ps_);
  if (dem_) couple();
}

template <int D>
void Simulation<D>::do_step() {
  const LocalExtremes ex = local_extremes<D>(ps_);
  double v_max = 0, a_max = 0;
  {
    ScopedPhase t(timers_, Phase::Wait);
    v_max = comm_.max(ex.v_max);
    a_max = comm_.max(ex.a_max);
  }
  if (!std::isfinite(v_max) || !std::isfinite(a_max)) {
    throw CollectiveSimulationError(
        fmt::format("the resin blew up at step {} (t = {:.6g} s): a velocity "
                    "or acceleration is not finite",
                    step_, time_));
  }
  dt_ = choose_time_step(case_.numerics, sp_, v_max, a_max);
  // Land on end_time exactly rather than overshoot it by up to a step.
  const double to_end = case_.numerics.end_time - time_;
  if (to_end > 0 && to_end < dt_.dt) dt_.dt = to_end;
  const double dt = dt_.dt, half = 0.5 * dt;

  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    if (ps_.kind[i] == Kind::Fluid) {
      ps_.v_half[i] = ps_.v[i] + half * ps_.a[i];
      ps_.rho_half[i] = ps_.rho[i] + half * ps_.drho[i];
      ps_.x[i] += dt * ps_.v_half[i];
      ps_.v[i] = ps_.v_half[i] + half * ps_.a[i];
      ps_.rho[i] = ps_.rho_half[i] + half * ps_.drho[i];
    }
  }
  // Rigid walls: exact for a piecewise-linear table within a segment.
  std::vector<Vec<D>> disp(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    disp[k] =
        walls_[k].moves ? Vec<D>(dt * to_vec<D>(walls_[k].velocity(time_ + half))) : Vec<D>::Zero();
  }
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    if (ps_.kind[i] == Kind::Wall && ps_.wall[i] >= 0)
      ps_.x[i] += disp[static_cast<std::size_t>(ps_.wall[i])];
  }
  time_ += dt;
  ++step_;
  set_wall_velocities(time_);

  const bool moved = nl_.needs_rebuild(ps_);
  bool rebuild = false;
  {
    ScopedPhase t(timers_, Phase::Wait);
    rebuild = comm_.any(moved);
  }
  if (rebuild) rebuild_neighbors();
  if (dem_) advance_fibers(time_ - dt, dt);
  compute_rates();
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    if (ps_.kind[i] == Kind::Fluid) {
      ps_.v[i] = ps_.v_half[i] + half * ps_.a[i];
      ps_.rho[i] = ps_.rho_half[i] + half * ps_.drho[i];
    }
  }
}

template <int D>
void Simulation<D>::check_health() const {
  bool bad = false;
  std::string what;
  for (std::size_t i = 0; i < ps_.n_owned && !bad; ++i) {
    for (int k = 0; k < D; ++k) {
      const double x = ps_.x[i][k];
      if (!std::isfinite(x)) {
        bad = true;
        what = fmt::format("particle {} has a non-finite position", ps_.gid[i]);
        break;
      }
      if (!case_.periodic[k] && (x < domain_.lo[k] || x > domain_.hi[k])) {
        bad = true;
        what = fmt::format(
            "particle {} left the domain along axis {} (x = {:.6g} m, domain "
            "[{:.6g}, {:.6g}])",
            ps_.gid[i], "xyz"[k], x, domain_.lo[k], domain_.hi[k]);
        break;
      }
    }
  }
  // Fibers stay in the mold's bounding box (a fiber through a wall).
  if (dem_ && !bad) {
    const DemParticles<D>& f = dem_->particles();
    for (std::size_t i = 0; i < f.n_owned && !bad; ++i) {
      if (!f.x[i].allFinite() || (f.x[i].array() < domain_.lo.array()).any() ||
          (f.x[i].array() > domain_.hi.array()).any()) {
        bad = true;
        what = fmt::format("fiber particle {} (fiber {}) left the mold", f.gid[i], f.fiber[i]);
      }
    }
  }
  bool any_bad = false;
  {
    ScopedPhase t(timers_, Phase::Wait);
    any_bad = comm_.any(bad);
  }
  if (any_bad) {
    throw CollectiveSimulationError(
        fmt::format("step {} (t = {:.6g} s): {}", step_, time_,
                    what.empty() ? "a particle on another rank failed" : what));
  }
}

template <int D>
void Simulation<D>::advance(std::int64_t n) {
  for (std::int64_t s = 0; s < n; ++s) do_step();
}

template <int D>
std::string Simulation<D>::write_snapshot() {
  ScopedPhase t(timers_, Phase::Io);
  if (!writer_) {
    std::filesystem::create_directories(opt_.output_dir);
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name);
    if (comm_.root()) {
      std::ofstream(std::filesystem::path(opt_.output_dir) / "case.yaml") << case_.source_text;
    }
  }
  SnapshotBuffers<D> buf(ps_, case_.output.fields);
  std::vector<ParticleSetView> views = buf.views();
  std::unique_ptr<DemSnapshotBuffers<D>> fibers;
  if (dem_) {
    dem_->store_state();
    fibers = std::make_unique<DemSnapshotBuffers<D>>(dem_->particles(), comm_);
    views.push_back(fibers->view());
  }
  ++snapshots_;
  last_snapshot_step_ = step_;
  return writer_->write(step_, time_, views);
}

template <int D>
void Simulation<D>::report_progress(double elapsed, std::int64_t steps_done, bool force) const {
  if (!opt_.log || !comm_.root()) return;
  if (!force && (case_.output.progress_every <= 0 || step_ % case_.output.progress_every != 0))
    return;
  const double rate = elapsed > 0 ? static_cast<double>(n_fluid_global_) * steps_done / elapsed : 0;
  const double remaining_sim = std::max(0.0, case_.numerics.end_time - time_);
  const double sim_per_wall = elapsed > 0 ? time_ / elapsed : 0;
  const double eta = sim_per_wall > 0 ? remaining_sim / sim_per_wall : 0;
  const WallMotion* piston = nullptr;
  for (const WallMotion& w : walls_)
    if (w.moves) piston = &w;
  std::string wall_info;
  if (piston) {
    wall_info = fmt::format("  {} v={:.3g} m/s p={:.3g} Pa", piston->name,
                            std::hypot(piston->velocity(time_)[0], piston->velocity(time_)[1],
                                       piston->velocity(time_)[2]),
                            piston->face_pressure);
  }
  *opt_.log << fmt::format(
                   "step {:>8}  t={:.4e} s  dt={:.3e} s ({})  {:.3g} particle-steps/s  "
                   "ETA {:02d}:{:02d}:{:02d}{}\n",
                   step_, time_, dt_.dt, to_string(dt_.limit), rate, static_cast<int>(eta / 3600),
                   static_cast<int>(eta / 60) % 60, static_cast<int>(eta) % 60, wall_info)
            << std::flush;
}

template <int D>
RunSummary Simulation<D>::run() {
  timers_.reset();
  const RunSummary s = drive_run(*this, n_fluid_global_, [](bool) {});
  report_timings(comm_, timers_, s.wall_seconds, opt_.log,
                 opt_.write_output ? opt_.output_dir : std::string());
  return s;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace sphdem
