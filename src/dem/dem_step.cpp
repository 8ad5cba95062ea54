// The DEM loops: pair search, contacts, bonds, walls, body and external
// forces, and the velocity-Verlet sub-step. The physics of each interaction
// is a pair kernel in terms/; this file owns the loops.
//
// Gather formulation (docs/dem.md, "Pairs"): every pair with an owned
// particle is evaluated once per rank that owns one of its two particles,
// from identical inputs (ghosts are exact copies), into a per-pair result;
// each owned particle then adds its pairs' results in increasing partner
// gid. The sums, and so the trajectories, are bitwise the same on any
// number of ranks, with no reverse communication.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cell_list.hpp"
#include "dem_profile.hpp"
#include "sphdem/dem.hpp"
#include "sphdem/errors.hpp"
#include "terms/contact_linear.hpp"
#include "terms/parallel_bond.hpp"
#include "terms/restitution_damping.hpp"

namespace sphdem {

dem_detail::DemProfile& dem_detail::dem_profile() {
  static DemProfile profile;
  return profile;
}

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

// A rectangle (dem.hpp): within its footprint, the plane's one-sided push;
// beyond a flagged edge and in front of the plane, the closest point of the
// edge or corner (clamped parameters); beyond an unflagged edge, nothing.
template <int D>
bool rect_contact(const DemWall<D>& w, const Vec<D>& x, double r, Vec<D>& n, double& delta) {
  const Vec<D> d = x - w.point;
  const double h = d.dot(w.normal);
  if (h >= r || h <= -r) return false;
  double s = d.dot(w.u) / w.u.squaredNorm();
  double t = d.dot(w.v) / w.v.squaredNorm();
  // An unflagged far edge is open (s < 1), so a particle exactly on a seam
  // meets one of the two rectangles.
  const bool past_s = s > 1 || (s == 1 && !(w.edges & 2));
  const bool past_t = t > 1 || (t == 1 && !(w.edges & 8));
  if (s >= 0 && !past_s && t >= 0 && !past_t) {
    n = -w.normal;
    delta = r - h;
    return true;
  }
  if (h < 0) return false;
  if (s < 0 || past_s) {
    if (!(w.edges & (s < 0 ? 1 : 2))) return false;
    s = s < 0 ? 0.0 : 1.0;
  }
  if (t < 0 || past_t) {
    if (!(w.edges & (t < 0 ? 4 : 8))) return false;
    t = t < 0 ? 0.0 : 1.0;
  }
  const Vec<D> c = w.point + s * w.u + t * w.v - x;
  const double dist = c.norm();
  if (dist >= r || dist == 0.0) return false;
  n = c / dist;
  delta = r - dist;
  return true;
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
  if (w.type == DemWall<D>::Type::Rect) return rect_contact<D>(w, x, r, n, delta);
  // Segment: beyond an unflagged end, nothing (a seam's neighbour, or a
  // corner the other segment owns); that end's own point too, so a particle
  // exactly on a seam meets one segment, not two.
  const Vec<D> ab = w.end - w.point;
  double t = (x - w.point).dot(ab) / ab.squaredNorm();
  if ((t < 0 && !(w.edges & DemWall<D>::kEndA)) || (t >= 1 && !(w.edges & DemWall<D>::kEndB)))
    return false;
  // A mold segment (with a normal into the mold) pushes from its ends only
  // in front of its line, as a rectangle from its edges.
  if ((t < 0 || t > 1) && (x - w.point).dot(w.normal) < 0) return false;
  t = std::clamp(t, 0.0, 1.0);
  const Vec<D> d = w.point + t * ab - x;
  const double dist = d.norm();
  if (dist >= r || dist == 0.0) return false;
  n = d / dist;
  delta = r - dist;
  return true;
}

// Local index of every gid present (owned and ghosts), for the bond partners.
template <int D>
class GidIndex {
 public:
  explicit GidIndex(const DemParticles<D>& ps) {
    order_.resize(ps.size());
    for (std::size_t i = 0; i < ps.size(); ++i)
      order_[i] = {ps.gid[i], static_cast<std::int32_t>(i)};
    std::sort(order_.begin(), order_.end());
  }
  std::int32_t find(std::int64_t gid) const {
    const auto it =
        std::lower_bound(order_.begin(), order_.end(), std::make_pair(gid, std::int32_t{-1}));
    return it != order_.end() && it->first == gid ? it->second : -1;
  }

