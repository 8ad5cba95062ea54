// The run driver (run.hpp): the step over the modules, the run loop with
// its output cadence, checkpoints, stop requests and progress, the health
// check, snapshots, and checkpoint write and restart.
#include "sphdem/solver/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <stdexcept>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/core/fault.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/io/io.hpp"
#include "sphdem/parallel/agreement.hpp"
#include "sphdem/solver/coupled_skins.hpp"
#include "sphdem/solver/coupling_module.hpp"
#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/output_cadence.hpp"
#include "sphdem/solver/resin_module.hpp"

namespace sphdem {

namespace {

// Fibers alone check their health every this many steps (a resin run
// checks at every rebuild of its lists as well).
constexpr std::int64_t kHealthEvery = 100;

// Large blocks (a field, a list, the records: 128 KiB and up) each in
// their own mapping, returned to the system when freed. glibc's default
// raises that threshold to the largest block freed so far (up to 32 MiB),
// after which the set-up's freed arrays (the fill's, every field moved by
// the first ghost append) stay resident in the heap under the run's own
// memory: about 30 bytes per particle at the peak (docs/performance.md,
// "The peak is the steady state"). Fields, lists and records keep their
// capacity across rebuilds, so the run maps no block per step.
void return_large_blocks_when_freed() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

// The set-up's small temporaries (the case's geometry) leave freed pages
// that glibc keeps resident: returned to the system once the run's own
// memory is in place (docs/performance.md, "16-bit neighbour lists").
void release_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace

template <int D>
Run<D>::Run(const Case& c, const Comm& comm, RunOptions opt)
    : case_(c),
      comm_(comm),
      opt_(std::move(opt)),
      walls_(make_wall_motions(c)),
      ctx_{case_, comm_, opt_, clock_, timers_, walls_, modules_} {
  return_large_blocks_when_freed();
  if (opt_.output_dir.empty()) opt_.output_dir = c.output.directory;
  if (!c.fill.empty()) {
    auto resin = std::make_unique<ResinModule<D>>(ctx_);
    resin_ = resin.get();
    modules_.push_back(std::move(resin));
  }
  if (c.fibers) {
    std::optional<FiberHost<D>> host;
    if (resin_)
      host.emplace(FiberHost<D>{resin_->decomposition(), resin_->domain(),
                                resin_->neighbor_cutoff(),
                                kFiberSkinShare * resin_->neighbor_skin()});
    auto fibers = std::make_unique<FiberModule<D>>(ctx_, host ? &*host : nullptr);
    fibers_ = fibers.get();
    modules_.push_back(std::move(fibers));
  }
  if (resin_ && fibers_) {
    auto coupling = std::make_unique<CouplingModule<D>>(ctx_, *resin_, *fibers_);
    coupling_ = coupling.get();
    modules_.push_back(std::move(coupling));
  }
  if (modules_.empty()) throw std::invalid_argument("sphdem: a run needs resin or fibers");
  check_health();
  // The rates of the initial state (the first step's first kick uses them).
  for (auto& m : modules_) m->rates();
  release_freed_memory();
}

template <int D>
Run<D>::~Run() = default;

template <int D>
std::vector<std::string> Run<D>::module_names() const {
  std::vector<std::string> names;
  for (const auto& m : modules_) names.emplace_back(m->name());
  return names;
}

template <int D>
std::int64_t Run<D>::counted_particles() const {
  std::int64_t n = 0;
  for (const auto& m : modules_) n += m->counted_particles();
  return n;
}

template <int D>
void Run<D>::do_step() {
  std::optional<TimeStep> ts;
  for (auto& m : modules_) {
    const std::optional<TimeStep> s = m->stable_dt();
    if (s && (!ts || s->dt < ts->dt)) ts = s;
  }
  if (!ts) throw std::logic_error("sphdem: no module of the run limits the step");
  // Land on end_time exactly rather than overshoot it by up to a step.
  const double to_end = case_.numerics.end_time - clock_.time;
  if (to_end > 0 && to_end < ts->dt) ts->dt = to_end;
  clock_.dt = *ts;
  const double dt = ts->dt;
  for (auto& m : modules_) m->predict(dt);
  clock_.time += dt;
  ++clock_.step;
  bool rebuild_needed = false;
  for (auto& m : modules_) rebuild_needed = m->moved() || rebuild_needed;
  if (rebuild_needed) rebuild(false);
  for (auto& m : modules_) m->substep(dt);
  for (auto& m : modules_) m->rates();
  for (auto& m : modules_) m->correct(dt);
}

// Every module follows the one whose lists asked: the fibers of a coupled
// run live on the resin's decomposition, which a rebuild may change.
template <int D>
void Run<D>::rebuild(bool restart) {
  for (auto& m : modules_) m->rebuild(restart);
  check_health();
}

template <int D>
void Run<D>::check_health() const {
  std::string problem;
  for (const auto& m : modules_) m->check_health(problem);
  // Every rank stops together, each with the lowest failing rank's message
  // (its own words: which particle, where), not just its rank number.
  std::optional<RankFailure> failure;
  {
    ScopedPhase t(timers_, Phase::Wait);
    failure = first_failure(comm_, problem.empty() ? std::nullopt : std::optional(problem));
  }
  if (!failure) return;
  throw CollectiveSimulationError(fmt::format("step {} (t = {:.6g} s): rank {}: {}", clock_.step,
                                              clock_.time, failure->rank, failure->message));
}

template <int D>
void Run<D>::advance(std::int64_t n) {
  for (std::int64_t s = 0; s < n; ++s) do_step();
  check_health();
}

template <int D>
std::string Run<D>::write_snapshot() {
  ScopedPhase t(timers_, Phase::Io);
  if (!writer_) {
    std::filesystem::create_directories(opt_.output_dir);
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name,
                                               effective_case_yaml(case_));
    if (comm_.root()) {
      std::ofstream(std::filesystem::path(opt_.output_dir) / "case.yaml")
          << effective_case_yaml(case_);
    }
  }
  SnapshotParts parts;
  for (auto& m : modules_) m->snapshot(parts);
  ++snapshots_;
  last_snapshot_step_ = clock_.step;
  return writer_->write(clock_.step, clock_.time, parts.views);
}

template <int D>
void Run<D>::report_progress(double elapsed, std::int64_t steps_done, bool force) const {
  if (!opt_.log || !comm_.root()) return;
  const int every = case_.output.progress_every;
  if (!force && (every <= 0 || clock_.step % every != 0)) return;
  const double rate = elapsed > 0 ? static_cast<double>(counted_particles()) *
                                        static_cast<double>(steps_done) / elapsed
                                  : 0;
  const double remaining_sim = std::max(0.0, case_.numerics.end_time - clock_.time);
  const double sim_per_wall = elapsed > 0 ? clock_.time / elapsed : 0;
  // At most 1e9 s (32 years; an absurd end_time): the casts below stay in int's range.
  const double eta = sim_per_wall > 0 ? std::min(remaining_sim / sim_per_wall, 1e9) : 0;
  std::string extra;
  for (const auto& m : modules_) m->progress(extra);
  *opt_.log << fmt::format(
                   "step {:>8}  t={:.4e} s  dt={:.3e} s ({})  {:.3g} particle-steps/s  "
                   "ETA {:02d}:{:02d}:{:02d}{}\n",
                   clock_.step, clock_.time, clock_.dt.dt, to_string(clock_.dt.limit), rate,
                   static_cast<int>(eta / 3600), static_cast<int>(eta / 60) % 60,
                   static_cast<int>(eta) % 60, extra)
            << std::flush;
}

// Snapshots on the output cadence, checkpoints and stop requests, the last
// state written when the run blows up, the final state always on disk,
// progress, and the summary.
template <int D>
RunSummary Run<D>::run() {
  timers_.reset();
  step_times_.reset();
  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const double end = case_.numerics.end_time;
  const std::int64_t step0 = clock_.step;
  const bool output = opt_.write_output;
  // A restart continues the series: its first state is already on disk.
  if (output && !restarted_) write_snapshot();
  OutputCadence cadence = resumed_output_cadence(case_.output, clock_.time);
  CheckpointCadence checkpoints(case_.checkpoint, opt_.checkpoint_every, opt_.stop_requested);
  bool stopped = false;
  set_current_step(clock_.step);
  try {
    while (clock_.time < end * (1 - 1e-12) && (!opt_.max_steps || clock_.step < *opt_.max_steps)) {
      set_current_step(clock_.step + 1);
      const auto step_start = std::chrono::steady_clock::now();
      const double idle_before = timers_.idle_seconds();
      do_step();
      step_times_.record(seconds_since(step_start) - (timers_.idle_seconds() - idle_before));
      if (step_times_.block_full()) {
        ScopedPhase t(timers_, Phase::Wait);
        step_times_.fold(comm_);
      }
      inject_step_fault(comm_.rank(), clock_.step);  // tests only (fault.hpp)
      if (clock_.step % kHealthEvery == 0) check_health();
      report_progress(elapsed(), clock_.step - step0, false);
      if (cadence.due(clock_.step, clock_.time) && output) write_snapshot();
      const CheckpointCadence::Decision decision = checkpoints.after_step(comm_, clock_.step);
      if (decision.write && output) {
        write_checkpoint();
        checkpoints.written();
      }
      if (decision.stop) {
        stopped = true;
        break;
      }
    }
    check_health();
  } catch (const SimulationError& e) {
    // Writing the last state is collective: only when every rank failed
    // (with one rank, always). A one-rank failure goes on to the app's fault
    // handler, which aborts the job (docs/architecture.md, "Errors").
    const bool collective = dynamic_cast<const CollectiveSimulationError*>(&e) != nullptr;
    if (!collective && comm_.size() > 1) throw;
    if (output) {
      const std::string last = write_snapshot();
      if (opt_.log && comm_.root()) *opt_.log << "last state written to " << last << "\n";
    }
    if (collective) throw;
    throw CollectiveSimulationError(e.what());
  }
  // The final state is always on disk, whatever the cadence (after a stop
  // request, in the checkpoint: a snapshot off the cadence would not be in
  // the series of an uninterrupted run).
  if (output && !stopped && last_snapshot_step_ != clock_.step) write_snapshot();
  if (output && checkpoints.enabled() && last_checkpoint_step_ != clock_.step) write_checkpoint();
  RunSummary s;
  s.stopped = stopped;
  s.last_checkpoint = last_checkpoint_;
  s.steps = clock_.step - step0;
  s.time = clock_.time;
  s.wall_seconds = elapsed();
  s.particle_steps_per_second =
      s.wall_seconds > 0
          ? static_cast<double>(counted_particles()) * static_cast<double>(s.steps) / s.wall_seconds
          : 0;
  const int every = case_.output.progress_every;
  if (every <= 0 || clock_.step % every != 0) report_progress(s.wall_seconds, s.steps, true);
  s.snapshots = snapshots_;
  step_times_.fold(comm_);  // the last, partial block
  report_timings(comm_, timers_, s.wall_seconds, step_times_.summary(), opt_.log,
                 opt_.write_output ? opt_.output_dir : std::string());
  return s;
}

// A checkpoint (docs/checkpoint.md): the run's position and the case it
// belongs to, then each module's part.
template <int D>
std::string Run<D>::write_checkpoint() {
  ScopedPhase t(timers_, Phase::Io);
  const std::string path = checkpoint_path(opt_.output_dir, case_.name, clock_.step);
  {
    CheckpointWriter w(comm_, path);
    w.attribute("case", case_.name);
    w.attribute("identity", case_identity_text(case_));
    w.attribute("case_text", effective_case_yaml(case_));
    w.attribute("ranks", static_cast<std::int64_t>(comm_.size()));
    w.attribute("step", clock_.step);
    w.attribute("time", clock_.time);
    w.attribute("dt", clock_.dt.dt);
    w.attribute("dt_limit", static_cast<std::int64_t>(clock_.dt.limit));
    w.attribute("snapshots", snapshots_);
    w.attribute("last_snapshot_step", last_snapshot_step_);
    for (auto& m : modules_) m->write_checkpoint(w);
    w.commit();
  }
  last_checkpoint_step_ = clock_.step;
  last_checkpoint_ = path;
  prune_checkpoints(comm_, opt_.output_dir, case_.name, case_.checkpoint.keep);
  if (opt_.log && comm_.root())
    *opt_.log << fmt::format("step {}: checkpoint {}\n", clock_.step, path) << std::flush;
  return path;
}

template <int D>
std::string Run<D>::restart_from(const std::string& checkpoint) {
  if (opt_.write_output) remove_stale_checkpoint_temporaries(comm_, opt_.output_dir, case_.name);
  const auto start = std::chrono::steady_clock::now();
  const std::string path =
      restart_from_checkpoint(checkpoint, opt_.output_dir, case_.name, comm_, opt_.log,
                              [this](const std::string& p) { load_checkpoint(p); });
  // The read, the migration to the owners and the first rebuild
  // (docs/checkpoint.md "At scale"), on rank 0's clock.
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (opt_.log && comm_.root())
    *opt_.log << fmt::format("restarting from {} (step {}, t = {:.6g} s; read in {:.3g} s)\n", path,
                             clock_.step, clock_.time, seconds)
              << std::flush;
  return path;
}

namespace {

// The clock of a checkpoint, validated: a checkpoint is input, and a
// restart deletes the snapshots and checkpoints after its step, so a step
// edited to -5 must be refused, never trusted (issue 15, defect 7).
void read_checkpoint_clock(const CheckpointReader& r, const std::string& path, Clock& clock,
                           bool resin) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  clock.step = r.integer_in("step", 0, std::numeric_limits<std::int64_t>::max() / 2);
  clock.time = r.real_in("time", 0, inf);
  clock.dt.dt = r.real_in("dt", 0, inf, /*lo_open=*/true);
  // The resin's limits (a fibers-only checkpoint has no dt_limit); Capillary
  // is DtLimit's last enumerator.
  clock.dt.limit =
      resin ? static_cast<DtLimit>(r.integer_in("dt_limit", static_cast<std::int64_t>(DtLimit::Cfl),
                                                static_cast<std::int64_t>(DtLimit::Capillary)))
            : DtLimit::Dem;
  if ((clock.step == 0) != (clock.time == 0))
    throw InputError(path, 0, "",
                     fmt::format("attributes 'step' ({}) and 'time' ({}) disagree: the checkpoint "
                                 "is corrupt",
                                 clock.step, clock.time));
  // A checkpoint of the output directory is named after its step: a file
  // that says otherwise would make the restart delete the wrong files.
  const std::string name = std::filesystem::path(path).filename().string();
  const auto stem_end = name.rfind(".ckpt.h5");
  const auto underscore = name.rfind('_', stem_end);
  if (stem_end != std::string::npos && underscore != std::string::npos &&
      stem_end > underscore + 1) {
    const std::string digits = name.substr(underscore + 1, stem_end - underscore - 1);
    if (std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; }) &&
        digits.size() < 19 && std::stoll(digits) != clock.step)
      throw InputError(path, 0, "",
                       fmt::format("the file is named for step {}, its attribute 'step' is {}: the "
                                   "checkpoint is corrupt",
                                   std::stoll(digits), clock.step));
  }
}

}  // namespace

