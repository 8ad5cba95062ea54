#pragma once
// The run loop both drivers share (Simulation: the resin, with or without
// fibers; DemRun: fibers only): snapshots on the output cadence,
// checkpoints and stop requests, the last state written when the run blows
// up, the final state always on disk, progress, and the summary. The
// driver declares drive_run a friend and provides do_step, write_snapshot,
// write_checkpoint, report_progress and the run's bookkeeping members.
#include <chrono>
#include <cstdint>
#include <string>

#include "sphdem/checkpoint.hpp"
#include "sphdem/errors.hpp"
#include "sphdem/fault.hpp"
#include "sphdem/output_cadence.hpp"
#include "sphdem/solver.hpp"

namespace sphdem {

// `checks(final)` runs after every step and once more after the last one
// (inside the blow-up guard); `particles` is the count the rate is per.
template <class Driver, class Checks>
RunSummary drive_run(Driver& d, std::int64_t particles, Checks checks) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const double end = d.case_.numerics.end_time;
  const std::int64_t step0 = d.step_;
  const bool output = d.opt_.write_output;
  set_current_step(d.step_);
  // A restart continues the series: its first state is already on disk.
  if (output && !d.restarted_) d.write_snapshot();
  OutputCadence cadence = resumed_output_cadence(d.case_.output, d.time_);
  CheckpointCadence checkpoints(d.case_.checkpoint, d.opt_.checkpoint_every, d.opt_.stop_requested);
  bool stopped = false;
  try {
    while (d.time_ < end * (1 - 1e-12) && (!d.opt_.max_steps || d.step_ < *d.opt_.max_steps)) {
      set_current_step(d.step_ + 1);
      d.do_step();
      inject_step_fault(d.comm_.rank(), d.step_);  // tests only (fault.hpp)
      checks(false);
      d.report_progress(elapsed(), d.step_ - step0, false);
      if (cadence.due(d.step_, d.time_) && output) d.write_snapshot();
      const CheckpointCadence::Decision decision = checkpoints.after_step(d.comm_, d.step_);
      if (decision.write && output) {
        d.write_checkpoint();
        checkpoints.written();
      }
      if (decision.stop) {
        stopped = true;
        break;
      }
    }
    checks(true);
  } catch (const SimulationError& e) {
    // Writing the last state is collective: only when every rank failed
    // (with one rank, always). A one-rank failure goes on to the app's fault
    // handler, which aborts the job (docs/architecture.md, "Errors").
    const bool collective = dynamic_cast<const CollectiveSimulationError*>(&e) != nullptr;
    if (!collective && d.comm_.size() > 1) throw;
    if (output) {
      const std::string last = d.write_snapshot();
      if (d.opt_.log && d.comm_.root()) *d.opt_.log << "last state written to " << last << "\n";
    }
    if (collective) throw;
    throw CollectiveSimulationError(e.what());
  }
  // The final state is always on disk, whatever the cadence (after a stop
  // request, in the checkpoint: a snapshot off the cadence would not be in
  // the series of an uninterrupted run).
  if (output && !stopped && d.last_snapshot_step_ != d.step_) d.write_snapshot();
  if (output && checkpoints.enabled() && d.last_checkpoint_step_ != d.step_) d.write_checkpoint();
  RunSummary s;
  s.stopped = stopped;
  s.last_checkpoint = d.last_checkpoint_;
  s.steps = d.step_ - step0;
  s.time = d.time_;
  s.wall_seconds = elapsed();
  s.particle_steps_per_second =
      s.wall_seconds > 0
          ? static_cast<double>(particles) * static_cast<double>(s.steps) / s.wall_seconds
          : 0;
  const int every = d.case_.output.progress_every;
  if (every <= 0 || d.step_ % every != 0) d.report_progress(s.wall_seconds, s.steps, true);
  s.snapshots = d.snapshots_;
  return s;
}

}  // namespace sphdem