 private:
  std::vector<std::pair<std::int64_t, std::int32_t>> order_;
};

template <int D>
int bond_slot(const BondSlots<D>& b, std::int64_t partner) {
  for (int s = 0; s < kMaxBonds; ++s)
    if (b[static_cast<std::size_t>(s)].partner == partner && !b[static_cast<std::size_t>(s)].broken)
      return s;
  return -1;
}

template <int D>
Vec<D> contact_history(const ContactSlots<D>& slots, std::int64_t partner) {
  for (const auto& c : slots)
    if (c.partner == partner) return c.xi;
  return Vec<D>::Zero();
}

// The contact damping of a pair from the two masses, remembering the last
// pair of masses (fibers are usually of one kind of particle: the log and
// sqrt of restitution_damping then run once per build, same values).
template <int D>
class PairDamping {
 public:
  explicit PairDamping(const DemParams<D>& p) : p_(p) {}
  void set(const DemParticles<D>& ps, DemPair<D>& pr) {
    const double ma = ps.mass[static_cast<std::size_t>(pr.a)];
    const double mb = ps.mass[static_cast<std::size_t>(pr.b)];
    if (!(ma == ma_ && mb == mb_)) {
      const terms::LinearContact law = contact_law(p_, ma * mb / (ma + mb));
      ma_ = ma;
      mb_ = mb;
      cn_ = law.cn;
      ct_ = law.ct;
    }
    pr.cn = cn_;
    pr.ct = ct_;
  }

