#pragma once
// The run driver (docs/architecture.md, "The run driver"): one Run<D> owns
// the clock, the output cadence and the snapshots, the checkpoints and the
// restart, the progress lines, the health checks, stop requests and the
// summary, over optional modules with one interface: the resin
// (ResinModule), the fibers (FiberModule) and their coupling
// (CouplingModule). A fibers-only run is a run without the resin module.
//
// A step calls each phase on every module, in the order resin, fibers,
// coupling:
//   stable_dt -> predict -> (clock moves on) -> moved -> rebuild (when a
//   module asked) -> substep -> rates -> correct
// which is, for the resin, kick-drift-kick leapfrog around one rate
// evaluation (docs/physics.md), for fibers alone one velocity-Verlet DEM
// step (predict), and for coupled fibers their DEM sub-steps over the
// resin's step (substep) followed by the coupling pass (rates).
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/geometry/walls.hpp"
#include "sphdem/io/io.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/timers.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

class CheckpointWriter;
class CheckpointReader;

struct RunOptions {
  std::string output_dir;                 // empty: the case's output.directory
  std::optional<std::int64_t> max_steps;  // stop when the step counter reaches it
  bool write_output = true;
  std::ostream* log = nullptr;  // progress lines (rank 0 only); null: silent
  // Checkpoints (docs/checkpoint.md): a step cadence that overrides the
  // case's checkpoint.every_steps, and a poll for a stop request (SIGTERM,
  // SIGUSR1): when it returns true on any rank, the run finishes the step,
  // writes a checkpoint and returns with RunSummary::stopped.
  std::optional<std::int64_t> checkpoint_every;
  std::function<bool()> stop_requested;
};

struct RunSummary {
  std::int64_t steps = 0;
  double time = 0;
  double wall_seconds = 0;
  double particle_steps_per_second = 0;  // counted particles x steps / wall time
  std::int64_t snapshots = 0;
  bool stopped = false;         // by a stop request, after writing a checkpoint
  std::string last_checkpoint;  // path of the last checkpoint this run wrote
};

// The run's clock.
struct Clock {
  double time = 0;
  std::int64_t step = 0;
  TimeStep dt;  // the last step and what limited it
};

// What a snapshot holds: the modules' particle sets, and the buffers their
// views point into (kept alive until the write).
struct SnapshotParts {
  std::vector<ParticleSetView> views;
  std::vector<std::shared_ptr<const void>> buffers;
};

template <int D>
class Module;

// What the modules share of their run. The modules read the clock; the
// moving walls' motions are the run's (the resin's pressure controllers
// update them, the fibers' piston segments follow them).
template <int D>
struct RunContext {
  const Case& case_data;
  const Comm& comm;
  const RunOptions& options;
  const Clock& clock;
  PhaseTimers& timers;
  std::vector<WallMotion>& walls;
  const std::vector<std::unique_ptr<Module<D>>>& modules;
};

// One part of a run. Every hook is collective when the module's work is
// (each rank calls the same hooks in the same order); the defaults do
// nothing. Called per step, never per particle.
template <int D>
class Module {
 public:
  virtual ~Module() = default;
  virtual const char* name() const = 0;
  // The particles a throughput (particle-steps/s) counts.
  virtual std::int64_t counted_particles() const { return 0; }

  // The step this module's state allows; nullopt: it follows the others'.
  virtual std::optional<TimeStep> stable_dt() { return std::nullopt; }
  // Before the clock moves on by dt.
  virtual void predict(double /*dt*/) {}
  // After the clock moved on: true (on every rank) when this module's
  // neighbour lists must be rebuilt, which rebuilds every module.
  virtual bool moved() { return false; }
  // Migration, ghosts and lists. restart: at a checkpoint's positions of
  // its last rebuild (docs/checkpoint.md).
  virtual void rebuild(bool /*restart*/) {}
  virtual void substep(double /*dt*/) {}
  virtual void rates() {}
  virtual void correct(double /*dt*/) {}

