#pragma once
// The step loop (DESIGN 3.1). One code path for every rank count.
// Integration: kick-drift-kick leapfrog (second order), with the rates at
// the end of the step evaluated on predicted velocity and density:
//   v_h = v + dt/2 a,  rho_h = rho + dt/2 drho,  x += dt v_h
//   rates(x, v_h + dt/2 a, rho_h + dt/2 drho) -> a', drho'
//   v = v_h + dt/2 a',  rho = rho_h + dt/2 drho'
// Only one neighbor pass per step (plus the wall extrapolation).
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>

#include "sphdem/case.hpp"
#include "sphdem/comm.hpp"
#include "sphdem/coupling_loops.hpp"
#include "sphdem/decomposition.hpp"
#include "sphdem/dem_domain.hpp"
#include "sphdem/dem_fibers.hpp"
#include "sphdem/halo.hpp"
#include "sphdem/neighbor.hpp"
#include "sphdem/particles.hpp"
#include "sphdem/sph.hpp"
#include "sphdem/timers.hpp"
#include "sphdem/walls.hpp"

namespace sphdem {

class SnapshotWriter;

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
  double particle_steps_per_second = 0;  // resin particles x steps / wall time
  std::int64_t snapshots = 0;
  bool stopped = false;         // by a stop request, after writing a checkpoint
  std::string last_checkpoint;  // path of the last checkpoint this run wrote
};

template <int D>
class Simulation {
 public:
  Simulation(const Case& c, const Comm& comm, RunOptions opt = {});
  ~Simulation();

  // Runs to end_time (or max_steps), writing output on its cadence.
  RunSummary run();
  // Advances exactly n steps without output (tests, benchmarks).
  void advance(std::int64_t n);

  const SphParticles<D>& particles() const { return ps_; }
  SphParticles<D>& particles() { return ps_; }
  double time() const { return time_; }
  std::int64_t step() const { return step_; }
  double last_dt() const { return dt_.dt; }
  DtLimit last_dt_limit() const { return dt_.limit; }
  const std::vector<WallMotion>& walls() const { return walls_; }
  std::int64_t global_fluid_count() const { return n_fluid_global_; }
  std::int64_t global_wall_count() const { return n_wall_global_; }
  const Box<D>& domain() const { return domain_; }
  const Case& case_data() const { return case_; }
  // Load balance (docs/parallel.md): the imbalance (max / mean - 1 of the
  // per-rank work) at the last check, and how many re-partitions happened.
  double last_imbalance() const { return last_imbalance_; }
  std::int64_t repartitions() const { return repartitions_; }
  const Decomposition<D>& decomposition() const { return dec_; }
  const PhaseTimers& timers() const { return timers_; }
  // The fibers of a coupled case (null without `fibers:`), docs/physics.md.
  const DemDomain<D>* dem() const { return dem_.get(); }
  const FiberPlacement& placement() const { return placement_; }
  double dem_dt() const { return dem_dt_; }                // the stable DEM sub-step
  std::int64_t dem_substeps() const { return substeps_; }  // in the last SPH step
  // Per owned particle: the void fraction of the last coupling pass.
  const std::vector<double>& resin_void_fraction() const { return resin_eps_; }
  // Momentum check of the last coupling pass, over all ranks: |sum of the
  // drags + sum of the reactions| / sum of |drag| (0 without drag).
  double coupling_momentum_residual() const { return momentum_residual_; }

  // Writes a snapshot now (collective); returns its path.
  std::string write_snapshot();

  // Checkpoints (docs/checkpoint.md, src/solver/simulation_checkpoint.cpp).
  // Collective. Writes the complete state; returns the file's path.
  std::string write_checkpoint();
  // Collective. Continues from a checkpoint (a path, or "latest": the
  // newest readable one in the output directory), written at any rank
  // count; the snapshot series continues from it. Throws InputError (every
  // rank) for a missing, truncated, corrupt or foreign checkpoint, leaving
  // the state untouched. Returns the path used.
  std::string restart_from(const std::string& checkpoint);

 private:
  // restart: rebuild at a checkpoint's positions of the last rebuild, with
  // no periodic wrap and no load-balance check (they happened then).
  void rebuild_neighbors(bool restart = false);
  void load_checkpoint(const std::string& path);
  void maybe_rebalance();
  std::vector<std::int64_t> cell_work() const;
  void compute_rates();
  void couple();
  void init_fibers();
  void advance_fibers(double t0, double dt);
  std::vector<double> face_means(const std::vector<WallFaceSample>& face);
  template <class Driver, class Checks>
  friend RunSummary drive_run(Driver& d, std::int64_t particles, Checks checks);  // run_loop.hpp
  void do_step();
  void check_health() const;
  void set_wall_velocities(double t);
  void report_progress(double wall_elapsed, std::int64_t steps_done, bool force) const;

  Case case_;
  const Comm& comm_;
  RunOptions opt_;
  SphParams sp_;
  TaitEos eos_;
  Box<D> domain_;
  SphParticles<D> ps_;
  NeighborList<D> nl_;
  Halo<D> halo_;
  std::vector<WallMotion> walls_;
  std::unique_ptr<SnapshotWriter> writer_;
  double time_ = 0;
  std::int64_t step_ = 0;
  TimeStep dt_;
  std::int64_t n_fluid_global_ = 0, n_wall_global_ = 0;
  std::int64_t snapshots_ = 0;
  std::int64_t last_snapshot_step_ = -1;
  Decomposition<D> dec_;
  mutable PhaseTimers timers_;  // instrumentation, also of const methods
  std::int64_t last_balance_step_ = 0;
  double last_imbalance_ = 0;
  std::int64_t repartitions_ = 0;
  // Fibers (coupled cases).
  std::unique_ptr<DemDomain<D>> dem_;
  FiberPlacement placement_;
  std::vector<int> dem_wall_owner_;  // per DEM wall: moving wall index or -1
  CouplingSettings coupling_;
  CouplingState<D> cstate_;
  std::vector<double> resin_eps_;
  double dem_dt_ = 0;
  std::int64_t substeps_ = 0;
  double momentum_residual_ = 0;
  double coupled_dt_ = 0;   // the step whose drag impulse the next coupling returns
  bool restarted_ = false;  // the state came from a checkpoint
  std::int64_t last_checkpoint_step_ = -1;
  std::string last_checkpoint_;
};

}  // namespace sphdem
