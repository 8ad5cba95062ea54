// The fibers' part of a checkpoint and its restart (docs/checkpoint.md),
// alone or coupled: the DEM particles and walls (dem_checkpoint.hpp), and
// for coupled fibers the step whose drag impulse the next coupling pass
// returns and the sub-step count of the work estimate.
#include <limits>
#include <memory>

#include "dem_checkpoint.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/solver/fiber_module.hpp"

namespace sphdem {

template <int D>
void FiberModule<D>::write_checkpoint(CheckpointWriter& w) {
  write_dem_checkpoint(w, *dem_);
  if (!coupled()) return;
  w.attribute("coupled_dt", coupled_dt_);
  w.attribute("dem_substeps", substeps_);
}

// Each rank reads its slice of the fibers' rows (never the whole set); the
// commit makes a new domain of them on the decomposition as it is then (a
// coupled run's resin re-partitions first), one migration taking each
// particle to its owner.
template <int D>
std::function<void()> FiberModule<D>::read_checkpoint(CheckpointReader& r,
                                                      const std::string& path) {
  auto fibers = std::make_shared<DemCheckpoint<D>>(read_dem_checkpoint(r, *dem_, path));
  double coupled_dt = 0;
  std::int64_t substeps = 0;
  if (coupled()) {
    coupled_dt = r.real_in("coupled_dt", 0, std::numeric_limits<double>::max());
    substeps = r.integer_in("dem_substeps", 0, std::numeric_limits<std::int64_t>::max() / 2);
  }
  return [this, fibers, coupled_dt, substeps] {
    restore_dem(dem_, coupled() ? host_->dec : *own_dec_, std::move(*fibers));
    coupled_dt_ = coupled_dt;
    substeps_ = substeps;
  };
}

template void FiberModule<2>::write_checkpoint(CheckpointWriter&);
template void FiberModule<3>::write_checkpoint(CheckpointWriter&);
template std::function<void()> FiberModule<2>::read_checkpoint(CheckpointReader&,
                                                               const std::string&);
template std::function<void()> FiberModule<3>::read_checkpoint(CheckpointReader&,
                                                               const std::string&);

}  // namespace sphdem
