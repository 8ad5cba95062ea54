// Decomposed DEM sub-stepping (dem_domain.hpp).
#include "sphdem/solver/dem_domain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sphdem/dem/dem_profile.hpp"

namespace sphdem {

template <int D>
DemDomain<D>::DemDomain(const Decomposition<D>& dec, const DemParams<D>& params,
                        std::vector<DemWall<D>> walls, DemParticles<D> particles, double halo_range,
                        Input input, double skin_limit)
    : dec_(dec), params_(params), walls_(std::move(walls)), ps_(std::move(particles)) {
  const Comm& comm = dec_.comm();
  double r_max = 0, r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ps_.n_owned; ++i) {
    r_max = std::max(r_max, ps_.radius[i]);
    r_min = std::min(r_min, ps_.radius[i]);
  }
  // Exact reductions: every rank gets the same radii, skin and range.
  r_max = comm.max(r_max);
  r_min = comm.min(r_min);
  n_global_ = static_cast<std::int64_t>(ps_.n_owned);
  if (input == Input::Share) n_global_ = comm.sum(n_global_);
  // The skin: at least skin(r_min); more when the decomposition's cells
  // leave room beyond 2 R_max (the halo must stay within one cell), up to
  // params.max_skin r_min. A wider skin means fewer rebuilds (each one a
  // migration, a ghost build and a pair-list build) for a few more
  // candidate pairs. The grid is the same on every rank, so is the skin;
  // the results do not depend on it (the list is complete either way).
  // A coupled run caps it (skin_limit): how far a fiber strays from its
  // rank's cells bounds what the coupling's ghosts must cover
  // (coupled_skins.hpp).
  double s = skin(r_min);
  if (n_global_ > 0) {
    double cell = std::numeric_limits<double>::infinity();
    for (int k = 0; k < D; ++k) cell = std::min(cell, dec_.grid().size(k));
    s = std::max(s, std::min(cell - 2.0 * r_max, params_.max_skin * r_min));
  }
  // A cap of 0 (a resin without a skin) leaves the smallest positive skin:
  // every move rebuilds, as the resin's lists do (a skin of 0 would mean
  // dem_build_pairs' default, a quarter of R_min).
  s = std::min(s, skin_limit);
  if (!(s > 0)) s = std::numeric_limits<double>::min();
  ws_.skin = n_global_ > 0 ? s : 0;
  range_ = std::max(halo_range, n_global_ > 0 ? 2.0 * r_max + s : 0.0);
  // Implicit bonds solve each fiber whole: every rank that owns a particle
  // of a fiber needs the others, at most chain_reach away. The halo reaches
  // one cell, so the drivers make the cells that large (chain_cell_size).
  if (params_.implicit_bonds) {
    range_ = std::max(range_, params_.chain_reach);
    for (int k = 0; k < D; ++k) {
      if (dec_.grid().size(k) < range_) {
        throw std::logic_error(
            fmt::format("DEM halo of {} m wider than the decomposition's cells ({} m)", range_,
                        dec_.grid().size(k)));
      }
    }
  }
  if (input == Input::Replicated) {
    dec_.keep_owned(ps_);
  } else if (comm.size() > 1) {
    std::array<bool, 3> periodic{false, false, false};
    for (int k = 0; k < D; ++k) periodic[static_cast<std::size_t>(k)] = dec_.grid().periodic(k);
    wrap_periodic<D>(ps_, dec_.grid().box(), periodic);
    migrate<D>(dec_, ps_);
    // Arrivals come by source rank: back to gid order, as keep_owned
    // leaves the generator's (or a whole checkpoint's) particles.
    std::vector<std::size_t> order(ps_.n_owned);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return ps_.gid[a] < ps_.gid[b]; });
    ps_.permute_owned(order);
  }
  rebuild();
}

