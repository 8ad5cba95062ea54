// The stable DEM step (contacts and bonds) and the DEM energies (kinetic,
// elastic in bonds, contacts and wall contacts).
#include <algorithm>
#include <cmath>
#include <limits>

#include "dem_kernels.hpp"

namespace sphdem {

template <int D>
double stable_dem_dt(const DemParams<D>& p, const DemParticles<D>& ps) {
  const std::size_t n = ps.size();
  std::vector<double> kt(n, p.kn), kr(n, 0.0);
  std::vector<std::int32_t> index;
  std::int64_t gid_max = -1;
  for (std::size_t i = 0; i < n; ++i) gid_max = std::max(gid_max, ps.gid[i]);
  index.assign(static_cast<std::size_t>(gid_max + 1), -1);
  for (std::size_t i = 0; i < n; ++i) index[ps.gid[i]] = static_cast<std::int32_t>(i);
  for (std::size_t i = 0; i < n; ++i) {
    kr[i] += p.kt_over_kn * p.kn * ps.radius[i] * ps.radius[i];
    for (const DemBond<D>& b : ps.bonds[i]) {
      if (b.partner < 0 || b.broken || b.partner > gid_max || index[b.partner] < 0) continue;
      const auto j = static_cast<std::size_t>(index[b.partner]);
      const terms::BondLaw law = bond_law(p, ps.radius[i], ps.radius[j], b.rbar);
      const double ka = std::max(law.kn, law.ks) * law.s.area;
      const double kb = std::max(law.kn * law.s.inertia, law.ks * law.s.polar);
      kt[i] += ka;
      kt[j] += ka;
      // A shear spring at arm R couples the two spins: 2 ks A R^2 each.
      kr[i] += kb + 2.0 * law.ks * law.s.area * ps.radius[i] * ps.radius[i];
      kr[j] += kb + 2.0 * law.ks * law.s.area * ps.radius[j] * ps.radius[j];
    }
  }
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (kt[i] > 0) dt = std::min(dt, std::sqrt(ps.mass[i] / kt[i]));
    if (kr[i] > 0) dt = std::min(dt, std::sqrt(ps.inertia[i] / kr[i]));
  }
  return p.dt_safety * dt;
}

template <int D>
double dem_kinetic_energy(const DemParticles<D>& ps) {
  double e = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    e += 0.5 * ps.mass[i] * ps.v[i].squaredNorm() + 0.5 * ps.inertia[i] * ps.omega[i].squaredNorm();
  }
  return e;
}

template <int D>
double dem_elastic_energy(const DemParams<D>& p, const std::vector<DemWall<D>>& walls,
                          const DemParticles<D>& ps) {
  std::int64_t gid_max = -1;
  for (std::size_t i = 0; i < ps.size(); ++i) gid_max = std::max(gid_max, ps.gid[i]);
  std::vector<std::int32_t> index(static_cast<std::size_t>(gid_max + 1), -1);
  for (std::size_t i = 0; i < ps.size(); ++i) index[ps.gid[i]] = static_cast<std::int32_t>(i);
  double e = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (const DemBond<D>& b : ps.bonds[i]) {
      if (b.partner < 0 || b.broken) continue;
      const auto j = static_cast<std::size_t>(index[b.partner]);
      e += terms::parallel_bond_energy<D>(bond_law(p, ps.radius[i], ps.radius[j], b.rbar), b);
    }
    for (const DemContact<D>& c : ps.contacts[i]) {
      if (c.partner == DemContact<D>::kNone) continue;
      const auto j = static_cast<std::size_t>(index[c.partner]);
      const double delta = ps.radius[i] + ps.radius[j] - (ps.x[j] - ps.x[i]).norm();
      const terms::LinearContact law =
          contact_law(p, ps.mass[i] * ps.mass[j] / (ps.mass[i] + ps.mass[j]));
      e += terms::linear_contact_energy<D>(law, delta, c.xi);
    }
    for (const DemContact<D>& c : ps.wall_contacts[i]) {
      if (c.partner == DemContact<D>::kNone) continue;
      Vec<D> nv;
      double delta = 0;
      wall_contact<D>(walls[static_cast<std::size_t>(-2 - c.partner)], ps.x[i], ps.radius[i], nv,
                      delta);
      e += terms::linear_contact_energy<D>(contact_law(p, ps.mass[i]), delta, c.xi);
    }
  }
  return e;
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                            \
  template double stable_dem_dt<D>(const DemParams<D>&, const DemParticles<D>&);             \
  template double dem_kinetic_energy<D>(const DemParticles<D>&);                             \
  template double dem_elastic_energy<D>(const DemParams<D>&, const std::vector<DemWall<D>>&, \
                                        const DemParticles<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