 private:
  const DemParams<D>& p_;
  double ma_ = -1, mb_ = -1, cn_ = 0, ct_ = 0;
};

// Contact or bond of one pair at the current state; fills f, ta, tb.
template <int D>
void evaluate_pair(const DemParams<D>& p, double dt, DemParticles<D>& ps, DemPair<D>& pr) {
  const auto i = static_cast<std::size_t>(pr.a), j = static_cast<std::size_t>(pr.b);
  const double ri = ps.radius[i], rj = ps.radius[j];
  const Vec<D> d = ps.x[j] - ps.x[i];
  const double dist2 = d.squaredNorm();
  DemBond<D>* bond = pr.bond >= 0 ? &ps.bonds[i][static_cast<std::size_t>(pr.bond)] : nullptr;
  if (bond && bond->broken) {  // broke at an earlier evaluation: a contact pair now
    bond = nullptr;
    pr.bond = -1;
  }
  pr.active = false;
  if (!bond && (dist2 >= (ri + rj) * (ri + rj) || dist2 == 0.0)) {
    pr.xi.setZero();  // separated: the contact's history ends
    return;
  }
  const double dist = std::sqrt(dist2);
  const Vec<D> nv = d / dist;
  const double delta = ri + rj - dist;
  const Vec<D> arm_i = (ri - 0.5 * delta) * nv, arm_j = -(rj - 0.5 * delta) * nv;
  Rot<D> couple = Rot<D>::Zero();
  if (bond) {
    const terms::BondMotion<D> motion =
        terms::bond_motion<D>(d, dist, (ps.v[j] - ps.v[i]) * dt, ps.omega[i] * dt, ps.omega[j] * dt,
                              ri - 0.5 * delta, rj - 0.5 * delta);
    const terms::BondLaw law = bond_law(p, ri, rj, bond->rbar);
    if (!terms::parallel_bond_update<D>(law, bond->rbar, motion, *bond)) return;
    pr.f = bond->fn * nv + bond->fs;
    couple = bond->mb;
    if constexpr (D == 3) couple += bond->mt * nv;
  } else {
    const terms::LinearContact law{p.kn, p.kt_over_kn * p.kn, pr.cn, pr.ct, p.friction};
    const Vec<D> v_rel =
        ps.v[j] + cross<D>(ps.omega[j], arm_j) - ps.v[i] - cross<D>(ps.omega[i], arm_i);
    pr.f = terms::linear_contact<D>(law, nv, delta, v_rel, dt, pr.xi);
  }
  pr.tb = moment<D>(arm_j, pr.f) + couple;
  pr.ta = -(moment<D>(arm_i, pr.f) + couple);
  pr.active = true;
}

// Contacts of owned particle i with its candidate walls (the walls within
// reach at the last build, in increasing index), history in its wall slots.
template <int D>
void wall_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                 DemParticles<D>& ps, std::size_t i, const std::int32_t* cand,
                 std::int32_t n_cand) {
  // Fast path, most particles: no wall within reach and no history to drop.
  bool busy = false;
  for (const auto& c : ps.wall_contacts[i]) busy = busy || c.partner != DemContact<D>::kNone;
  for (std::int32_t k = 0; k < n_cand && !busy; ++k) {
    Vec<D> nv;
    double delta;
    busy =
        wall_contact<D>(walls[static_cast<std::size_t>(cand[k])], ps.x[i], ps.radius[i], nv, delta);
  }
  if (!busy) return;
  const WallContactSlots<D> old = ps.wall_contacts[i];
  WallContactSlots<D>& slots = ps.wall_contacts[i];
  slots = WallContactSlots<D>{};
  int used = 0;
  const double ri = ps.radius[i];
  for (std::int32_t k = 0; k < n_cand; ++k) {
    const auto w = static_cast<std::size_t>(cand[k]);
    Vec<D> nv;
    double delta;
    if (!wall_contact<D>(walls[w], ps.x[i], ri, nv, delta)) continue;
    const std::int64_t key = wall_key(static_cast<int>(w));
    const Vec<D> arm_i = (ri - delta) * nv;
    const Vec<D> v_rel = walls[w].velocity - ps.v[i] - cross<D>(ps.omega[i], arm_i);
    Vec<D> xi = Vec<D>::Zero();
    for (const auto& c : old)
      if (c.partner == key) xi = c.xi;
    const Vec<D> f = terms::linear_contact<D>(contact_law(p, ps.mass[i]), nv, delta, v_rel, dt, xi);
    if (used == kMaxWallContacts<D>) {
      throw SimulationError(fmt::format("DEM particle {} touches more than {} walls", ps.gid[i],
                                        kMaxWallContacts<D>));
    }
    slots[static_cast<std::size_t>(used)] = {key, xi};
    ++used;
    ps.force[i] -= f;
    ps.torque[i] -= moment<D>(arm_i, f);
  }
}

}  // namespace