template <int D>
void DemDomain<D>::rebuild() {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().rebuild);
  store_state();
  // A periodic resin's fibers cross its periodic faces (shear cells).
  std::array<bool, 3> periodic{false, false, false};
  for (int k = 0; k < D; ++k) periodic[static_cast<std::size_t>(k)] = dec_.grid().periodic(k);
  wrap_periodic<D>(ps_, dec_.grid().box(), periodic);
  // One rank: migration would keep every particle in its order (a copy of
  // every field); dropping the ghosts is all it does.
  // Several: only the particles that change rank are copied (every DEM sum
  // runs in gid order, so the local order does not matter).
  dem_detail::DemTimer t_migrate(dem_detail::dem_profile().rebuild_migrate);
  if (dec_.comm().size() > 1) {
    migrate_in_place<D>(dec_, ps_);
  } else {
    ps_.clear_ghosts();
  }
  t_migrate.stop();
  dem_detail::DemTimer t_ghosts(dem_detail::dem_profile().rebuild_ghosts);
  halo_.build(dec_, ps_, range_);
  t_ghosts.stop();
  dem_build_pairs(params_, walls_, ps_, ws_);
  ++rebuilds_;
}

template <int D>
void DemDomain<D>::advance(std::int64_t n, double dt) {
  if (params_.subcycle_bonds) {
    advance_subcycled(n, dt);
    return;
  }
  if (!ws_.forces_valid) dem_force_kick(params_, 0.0, walls_, ps_, ws_);
  const double limit2 = 0.25 * ws_.skin * ws_.skin;
  for (std::int64_t s = 0; s < n; ++s) {
    dem_kick_drift(params_, dt, walls_, ps_);
    if (vote_and_forward(limit2, false)) rebuild();
    dem_force_kick(params_, dt, walls_, ps_, ws_);
  }
}

// The ghosts' new state and the rebuild vote in one synchronisation (a
// sub-step's only one): every rank rebuilds at the same sub-step, whatever
// the rank count. A rebuild then replaces the ghosts just updated.
template <int D>
bool DemDomain<D>::vote_and_forward(double limit2, bool force) {
  const dem_detail::DemTimer t_collective(dem_detail::dem_profile().collective);
  const double local =
      force ? std::numeric_limits<double>::infinity() : dem_max_displacement2(ps_, walls_, ws_);
  return halo_.forward_max(ps_, DemGroup::State, local) > limit2;
}

// Bond sub-cycling (docs/dem.md): the ghosts' state travels after every
// inner drift; the rebuild vote only at the outer step (bonded pairs are
// listed whatever their distance, and contacts are evaluated only there).
template <int D>
void DemDomain<D>::advance_subcycled(std::int64_t n, double dt) {
  const double limit2 = 0.25 * ws_.skin * ws_.skin;
  const std::int64_t inner = dem_bond_substeps(params_, dt);
  const auto refresh = [&] {
    const dem_detail::DemTimer t_halo(dem_detail::dem_profile().halo);
    halo_.forward(ps_, DemGroup::State);
  };
  const bool implicit = params_.implicit_bonds;
  const auto settle = [&] {
    // Implicit bonds: a bond that broke here may be in another rank's chain
    // as a ghost's stale copy; a rebuild sends every rank the new slots
    // before the next solve, so all solve the same chain.
    const bool broke = implicit && ws_.bond_broke;
    ws_.bond_broke = false;
    if (vote_and_forward(limit2, broke)) rebuild();
  };
  for (std::int64_t s = 0; s < n; ++s) {
    if (implicit) {
      dem_implicit_step(params_, dt, walls_, ps_, ws_, refresh, settle);
    } else {
      dem_subcycled_step(params_, dt, inner, walls_, ps_, ws_, refresh, settle);
    }
  }
}

template <int D>
double DemDomain<D>::stable_dt() const {
  return dec_.comm().min(stable_dem_dt(params_, ps_));
}

template class DemDomain<2>;
template class DemDomain<3>;

}  // namespace sphdem
