#pragma once
// The DEM pair and wall kernels' glue (dem_pair_list.cpp, dem_forces.cpp,
// dem_stable_step.cpp): contact and bond laws from the parameters, wall
// contact geometry, the gid index, and one pair's or one particle's walls'
// forces. The physics of each interaction is a pair kernel in terms/.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "sphdem/core/errors.hpp"
#include "sphdem/dem/dem.hpp"
#include "terms/contact_linear.hpp"
#include "terms/parallel_bond.hpp"
#include "terms/restitution_damping.hpp"

namespace sphdem {

// Internal linkage, as when these lived in one file with their loops: GCC
// then inlines the single-call ones (evaluate_pair, wall_forces) into the
// loops, which fixes where multiply-adds are fused and so keeps the results
// bitwise what they were.
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
// The (gid, local index) pairs in order; when the gids present span a range
// of at most 4 n + 64 values (a rank's particles and ghosts usually do),
// by a counting sort with a table of where each gid's entries start, so a
// lookup is two loads instead of a binary search (the pair-list build asks
// twice per bond at every rebuild). The same order and answers either way.
template <int D>
class GidIndex {
 public:
  explicit GidIndex(const DemParticles<D>& ps) {
    const std::size_t n = ps.size();
    order_.resize(n);
    if (n == 0) return;
    const auto [lo, hi] =
        std::minmax_element(ps.gid.begin(), ps.gid.begin() + static_cast<std::ptrdiff_t>(n));
    // The span as unsigned: no overflow for any pair of int64 gids.
    const std::uint64_t span = static_cast<std::uint64_t>(*hi) - static_cast<std::uint64_t>(*lo);
    if (span >= 4 * static_cast<std::uint64_t>(n) + 64) {
      for (std::size_t i = 0; i < n; ++i) order_[i] = {ps.gid[i], static_cast<std::int32_t>(i)};
      std::sort(order_.begin(), order_.end());
      return;
    }
    lo_ = *lo;
    start_.assign(static_cast<std::size_t>(span) + 2, 0);
    for (std::size_t i = 0; i < n; ++i) ++start_[slot(ps.gid[i]) + 1];
    for (std::size_t g = 1; g < start_.size(); ++g) start_[g] += start_[g - 1];
    std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i)  // ascending i: each gid's entries in local order
      order_[static_cast<std::size_t>(fill[slot(ps.gid[i])]++)] = {ps.gid[i],
                                                                   static_cast<std::int32_t>(i)};
  }
  std::int32_t find(std::int64_t gid) const {
    const auto [first, last] = range(gid);
    return first != last ? first->second : -1;
  }
  // With periodic images a gid can be present more than once: the copy
  // nearest to x (the first in local order on a tie).
  std::int32_t find_nearest(std::int64_t gid, const Vec<D>& x, const DemParticles<D>& ps) const {
    auto [it, last] = range(gid);
    std::int32_t best = -1;
    double best_d2 = 0;
    for (; it != last; ++it) {
      const double d2 = (ps.x[static_cast<std::size_t>(it->second)] - x).squaredNorm();
      if (best < 0 || d2 < best_d2) {
        best = it->second;
        best_d2 = d2;
      }
    }
    return best;
  }

 private:
  using Entry = std::pair<std::int64_t, std::int32_t>;
  using Iter = typename std::vector<Entry>::const_iterator;
  std::size_t slot(std::int64_t gid) const {
    return static_cast<std::size_t>(static_cast<std::uint64_t>(gid) -
                                    static_cast<std::uint64_t>(lo_));
  }
  // The entries of gid.
  std::pair<Iter, Iter> range(std::int64_t gid) const {
    if (start_.empty()) {
      const Iter first = std::lower_bound(order_.begin(), order_.end(), Entry{gid, -1});
      Iter last = first;
      while (last != order_.end() && last->first == gid) ++last;
      return {first, last};
    }
    if (gid < lo_ || slot(gid) + 1 >= start_.size()) return {order_.end(), order_.end()};
    return {order_.begin() + start_[slot(gid)], order_.begin() + start_[slot(gid) + 1]};
  }

  std::vector<Entry> order_;
  std::int64_t lo_ = 0;
  std::vector<std::int32_t> start_;  // empty: gids too sparse, binary search
};

template <int D>
int bond_slot(const BondSlots<D>& b, std::int64_t partner) {
  for (int s = 0; s < kMaxBonds; ++s)
    if (b[static_cast<std::size_t>(s)].partner == partner && !b[static_cast<std::size_t>(s)].broken)
      return s;
  return -1;
}

// The stored history of the contact with `partner`, or null: the pair was
// not touching at the last evaluation before the slots were written.
template <int D>
const DemContact<D>* contact_history(const ContactSlots<D>& slots, std::int64_t partner) {
  for (const auto& c : slots)
    if (c.partner == partner) return &c;
  return nullptr;
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

// The bond law of the last radii asked for (a fiber's bonds share them):
// bond_law's divisions and the stiffness's quotients once per kind of bond
// instead of once per bond and step, the same values.
template <int D>
class BondLawCache {
 public:
  explicit BondLawCache(const DemParams<D>& p) : p_(p) {}
  const terms::PreparedBondLaw& get(double r1, double r2, double rbar) {
    if (!(r1 == r1_ && r2 == r2_ && rbar == rbar_)) {
      law_ = terms::PreparedBondLaw(bond_law(p_, r1, r2, rbar), rbar);
      r1_ = r1;
      r2_ = r2;
      rbar_ = rbar;
    }
    return law_;
  }

 private:
  const DemParams<D>& p_;
  double r1_ = -1, r2_ = -1, rbar_ = -1;
  terms::PreparedBondLaw law_;
};

// Contact or bond of one pair at the current state; fills f, ta, tb.
template <int D>
void evaluate_pair(const DemParams<D>& p, double dt, DemParticles<D>& ps, DemPair<D>& pr,
                   BondLawCache<D>& laws) {
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
    const bool intact = terms::parallel_bond_update<D>(laws.get(ri, rj, bond->rbar), motion, *bond);
    ps.bond_peaks[i][static_cast<std::size_t>(pr.bond)].record(bond->sigma, bond->tau);
    if (!intact) return;
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

// Adds owned particle i's pair results for the pairs `keep` selects to f
// and t, in increasing partner gid (the adjacency order): the one gather
// of the explicit, bond and slow force loops, so their sums are formed
// in the same order (docs/dem.md, "Pairs").
template <int D, class Keep>
[[gnu::always_inline]] inline void gather_pairs(const DemWorkspace<D>& ws, std::size_t i, Vec<D>& f,
                                                Rot<D>& t, Keep keep) {
  for (std::int32_t e = ws.adj_start[i]; e < ws.adj_start[i + 1]; ++e) {
    const std::int32_t entry = ws.adj[static_cast<std::size_t>(e)];
    const DemPair<D>& pr = ws.pairs[static_cast<std::size_t>(entry / 2)];
    if (!pr.active || !keep(pr)) continue;
    if (entry % 2) {
      f += pr.f;
      t += pr.tb;
    } else {
      f -= pr.f;
      t += pr.ta;
    }
  }
}

// Contacts of owned particle i with its candidate walls (the walls within
// reach at the last build, in increasing index), history in its wall slots.
template <int D>
void wall_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                 DemParticles<D>& ps, std::size_t i, const std::int32_t* cand,
                 std::int32_t n_cand) {
  // No candidate wall: the build dropped the particle's wall history
  // (dem_build_wall_lists), so there is nothing to do and its slots need not
  // be read.
  if (n_cand == 0) return;
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

}  // namespace sphdem
