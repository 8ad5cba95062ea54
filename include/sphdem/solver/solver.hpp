#pragma once
// A run with resin (run.hpp): the case's resin, with its fibers and their
// coupling when the case has `fibers:`. Run<D> with the accessors of the
// resin's modules (tests, benchmarks, the command line).
#include <cstdint>
#include <vector>

#include "sphdem/solver/coupling_module.hpp"
#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/resin_module.hpp"
#include "sphdem/solver/run.hpp"

namespace sphdem {

template <int D>
class Simulation : public Run<D> {
 public:
  // std::invalid_argument for a case without `fill:` (DemRun runs those).
  Simulation(const Case& c, const Comm& comm, RunOptions opt = {});

  const SphParticles<D>& particles() const { return this->resin()->particles(); }
  SphParticles<D>& particles() { return this->resin()->particles(); }
  std::int64_t global_fluid_count() const { return this->resin()->global_fluid_count(); }
  std::int64_t global_wall_count() const { return this->resin()->global_wall_count(); }
  const Box<D>& domain() const { return this->resin()->domain(); }
  double last_imbalance() const { return this->resin()->last_imbalance(); }
  std::int64_t repartitions() const { return this->resin()->repartitions(); }
  const Decomposition<D>& decomposition() const { return this->resin()->decomposition(); }
  // Collective, with output.front_events: weld lines since the last call
  // and the trapped-air pockets now (ResinModule::collect_front_events).
  std::vector<FrontEvent> front_events() { return this->resin()->collect_front_events(); }
  // The fibers of a coupled case (null without `fibers:`), docs/physics.md.
  const DemDomain<D>* dem() const { return this->fibers() ? &this->fibers()->dem() : nullptr; }
  const FiberPlacement& placement() const;
  double dem_dt() const { return this->fibers() ? this->fibers()->dem_dt() : 0.0; }
  // In the last resin step.
  std::int64_t dem_substeps() const { return this->fibers() ? this->fibers()->substeps() : 0; }
  // Per owned particle: the void fraction of the last coupling pass.
  const std::vector<double>& resin_void_fraction() const;
  // Momentum check of the last coupling pass (CouplingModule).
  double coupling_momentum_residual() const {
    return this->coupling() ? this->coupling()->momentum_residual() : 0.0;
  }
};

}  // namespace sphdem
