// The DEM-only run (dem_run.hpp): fibers in the mold, pushed by the piston,
// no resin. Same progress lines and output cadence as the SPH run.
#include "sphdem/dem_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <stdexcept>

#include "dem_snapshot.hpp"
#include "run_loop.hpp"
#include "sphdem/checkpoint.hpp"
#include "sphdem/errors.hpp"
#include "sphdem/geometry.hpp"
#include "sphdem/io.hpp"
#include "sphdem/output_cadence.hpp"
#include "sphdem/timers.hpp"

namespace sphdem {

namespace {

template <int D>
DemParams<D> dem_params(const Case& c) {
  const FiberSettings& f = *c.fibers;
  DemParams<D> p;
  p.youngs_modulus = f.youngs_modulus;
  p.kbar_star = f.stiffness_ratio;
  p.tensile_strength = f.tensile_strength.value_or(std::numeric_limits<double>::infinity());
  p.shear_strength = f.shear_strength.value_or(std::numeric_limits<double>::infinity());
  p.restitution = f.restitution;
  p.friction = f.friction;
  p.dt_safety = f.dt_safety;
  p.gravity = to_vec<D>(c.body_force);
  p.kn = contact_stiffness_from_bond(p, 0.5 * f.diameter, f.contact_stiffness_fraction);
  return p;
}

template <int D>
FiberSpec<D> fiber_spec(const FiberSettings& f) {
  FiberSpec<D> s;
  s.count = f.count;
  s.fraction = f.area_fraction;
  s.particles_per_fiber = f.particles_per_fiber;
  s.radius = 0.5 * f.diameter;
  s.density = f.density;
  s.lo = to_vec<D>(f.region.lo);
  s.hi = to_vec<D>(f.region.hi);
  s.angle = f.angle;
  // 3D: the angle turns the fiber from +x in the x-y plane.
  if constexpr (D == 3)
    if (f.angle) s.direction = Vec<3>(std::cos(*f.angle), std::sin(*f.angle), 0.0);
  s.seed = f.seed;
  return s;
}

}  // namespace

template <int D>
DemSystem<D> case_fibers(const Case& c, std::vector<int>& wall_owner, FiberPlacement& placement) {
  DemSystem<D> all;
  all.walls = dem_walls_from_case<D>(c, wall_owner);
  all.params = dem_params<D>(c);
  const FiberSettings& f = *c.fibers;
  try {
    placement = place_fibers(fiber_spec<D>(f), all);
  } catch (const std::runtime_error& e) {
    const bool from_set = f.amount_line == 0;
    throw InputError(from_set ? "--set" : c.source_file, f.amount_line,
                     f.count > 0 ? "fibers.count" : "fibers.area_fraction", e.what());
  }
  return all;
}

template <int D>
DemRun<D>::DemRun(const Case& c, const Comm& comm, RunOptions opt)
    : case_(c), comm_(comm), opt_(std::move(opt)), motions_(make_wall_motions(c)) {
  if (!c.fibers) throw std::invalid_argument("sphdem: DemRun needs a case with fibers");
  if (opt_.output_dir.empty()) opt_.output_dir = c.output.directory;
  // Every rank places the same fibers (same seed), then keeps its own.
  DemSystem<D> all = case_fibers<D>(c, wall_owner_, placement_);
  const FiberSettings& f = *c.fibers;
  dt_ = all.stable_dt();
  box_.lo = box_.hi = all.walls.front().point;
  for (const DemWall<D>& w : all.walls) {
    box_.lo = box_.lo.cwiseMin(w.point).cwiseMin(w.end);
    box_.hi = box_.hi.cwiseMax(w.point).cwiseMax(w.end);
  }
  // The cells cover the mold and the health check's margin around it.
  const double margin = 0.1 * (box_.hi - box_.lo).maxCoeff();
  const Box<D> cells{box_.lo.array() - margin, box_.hi.array() + margin};
  const double r = 0.5 * f.diameter;
  dec_ = std::make_unique<Decomposition<D>>(comm, cells, std::array<bool, 3>{false, false, false},
                                            DemDomain<D>::reach(r, r));
  std::vector<std::int64_t> work(static_cast<std::size_t>(dec_->grid().cells()), 0);
  for (std::size_t i = 0; i < all.particles.n_owned; ++i)
    ++work[static_cast<std::size_t>(dec_->grid().cell_of(all.particles.x[i]))];
  dec_->partition(work, true);
  dem_ = std::make_unique<DemDomain<D>>(*dec_, all.params, all.walls, std::move(all.particles));
}

template <int D>
DemRun<D>::~DemRun() = default;

template <int D>
void DemRun<D>::do_step() {
  double dt = dt_;
  const double to_end = case_.numerics.end_time - time_;
  if (to_end > 0 && to_end < dt) dt = to_end;
  // Rigid translation at the table's mid-step velocity: exact within a
  // segment of the piecewise-linear table.
  std::vector<DemWall<D>>& walls = dem_->walls();
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const int w = wall_owner_[k];
    if (w >= 0)
      walls[k].velocity =
          to_vec<D>(motions_[static_cast<std::size_t>(w)].velocity(time_ + 0.5 * dt));
  }
  dem_->advance(1, dt);
  time_ += dt;
  ++step_;
}

