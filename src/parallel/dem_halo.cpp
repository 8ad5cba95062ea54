// DEM ghost plan and the per-step forward exchanges (docs/parallel.md).
#include "sphdem/parallel/dem_halo.hpp"

#include "exchange.hpp"
#include "ghost_fields.hpp"
#include "ghost_targets.hpp"

namespace sphdem {

template <int D>
void DemHalo<D>::build(const Decomposition<D>& dec, DemParticles<D>& ps, double range) {
  comm_ = dec.comm().raw();
  bool periodic = false;
  for (int k = 0; k < D; ++k) periodic = periodic || dec.grid().periodic(k);
  if (dec.comm().size() == 1 && !periodic) {
    // No other rank and no periodic image: no ghosts (skips a walk over
    // the neighbor cells of every particle).
    ps.clear_ghosts();
    plan_ = GhostPlan<D>{};
    return;
  }
  detail::build_ghosts<D>(dec, ps, range, plan_, send_buf_, recv_buf_);
}

template <int D>
void DemHalo<D>::forward(DemParticles<D>& ps, DemGroup group) {
  detail::forward_groups<D>(comm_, plan_, ps, group_bit(group), send_buf_, recv_buf_);
}

template <int D>
double DemHalo<D>::forward_max(DemParticles<D>& ps, DemGroup group, double value) {
  detail::forward_groups<D>(comm_, plan_, ps, group_bit(group), send_buf_, recv_buf_, &value);
  return value;
}

template class DemHalo<2>;
template class DemHalo<3>;

}  // namespace sphdem