// Reads everything first, then commits: a refused checkpoint leaves the run
// as it was (so `latest` can try an older one). The commit rebuilds the
// modules' lists where the checkpointed run last rebuilt them, so the next
// rebuild falls on the same step as in the uninterrupted run.
template <int D>
void Run<D>::load_checkpoint(const std::string& path) {
  CheckpointReader r(comm_, path);
  check_case_identity(case_, r.text("identity"), path);
  std::vector<std::function<void()>> commits;
  for (auto& m : modules_) commits.push_back(m->read_checkpoint(r, path));
  Clock clock;
  read_checkpoint_clock(r, path, clock, resin_ != nullptr);
  // The resumed output cadence counts the intervals up to the time one by
  // one (resumed_output_cadence): a time of 1e300 would never end.
  constexpr double kMaxIntervals = 1e9;
  if (const std::optional<double> every = case_.output.every_time;
      every && *every > 0 && clock.time / *every > kMaxIntervals)
    throw InputError(path, 0, "",
                     fmt::format("attribute 'time' ({} s) is more than {:g} output intervals "
                                 "(output.every_time {} s): the checkpoint is corrupt",
                                 clock.time, kMaxIntervals, *every));
  // Every snapshot of the series is of a step up to this one (-1: none yet).
  const std::int64_t snapshots = r.integer_in("snapshots", 0, clock.step + 1);
  const std::int64_t last_snapshot = r.integer_in("last_snapshot_step", -1, clock.step);

  // Commit.
  for (const std::function<void()>& commit : commits)
    if (commit) commit();
  rebuild(/*restart=*/true);
  for (auto& m : modules_) m->restarted();
  clock_ = clock;
  snapshots_ = snapshots;
  last_snapshot_step_ = last_snapshot;
  restarted_ = true;
  last_checkpoint_step_ = clock_.step;
  last_checkpoint_ = path;
  if (opt_.write_output) {
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name,
                                               effective_case_yaml(case_));
    writer_->resume(clock_.step);
    discard_checkpoints_after(comm_, opt_.output_dir, case_.name, clock_.step);
  }
}

template class Run<2>;
template class Run<3>;

}  // namespace sphdem
