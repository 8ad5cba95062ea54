#pragma once
// What every run driver's checkpoint shares (Simulation and DemRun,
// docs/checkpoint.md): the leading attributes, the bookkeeping once a
// checkpoint is published, and the logged restart.
#include <fmt/format.h>

#include <cstdint>
#include <ostream>
#include <string>

#include "sphdem/case.hpp"
#include "sphdem/checkpoint.hpp"
#include "sphdem/comm.hpp"
#include "sphdem/config.hpp"
#include "sphdem/solver.hpp"

namespace sphdem {

// The run's position and the case it belongs to.
struct RunPosition {
  std::int64_t step = 0;
  double time = 0, dt = 0;
  std::int64_t snapshots = 0, last_snapshot_step = -1;
};

inline void write_run_attributes(CheckpointWriter& w, const Comm& comm, const Case& c,
                                 const RunPosition& at) {
  w.attribute("case", c.name);
  w.attribute("identity", case_identity_text(c));
  w.attribute("case_text", effective_case_yaml(c));
  w.attribute("ranks", static_cast<std::int64_t>(comm.size()));
  w.attribute("step", at.step);
  w.attribute("time", at.time);
  w.attribute("dt", at.dt);
  w.attribute("snapshots", at.snapshots);
  w.attribute("last_snapshot_step", at.last_snapshot_step);
}

// After the rename: keep the newest `checkpoint.keep`, say so.
inline void checkpoint_published(const Comm& comm, const RunOptions& opt, const Case& c,
                                 std::int64_t step, const std::string& path) {
  prune_checkpoints(comm, opt.output_dir, c.name, c.checkpoint.keep);
  if (opt.log && comm.root())
    *opt.log << fmt::format("step {}: checkpoint {}\n", step, path) << std::flush;
}

// restart_from_checkpoint with the log line; `load` commits the state, after
// which step and time (read by reference) are the checkpoint's.
template <class Load>
std::string restart_logged(const std::string& checkpoint, const RunOptions& opt, const Case& c,
                           const Comm& comm, Load load, const std::int64_t& step,
                           const double& time) {
  const std::string path =
      restart_from_checkpoint(checkpoint, opt.output_dir, c.name, comm, opt.log, load);
  if (opt.log && comm.root())
    *opt.log << fmt::format("restarting from {} (step {}, t = {:.6g} s)\n", path, step, time)
             << std::flush;
  return path;
}

}  // namespace sphdem
