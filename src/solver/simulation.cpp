// The resin module (resin_module.hpp) and Simulation, a run with resin.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <ostream>
#include <span>
#include <stdexcept>

#include "distributed_fill.hpp"
#include "front_events_output.hpp"
#include "injection_pressure.hpp"
#include "resin_leapfrog.hpp"
#include "snapshot_fields.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/exact_sum.hpp"
#include "sphdem/parallel/ordered_sum.hpp"
#include "sphdem/solver/coupled_skins.hpp"
#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/resin_cells.hpp"
#include "sphdem/solver/resin_module.hpp"
#include "sphdem/solver/solver.hpp"
#include "sphdem/sph/fluid_rates.hpp"
#include "sphdem/sph/implicit_viscosity.hpp"

namespace sphdem {

namespace {

// The run's decomposition; a domain too large for its cells is the case's
// fault (the domain, or the mold it defaults to).
template <int D>
Decomposition<D> case_decomposition(const Comm& comm, const Case& c, const Box<D>& domain,
                                    double min_cell, long max_top_cells) {
  try {
    return Decomposition<D>(comm, domain, c.periodic, min_cell, max_top_cells);
  } catch (const std::length_error& e) {
    throw input_error_at(c, c.domain_lo ? "domain" : "mold", e.what());
  }
}

}  // namespace

double resin_min_cell(const Case& c, double neighbor_cutoff) {
  return std::max(neighbor_cutoff, implicit_chain_reach(c));
}

template <int D>
ResinModule<D>::ResinModule(const RunContext<D>& ctx)
    : ctx_(ctx),
      case_(ctx.case_data),
      comm_(ctx.comm),
      timers_(ctx.timers),
      walls_(ctx.walls),
      sp_(make_sph_params(case_)),
      eos_(case_.resin.density, case_.resin.sound_speed, case_.resin.gamma),
      domain_(simulation_domain<D>(case_)),
      nl_(2.0 * case_.h(), case_.numerics.neighbor_skin * 2.0 * case_.h()),
      support_(2.0 * case_.h(), kSupportListMargin * 2.0 * case_.h()),
      dec_(case_decomposition<D>(comm_, case_, domain_, resin_min_cell(case_, nl_.cutoff()),
                                 max_blocks(comm_.size(), case_.parallel.min_top_cells,
                                            case_.parallel.top_cells_per_rank))) {
  // The trapped-air grid of the front events: too many cells is the
  // case's fault, found at the start rather than at the first output.
  if (case_.output.front_events) {
    try {
      make_void_grid<D>(domain_, sp_.spacing);
    } catch (const std::length_error& e) {
      throw input_error_at(case_, "output.front_events", e.what());
    }
  }
  // Only the fields the case's options use take memory (docs/performance.md).
  drop_unused_fields<D>(sp_, any_slip_wall(case_), ps_);
  // Each rank fills only its share, partitioned by the lattice's work.
  const InitialCounts counts = fill_distributed<D>(case_, dec_, ps_);
  n_fluid_global_ = static_cast<std::int64_t>(counts.fluid);
  n_wall_global_ = static_cast<std::int64_t>(counts.wall);
  last_imbalance_ = dec_.imbalance(ps_);
  set_wall_velocities(0.0);
  rebuild(/*restart=*/false);
  busy_since_last_check();  // the first interval starts with the steps
}

template <int D>
void ResinModule<D>::set_wall_velocities(double t) {
  std::vector<Vec<D>> v(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) v[k] = to_vec<D>(walls_[k].velocity(t));
  lanes::for_each_of_kind(ps_.kind.data(), ps_.n_owned, Kind::Wall, [&](std::size_t i) {
    const std::int32_t k = ps_.wall[i];
    ps_.v[i] = k >= 0 ? v[static_cast<std::size_t>(k)] : Vec<D>::Zero();
  });
}

// Migration, halo and lists are rebuilt together: the halo plan and the
// lists index the particles that migration rearranges. restart: at a
// checkpoint's positions of the last rebuild, with no periodic wrap and no
// load-balance check (they happened then).
template <int D>
void ResinModule<D>::rebuild(bool restart) {
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
}

// The work per rank changes only when particles migrate, so the imbalance is
// measured right after a migration, at most once per balance_every steps.
// Re-partitioning only at a rebuild the step needs anyway (never forcing an
// extra one) keeps the rebuild steps, where periodic positions wrap, the
// same at every rank count; the gather in global-id order does the rest.
template <int D>
void ResinModule<D>::maybe_rebalance() {
  const int every = case_.parallel.balance_every;
  const std::int64_t step = ctx_.clock.step;
  if (every <= 0 || step - last_balance_step_ < every) return;
  const bool by_time = case_.parallel.balance_weight == BalanceWeight::Time;
  const double busy = busy_since_last_check();  // before this phase starts
  ScopedPhase t(timers_, Phase::Rebalance);
  last_balance_step_ = step;
  const std::vector<std::int64_t> work = cell_work();
  const double before = by_time ? dec_.time_imbalance(busy) : dec_.imbalance(work);
  last_imbalance_ = before;
  if (!(before > case_.parallel.imbalance_threshold)) return;
  last_imbalance_ =
      by_time ? dec_.partition_by_time(work, busy) : dec_.partition(work, /*replicated=*/false);
  const MigrationCounts moved = migrate<D>(dec_, ps_);
  ++repartitions_;
  const std::int64_t total_moved = comm_.sum(static_cast<std::int64_t>(moved.sent));
  std::ostream* log = ctx_.options.log;
  if (log && comm_.root()) {
    *log << fmt::format(
                "step {}: re-partitioned over {} ranks{}: imbalance {:.1f} % -> {:.1f} %, {} "
                "particles moved\n",
                step, comm_.size(), by_time ? " by measured time" : "", 100 * before,
                100 * last_imbalance_, total_moved)
         << std::flush;
  }
}

template <int D>
double ResinModule<D>::busy_since_last_check() {
  const auto now = std::chrono::steady_clock::now();
  const double idle = timers_.idle_seconds();
  const double busy =
      std::chrono::duration<double>(now - balance_clock_).count() - (idle - balance_idle_);
  balance_clock_ = now;
  balance_idle_ = idle;
  return busy;
}

// Work per cell of this rank's particles: the resin's (decomposition.hpp)
// plus that of the modules on this decomposition (the fibers of a coupled
// run).
template <int D>
std::vector<std::int64_t> ResinModule<D>::cell_work() const {
  std::vector<std::int64_t> work = dec_.cell_work(ps_, ps_.n_owned);
  for (const auto& m : ctx_.modules)
    if (m.get() != this) m->add_cell_work(dec_, work);
  return work;
}

// Mean face pressure per wall over all ranks (NaN for a wall touching no
// resin), summed in global-id order: bitwise the same at every rank count.
template <int D>
std::vector<double> ResinModule<D>::face_means(const std::vector<WallFaceSample>& face) {
  if (walls_.empty()) return {};
  ScopedPhase t(timers_, Phase::Wait);
  std::vector<OrderedTerm> terms;
  terms.reserve(face.size());
  for (const WallFaceSample& f : face) terms.push_back({f.gid, f.wall, f.p});
  const std::vector<KeySum> sums = ordered_sums(comm_, terms, walls_.size(), &face_capacity_);
  std::vector<double> mean(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) {
    mean[k] = sums[k].count > 0 ? sums[k].sum / static_cast<double>(sums[k].count) : std::nan("");
  }
  return mean;
}

template <int D>
void ResinModule<D>::rates() {
  {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.forward(ps_, SphGroup::State);
  }
  // In 3D the lists cut to the support and a margin (support_lists.hpp),
  // the same bits as nl_ for every sum of this step: the wall state, the
  // passes, the rates, the heat and the weld lines.
  const NeighborList<D>& nl = D == 3 && support_lists_on() ? support_.lists(nl_, ps_) : nl_;
  compute_fluid_pressure<D>(eos_, sp_.pressure_floor, ps_);
  const double time = ctx_.clock.time;
  std::vector<WallKinematics<D>> kin(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    kin[k].accel = to_vec<D>(walls_[k].acceleration(time));
    kin[k].pressure_floor = -walls_[k].adhesion_pressure;
    kin[k].slip = walls_[k].slip;
    kin[k].thermal = walls_[k].thermal;
  }
  const std::vector<WallFaceSample> face = compute_wall_state<D>(sp_, eos_, nl, kin, ps_);
  update_wall_controllers(walls_, face_means(face), ctx_.clock.dt.dt);
  {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.forward(ps_, SphGroup::WallState);
  }
  compute_fluid_passes_and_rates<D>(sp_, nl, ps_, [this](SphGroup g) {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.forward(ps_, g);
  });
  if (sp_.thermal) compute_heat_rates<D>(sp_, nl, ps_);
  if (case_.output.front_events) {
    for (const WeldMark<D>& w : mark_weld_lines<D>(sp_, nl, ps_)) {
      weld_events_.push_back({ps_.gid[w.i], 0, time});
      for (int d = 0; d < D; ++d) weld_events_.push_back({ps_.gid[w.i], d + 1, w.at[d]});
    }
  }
}

template <int D>
std::vector<FrontEvent> ResinModule<D>::collect_front_events(bool pockets) {
  std::vector<FrontEvent> events;
  if (!case_.output.front_events) return events;
  const std::vector<OrderedTerm> all = gather_terms(comm_, weld_events_);
  weld_events_.clear();
  for (const OrderedTerm& t : all) {  // sorted by (id, key): key 0 starts an event
    if (t.key == 0)
      events.push_back({FrontEvent::Kind::WeldLine, t.value, {}, t.order, 0.0});
    else
      events.back().x[static_cast<std::size_t>(t.key - 1)] = t.value;
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const FrontEvent& a, const FrontEvent& b) { return a.time < b.time; });
  if (!pockets) return events;
  const VoidGrid<D> grid = make_void_grid<D>(domain_, sp_.spacing);
  std::vector<double> marks;
  mark_void_grid<D>(grid, sp_.spacing, ps_, case_.mold.shapes, case_.mold.vents, marks);
  {
    ScopedPhase t(timers_, Phase::Wait);
    comm_.sum(std::span<double>(marks));
  }
  std::int64_t k = 0;
  for (const AirPocket& p : find_air_pockets<D>(grid, marks))
    events.push_back({FrontEvent::Kind::TrappedAir, ctx_.clock.time, p.centroid, k++, p.size});
  return events;
}

