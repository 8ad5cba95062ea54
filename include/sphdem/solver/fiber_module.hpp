#pragma once
// The fibers of a run (run.hpp, docs/dem.md): the case's fibers as bonded
// DEM particles in the mold, whose boundary is DEM walls (segments in 2D,
// rectangles in 3D) and whose moving walls (the piston) move, decomposed
// over the ranks (DemDomain; bitwise the same on any number of ranks).
//  - Alone (no resin): on their own decomposition of the mold's bounding
//    box, weighted by the DEM particles per cell; one velocity-Verlet step
//    of the stable DEM step per run step.
//  - Coupled: on the resin's decomposition, their ghosts as far as the SPH
//    kernel reaches; DEM sub-steps over each resin step, the drag of the
//    last coupling pass held.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/dem/dem_fibers.hpp"
#include "sphdem/geometry/mold_walls.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/solver/dem_domain.hpp"
#include "sphdem/solver/run.hpp"

namespace sphdem {

// The case's fibers, placed (all of them, or a rank's share), with the walls
// and the parameters of the case. InputError naming fibers.count or
// fibers.area_fraction when they do not fit.
template <int D>
DemSystem<D> case_fibers(const Case& c, std::vector<int>& wall_owner, FiberPlacement& placement,
                         const FiberShare<D>* share = nullptr);

// Where coupled fibers live: the resin's decomposition, the mold box they
// must stay in, how far their ghosts reach (the resin's cut-off) and the
// largest skin their lists may have (coupled_skins.hpp).
template <int D>
struct FiberHost {
  const Decomposition<D>& dec;
  Box<D> domain;
  double halo_range;
  double skin_limit;
};

// A DEM sub-step of a coupled run is at most this times the fibers' drag
// time (explicit drag: stable below 2; docs/physics.md "The stable window").
inline constexpr double kFiberDragStep = 1.0;

// With implicit bonds, the farthest two particles of a fiber can be apart:
// its straight length between end centres, 10 % stretched (a bond breaks
// long before; glass at 3.5 %); 0 otherwise. The DEM halo and the cells of
// the decomposition the fibers run on are at least this (docs/dem.md,
// "Implicit bonds").
double implicit_chain_reach(const Case& c);

// The load-balance work of coupled fibers (docs/parallel.md, "Which
// weights, when"): each fiber particle costs its DEM sub-steps per resin step
// (at least 1) at kDemSubstepWork each, a DEM particle-step being about
// half a resin particle-step (measured on the plate: 3 pairs against 20
// neighbours). add_fiber_work adds that to the block of `dec` each
// of the first n particles of `f` lies in: a coupled run's share of
// ResinModule::cell_work (FiberModule::add_cell_work), and what `sphdem
// partition --fiber-substeps` weighs the placed fibers with.
inline constexpr std::int64_t kDemSubstepWork = kFluidWork / 2;
inline std::int64_t fiber_particle_work(std::int64_t substeps) {
  return kDemSubstepWork * std::max<std::int64_t>(substeps, 1);
}
template <int D>
void add_fiber_work(const Decomposition<D>& dec, const DemParticles<D>& f, std::size_t n,
                    std::int64_t substeps, std::vector<std::int64_t>& work);

template <int D>
class FiberModule final : public Module<D> {
 public:
  // Places the fibers (InputError naming fibers.count or
  // fibers.area_fraction when they do not fit). host: null for fibers
  // alone. Collective.
  FiberModule(const RunContext<D>& ctx, const FiberHost<D>* host);
  ~FiberModule() override;

  const char* name() const override { return "fibers"; }
  std::int64_t counted_particles() const override;
  std::optional<TimeStep> stable_dt() override;
  void predict(double dt) override;
  void rebuild(bool restart) override;
  void substep(double dt) override;
  void check_health(std::string& problem) const override;
  void add_cell_work(const Decomposition<D>& dec, std::vector<std::int64_t>& work) const override;
  void snapshot(SnapshotParts& parts) override;
  void progress(std::string& line) const override;
  void write_checkpoint(CheckpointWriter& w) override;
  std::function<void()> read_checkpoint(CheckpointReader& r, const std::string& path) override;

  bool coupled() const { return host_.has_value(); }
  const DemDomain<D>& dem() const { return *dem_; }
  DemDomain<D>& dem() { return *dem_; }
  const FiberPlacement& placement() const { return placement_; }
  double dem_dt() const { return dem_dt_; }  // the stable DEM step
  // The bonds' stable step: dem_dt() when explicit, the inner step when
  // the bonds are sub-cycled (docs/dem.md, "Bond sub-cycling").
  double bond_dt() const { return bond_dt_; }
  // Coupled: the sub-steps of the last resin step, and that step (whose
  // drag impulse the next coupling pass returns).
  std::int64_t substeps() const { return substeps_; }
  double coupled_dt() const { return coupled_dt_; }
  // Coupled: the sub-steps also stay below the fibers' drag time m_f/(K V_f)
  // (the drag is explicit in the particle's velocity; docs/physics.md "The
  // stable window"). Set by the coupling pass; 0: no limit.
  void limit_substep(double drag_time) { drag_time_ = drag_time; }

 private:
  // The DEM walls of moving walls at the motions' velocity at time t.
  void move_walls(double t);

  const RunContext<D>& ctx_;
  std::optional<FiberHost<D>> host_;
  FiberPlacement placement_;
  std::vector<int> wall_owner_;                // per DEM wall: moving wall index or -1
  Box<D> health_box_;                          // a fiber particle outside it ends the run
  std::unique_ptr<Decomposition<D>> own_dec_;  // alone: the fibers' own cells
  std::unique_ptr<DemDomain<D>> dem_;
  double dem_dt_ = 0, bond_dt_ = 0;
  std::int64_t substeps_ = 0;
  double coupled_dt_ = 0;
  double drag_time_ = 0;
};

}  // namespace sphdem
