// Decomposed DEM sub-stepping (dem_domain.hpp).
#include "sphdem/dem_domain.hpp"

#include <algorithm>
#include <limits>

namespace sphdem {

template <int D>
DemDomain<D>::DemDomain(const Decomposition<D>& dec, const DemParams<D>& params,
                        std::vector<DemWall<D>> walls, DemParticles<D> all, double halo_range)
    : dec_(dec), params_(params), walls_(std::move(walls)), ps_(std::move(all)) {
  double r_max = 0, r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    r_max = std::max(r_max, ps_.radius[i]);
    r_min = std::min(r_min, ps_.radius[i]);
  }
  n_global_ = static_cast<std::int64_t>(ps_.n_owned);
  ws_.skin = ps_.n_owned > 0 ? skin(r_min) : 0;
  range_ = std::max(halo_range, ps_.n_owned > 0 ? reach(r_min, r_max) : 0.0);
  dec_.keep_owned(ps_);
  rebuild();
}

template <int D>
void DemDomain<D>::rebuild() {
  store_state();
  migrate<D>(dec_, ps_);
  halo_.build(dec_, ps_, range_);
  dem_build_pairs(params_, ps_, ws_);
  ++rebuilds_;
}

template <int D>
void DemDomain<D>::advance(std::int64_t n, double dt) {
  const Comm& comm = dec_.comm();
  if (!ws_.forces_valid) dem_force_kick(params_, 0.0, walls_, ps_, ws_);
  const double limit2 = 0.25 * ws_.skin * ws_.skin;
  for (std::int64_t s = 0; s < n; ++s) {
    dem_kick_drift(dt, walls_, ps_);
    // One small collective per sub-step: every rank rebuilds at the same
    // sub-step, whatever the rank count.
    if (comm.max(dem_max_displacement2(ps_, ws_)) > limit2) {
      rebuild();
    } else {
      halo_.update_state(ps_);
    }
    dem_force_kick(params_, dt, walls_, ps_, ws_);
  }
}

template <int D>
double DemDomain<D>::stable_dt() const {
  return dec_.comm().min(stable_dem_dt(params_, ps_));
}

template class DemDomain<2>;
template class DemDomain<3>;

}  // namespace sphdem
