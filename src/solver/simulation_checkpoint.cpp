// The resin's part of a checkpoint and its restart (docs/checkpoint.md).
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
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "front_events_output.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/solver/resin_module.hpp"

namespace sphdem {

namespace {

// The thermal state (resin.thermal): per-particle columns of their own, not
// registry checkpoint fields, so that the checkpoints of isothermal cases
// keep their format (docs/checkpoint.md).
constexpr const char* kThermalColumns[] = {"temperature", "dtemp"};
// The implicit viscous solve's first guess (implicit cases only, likewise).
constexpr const char* kViscousGuessColumn = "visc_acc";

template <int D>
std::vector<double>& thermal_field(SphParticles<D>& ps, int k) {
  return k == 0 ? ps.temperature : ps.dtemp;
}

std::string wall_names(const std::vector<WallMotion>& walls) {
  std::string names;
  for (const WallMotion& w : walls) names += w.name + "\n";
  return names;
}

}  // namespace

template <int D>
void ResinModule<D>::write_checkpoint(CheckpointWriter& w) {
  write_front_events(false);  // the weld lines so far: a restart continues the list
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
  CheckpointColumn build{"x_at_build", ColumnType::F64, D, sizeof(Vec<D>), {}};
  build.data.resize(ps_.n_owned * sizeof(Vec<D>));
  if (nl_.positions_at_build() != ps_.n_owned)
    throw std::logic_error("sphdem: neighbor list and particles disagree at a checkpoint");
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    const Vec<D> xb = nl_.position_at_build(i);  // a float's value: exact as a double
    std::memcpy(build.data.data() + i * sizeof(Vec<D>), xb.data(), sizeof(Vec<D>));
  }
  cols.push_back(std::move(build));
  if (sp_.implicit_viscosity) {  // the next solve's first guess
    CheckpointColumn c{kViscousGuessColumn, ColumnType::F64, D, sizeof(Vec<D>), {}};
    c.data.resize(ps_.n_owned * sizeof(Vec<D>));
    if (ps_.n_owned > 0) std::memcpy(c.data.data(), ps_.visc_acc.data(), c.data.size());
    cols.push_back(std::move(c));
  }
  for (int k = 0; k < 2 && sp_.thermal; ++k) {
    const std::vector<double>& f = thermal_field(ps_, k);
    CheckpointColumn c{kThermalColumns[k], ColumnType::F64, 1, sizeof(double), {}};
    c.data.resize(ps_.n_owned * sizeof(double));
    if (ps_.n_owned > 0) std::memcpy(c.data.data(), f.data(), c.data.size());
    cols.push_back(std::move(c));
  }
  w.particles("sph", cols);
}