template <int D>
void ResinModule<D>::write_front_events(bool pockets) {
  if (!case_.output.front_events) return;
  const std::vector<FrontEvent> events = collect_front_events(pockets);
  if (comm_.root() && ctx_.options.write_output) {
    append_front_events(ctx_.options.output_dir, case_.name, ctx_.clock.time, events,
                        !front_series_started_);
  }
  front_series_started_ = true;
}

template <int D>
std::optional<TimeStep> ResinModule<D>::stable_dt() {
  // The maxima of the last second kick when it computed them (correct).
  const LocalExtremes ex = extremes_at_kick_ && extremes_at_kick_->n_owned == ps_.n_owned
                               ? extremes_at_kick_->maxima
                               : local_extremes<D>(ps_);
  extremes_at_kick_.reset();
  // One allreduce for the three largest values (a maximum is exact: the
  // same values as three reductions).
  std::array<double, 3> maxes{ex.v_max, ex.a_max, ex.mu_max};
  {
    ScopedPhase t(timers_, Phase::Wait);
    max_over_ranks(comm_, maxes);
  }
  const double v_max = maxes[0], a_max = maxes[1];
  const double mu_max = sp_.variable_viscosity ? maxes[2] : -1.0;
  if (!std::isfinite(v_max) || !std::isfinite(a_max)) {
    throw CollectiveSimulationError(
        fmt::format("the resin blew up at step {} (t = {:.6g} s): a velocity "
                    "or acceleration is not finite",
                    ctx_.clock.step, ctx_.clock.time));
  }
  return choose_time_step(case_.numerics, sp_, v_max, a_max, mu_max);
}