template <int D>
void dem_build_pairs(const DemParams<D>& p, const std::vector<DemWall<D>>& walls,
                     DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().rebuild_pairs);
  const std::size_t n = ps.size(), n_own = ps.n_owned;
  double r_max = 0, r_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    r_max = std::max(r_max, ps.radius[i]);
    r_min = std::min(r_min, ps.radius[i]);
  }
  if (ws.skin <= 0) ws.skin = n > 0 ? 0.25 * r_min : 0;
  const double skin = ws.skin;
  const GidIndex<D> index(ps);
  PairDamping<D> damping(p);
  ws.pairs.clear();

  // Bonds first: the smaller gid's slots name the partner.
  for (std::size_t i = 0; i < n; ++i) {
    for (int s = 0; s < kMaxBonds; ++s) {
      const DemBond<D>& b = ps.bonds[i][static_cast<std::size_t>(s)];
      if (b.partner < 0 || b.broken) continue;
      const std::int32_t j = index.find(b.partner);
      if (j < 0) {
        if (i < n_own) {
          throw SimulationError(fmt::format(
              "bond {}-{}: partner {} is neither on this rank nor one of its ghosts (a bond "
              "stretched past the halo width without breaking?)",
              ps.gid[i], b.partner, b.partner));
        }
        continue;
      }
      if (i >= n_own && static_cast<std::size_t>(j) >= n_own) continue;
      DemPair<D> pr;
      pr.a = static_cast<std::int32_t>(i);
      pr.b = j;
      pr.bond = static_cast<std::int8_t>(s);
      damping.set(ps, pr);
      ws.pairs.push_back(pr);
    }
  }
  // Contact candidates within R_a + R_b + skin.
  dem_detail::CellList<D> cells;
  cells.build(ps.x, n, 2.0 * r_max + skin, ws.cell_start, ws.cell_items);
  // Each unordered pair once (local index j > i), then ordered by gid.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec<D> xi = ps.x[i];
    const double ri = ps.radius[i] + skin;
    cells.for_each_near(xi, [&](std::int32_t jj) {
      const auto j = static_cast<std::size_t>(jj);
      if (j <= i || (i >= n_own && j >= n_own) || ps.gid[i] == ps.gid[j]) return;
      const double reach = ri + ps.radius[j];
      if ((ps.x[j] - xi).squaredNorm() >= reach * reach) return;
      const bool i_first = ps.gid[i] < ps.gid[j];
      const std::size_t a = i_first ? i : j, b = i_first ? j : i;
      if (bond_slot<D>(ps.bonds[a], ps.gid[b]) >= 0) return;  // listed as a bond
      DemPair<D> pr;
      pr.a = static_cast<std::int32_t>(a);
      pr.b = static_cast<std::int32_t>(b);
      pr.xi = contact_history<D>(ps.contacts[a], ps.gid[b]);
      damping.set(ps, pr);
      ws.pairs.push_back(pr);
    });
  }

  // Per owned particle, its pairs by partner gid.
  std::vector<std::int32_t> count(n_own + 1, 0);
  for (const DemPair<D>& pr : ws.pairs) {
    if (static_cast<std::size_t>(pr.a) < n_own) ++count[static_cast<std::size_t>(pr.a) + 1];
    if (static_cast<std::size_t>(pr.b) < n_own) ++count[static_cast<std::size_t>(pr.b) + 1];
  }
  for (std::size_t i = 0; i < n_own; ++i) count[i + 1] += count[i];
  ws.adj_start = count;
  ws.adj.assign(static_cast<std::size_t>(count[n_own]), 0);
  for (std::size_t k = 0; k < ws.pairs.size(); ++k) {
    const DemPair<D>& pr = ws.pairs[k];
    const auto e = static_cast<std::int32_t>(2 * k);
    if (static_cast<std::size_t>(pr.a) < n_own) ws.adj[count[static_cast<std::size_t>(pr.a)]++] = e;
    if (static_cast<std::size_t>(pr.b) < n_own)
      ws.adj[count[static_cast<std::size_t>(pr.b)]++] = e + 1;
  }
  const auto partner_gid = [&](std::int32_t e) {
    const DemPair<D>& pr = ws.pairs[static_cast<std::size_t>(e / 2)];
    return ps.gid[static_cast<std::size_t>(e % 2 ? pr.a : pr.b)];
  };
  for (std::size_t i = 0; i < n_own; ++i) {
    std::sort(ws.adj.begin() + ws.adj_start[i], ws.adj.begin() + ws.adj_start[i + 1],
              [&](std::int32_t x, std::int32_t y) { return partner_gid(x) < partner_gid(y); });
  }
  ws.x_ref.assign(ps.x.begin(), ps.x.begin() + static_cast<std::ptrdiff_t>(n_own));
  dem_build_wall_lists(walls, ps, ws);
  ws.pairs_valid = true;
}

