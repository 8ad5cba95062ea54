#pragma once
// Packs DEM particles for the snapshot writer: set "dem" (position,
// velocity, angular_velocity, radius, fiber) with its bonds as line cells
// (bond_tensile_stress, bond_shear_stress, broken, fiber, fiber_direction).
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "sphdem/dem_particles.hpp"
#include "sphdem/io.hpp"

namespace sphdem {

template <int D>
class DemSnapshotBuffers {
 public:
  // contribute = false: this rank passes no rows (another holds the copy).
  DemSnapshotBuffers(const DemParticles<D>& ps, bool contribute) {
    if (!contribute) return;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      id_.push_back(ps.gid[i]);
      for (int k = 0; k < D; ++k) {
        position_.push_back(ps.x[i][k]);
        velocity_.push_back(ps.v[i][k]);
      }
      for (int k = 0; k < (D == 2 ? 1 : 3); ++k) omega_.push_back(ps.omega[i][k]);
      radius_.push_back(ps.radius[i]);
      fiber_.push_back(static_cast<double>(ps.fiber[i]));
    }
    pack_bonds(ps);
  }

  ParticleSetView view() const {
    ParticleSetView v;
    v.name = "dem";
    v.n_local = id_.size();
    v.id = id_.data();
    v.dimension = D;
    v.position = position_.data();
    v.fields = {{"velocity", "m/s", D, velocity_.data()},
                {"radius", "m", 1, radius_.data()},
                {"fiber", "1", 1, fiber_.data()}};
    if constexpr (D == 2) {
      v.fields.push_back({"angular_velocity", "rad/s", 1, omega_.data()});
    } else {
      v.fields.push_back({"angular_velocity", "rad/s", 3, omega_.data()});
    }
    v.has_lines = true;
    v.lines.n_local = line_id_.size();
    v.lines.id = line_id_.data();
    v.lines.nodes = nodes_.data();
    v.lines.fields = {{"bond_tensile_stress", "Pa", 1, sigma_.data()},
                      {"bond_shear_stress", "Pa", 1, tau_.data()},
                      {"broken", "1", 1, broken_.data()},
                      {"fiber", "1", 1, line_fiber_.data()},
                      {"fiber_direction", "1", D, direction_.data()}};
    return v;
  }

 private:
  // End-to-end unit direction of every fiber, its first nonzero component
  // positive (a fiber has no head).
  static std::map<std::int32_t, Vec<D>> fiber_directions(const DemParticles<D>& ps) {
    std::map<std::int32_t, std::pair<std::size_t, std::size_t>> ends;  // lowest, highest gid
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.fiber[i] < 0) continue;
      auto [it, fresh] = ends.emplace(ps.fiber[i], std::make_pair(i, i));
      if (ps.gid[i] < ps.gid[it->second.first]) it->second.first = i;
      if (ps.gid[i] > ps.gid[it->second.second]) it->second.second = i;
    }
    std::map<std::int32_t, Vec<D>> out;
    for (const auto& [f, e] : ends) {
      Vec<D> d = ps.x[e.second] - ps.x[e.first];
      const double n = d.norm();
      d = n > 0 ? Vec<D>(d / n) : Vec<D>::Zero();
      for (int k = 0; k < D; ++k) {
        if (d[k] == 0) continue;
        if (d[k] < 0) d = -d;
        break;
      }
      out[f] = d;
    }
    return out;
  }

  void pack_bonds(const DemParticles<D>& ps) {
    const std::map<std::int32_t, Vec<D>> dir = fiber_directions(ps);
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      for (const DemBond<D>& b : ps.bonds[i]) {
        if (b.partner < 0) continue;
        line_id_.push_back(static_cast<std::int64_t>(line_id_.size()));
        nodes_.insert(nodes_.end(), {ps.gid[i], b.partner});
        sigma_.push_back(b.sigma);
        tau_.push_back(b.tau);
        broken_.push_back(b.broken ? 1.0 : 0.0);
        line_fiber_.push_back(static_cast<double>(ps.fiber[i]));
        const auto it = dir.find(ps.fiber[i]);
        for (int k = 0; k < D; ++k) direction_.push_back(it != dir.end() ? it->second[k] : 0.0);
      }
    }
  }

  std::vector<std::int64_t> id_, line_id_, nodes_;
  std::vector<double> position_, velocity_, omega_, radius_, fiber_;
  std::vector<double> sigma_, tau_, broken_, line_fiber_, direction_;
};

}  // namespace sphdem