// The first kick and the drift; the walls move rigidly, exactly for a
// piecewise-linear table within a segment.
// With resin.thermal the temperature steps like the density, and a particle
// below the no-flow temperature at the start of the step is frozen for it:
// it holds its position at zero velocity (docs/physics.md "No-flow
// temperature").
template <int D>
void ResinModule<D>::predict(double dt) {
  const double half = 0.5 * dt;
  if (sp_.thermal) {
    for (std::size_t i = 0; i < ps_.n_owned; ++i) {
      if (ps_.kind[i] != Kind::Fluid) continue;
      ps_.frozen[i] = ps_.temperature[i] < sp_.no_flow_temperature ? 1 : 0;
      if (ps_.frozen[i]) ps_.a[i].setZero();
      ps_.temp_half[i] = ps_.temperature[i] + half * ps_.dtemp[i];
      ps_.temperature[i] = ps_.temp_half[i] + half * ps_.dtemp[i];
    }
  }
  const double time = ctx_.clock.time;
  std::vector<Vec<D>> disp(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    disp[k] =
        walls_[k].moves ? Vec<D>(dt * to_vec<D>(walls_[k].velocity(time + half))) : Vec<D>::Zero();
  }
  // Each particle's update reads only its own fields: the resin in one pass
  // (resin_leapfrog.hpp, eight at a time), the moving walls in another.
  // Where no wall moves, the pass also runs the rebuild check (moved()) on
  // the positions it writes (docs/performance.md, "The streaming passes").
  // (A wall that does not move adds a zero displacement below: no change.)
  moved_at_drift_.reset();
  box_at_drift_.reset();
  bool walls_move = false;
  for (const WallMotion& w : walls_) walls_move = walls_move || w.moves;
  if (walls_move)
    kick_drift_resin<D>(ps_, dt);
  else
    moved_at_drift_ = kick_drift_resin_and_check<D>(ps_, dt, nl_, &box_at_drift_);
  if (walls_.empty()) return;
  lanes::for_each_of_kind(ps_.kind.data(), ps_.n_owned, Kind::Wall, [&](std::size_t i) {
    if (ps_.wall[i] >= 0) ps_.x[i] += disp[static_cast<std::size_t>(ps_.wall[i])];
  });
}

