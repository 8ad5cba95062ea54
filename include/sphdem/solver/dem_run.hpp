#pragma once
// A fibers-only run (a case with `fibers:` and no `fill:`, docs/dem.md):
// Run<D> without the resin, with the accessors of its fiber module.
#include <cstdint>

#include "sphdem/solver/fiber_module.hpp"
#include "sphdem/solver/run.hpp"

namespace sphdem {

template <int D>
class DemRun : public Run<D> {
 public:
  // std::invalid_argument for a case without `fibers:` or with `fill:`;
  // InputError naming fibers.count or fibers.area_fraction when the fibers
  // do not fit.
  DemRun(const Case& c, const Comm& comm, RunOptions opt = {});

  const DemDomain<D>& dem() const { return this->fibers()->dem(); }
  DemDomain<D>& dem() { return this->fibers()->dem(); }
  const FiberPlacement& placement() const { return this->fibers()->placement(); }
  double dt() const { return this->fibers()->dem_dt(); }  // the stable DEM step
};

}  // namespace sphdem