  // This rank's first problem (a particle out of its domain, not finite)
  // appended to `problem` when that is still empty.
  virtual void check_health(std::string& /*problem*/) const {}
  // Work per cell of `dec` for the load balance (modules on another
  // module's decomposition add theirs).
  virtual void add_cell_work(const Decomposition<D>& /*dec*/,
                             std::vector<std::int64_t>& /*work*/) const {}

  virtual void snapshot(SnapshotParts& /*parts*/) {}
  // Appended to the progress line.
  virtual void progress(std::string& /*line*/) const {}

  virtual void write_checkpoint(CheckpointWriter& /*w*/) {}
  // Reads the module's part of a checkpoint and returns what commits it:
  // nothing changes until every module has read its part (a refused
  // checkpoint leaves the run as it was).
  virtual std::function<void()> read_checkpoint(CheckpointReader& /*r*/,
                                                const std::string& /*path*/) {
    return {};
  }
  // After the commit and the restart rebuild.
  virtual void restarted() {}
};

template <int D>
class ResinModule;
template <int D>
class FiberModule;
template <int D>
class CouplingModule;

template <int D>
class Run {
 public:
  // The modules the case asks for: the resin with `fill:`, the fibers with
  // `fibers:`, their coupling with both.
  Run(const Case& c, const Comm& comm, RunOptions opt = {});
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  // Runs to end_time (or max_steps), writing output on its cadence.
  RunSummary run();
  // Advances exactly n steps without output (tests, benchmarks).
  void advance(std::int64_t n);

  // Writes a snapshot now (collective); returns its path.
  std::string write_snapshot();
  // Checkpoints (docs/checkpoint.md). Collective. Writes the complete
  // state; returns the file's path.
  std::string write_checkpoint();
  // Collective. Continues from a checkpoint (a path, or "latest": the
  // newest readable one in the output directory), written at any rank
  // count; the snapshot series continues from it. Throws InputError (every
  // rank) for a missing, truncated, corrupt or foreign checkpoint, leaving
  // the state untouched. Returns the path used.
  std::string restart_from(const std::string& checkpoint);

  double time() const { return clock_.time; }
  std::int64_t step() const { return clock_.step; }
  double last_dt() const { return clock_.dt.dt; }
  DtLimit last_dt_limit() const { return clock_.dt.limit; }
  const Case& case_data() const { return case_; }
  const std::vector<WallMotion>& walls() const { return walls_; }
  const PhaseTimers& timers() const { return timers_; }
  // The modules in step order ("resin", "fibers", "coupling").
  std::vector<std::string> module_names() const;
  // Null when the case has no such part.
  const ResinModule<D>* resin() const { return resin_; }
  ResinModule<D>* resin() { return resin_; }
  const FiberModule<D>* fibers() const { return fibers_; }
  FiberModule<D>* fibers() { return fibers_; }
  const CouplingModule<D>* coupling() const { return coupling_; }

 private:
  void do_step();
  void rebuild(bool restart);
  void check_health() const;
  void report_progress(double elapsed, std::int64_t steps_done, bool force) const;
  void load_checkpoint(const std::string& path);
  std::int64_t counted_particles() const;

  Case case_;
  const Comm& comm_;
  RunOptions opt_;
  Clock clock_;
  mutable PhaseTimers timers_;  // instrumentation, also of const methods
  StepTimes step_times_;        // each step's busy time (docs/parallel.md, "Per-step times")
  std::vector<WallMotion> walls_;
  std::vector<std::unique_ptr<Module<D>>> modules_;
  RunContext<D> ctx_;
  ResinModule<D>* resin_ = nullptr;
  FiberModule<D>* fibers_ = nullptr;
  CouplingModule<D>* coupling_ = nullptr;
  std::unique_ptr<SnapshotWriter> writer_;
  std::int64_t snapshots_ = 0;
  std::int64_t last_snapshot_step_ = -1;
  bool restarted_ = false;  // the state came from a checkpoint
  std::int64_t last_checkpoint_step_ = -1;
  std::string last_checkpoint_;
};

}  // namespace sphdem