// Rebuild once some particle moved more than half the skin (the verdict
// of the drift's pass, or needs_rebuild) and the box of all moves says a
// pair may have come within the support unlisted (NeighborList::move_box,
// docs/performance.md "Rebuilds on the particles' relative moves"), or some
// particle moved the farthest a run allows: its skin, or in a coupled run
// kCoupledResinMoveShare of it, for the coupling's ghosts
// (coupled_skins.hpp).
template <int D>
bool ResinModule<D>::moved() {
  set_wall_velocities(ctx_.clock.time);
  const bool moved = moved_at_drift_ ? *moved_at_drift_ : nl_.needs_rebuild(ps_);
  std::optional<typename NeighborList<D>::MoveBox> box = box_at_drift_;
  moved_at_drift_.reset();
  box_at_drift_.reset();
  const double max_move = case_.fibers ? kCoupledResinMoveShare : 1.0;
  constexpr std::size_t kBox = 2 * D + 2;
  if (box) {  // the verdict and the box in one reduction
    std::array<double, kBox + 1> both;
    both[0] = moved ? 1.0 : 0.0;
    std::copy(box->begin(), box->end(), both.begin() + 1);
    {
      ScopedPhase t(timers_, Phase::Wait);
      comm_.max(both);
    }
    if (both[0] == 0.0) return false;
    std::copy(both.begin() + 1, both.end(), box->begin());
    return nl_.box_needs_rebuild(*box, max_move);
  }
  {
    ScopedPhase t(timers_, Phase::Wait);
    if (!comm_.any(moved)) return false;
  }
  box = nl_.move_box(ps_);
  {
    ScopedPhase t(timers_, Phase::Wait);
    comm_.max(*box);
  }
  return nl_.box_needs_rebuild(*box, max_move);
}

// The second kick, with the rates at the end of the step.
template <int D>
void ResinModule<D>::correct(double dt) {
  // Without a solve between them, the two kicks in one pass
  // (resin_leapfrog.hpp, eight at a time).
  const bool solve = sp_.implicit_viscosity;
  extremes_at_kick_.reset();
  // Without a solve nothing changes the velocities and accelerations before
  // the next step's stable_dt: the kick's pass takes their maxima too.
  if (solve) {
    kick_resin<D>(ps_, dt, /*density=*/false, sp_.thermal);
  } else {
    extremes_at_kick_ = {kick_resin_and_extremes<D>(ps_, dt, /*density=*/true, sp_.thermal),
                         ps_.n_owned};
  }
  // Before the density kick: the solve reads the densities of the rates,
  // which the ghosts hold too (rank-count independence).
  if (solve) {
    solve_viscosity(dt);
    kick_density_resin<D>(ps_, dt, sp_.thermal);
  }
  // The density kick read the velocities before the solve; the particles
  // drift with the solve's (docs/physics.md "Implicit viscosity", the density).
  if (sp_.implicit_viscosity) {
    add_viscous_density<D>(sp_, dt, nl_, ps_, [this](SphGroup g) {
      ScopedPhase t(timers_, Phase::Halo);
      halo_.forward(ps_, g);
    });
  }
  shift_particles<D>(sp_, dt, nl_, ps_, [this](SphGroup g) {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.forward(ps_, g);
  });
}

