#pragma once
// The resin of a run (run.hpp): weakly compressible SPH particles and the
// mold's wall particles, on a decomposition of the mold (docs/parallel.md),
// stepped with kick-drift-kick leapfrog (second order), the rates at the
// end of the step evaluated on predicted velocity and density:
//   v_h = v + dt/2 a,  rho_h = rho + dt/2 drho,  x += dt v_h
//   rates(x, v_h + dt/2 a, rho_h + dt/2 drho) -> a', drho'
//   v = v_h + dt/2 a',  rho = rho_h + dt/2 drho'
// Only one neighbor pass per step (plus the wall extrapolation). Its
// decomposition also carries the fibers of a coupled run.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/neighbor/support_lists.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/halo.hpp"
#include "sphdem/parallel/ordered_sum.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/solver/run.hpp"
#include "sphdem/sph/front_events.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
class ResinModule final : public Module<D> {
 public:
  // Builds, partitions and lists the case's particles (collective).
  explicit ResinModule(const RunContext<D>& ctx);

  const char* name() const override { return "resin"; }
  std::int64_t counted_particles() const override { return n_fluid_global_; }
  std::optional<TimeStep> stable_dt() override;
  void predict(double dt) override;
  bool moved() override;
  void rebuild(bool restart) override;
  void rates() override;
  void correct(double dt) override;
  void check_health(std::string& problem) const override;
  void snapshot(SnapshotParts& parts) override;
  void progress(std::string& line) const override;
  void write_checkpoint(CheckpointWriter& w) override;
  std::function<void()> read_checkpoint(CheckpointReader& r, const std::string& path) override;
  void restarted() override;

  const SphParticles<D>& particles() const { return ps_; }
  SphParticles<D>& particles() { return ps_; }
  std::int64_t global_fluid_count() const { return n_fluid_global_; }
  std::int64_t global_wall_count() const { return n_wall_global_; }
  const Box<D>& domain() const { return domain_; }
  double neighbor_cutoff() const { return nl_.cutoff(); }
  double neighbor_skin() const { return nl_.skin(); }
  std::int64_t neighbor_builds() const { return nl_.builds(); }
  std::int64_t support_cuts() const { return support_.cuts(); }         // 3D: SupportLists
  std::size_t neighbor_pairs() const { return nl_.total_pairs(); }      // this rank's lists
  std::size_t neighbor_wide_pairs() const { return nl_.wide_pairs(); }  // of those, 32-bit
  // Load balance (docs/parallel.md): the imbalance (max / mean - 1 of the
  // per-rank work) at the last check, and how many re-partitions happened.
  double last_imbalance() const { return last_imbalance_; }
  std::int64_t repartitions() const { return repartitions_; }
  // The weights of a re-partition: the work per block of this rank's
  // particles, the resin's and walls' (Decomposition::cell_work) plus the
  // other modules' on this decomposition (a coupled run's fibers,
  // add_fiber_work). The first partition and a restart's weigh the resin
  // and walls only (docs/parallel.md, "Which weights, when").
  std::vector<std::int64_t> cell_work() const;
  // Conjugate-gradient iterations of the last implicit viscous solve.
  int viscous_iterations() const { return cg_iterations_; }
  const Decomposition<D>& decomposition() const { return dec_; }
  // Collective (output.front_events): the weld-line events since the last
  // call, by time then particle id, and (pockets) the trapped-air pockets
  // now; the same list on every rank at every rank count. Snapshots (with
  // pockets) and checkpoints (without) append it to
  // <output>/<case>_front_events.csv.
  std::vector<FrontEvent> collect_front_events(bool pockets = true);

 private:
  void maybe_rebalance();
  // parallel.balance_weight: time: this rank's busy seconds (wall time less
  // the idle phases, PhaseTimers::idle) since the last call, which starts
  // the next interval.
  double busy_since_last_check();
  std::vector<double> face_means(const std::vector<WallFaceSample>& face);
  void set_wall_velocities(double t);
  void write_front_events(bool pockets);
  void solve_viscosity(double dt);

  const RunContext<D>& ctx_;
  const Case& case_;
  const Comm& comm_;
  PhaseTimers& timers_;
  std::vector<WallMotion>& walls_;
  SphParams sp_;
  TaitEos eos_;
  Box<D> domain_;
  SphParticles<D> ps_;
  NeighborList<D> nl_;
  // In 3D, nl_ cut to the support for each step's sums (support_lists.hpp).
  SupportLists<D> support_;
  Halo<D> halo_;
  std::int64_t n_fluid_global_ = 0, n_wall_global_ = 0;
  Decomposition<D> dec_;
  std::int64_t last_balance_step_ = 0;
  double last_imbalance_ = 0;
  std::int64_t repartitions_ = 0;
  // Where the busy interval of the next check starts (busy_since_last_check).
  std::chrono::steady_clock::time_point balance_clock_ = std::chrono::steady_clock::now();
  double balance_idle_ = 0;
  bool pressure_series_started_ = false;  // the injection pressure CSV of this run
  std::size_t face_capacity_ = 0;         // face terms per rank gathered in one call (face_means)
  // Weld lines flagged since the last collect_front_events: per particle
  // (order = id) the time (key 0) and the position (keys 1..D).
  std::vector<OrderedTerm> weld_events_;
  bool front_series_started_ = false;  // the front events CSV of this run
  int cg_iterations_ = 0;              // of the last implicit viscous solve
  // Two checks that ride on the passes of the kicks (docs/performance.md,
  // "The streaming passes"): the drift's rebuild verdict for moved(), and
  // the second kick's maxima for the next stable_dt, with the owned count
  // they cover. Empty: moved() and stable_dt() run their own pass.
  std::optional<bool> moved_at_drift_;
  // With it (AVX-512, a run without fibers), the drift's box of all moves.
  std::optional<typename NeighborList<D>::MoveBox> box_at_drift_;
  struct KickExtremes {
    LocalExtremes maxima;
    std::size_t n_owned;
  };
  std::optional<KickExtremes> extremes_at_kick_;
};

}  // namespace sphdem
