// The coupling passes (coupling_loops.hpp). Both passes walk the candidate
// pairs of coupling_pairs.hpp (one search, kept between passes when the
// caller asks), keeping those within the kernel support in increasing
// global id.
#include "sphdem/coupling/coupling_loops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "terms/continuity_void.hpp"
#include "terms/reaction.hpp"
#include "terms/rotation.hpp"
#include "terms/shepard.hpp"
#include "terms/void_fraction.hpp"

namespace sphdem {

namespace {

// A candidate within the support: its index and distance (the candidates
// are listed by gid already, so no id is carried), and for a resin
// neighbour of the drag pass its volume m_r / rho_r and W(r), computed once
// for the pass's three walks over the list (Shepard sums, torque offset,
// rotation fit).
struct Near {
  std::int32_t index;
  double r;
  double vol = 0, w = 0;
};

// The candidates [begin, end) of `items` (indices into `x`, by gid) within
// `support` of p, in the same order.
template <int D>
void near_in_list(const std::vector<std::int32_t>& items, std::int32_t begin, std::int32_t end,
                  const std::vector<Vec<D>>& x, const Vec<D>& p, double support,
                  std::vector<Near>& out) {
  // Every candidate written, the count advanced only for those within the
  // support: no branch on the distance, which the skin makes unpredictable
  // (docs/performance.md, "The coupling's filters without branches"). The
  // square roots after, of the same r^2: the same values.
  const double support2 = support * support;
  out.resize(static_cast<std::size_t>(std::max(end - begin, 0)));
  std::size_t n = 0;
  for (std::int32_t k = begin; k < end; ++k) {
    const std::int32_t j = items[static_cast<std::size_t>(k)];
    const double r2 = (p - x[static_cast<std::size_t>(j)]).squaredNorm();
    out[n] = Near{j, r2};  // r holds r^2 until the square roots below
    n += r2 < support2 ? 1 : 0;
  }
  out.resize(n);
  for (Near& e : out) e.r = std::sqrt(e.r);
}

template <int D>
double dem_volume(const DemParticles<D>& dem, std::size_t f) {
  return particle_volume<D>(2.0 * dem.radius[f]);
}

// The resin spin and rotational friction at owned DEM particle f
// (terms/rotation.hpp) from its resin neighbours `near`, the lever that
// returns the angular impulse of the last step to them, and the torque the
// next first kick uses. Runs after f's drag (mean_drag, drag_coeff).
template <int D>
void hydrodynamic_torque(const SphParticles<D>& sph, const std::vector<Near>& near,
                         DemParticles<D>& dem, std::size_t f, double dt, bool exponential) {
  const Rot<D> mean_torque = dt > 0 ? Rot<D>(dem.torque_impulse[f] / dt) : Rot<D>::Zero();
  dem.torque_impulse[f].setZero();
  dem.torque_coeff[f] = 0.0;
  dem.resin_spin[f].setZero();
  dem.torque_lever[f].setZero();
  dem.resin_offset[f].setZero();
  if (dem.shepard_sum[f] > 0.0) {
    const auto resin_of = [](const Near& n) { return static_cast<std::size_t>(n.index); };
    Vec<D> sum = Vec<D>::Zero();
    for (const Near& n : near) sum += (n.vol * n.w) * (sph.x[resin_of(n)] - dem.x[f]);
    const Vec<D> offset = sum / dem.shepard_sum[f];
    terms::RotationFit<D> fit;
    for (const Near& n : near) {
      const std::size_t r = resin_of(n);
      fit.add(n.vol * n.w, sph.x[r] - dem.x[f] - offset, sph.v[r] - dem.resin_velocity[f]);
    }
    if (fit.solvable()) {
      dem.torque_coeff[f] = terms::rotational_friction<D>(dem.drag_coeff[f], dem.radius[f]);
      dem.resin_spin[f] = fit.spin();
      dem.torque_lever[f] =
          fit.lever(terms::torque_to_return<D>(mean_torque, offset, dem.mean_drag[f]));
      dem.resin_offset[f] = offset;
    }
  }
  if (exponential) return;  // the kicks relax the spin (drag_exchange.hpp)
  const Rot<D> torque = dem.torque_coeff[f] * (dem.resin_spin[f] - dem.omega[f]);
  dem.torque[f] += torque - dem.hydro_torque[f];
  dem.hydro_torque[f] = torque;
}

}  // namespace

template <int D>
void drag_on_fibers(const CouplingSettings& s, const SphParticles<D>& sph, DemParticles<D>& dem,
                    CouplingState<D>& st, double dt) {
  const WendlandC2<D> kernel(s.h);
  const double support = kernel.support();
  const std::size_t n_dem = dem.size();
  dem.shepard_sum.assign(n_dem, 0.0);
  dem.mean_drag.assign(n_dem, Vec<D>::Zero());
  dem.void_fraction.assign(n_dem, 1.0);
  dem.resin_velocity.assign(n_dem, Vec<D>::Zero());
  dem.resin_temperature.assign(n_dem, 0.0);

  if (!st.keep_pairs) st.pairs.invalidate();
  update_coupling_pairs<D>(st.pairs, sph, dem, support, st.keep_pairs ? st.skin : 0.0,
                           st.generation);
  const CouplingPairs<D>& pairs = st.pairs;
  std::vector<Near> near, near_dem;

  for (std::size_t f = 0; f < dem.n_owned; ++f) {
    double phi = 0;
    near_in_list<D>(pairs.dem_items, pairs.dem_start[f], pairs.dem_start[f + 1], dem.x, dem.x[f],
                    support, near_dem);
    for (const Near& n : near_dem) {
      phi +=
          terms::solid_fraction<D>(kernel, dem_volume(dem, static_cast<std::size_t>(n.index)), n.r);
    }
    const double eps = terms::void_fraction(phi, s.drag.eps_min);
    const int sharing = static_cast<int>(near_dem.size());  // f itself included
    terms::ShepardSum<D> shepard;
    double mu_sum = 0.0;  // sum_r V_r W_fr mu_r, a viscosity law's local viscosity
    double sum_t = 0.0;   // sum_r V_r W_fr T_r, the resin temperature's Shepard numerator
    near_in_list<D>(pairs.resin_items, pairs.resin_start[f], pairs.resin_start[f + 1], sph.x,
                    dem.x[f], support, near);
    for (Near& n : near) {
      const auto r = static_cast<std::size_t>(n.index);
      n.vol = sph.mass[r] / sph.rho[r];
      n.w = kernel.w(n.r);
      const double vol_r = n.vol, w = n.w;
      shepard.add(vol_r, w, sph.v[r]);
      if (s.drag.local_viscosity) mu_sum += vol_r * w * sph.viscosity[r];
      if (!sph.temperature.empty()) sum_t += vol_r * w * sph.temperature[r];
    }
    dem.resin_temperature[f] = shepard.has_resin() ? sum_t / shepard.s : 0.0;
    if (s.exponential_drag) {
      // sum_r w_r^2 / m_r, w_r = V_r W_fr / S_f, m_r per the DEM's depth.
      double inverse_sum = 0.0;
      for (const Near& n : near) {
        const auto r = static_cast<std::size_t>(n.index);
        const double w = shepard.has_resin() ? n.vol * n.w / shepard.s : 0.0;
        inverse_sum += w * w / (s.thickness * sph.mass[r]);
      }
      dem.drag_parcel_mass[f] = drag_parcel_mass(inverse_sum, sharing);
    }
    CouplingParams law = s.drag;
    if (s.drag.local_viscosity && shepard.has_resin()) law.mu = mu_sum / shepard.s;
    dem.void_fraction[f] = eps;
    dem.shepard_sum[f] = shepard.s;
    dem.resin_velocity[f] = shepard.mean();
    if (dt > 0) dem.mean_drag[f] = dem.drag_impulse[f] / dt;
    dem.drag_impulse[f].setZero();
    const double d = 2.0 * dem.radius[f];
    const double vol = s.thickness * particle_volume<D>(d);
    const Vec<D> vbar = shepard.mean();
    dem.drag_coeff[f] =
        shepard.has_resin() ? drag_k(law, eps, d, (vbar - dem.v[f]).norm()) * vol : 0.0;
    dem.drag_velocity[f] = vbar;
    if (!s.exponential_drag) {
      // The force the next first kick uses follows the new law.
      const Vec<D> drag = dem.drag_coeff[f] * (vbar - dem.v[f]);
      dem.force[f] += drag - dem.drag_force[f];
      dem.drag_force[f] = drag;
    }
    if (s.hydrodynamic_torque) hydrodynamic_torque<D>(sph, near, dem, f, dt, s.exponential_drag);
  }
}

// Loops over the DEM particles in increasing gid and adds each one's share
// to its resin neighbours: every resin particle then sums its DEM
// neighbours in gid order (rank-independent), at a cost set by the few DEM
// particles rather than by the whole resin.
template <int D>
Vec<D> reaction_on_resin(const CouplingSettings& s, const DemParticles<D>& dem,
                         SphParticles<D>& sph, CouplingState<D>& st,
                         std::vector<double>& resin_void_fraction, double& resin_drag_rate,
                         double impulse_dt) {
  const WendlandC2<D> kernel(s.h);
  const double support = kernel.support();
  resin_void_fraction.assign(sph.n_owned, 1.0);
  resin_drag_rate = 0;
  Vec<D> total = Vec<D>::Zero();
  if (dem.size() == 0) return total;
  // The drag pass's pairs: it checked them at these positions, so only a
  // reaction without that pass (other particles) searches; no second walk
  // over every resin position (issue 19).
  if (!st.pairs.built_for(sph, dem) || st.pairs.generation != st.generation ||
      st.pairs.support != support)
    update_coupling_pairs<D>(st.pairs, sph, dem, support, st.keep_pairs ? st.skin : 0.0,
                             st.generation);
  const CouplingPairs<D>& pairs = st.pairs;
  // The owned resin particles near the fibers, by slot: the ones that receive.
  const std::size_t n_slots = pairs.slot_resin.size();
  auto& slots = st.slots;
  slots.assign(n_slots, {});
  for (std::size_t k = 0; k < n_slots; ++k) {
    const auto r = static_cast<std::size_t>(pairs.slot_resin[k]);
    slots[k].vol = sph.mass[r] / sph.rho[r];
  }
  const double support2 = support * support;
  thread_local std::vector<std::int32_t> kept;
  thread_local std::vector<double> kept_dist;
  for (const std::int32_t fi : pairs.dem_order) {
    const auto f = static_cast<std::size_t>(fi);
    const double vol_f = dem_volume(dem, f);
    // Each neighbour r takes V_r W_fr of -F_mean / S_f (reaction.hpp).
    const Vec<D> share = terms::reaction_per_weight<D>(dem.shepard_sum[f], dem.mean_drag[f]);
    // sum_f (V_r W_fr / S_f) K_f V_f: the drag coefficient r is held by [kg/s].
    const double coeff_per_weight =
        dem.shepard_sum[f] > 0.0 ? dem.drag_coeff[f] / dem.shepard_sum[f] : 0.0;
    // The candidates that receive, owned (a ghost's owner receives) and
    // within the support, in list order, and their distances: the square
    // roots in a loop of their own, off each pair's chain
    // (docs/performance.md, "The coupling's filters without branches").
    const std::int32_t c0 = pairs.resin_start[f], c1 = pairs.resin_start[f + 1];
    const auto n_cand = static_cast<std::size_t>(std::max(c1 - c0, 0));
    kept.resize(n_cand);
    kept_dist.resize(n_cand);
    std::size_t n_kept = 0;
    for (std::int32_t c = c0; c < c1; ++c) {
      const auto r = static_cast<std::size_t>(pairs.resin_items[static_cast<std::size_t>(c)]);
      const Vec<D> d = sph.x[r] - dem.x[f];
      const double dist2 = d.squaredNorm();
      kept[n_kept] = c;
      kept_dist[n_kept] = dist2;
      n_kept += (pairs.resin_slot[static_cast<std::size_t>(c)] >= 0) & (dist2 < support2) ? 1 : 0;
    }
    for (std::size_t e = 0; e < n_kept; ++e) kept_dist[e] = std::sqrt(kept_dist[e]);
    for (std::size_t e = 0; e < n_kept; ++e) {
      const std::int32_t c = kept[e];
      const std::int32_t k = pairs.resin_slot[static_cast<std::size_t>(c)];
      auto& slot = slots[static_cast<std::size_t>(k)];
      const auto r = static_cast<std::size_t>(pairs.resin_items[static_cast<std::size_t>(c)]);
      const Vec<D> d = sph.x[r] - dem.x[f];
      const double dist = kept_dist[e];
      const double w = kernel.w(dist);
      slot.force += (slot.vol * w) * share;
      if (s.hydrodynamic_torque) {
        slot.force += terms::torque_reaction_force<D>(slot.vol * w, dem.torque_lever[f],
                                                      d - dem.resin_offset[f]);
      }
      slot.held += (slot.vol * w) * coeff_per_weight;
      slot.phi += terms::solid_fraction<D>(kernel, vol_f, dist);
      slot.phi_rate +=
          terms::solid_fraction_rate(vol_f, kernel.f(dist), (sph.v[r] - dem.v[f]).dot(d));
      slot.touched = true;
    }
  }
  for (std::size_t k = 0; k < n_slots; ++k) {
    const auto& slot = slots[k];
    if (!slot.touched) continue;
    const auto r = static_cast<std::size_t>(pairs.slot_resin[k]);
    // 2D: the drag is per depth `thickness`, the resin's mass per metre.
    if (impulse_dt > 0) {
      if (!sph.is_frozen(r)) {
        const Vec<D> dv = (impulse_dt / (s.thickness * sph.mass[r])) * slot.force;
        sph.v_half[r] += dv;
        sph.v[r] += dv;
      }
    } else {
      sph.a[r] += slot.force / (s.thickness * sph.mass[r]);
    }
    total += slot.force;
    resin_drag_rate = std::max(resin_drag_rate, slot.held / (s.thickness * sph.mass[r]));
    const double eps = terms::void_fraction(slot.phi, s.drag.eps_min);
    resin_void_fraction[r] = eps;
    if (s.void_fraction_in_continuity) {
      const double rate =
          terms::clipped_solid_fraction_rate(slot.phi, slot.phi_rate, s.drag.eps_min);
      sph.drho[r] = terms::continuity_void_fraction(sph.drho[r], sph.rho[r], rate, eps);
    }
  }
  return total;
}

template void drag_on_fibers<2>(const CouplingSettings&, const SphParticles<2>&, DemParticles<2>&,
                                CouplingState<2>&, double);
template void drag_on_fibers<3>(const CouplingSettings&, const SphParticles<3>&, DemParticles<3>&,
                                CouplingState<3>&, double);
template Vec<2> reaction_on_resin<2>(const CouplingSettings&, const DemParticles<2>&,
                                     SphParticles<2>&, CouplingState<2>&, std::vector<double>&,
                                     double&, double);
template Vec<3> reaction_on_resin<3>(const CouplingSettings&, const DemParticles<3>&,
                                     SphParticles<3>&, CouplingState<3>&, std::vector<double>&,
                                     double&, double);

}  // namespace sphdem