// The implicit viscous step (implicit_viscosity.hpp) on the velocities of
// the second kick, at the positions the rates were evaluated on. Every rank
// reaches the same iteration count and verdict (exact sums), so a solve that
// fails throws on every rank together.
template <int D>
void ResinModule<D>::solve_viscosity(double dt) {
  ViscousSolveHooks hooks;
  hooks.forward = [this](SphGroup g) {
    ScopedPhase t(timers_, Phase::Halo);
    halo_.forward(ps_, g);
  };
  hooks.max = [this](std::span<double> v) {
    ScopedPhase t(timers_, Phase::Wait);
    max_over_ranks(comm_, v);
  };
  hooks.exact_sum = [this](std::span<Int128> v) {
    ScopedPhase t(timers_, Phase::Wait);
    exact_sum(comm_, v);
  };
  const Numerics& num = case_.numerics;
  std::vector<WallSlipLaw> slip(walls_.size());
  for (std::size_t k = 0; k < walls_.size(); ++k) slip[k] = walls_[k].slip;
  const ViscousSolveStats s = solve_implicit_viscosity<D>(
      sp_, dt, num.implicit_tolerance, num.implicit_max_iterations, nl_, ps_, slip, hooks);
  cg_iterations_ = s.iterations;
  if (!s.converged) {
    throw CollectiveSimulationError(fmt::format(
        "the implicit viscous solve did not converge at step {} (t = {:.6g} s, dt = {:.3g} s): "
        "relative residual {:.3g} after {} iterations, above numerics.implicit_tolerance = {:.3g} "
        "(raise numerics.implicit_max_iterations = {}, or check the viscosity and the time step)",
        ctx_.clock.step, ctx_.clock.time, dt, s.residual, s.iterations, num.implicit_tolerance,
        num.implicit_max_iterations));
  }
}

template <int D>
void ResinModule<D>::check_health(std::string& problem) const {
  for (std::size_t i = 0; i < ps_.n_owned && problem.empty(); ++i) {
    for (int k = 0; k < D; ++k) {
      const double x = ps_.x[i][k];
      if (!std::isfinite(x)) {
        problem = fmt::format("particle {} has a non-finite position", ps_.gid[i]);
        break;
      }
      if (!case_.periodic[k] && (x < domain_.lo[k] || x > domain_.hi[k])) {
        problem = fmt::format(
            "particle {} left the domain along axis {} (x = {:.6g} m, domain "
            "[{:.6g}, {:.6g}])",
            ps_.gid[i], "xyz"[k], x, domain_.lo[k], domain_.hi[k]);
        break;
      }
    }
  }
}

template <int D>
void ResinModule<D>::snapshot(SnapshotParts& parts) {
  auto buf = std::make_shared<const SnapshotBuffers<D>>(ps_, case_.output.fields);
  for (ParticleSetView& v : buf->views()) parts.views.push_back(std::move(v));
  parts.buffers.push_back(std::move(buf));
  if (comm_.root() && ctx_.options.write_output) {
    append_injection_pressure(ctx_.options.output_dir, case_.name, ctx_.clock.step, ctx_.clock.time,
                              walls_, !pressure_series_started_);
  }
  pressure_series_started_ = true;
  write_front_events(true);
}

// The piston (the last moving wall): its speed and face pressure, the
// injection pressure (injection_pressure.hpp).
template <int D>
void ResinModule<D>::progress(std::string& line) const {
  if (sp_.implicit_viscosity) line += fmt::format("  cg={}", cg_iterations_);
  const WallMotion* piston = nullptr;
  for (const WallMotion& w : walls_)
    if (w.moves) piston = &w;
  if (!piston) return;
  const double t = ctx_.clock.time;
  line += fmt::format(
      "  {} v={:.3g} m/s p={:.3g} Pa", piston->name,
      std::hypot(piston->velocity(t)[0], piston->velocity(t)[1], piston->velocity(t)[2]),
      piston->face_pressure);
}

template class ResinModule<2>;
template class ResinModule<3>;

template <int D>
Simulation<D>::Simulation(const Case& c, const Comm& comm, RunOptions opt)
    : Run<D>(c.fill.empty() ? throw std::invalid_argument("sphdem: Simulation needs resin (fill:)")
                            : c,
             comm, std::move(opt)) {}

template <int D>
const FiberPlacement& Simulation<D>::placement() const {
  static const FiberPlacement none;
  return this->fibers() ? this->fibers()->placement() : none;
}

template <int D>
const std::vector<double>& Simulation<D>::resin_void_fraction() const {
  static const std::vector<double> none;
  return this->coupling() ? this->coupling()->resin_void_fraction() : none;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace sphdem