template <int D>
void dem_store_pair_state(DemParticles<D>& ps, const DemWorkspace<D>& ws) {
  if (!ws.pairs_valid) return;
  const std::size_t n_own = ps.n_owned;
  for (std::size_t i = 0; i < n_own; ++i) {
    ContactSlots<D>& slots = ps.contacts[i];
    slots = ContactSlots<D>{};
    std::size_t used = 0;
    for (std::int32_t e = ws.adj_start[i]; e < ws.adj_start[i + 1]; ++e) {
      const std::int32_t entry = ws.adj[static_cast<std::size_t>(e)];
      if (entry % 2) continue;  // i is b: the pair's state lives on a
      const DemPair<D>& pr = ws.pairs[static_cast<std::size_t>(entry / 2)];
      if (pr.bond >= 0 || !pr.active) continue;
      if (used == slots.size()) {
        throw SimulationError(fmt::format("DEM particle {} has more than {} owned contacts",
                                          ps.gid[i], kMaxContacts<D>));
      }
      slots[used++] = {ps.gid[static_cast<std::size_t>(pr.b)], pr.xi};
    }
  }
}

template <int D>
double dem_max_displacement2(const DemParticles<D>& ps, const std::vector<DemWall<D>>& walls,
                             const DemWorkspace<D>& ws) {
  double m = 0;
  for (std::size_t i = 0; i < ps.n_owned && i < ws.x_ref.size(); ++i)
    m = std::max(m, (ps.x[i] - ws.x_ref[i]).squaredNorm());
  for (std::size_t w = 0; w < walls.size() && w < ws.wall_ref.size(); ++w)
    m = std::max(m, (walls[w].point - ws.wall_ref[w]).squaredNorm());
  return m;
}

// Per owned particle, the walls within its radius + skin: while neither it
// nor a wall moves more than skin / 2, no other wall can touch it.
template <int D>
void dem_build_wall_lists(const std::vector<DemWall<D>>& walls, const DemParticles<D>& ps,
                          DemWorkspace<D>& ws) {
  ws.wall_start.assign(ps.n_owned + 1, 0);
  ws.wall_items.clear();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    for (std::size_t w = 0; w < walls.size(); ++w) {
      Vec<D> nv;
      double delta;
      if (wall_contact<D>(walls[w], ps.x[i], ps.radius[i] + ws.skin, nv, delta))
        ws.wall_items.push_back(static_cast<std::int32_t>(w));
    }
    ws.wall_start[i + 1] = static_cast<std::int32_t>(ws.wall_items.size());
  }
  ws.wall_ref.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) ws.wall_ref[w] = walls[w].point;
}

template <int D>
void compute_dem_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                        DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const std::size_t n_own = ps.n_owned;
  dem_detail::DemProfile& prof = dem_detail::dem_profile();
  dem_detail::DemTimer t_pairs(prof.pairs);
  for (DemPair<D>& pr : ws.pairs) evaluate_pair<D>(p, dt, ps, pr);
  t_pairs.stop();
  dem_detail::DemTimer t_gather(prof.gather);
  for (std::size_t i = 0; i < n_own; ++i) {
    // The resin's drag, linear in the particle's own velocity with the
    // coefficient and resin velocity of the last coupling pass (so it stays
    // stable however many sub-steps the SPH step holds).
    ps.drag_force[i] = ps.drag_coeff[i] * (ps.drag_velocity[i] - ps.v[i]);
    Vec<D> f =
        ps.mass[i] * (p.gravity - p.global_damping * ps.v[i]) + ps.f_ext[i] + ps.drag_force[i];
    Rot<D> t = -p.global_damping * ps.inertia[i] * ps.omega[i];
    for (std::int32_t e = ws.adj_start[i]; e < ws.adj_start[i + 1]; ++e) {
      const std::int32_t entry = ws.adj[static_cast<std::size_t>(e)];
      const DemPair<D>& pr = ws.pairs[static_cast<std::size_t>(entry / 2)];
      if (!pr.active) continue;
      if (entry % 2) {
        f += pr.f;
        t += pr.tb;
      } else {
        f -= pr.f;
        t += pr.ta;
      }
    }
    ps.force[i] = f;
    ps.torque[i] = t;
  }
  t_gather.stop();
  dem_detail::DemTimer t_walls(prof.walls);
  for (std::size_t i = 0; i < n_own; ++i) {
    wall_forces<D>(p, dt, walls, ps, i, ws.wall_items.data() + ws.wall_start[i],
                   ws.wall_start[i + 1] - ws.wall_start[i]);
  }
  ws.forces_valid = true;
}