// A fiber through a wall (a step too large for an impact) ends the run.
template <int D>
void DemRun<D>::check_health() const {
  const DemParticles<D>& ps = dem_->particles();
  const double margin = 0.1 * (box_.hi - box_.lo).maxCoeff();
  std::string error;
  for (std::size_t i = 0; i < ps.n_owned && error.empty(); ++i) {
    const Vec<D>& x = ps.x[i];
    if (!x.allFinite() || (x.array() < box_.lo.array() - margin).any() ||
        (x.array() > box_.hi.array() + margin).any()) {
      error = fmt::format("step {} (t = {:.6g} s): DEM particle {} (fiber {}) left the mold", step_,
                          time_, ps.gid[i], ps.fiber[i]);
    }
  }
  // Every rank stops together; the lowest rank with a problem names it.
  const int bad = static_cast<int>(
      comm_.min(static_cast<std::int64_t>(error.empty() ? comm_.size() : comm_.rank())));
  if (bad < comm_.size()) {
    throw CollectiveSimulationError(bad == comm_.rank()
                                        ? error
                                        : fmt::format("step {}: a DEM particle on rank {} "
                                                      "left the mold",
                                                      step_, bad));
  }
}

template <int D>
void DemRun<D>::advance(std::int64_t n) {
  for (std::int64_t s = 0; s < n; ++s) do_step();
  check_health();
}

template <int D>
std::string DemRun<D>::write_snapshot() {
  if (!writer_) {
    std::filesystem::create_directories(opt_.output_dir);
    writer_ = std::make_unique<SnapshotWriter>(comm_, opt_.output_dir, case_.name);
    if (comm_.root())
      std::ofstream(std::filesystem::path(opt_.output_dir) / "case.yaml") << case_.source_text;
  }
  dem_->store_state();
  const DemSnapshotBuffers<D> buf(dem_->particles(), comm_);
  ++snapshots_;
  last_snapshot_step_ = step_;
  return writer_->write(step_, time_, {buf.view()});
}

template <int D>
void DemRun<D>::report_progress(double elapsed, std::int64_t steps_done, bool force) const {
  if (!opt_.log || !comm_.root()) return;
  const int every = case_.output.progress_every;
  if (!force && (every <= 0 || step_ % every != 0)) return;
  const double n = static_cast<double>(dem_->global_count());
  const double rate = elapsed > 0 ? n * static_cast<double>(steps_done) / elapsed : 0;
  const double remaining_sim = std::max(0.0, case_.numerics.end_time - time_);
  const double sim_per_wall = elapsed > 0 ? time_ / elapsed : 0;
  const double eta = sim_per_wall > 0 ? remaining_sim / sim_per_wall : 0;
  std::string wall_info;
  for (std::size_t k = 0; k < dem_->walls().size() && wall_info.empty(); ++k) {
    if (wall_owner_[k] < 0) continue;
    const WallMotion& m = motions_[static_cast<std::size_t>(wall_owner_[k])];
    wall_info = fmt::format("  {} v={:.3g} m/s", m.name, dem_->walls()[k].velocity.norm());
  }
  *opt_.log << fmt::format(
                   "step {:>8}  t={:.4e} s  dt={:.3e} s (dem)  {:.3g} particle-steps/s  "
                   "ETA {:02d}:{:02d}:{:02d}{}\n",
                   step_, time_, dt_, rate, static_cast<int>(eta / 3600),
                   static_cast<int>(eta / 60) % 60, static_cast<int>(eta) % 60, wall_info)
            << std::flush;
}

template <int D>
RunSummary DemRun<D>::run() {
  return drive_run(*this, dem_->global_count(), [this](bool final) {
    if (final || step_ % 100 == 0) check_health();
  });
}

template DemSystem<2> case_fibers<2>(const Case&, std::vector<int>&, FiberPlacement&);
template DemSystem<3> case_fibers<3>(const Case&, std::vector<int>&, FiberPlacement&);
template class DemRun<2>;
template class DemRun<3>;

}  // namespace sphdem