// The commit puts the particles at their positions of the last rebuild
// (the run then rebuilds there) and restarted() gives them their current
// positions back.
template <int D>
std::function<void()> ResinModule<D>::read_checkpoint(CheckpointReader& r,
                                                      const std::string& path) {
  const std::int64_t n = r.count("sph");
  if (n != n_fluid_global_ + n_wall_global_)
    throw InputError(path, 0, "",
                     fmt::format("the checkpoint holds {} SPH particles, the case makes {}", n,
                                 n_fluid_global_ + n_wall_global_));
  std::vector<CheckpointColumn> cols = r.particles("sph");
  auto build = std::make_shared<CheckpointColumn>(take_column(cols, "x_at_build", path));
  if (build->row_bytes != sizeof(Vec<D>))
    throw InputError(path, 0, "", "field 'x_at_build' has the wrong size");
  std::vector<CheckpointColumn> thermal;
  for (int k = 0; k < 2 && sp_.thermal; ++k) {
    thermal.push_back(take_column(cols, kThermalColumns[k], path));
    if (thermal.back().row_bytes != sizeof(double))
      throw InputError(path, 0, "",
                       std::string("field '") + kThermalColumns[k] + "' has the wrong size");
  }
  std::optional<CheckpointColumn> guess;
  if (sp_.implicit_viscosity) {
    guess = take_column(cols, kViscousGuessColumn, path);
    if (guess->row_bytes != sizeof(Vec<D>))
      throw InputError(path, 0, "",
                       std::string("field '") + kViscousGuessColumn + "' has the wrong size");
  }
  auto loaded = std::make_shared<SphParticles<D>>();
  drop_unused_fields<D>(sp_, any_slip_wall(case_), *loaded);  // the fields of the running case
  const std::size_t rows = cols.empty() ? 0 : cols.front().rows();
  assign_checkpoint_columns(*loaded, cols, rows, path);
  for (int k = 0; k < static_cast<int>(thermal.size()); ++k) {
    if (thermal[k].rows() != rows)
      throw InputError(path, 0, "",
                       std::string("field '") + kThermalColumns[k] + "' has the wrong size");
    if (rows > 0)
      std::memcpy(thermal_field(*loaded, k).data(), thermal[k].data.data(), rows * sizeof(double));
  }
  if (guess) {
    if (guess->rows() != rows)
      throw InputError(path, 0, "",
                       std::string("field '") + kViscousGuessColumn + "' has the wrong size");
    if (rows > 0)
      std::memcpy(static_cast<void*>(loaded->visc_acc.data()), guess->data.data(),
                  rows * sizeof(Vec<D>));
  }
  if (r.text("wall_names") != wall_names(walls_))
    throw InputError(path, 0, "",
                     "the checkpoint's moving and sliding walls differ from the case's");
  std::vector<double> scale = r.reals("wall_scale");
  std::vector<double> face = r.reals("wall_face_pressure");
  if (scale.size() != walls_.size() || face.size() != walls_.size())
    throw InputError(path, 0, "", "the checkpoint's wall state does not match the case's walls");
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max() / 2;
  const std::int64_t last_balance = r.integer_in("last_balance_step", 0, kMax);
  const std::int64_t repartitions = r.integer_in("repartitions", 0, kMax);

  return [this, loaded, build, scale = std::move(scale), face = std::move(face), last_balance,
          repartitions] {
    ps_ = std::move(*loaded);
    for (std::size_t i = 0; i < ps_.n_owned; ++i) {
      ps_.p[i] = 0.0;  // derived, recomputed before use
      ps_.vwall[i] = ps_.v[i];
      ps_.rho_half[i] = ps_.rho[i];
      if (sp_.thermal) ps_.temp_half[i] = ps_.temperature[i];
      // v_half is free until the next step's first kick: it carries the
      // current position through the rebuild at the positions of the last one.
      ps_.v_half[i] = ps_.x[i];
      std::memcpy(static_cast<void*>(ps_.x[i].data()), build->data.data() + i * sizeof(Vec<D>),
                  sizeof(Vec<D>));
    }
    dec_.partition(dec_.cell_work(ps_, ps_.n_owned), /*replicated=*/false);
    for (std::size_t k = 0; k < walls_.size(); ++k) {
      walls_[k].scale = scale[k];
      walls_[k].face_pressure = face[k];
    }
    last_balance_step_ = last_balance;
    repartitions_ = repartitions;
  };
}

template <int D>
void ResinModule<D>::restarted() {
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    ps_.x[i] = ps_.v_half[i];
    ps_.v_half[i] = ps_.v[i];
  }
  last_imbalance_ = dec_.imbalance(ps_);
  moved_at_drift_.reset();
  extremes_at_kick_.reset();  // the positions and velocities changed above
  busy_since_last_check();    // the first interval starts with the steps
  // The front events list continues after the checkpoint's time.
  if (case_.output.front_events && comm_.root() && ctx_.options.write_output)
    append_front_events(ctx_.options.output_dir, case_.name, ctx_.clock.time, {}, true);
  front_series_started_ = true;
}

template void ResinModule<2>::write_checkpoint(CheckpointWriter&);
template void ResinModule<3>::write_checkpoint(CheckpointWriter&);
template std::function<void()> ResinModule<2>::read_checkpoint(CheckpointReader&,
                                                               const std::string&);
template std::function<void()> ResinModule<3>::read_checkpoint(CheckpointReader&,
                                                               const std::string&);
template void ResinModule<2>::restarted();
template void ResinModule<3>::restarted();

}  // namespace sphdem
