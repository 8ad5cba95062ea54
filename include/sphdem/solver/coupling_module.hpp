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
  void rates() override;

  // Per owned resin particle: the void fraction of the last pass.
  const std::vector<double>& resin_void_fraction() const { return resin_eps_; }
  // Momentum check of the last pass, over all ranks: |sum of the drags +
  // sum of the reactions| / sum of |drag| (0 without drag).
  double momentum_residual() const { return momentum_residual_; }
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
};

}  // namespace sphdem
