// DemRun<D>: checkpoint and restart of a fibers-only run (docs/checkpoint.md).
// The DEM particles go through the same column templates as the resin's,
// group "dem"; every rank reads the whole group back, since DemDomain starts
// from the full set and keeps the particles in its cells. The walls' state
// (the piston's segments move) is stored as numbers.
#include <fmt/format.h>

#include <ostream>

#include "dem_checkpoint.hpp"
#include "run_checkpoint.hpp"
#include "sphdem/checkpoint.hpp"
#include "sphdem/dem_run.hpp"
#include "sphdem/io.hpp"

namespace sphdem {

template <int D>
std::string DemRun<D>::write_checkpoint() {
  const std::string path = checkpoint_path(opt_.output_dir, case_.name, step_);
  {
    CheckpointWriter w(comm_, path);
    write_run_attributes(w, comm_, case_, {step_, time_, dt_, snapshots_, last_snapshot_step_});
    write_dem_checkpoint(w, *dem_);
    w.commit();
  }
  last_checkpoint_step_ = step_;
  last_checkpoint_ = path;
  checkpoint_published(comm_, opt_, case_, step_, path);
  return path;
}

template <int D>
std::string DemRun<D>::restart_from(const std::string& checkpoint) {
  return restart_logged(
      checkpoint, opt_, case_, comm_, [this](const std::string& p) { load_checkpoint(p); }, step_,
      time_);
}

// Reads everything first, then commits (see Simulation::load_checkpoint).
template <int D>
void DemRun<D>::load_checkpoint(const std::string& path) {
  CheckpointReader r(comm_, path);
  check_case_identity(case_, r.text("identity"), path);
  DemCheckpoint<D> fibers = read_dem_checkpoint(r, *dem_, path);
  const std::int64_t step = r.integer("step");
  const double time = r.real("time");
  const std::int64_t snapshots = r.integer("snapshots");
  const std::int64_t last_snapshot = r.integer("last_snapshot_step");

  // Commit: a new domain from the checkpoint's particles, on the same cells.
  restore_dem(dem_, *dec_, std::move(fibers));
  step_ = step;
  time_ = time;
  snapshots_ = snapshots;
  last_snapshot_step_ = last_snapshot;
  restarted_ = true;
  last_checkpoint_step_ = step_;
  last_checkpoint_ = path;
  if (opt_.write_output) {
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name);
    writer_->resume(step_);
    discard_checkpoints_after(comm_, opt_.output_dir, case_.name, step_);
  }
}

template std::string DemRun<2>::write_checkpoint();
template std::string DemRun<3>::write_checkpoint();
template std::string DemRun<2>::restart_from(const std::string&);
template std::string DemRun<3>::restart_from(const std::string&);

}  // namespace sphdem
