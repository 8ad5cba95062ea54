// The DEM loops: pair search, contacts, bonds, walls, body and external
// forces, and the velocity-Verlet sub-step. The physics of each interaction
// is a pair kernel in terms/ (STYLE habit 7); this file owns the loops.
//
// Every pair is evaluated once, by its owner (the smaller gid, see
// dem_particles.hpp), which holds the pair's state and updates it; the
// force goes to both particles. (With DEM ghosts the rank of the larger gid
// will evaluate the same pair from the ghost's copy of the slots, docs/dem.md.)
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cell_list.hpp"
#include "sphdem/dem.hpp"
#include "sphdem/errors.hpp"
#include "terms/contact_linear.hpp"
#include "terms/parallel_bond.hpp"
#include "terms/restitution_damping.hpp"

namespace sphdem {

namespace {

template <int D>
terms::LinearContact contact_law(const DemParams<D>& p, double m_eff) {
  const double kt = p.kt_over_kn * p.kn;
  return {p.kn, kt, terms::restitution_damping(p.restitution, m_eff, p.kn),
          terms::restitution_damping(p.restitution, m_eff, kt), p.friction};
}

template <int D>
terms::BondLaw bond_law(const DemParams<D>& p, double r1, double r2, double rbar) {
  terms::BondLaw law;
  law.s = terms::bond_section<D>(rbar, p.thickness);
  law.kn = p.youngs_modulus / (r1 + r2);
  law.ks = law.kn / p.kbar_star;
  law.sigma_c = p.tensile_strength;
  law.tau_c = p.shear_strength;
  return law;
}

// Closest point of wall w to x and whether x is within reach r of it.
template <int D>
bool wall_contact(const DemWall<D>& w, const Vec<D>& x, double r, Vec<D>& n, double& delta) {
  if (w.type == DemWall<D>::Type::Plane) {
    const double dist = (x - w.point).dot(w.normal);
    if (dist >= r || dist <= -r) return false;
    n = -w.normal;
    delta = r - dist;
    return true;
  }
  const Vec<D> ab = w.end - w.point;
  const double t = std::clamp((x - w.point).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  const Vec<D> d = w.point + t * ab - x;
  const double dist = d.norm();
  if (dist >= r || dist == 0.0) return false;
  n = d / dist;
  delta = r - dist;
  return true;
}

template <int D>
const DemContact<D>* find_history(const ContactSlots<D>& old, std::int64_t key) {
  for (const auto& c : old)
    if (c.partner == key) return &c;
  return nullptr;
}

template <int D>
void store_history(ContactSlots<D>& slots, int& used, std::int64_t owner, std::int64_t key,
                   const Vec<D>& xi) {
  if (used == kMaxContacts<D>) {
    throw SimulationError(
        fmt::format("DEM particle {} has more than {} owned contacts", owner, kMaxContacts<D>));
  }
  slots[used].partner = key;
  slots[used].xi = xi;
  ++used;
}

template <int D>
bool bonded(const BondSlots<D>& b, std::int64_t partner) {
  for (const auto& s : b)
    if (s.partner == partner && !s.broken) return true;
  return false;
}

}  // namespace

template <int D>
void compute_dem_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                        DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const std::size_t n = ps.size();
  double r_max = 0;
  std::int64_t gid_max = -1;
  for (std::size_t i = 0; i < n; ++i) {
    r_max = std::max(r_max, ps.radius[i]);
    gid_max = std::max(gid_max, ps.gid[i]);
  }
  ws.index_of_gid.assign(static_cast<std::size_t>(gid_max + 1), -1);
  for (std::size_t i = 0; i < n; ++i) ws.index_of_gid[ps.gid[i]] = static_cast<std::int32_t>(i);
  dem_detail::CellList<D> cells;
  cells.build(ps.x, n, 2.0 * r_max, ws.cell_start, ws.cell_items);

  // Body, external and damping forces.
  for (std::size_t i = 0; i < n; ++i) {
    ps.force[i] = ps.mass[i] * (p.gravity - p.global_damping * ps.v[i]) + ps.f_ext[i];
    ps.torque[i] = -p.global_damping * ps.inertia[i] * ps.omega[i];
  }

  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t gi = ps.gid[i];
    const double ri = ps.radius[i];
    // Contacts: the old history is looked up by key, the slots are refilled
    // with the pairs still in contact (a separated pair's history is dropped).
    const ContactSlots<D> old = ps.contacts[i];
    ps.contacts[i] = ContactSlots<D>{};
    int used = 0;
    cells.for_each_near(ps.x[i], [&](std::int32_t jj) {
      const auto j = static_cast<std::size_t>(jj);
      const std::int64_t gj = ps.gid[j];
      if (gj <= gi) return;
      const Vec<D> d = ps.x[j] - ps.x[i];
      const double rj = ps.radius[j];
      const double dist2 = d.squaredNorm();
      if (dist2 >= (ri + rj) * (ri + rj) || dist2 == 0.0) return;
      if (bonded<D>(ps.bonds[i], gj)) return;  // bonded pairs get no contact force
      const double dist = std::sqrt(dist2);
      const Vec<D> nv = d / dist;
      const double delta = ri + rj - dist;
      const Vec<D> arm_i = (ri - 0.5 * delta) * nv, arm_j = -(rj - 0.5 * delta) * nv;
      const Vec<D> v_rel =
          ps.v[j] + cross<D>(ps.omega[j], arm_j) - ps.v[i] - cross<D>(ps.omega[i], arm_i);
      const DemContact<D>* h = find_history<D>(old, gj);
      Vec<D> xi = h ? h->xi : Vec<D>::Zero();
      const double m_eff = ps.mass[i] * ps.mass[j] / (ps.mass[i] + ps.mass[j]);
      const Vec<D> f = terms::linear_contact<D>(contact_law(p, m_eff), nv, delta, v_rel, dt, xi);
      store_history<D>(ps.contacts[i], used, gi, gj, xi);
      ps.force[j] += f;
      ps.torque[j] += moment<D>(arm_j, f);
      ps.force[i] -= f;
      ps.torque[i] -= moment<D>(arm_i, f);
    });
    for (std::size_t w = 0; w < walls.size(); ++w) {
      Vec<D> nv;
      double delta;
      if (!wall_contact<D>(walls[w], ps.x[i], ri, nv, delta)) continue;
      const std::int64_t key = wall_key(static_cast<int>(w));
      const Vec<D> arm_i = (ri - delta) * nv;
      const Vec<D> v_rel = walls[w].velocity - ps.v[i] - cross<D>(ps.omega[i], arm_i);
      const DemContact<D>* h = find_history<D>(old, key);
      Vec<D> xi = h ? h->xi : Vec<D>::Zero();
      const Vec<D> f =
          terms::linear_contact<D>(contact_law(p, ps.mass[i]), nv, delta, v_rel, dt, xi);
      store_history<D>(ps.contacts[i], used, gi, key, xi);
      ps.force[i] -= f;
      ps.torque[i] -= moment<D>(arm_i, f);
    }

