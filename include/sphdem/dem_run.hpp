#pragma once
// A DEM-only run (a case with `fibers:` and no `fill:`, docs/dem.md): the
// fibers of the case in the mold, whose boundary is DEM walls (segments in
// 2D, rectangles in 3D) and whose moving walls (the piston) are moving
// walls, stepped with velocity Verlet at the stable DEM step.
//
// Ranks: the fibers are decomposed over the mold's bounding box with METIS
// weighted by the DEM particles per cell (DemDomain); results are bitwise
// the same on any number of ranks.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sphdem/case.hpp"
#include "sphdem/comm.hpp"
#include "sphdem/decomposition.hpp"
#include "sphdem/dem_domain.hpp"
#include "sphdem/dem_fibers.hpp"
#include "sphdem/solver.hpp"
#include "sphdem/walls.hpp"

namespace sphdem {

// The DEM walls of a case (src/solver/dem_walls.cpp): the parts of the
// mold shapes' edges (2D segments) or faces (3D rectangles, a mold of
// boxes) on the boundary of their union (fixed), then the edges or faces of
// each moving wall's region that touch the cavity (moving). In wall_owner,
// -1 for a fixed wall, else the moving wall's index. InputError naming
// moving_walls[i].region when a moving wall touches no part of the mold.
template <int D>
std::vector<DemWall<D>> dem_walls_from_case(const Case& c, std::vector<int>& wall_owner);

// The case's fibers, placed (every rank the same), with the walls and the
// parameters of the case. InputError naming fibers.count or
// fibers.area_fraction when they do not fit.
template <int D>
DemSystem<D> case_fibers(const Case& c, std::vector<int>& wall_owner, FiberPlacement& placement);

template <int D>
class DemRun {
 public:
  // Places the fibers (InputError naming fibers.count or
  // fibers.area_fraction when they do not fit).
  DemRun(const Case& c, const Comm& comm, RunOptions opt = {});
  ~DemRun();

  // Runs to end_time (or max_steps), writing output on its cadence.
  RunSummary run();
  // Advances exactly n steps without output.
  void advance(std::int64_t n);
  std::string write_snapshot();  // collective
  // Checkpoints (docs/checkpoint.md, src/solver/dem_run_checkpoint.cpp),
  // as Simulation's: collective; a refused checkpoint (InputError on every
  // rank) leaves the state untouched.
  std::string write_checkpoint();
  std::string restart_from(const std::string& checkpoint);  // a path or "latest"

  const DemDomain<D>& dem() const { return *dem_; }
  DemDomain<D>& dem() { return *dem_; }
  const FiberPlacement& placement() const { return placement_; }
  double dt() const { return dt_; }
  std::int64_t step() const { return step_; }
  double time() const { return time_; }

 private:
  template <class Driver, class Checks>
  friend RunSummary drive_run(Driver& d, std::int64_t particles, Checks checks);  // run_loop.hpp
  void do_step();
  void check_health() const;
  void report_progress(double elapsed, std::int64_t steps_done, bool force) const;

  Case case_;
  const Comm& comm_;
  RunOptions opt_;
  FiberPlacement placement_;
  Box<D> box_;  // the mold's bounding box, for the health check and the cells
  std::unique_ptr<Decomposition<D>> dec_;
  std::unique_ptr<DemDomain<D>> dem_;
  std::vector<WallMotion> motions_;
  std::vector<int> wall_owner_;  // per DEM wall: moving wall index or -1
  std::unique_ptr<SnapshotWriter> writer_;
  double dt_ = 0, time_ = 0;
  std::int64_t step_ = 0, snapshots_ = 0, last_snapshot_step_ = -1;
  void load_checkpoint(const std::string& path);
  bool restarted_ = false;  // the state came from a checkpoint
  std::int64_t last_checkpoint_step_ = -1;
  std::string last_checkpoint_;
};

}  // namespace sphdem