template <int D>
void dem_kick_drift(double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps) {
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  const double half = 0.5 * dt;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (!(ps.fixed[i] & kFixedMotion)) {
      ps.v[i] += (half / ps.mass[i]) * ps.force[i];
      ps.omega[i] += (half / ps.inertia[i]) * ps.torque[i];
      ps.drag_impulse[i] += half * ps.drag_force[i];  // what the resin must get back
    }
    ps.x[i] += dt * ps.v[i];
  }
  for (DemWall<D>& w : walls) {
    w.point += dt * w.velocity;
    w.end += dt * w.velocity;
  }
}

// The incremental springs advance by the half-step velocities times dt,
// i.e. by exactly the displacement of the drift.
template <int D>
void dem_force_kick(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                    DemParticles<D>& ps, DemWorkspace<D>& ws) {
  compute_dem_forces(p, dt, walls, ps, ws);
  const dem_detail::DemTimer timer(dem_detail::dem_profile().kick_drift);
  const double half = 0.5 * dt;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.fixed[i] & kFixedMotion) continue;
    ps.v[i] += (half / ps.mass[i]) * ps.force[i];
    ps.omega[i] += (half / ps.inertia[i]) * ps.torque[i];
    ps.drag_impulse[i] += half * ps.drag_force[i];
  }
}

template <int D>
void dem_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
              DemWorkspace<D>& ws) {
  if (!ws.pairs_valid) dem_build_pairs(p, walls, ps, ws);
  if (!ws.forces_valid) compute_dem_forces(p, 0.0, walls, ps, ws);
  dem_kick_drift(dt, walls, ps);
  if (dem_max_displacement2(ps, walls, ws) > 0.25 * ws.skin * ws.skin) {
    dem_store_pair_state(ps, ws);
    dem_build_pairs(p, walls, ps, ws);
  }
  dem_force_kick(p, dt, walls, ps, ws);
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

#define SPHDEM_DEM_INSTANTIATE(D)                                                                  \
  template void compute_dem_forces<D>(const DemParams<D>&, double, const std::vector<DemWall<D>>&, \
                                      DemParticles<D>&, DemWorkspace<D>&);                         \
  template void dem_step<D>(const DemParams<D>&, double, std::vector<DemWall<D>>&,                 \
                            DemParticles<D>&, DemWorkspace<D>&);                                   \
  template void dem_build_pairs<D>(const DemParams<D>&, const std::vector<DemWall<D>>&,            \
                                   DemParticles<D>&, DemWorkspace<D>&);                            \
  template void dem_store_pair_state<D>(DemParticles<D>&, const DemWorkspace<D>&);                 \
  template double dem_max_displacement2<D>(const DemParticles<D>&, const std::vector<DemWall<D>>&, \
                                           const DemWorkspace<D>&);                                \
  template void dem_kick_drift<D>(double, std::vector<DemWall<D>>&, DemParticles<D>&);             \
  template void dem_force_kick<D>(const DemParams<D>&, double, const std::vector<DemWall<D>>&,     \
                                  DemParticles<D>&, DemWorkspace<D>&);                             \
  template double stable_dem_dt<D>(const DemParams<D>&, const DemParticles<D>&);                   \
  template double dem_kinetic_energy<D>(const DemParticles<D>&);                                   \
  template double dem_elastic_energy<D>(const DemParams<D>&, const std::vector<DemWall<D>>&,       \
                                        const DemParticles<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