    // Bonds owned by i.
    for (DemBond<D>& b : ps.bonds[i]) {
      if (b.partner < 0 || b.broken) continue;
      const std::int32_t jj = b.partner < static_cast<std::int64_t>(ws.index_of_gid.size())
                                  ? ws.index_of_gid[b.partner]
                                  : -1;
      if (jj < 0) {
        throw SimulationError(
            fmt::format("bond {}-{}: partner {} is not on this rank", gi, b.partner, b.partner));
      }
      const auto j = static_cast<std::size_t>(jj);
      const double rj = ps.radius[j];
      const Vec<D> d = ps.x[j] - ps.x[i];
      const double dist = d.norm();
      const Vec<D> nv = d / dist;
      const double delta = ri + rj - dist;
      const Vec<D> arm_i = (ri - 0.5 * delta) * nv, arm_j = -(rj - 0.5 * delta) * nv;
      const Vec<D> v_rel =
          ps.v[j] + cross<D>(ps.omega[j], arm_j) - ps.v[i] - cross<D>(ps.omega[i], arm_i);
      const Rot<D> dtheta = (ps.omega[j] - ps.omega[i]) * dt;
      double spin_n = 0;
      if constexpr (D == 3) spin_n = 0.5 * (ps.omega[i] + ps.omega[j]).dot(nv);
      const terms::BondLaw law = bond_law(p, ri, rj, b.rbar);
      if (!terms::parallel_bond_update<D>(law, b.rbar, nv, v_rel, dtheta, spin_n, dt, b)) continue;
      const Vec<D> f = b.fn * nv + b.fs;
      Rot<D> couple = b.mb;
      if constexpr (D == 3) couple += b.mt * nv;
      ps.force[j] += f;
      ps.torque[j] += moment<D>(arm_j, f) + couple;
      ps.force[i] -= f;
      ps.torque[i] -= moment<D>(arm_i, f) + couple;
    }
  }
  ws.forces_valid = true;
}

template <int D>
void dem_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
              DemWorkspace<D>& ws) {
  if (!ws.forces_valid) compute_dem_forces(p, 0.0, walls, ps, ws);
  const std::size_t n = ps.size();
  const double half = 0.5 * dt;
  auto kick = [&] {
    for (std::size_t i = 0; i < n; ++i) {
      if (ps.fixed[i] & kFixedMotion) continue;
      ps.v[i] += (half / ps.mass[i]) * ps.force[i];
      ps.omega[i] += (half / ps.inertia[i]) * ps.torque[i];
    }
  };
  kick();
  for (std::size_t i = 0; i < n; ++i) ps.x[i] += dt * ps.v[i];
  for (DemWall<D>& w : walls) {
    w.point += dt * w.velocity;
    w.end += dt * w.velocity;
  }
  // The incremental springs advance by the half-step velocities times dt,
  // i.e. by exactly the displacement of the drift.
  compute_dem_forces(p, dt, walls, ps, ws);
  kick();
}

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
    const terms::LinearContact law = contact_law(p, ps.mass[i]);
    for (const DemContact<D>& c : ps.contacts[i]) {
      if (c.partner == DemContact<D>::kNone) continue;
      double delta = 0;
      if (c.partner >= 0) {
        const auto j = static_cast<std::size_t>(index[c.partner]);
        delta = ps.radius[i] + ps.radius[j] - (ps.x[j] - ps.x[i]).norm();
      } else {
        Vec<D> nv;
        wall_contact<D>(walls[static_cast<std::size_t>(-2 - c.partner)], ps.x[i], ps.radius[i], nv,
                        delta);
      }
      e += terms::linear_contact_energy<D>(law, delta, c.xi);
    }
  }
  return e;
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                                  \
  template void compute_dem_forces<D>(const DemParams<D>&, double, const std::vector<DemWall<D>>&, \
                                      DemParticles<D>&, DemWorkspace<D>&);                         \
  template void dem_step<D>(const DemParams<D>&, double, std::vector<DemWall<D>>&,                 \
                            DemParticles<D>&, DemWorkspace<D>&);                                   \
  template double stable_dem_dt<D>(const DemParams<D>&, const DemParticles<D>&);                   \
  template double dem_kinetic_energy<D>(const DemParticles<D>&);                                   \
  template double dem_elastic_energy<D>(const DemParams<D>&, const std::vector<DemWall<D>>&,       \
                                        const DemParticles<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
