// Simulation<D>: checkpoint and restart (docs/checkpoint.md).
//
// Bitwise continuation. The gather formulation makes the rates independent
// of the particle layout and of the rank count; what else a continued run
// must reproduce is *when* the neighbor lists are rebuilt, because periodic
// positions wrap (x -= L, a rounding) only at a rebuild. So a checkpoint
// stores each particle's position at the last rebuild (x_at_build), and a
// restart rebuilds there: the particles are migrated, sorted and listed at
// those positions (no wrap: they were wrapped then), exactly as the run did,
// then take their current positions back. The next rebuild, and the wrap,
// then fall on the same step as in the uninterrupted run.
#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <ostream>

#include "dem_checkpoint.hpp"
#include "run_checkpoint.hpp"
#include "sphdem/checkpoint.hpp"
#include "sphdem/io.hpp"
#include "sphdem/solver.hpp"

namespace sphdem {

namespace {

std::string wall_names(const std::vector<WallMotion>& walls) {
  std::string names;
  for (const WallMotion& w : walls) names += w.name + "\n";
  return names;
}

}  // namespace

template <int D>
std::string Simulation<D>::write_checkpoint() {
  ScopedPhase t(timers_, Phase::Io);
  const std::string path = checkpoint_path(opt_.output_dir, case_.name, step_);
  {
    CheckpointWriter w(comm_, path);
    write_run_attributes(w, comm_, case_, {step_, time_, dt_.dt, snapshots_, last_snapshot_step_});
    w.attribute("dt_limit", static_cast<std::int64_t>(dt_.limit));
    w.attribute("last_balance_step", last_balance_step_);
    w.attribute("repartitions", repartitions_);
    std::vector<double> scale, face;
    for (const WallMotion& m : walls_) {
      scale.push_back(m.scale);
      face.push_back(m.face_pressure);
    }
    w.attribute("wall_names", wall_names(walls_));
    w.attribute("wall_scale", scale);
    w.attribute("wall_face_pressure", face);
    std::vector<CheckpointColumn> cols = checkpoint_columns(ps_);
    const std::vector<Vec<D>>& xb = nl_.positions_at_build();
    CheckpointColumn build{"x_at_build", ColumnType::F64, D, sizeof(Vec<D>), {}};
    build.data.resize(ps_.n_owned * sizeof(Vec<D>));
    if (xb.size() != ps_.n_owned)
      throw std::logic_error("sphdem: neighbor list and particles disagree at a checkpoint");
    if (ps_.n_owned > 0) std::memcpy(build.data.data(), xb.data(), build.data.size());
    cols.push_back(std::move(build));
    w.particles("sph", cols);
    if (dem_) {  // the fibers of a coupled run, as DemRun stores them
      write_dem_checkpoint(w, *dem_);
      // The step whose drag impulse the next coupling pass returns, and the
      // sub-step count of the work estimate.
      w.attribute("coupled_dt", coupled_dt_);
      w.attribute("dem_substeps", substeps_);
    }
    w.commit();
  }
  last_checkpoint_step_ = step_;
  last_checkpoint_ = path;
  checkpoint_published(comm_, opt_, case_, step_, path);
  return path;
}

template <int D>
std::string Simulation<D>::restart_from(const std::string& checkpoint) {
  return restart_logged(
      checkpoint, opt_, case_, comm_, [this](const std::string& p) { load_checkpoint(p); }, step_,
      time_);
}

// Reads everything first, then commits: a refused checkpoint leaves the
// simulation as it was (so `latest` can try an older one).
template <int D>
void Simulation<D>::load_checkpoint(const std::string& path) {
  CheckpointReader r(comm_, path);
  check_case_identity(case_, r.text("identity"), path);
  const std::int64_t n = r.count("sph");
  if (n != n_fluid_global_ + n_wall_global_)
    throw InputError(path, 0, "",
                     fmt::format("the checkpoint holds {} SPH particles, the case makes {}", n,
                                 n_fluid_global_ + n_wall_global_));
  std::vector<CheckpointColumn> cols = r.particles("sph");
  const CheckpointColumn build = take_column(cols, "x_at_build", path);
  if (build.row_bytes != sizeof(Vec<D>))
    throw InputError(path, 0, "", "field 'x_at_build' has the wrong size");
  SphParticles<D> loaded;
  const std::size_t rows = cols.empty() ? 0 : cols.front().rows();
  assign_checkpoint_columns(loaded, cols, rows, path);
  if (r.text("wall_names") != wall_names(walls_))
    throw InputError(path, 0, "",
                     "the checkpoint's moving and sliding walls differ from the case's");
  const std::vector<double> scale = r.reals("wall_scale");
  const std::vector<double> face = r.reals("wall_face_pressure");
  if (scale.size() != walls_.size() || face.size() != walls_.size())
    throw InputError(path, 0, "", "the checkpoint's wall state does not match the case's walls");
  // The fibers of a coupled run: every rank reads them all (DemDomain keeps
  // those in its cells).
  DemCheckpoint<D> fibers;
  double coupled_dt = 0;
  std::int64_t dem_substeps = 0;
  if (dem_) {
    fibers = read_dem_checkpoint(r, *dem_, path);
    coupled_dt = r.real("coupled_dt");
    dem_substeps = r.integer("dem_substeps");
  }
  const std::int64_t step = r.integer("step");
  const double time = r.real("time");
  const double dt = r.real("dt");
  const std::int64_t dt_limit = r.integer("dt_limit");
  const std::int64_t snapshots = r.integer("snapshots");
  const std::int64_t last_snapshot = r.integer("last_snapshot_step");
  const std::int64_t last_balance = r.integer("last_balance_step");
  const std::int64_t repartitions = r.integer("repartitions");

  // Commit.
  ps_ = std::move(loaded);
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    ps_.p[i] = 0.0;  // derived, recomputed before use
    ps_.vwall[i] = ps_.v[i];
    ps_.rho_half[i] = ps_.rho[i];
    // v_half is free until the next step's first kick: it carries the
    // current position through the rebuild at the positions of the last one.
    ps_.v_half[i] = ps_.x[i];
    std::memcpy(static_cast<void*>(ps_.x[i].data()), build.data.data() + i * sizeof(Vec<D>),
                sizeof(Vec<D>));
  }
  dec_.partition(dec_.cell_work(ps_, ps_.n_owned), /*replicated=*/false);
  // The fibers: a new DEM domain on the new map (before the rebuild, which
  // rebuilds it too).
  if (dem_) {
    restore_dem(dem_, dec_, std::move(fibers));
    coupled_dt_ = coupled_dt;
    substeps_ = dem_substeps;
  }
  rebuild_neighbors(/*restart=*/true);
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    ps_.x[i] = ps_.v_half[i];
    ps_.v_half[i] = ps_.v[i];
  }
  last_imbalance_ = dec_.imbalance(ps_);
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    walls_[k].scale = scale[k];
    walls_[k].face_pressure = face[k];
  }
  step_ = step;
  time_ = time;
  dt_.dt = dt;
  dt_.limit = static_cast<DtLimit>(dt_limit);
  snapshots_ = snapshots;
  last_snapshot_step_ = last_snapshot;
  last_balance_step_ = last_balance;
  repartitions_ = repartitions;
  restarted_ = true;
  last_checkpoint_step_ = step_;
  last_checkpoint_ = path;
  if (opt_.write_output) {
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name);
    writer_->resume(step_);
    discard_checkpoints_after(comm_, opt_.output_dir, case_.name, step_);
  }
}

template std::string Simulation<2>::write_checkpoint();
template std::string Simulation<3>::write_checkpoint();
template std::string Simulation<2>::restart_from(const std::string&);
template std::string Simulation<3>::restart_from(const std::string&);

}  // namespace sphdem
