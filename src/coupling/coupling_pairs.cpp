// The coupling passes' candidate pairs (coupling_pairs.hpp): cell lists
// over the resin near the fibers and over the DEM particles, searched once
// per build; candidates sorted by global id.
#include "sphdem/coupling/coupling_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "sphdem/dem/cell_list.hpp"

namespace sphdem {

namespace {

// The bounding box of the DEM particles grown by `margin`: resin farther
// away has no DEM neighbour and is left out of the search.
template <int D>
struct Reach {
  Vec<D> lo, hi;
  Reach(const DemParticles<D>& dem, double margin) {
    lo = Vec<D>::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (std::size_t f = 0; f < dem.size(); ++f) {
      lo = lo.cwiseMin(dem.x[f]);
      hi = hi.cwiseMax(dem.x[f]);
    }
    lo.array() -= margin;
    hi.array() += margin;
  }
  bool contains(const Vec<D>& x) const {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
};

// Appends the candidates `cand` (gid, index), sorted by gid, to `items`.
void append_sorted(std::vector<std::pair<std::int64_t, std::int32_t>>& cand,
                   std::vector<std::int32_t>& items) {
  std::sort(cand.begin(), cand.end());
  for (const auto& c : cand) items.push_back(c.second);
}

template <int D>
void build(CouplingPairs<D>& p, const SphParticles<D>& sph, const DemParticles<D>& dem,
           double support, double skin, std::int64_t generation) {
  const double cutoff = support + skin, cutoff2 = cutoff * cutoff;
  const std::size_t n_dem = dem.size();
  std::vector<std::pair<std::int64_t, std::int32_t>> cand;

  // DEM -> resin, for every DEM particle.
  std::vector<std::int32_t> resin;
  std::vector<Vec<D>> resin_x;
  const Reach<D> reach(dem, cutoff);
  for (std::size_t r = 0; r < sph.size(); ++r) {
    if (sph.kind[r] != Kind::Fluid || !reach.contains(sph.x[r])) continue;
    resin.push_back(static_cast<std::int32_t>(r));
    resin_x.push_back(sph.x[r]);
  }
  std::vector<std::int32_t> start, items;
  dem_detail::CellList<D> resin_cells;
  resin_cells.build(resin_x, resin_x.size(), cutoff, start, items);
  p.resin_start.assign(1, 0);
  p.resin_items.clear();
  for (std::size_t f = 0; f < n_dem; ++f) {
    cand.clear();
    resin_cells.for_each_near(dem.x[f], [&](std::int32_t k) {
      const auto r = static_cast<std::size_t>(resin[static_cast<std::size_t>(k)]);
      if ((dem.x[f] - sph.x[r]).squaredNorm() < cutoff2)
        cand.emplace_back(sph.gid[r], static_cast<std::int32_t>(r));
    });
    append_sorted(cand, p.resin_items);
    p.resin_start.push_back(static_cast<std::int32_t>(p.resin_items.size()));
  }
  // The owned resin in some list gets a slot, in increasing SPH index.
  std::vector<std::int32_t> slot_of(sph.n_owned, -1);
  for (const std::int32_t r : p.resin_items)
    if (static_cast<std::size_t>(r) < sph.n_owned) slot_of[static_cast<std::size_t>(r)] = 0;
  p.slot_resin.clear();
  for (std::size_t r = 0; r < sph.n_owned; ++r) {
    if (slot_of[r] < 0) continue;
    slot_of[r] = static_cast<std::int32_t>(p.slot_resin.size());
    p.slot_resin.push_back(static_cast<std::int32_t>(r));
  }
  p.resin_slot.resize(p.resin_items.size());
  for (std::size_t k = 0; k < p.resin_items.size(); ++k) {
    const auto r = static_cast<std::size_t>(p.resin_items[k]);
    p.resin_slot[k] = r < sph.n_owned ? slot_of[r] : -1;
  }

  // DEM -> DEM, for the owned ones.
  dem_detail::CellList<D> dem_cells;
  dem_cells.build(dem.x, n_dem, cutoff, start, items);
  p.dem_start.assign(1, 0);
  p.dem_items.clear();
  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    cand.clear();
    dem_cells.for_each_near(dem.x[f], [&](std::int32_t j) {
      const auto ju = static_cast<std::size_t>(j);
      if ((dem.x[f] - dem.x[ju]).squaredNorm() < cutoff2) cand.emplace_back(dem.gid[ju], j);
    });
    append_sorted(cand, p.dem_items);
    p.dem_start.push_back(static_cast<std::int32_t>(p.dem_items.size()));
  }
  p.dem_order.resize(n_dem);
  std::iota(p.dem_order.begin(), p.dem_order.end(), 0);
  std::sort(p.dem_order.begin(), p.dem_order.end(), [&](std::int32_t a, std::int32_t b) {
    return dem.gid[static_cast<std::size_t>(a)] < dem.gid[static_cast<std::size_t>(b)];
  });

  p.resin_x0 = sph.x;
  p.dem_x0 = dem.x;
  p.n_sph = sph.size();
  p.n_sph_owned = sph.n_owned;
  p.n_dem = n_dem;
  p.n_dem_owned = dem.n_owned;
  p.generation = generation;
  p.support = support;
  p.skin = skin;
  p.valid = true;
  ++p.builds;
}

// Whether the list still holds every pair within the support: the same
// particles, and no DEM particle plus resin particle (or two DEM particles)
// moved farther than the skin together.
template <int D>
bool still_complete(const CouplingPairs<D>& p, const SphParticles<D>& sph,
                    const DemParticles<D>& dem, double support, double skin,
                    std::int64_t generation) {
  if (!p.built_for(sph, dem) || p.generation != generation || p.support != support ||
      p.skin != skin)
    return false;
  double dem2 = 0, resin2 = 0;
  for (std::size_t f = 0; f < dem.size(); ++f)
    dem2 = std::max(dem2, (dem.x[f] - p.dem_x0[f]).squaredNorm());
  for (std::size_t r = 0; r < sph.size(); ++r) {
    if (sph.kind[r] == Kind::Fluid)
      resin2 = std::max(resin2, (sph.x[r] - p.resin_x0[r]).squaredNorm());
  }
  const double moved = std::sqrt(dem2) + std::sqrt(std::max(dem2, resin2));
  // A NaN fails the test (and the rebuild's cell list reports it). Nothing
  // moved: the list is exact even without a skin.
  return moved == 0 || moved < skin * (1 - 1e-9);
}

}  // namespace

template <int D>
bool update_coupling_pairs(CouplingPairs<D>& pairs, const SphParticles<D>& sph,
                           const DemParticles<D>& dem, double support, double skin,
                           std::int64_t generation) {
  if (still_complete<D>(pairs, sph, dem, support, skin, generation)) return false;
  build<D>(pairs, sph, dem, support, skin, generation);
  return true;
}

template bool update_coupling_pairs<2>(CouplingPairs<2>&, const SphParticles<2>&,
                                       const DemParticles<2>&, double, double, std::int64_t);
template bool update_coupling_pairs<3>(CouplingPairs<3>&, const SphParticles<3>&,
                                       const DemParticles<3>&, double, double, std::int64_t);

}  // namespace sphdem
