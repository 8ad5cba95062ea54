#pragma once
// The coupling of a run with resin and fibers (run.hpp, docs/physics.md
// "Coupling"): after the resin's rates, the drag on the fibers, then its
// reaction on the resin (coupling_loops.hpp), with the void fraction of
// the fibers in the resin's continuity equation when the case asks.
#include <vector>

#include "sphdem/coupling/coupling_loops.hpp"
#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/resin_module.hpp"
#include "sphdem/solver/run.hpp"

namespace sphdem {

template <int D>
class CouplingModule final : public Module<D> {
 public:
  CouplingModule(const RunContext<D>& ctx, ResinModule<D>& resin, FiberModule<D>& fibers);

  const char* name() const override { return "coupling"; }
  // The resin's side of the drag exchange is explicit: the step is kept
  // below kResinDragStep / (the largest resin drag rate of the last pass),
  // docs/physics.md "The stable window".
  std::optional<TimeStep> stable_dt() override;
  // The particles were reordered: the coupling pairs are searched afresh.
  void rebuild(bool restart) override;
  void rates() override;
  void write_checkpoint(CheckpointWriter& w) override;
  std::function<void()> read_checkpoint(CheckpointReader& r, const std::string& path) override;

  // Per owned resin particle: the void fraction of the last pass.
  const std::vector<double>& resin_void_fraction() const { return resin_eps_; }
  // Momentum check of the last pass, over all ranks: |sum of the drags +
  // sum of the reactions| / sum of |drag| (0 without drag).
  double momentum_residual() const { return momentum_residual_; }
  // Over all ranks, the largest sum_f (V_r W_fr / S_f) K_f V_f / m_r of the
  // last pass [1/s] (coupling_loops.hpp).
  double resin_drag_rate() const { return resin_drag_rate_; }
  // Over all ranks, the smallest m_f / (K_f V_f) of the last pass [s]
  // (0 without drag): the fibers' drag time.
  double fiber_drag_time() const { return fiber_drag_time_; }
  // The per-DEM-particle results (owned first).
  const CouplingState<D>& state() const { return cstate_; }

 private:
  const RunContext<D>& ctx_;
  ResinModule<D>& resin_;
  FiberModule<D>& fibers_;
  CouplingSettings coupling_;
  CouplingState<D> cstate_;
  std::vector<double> resin_eps_;
  double momentum_residual_ = 0;
  double resin_drag_rate_ = 0;
  double fiber_drag_time_ = 0;
};

// dt * (resin drag rate) below which the explicit reaction on the resin
// stays stable (measured on the shear cell of tests/test_coupled_window.cpp,
// docs/physics.md "The stable window").
inline constexpr double kResinDragStep = 1.0;

}  // namespace sphdem
