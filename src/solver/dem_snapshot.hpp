#pragma once
// Packs DEM particles for the snapshot writer: set "dem" (position, the
// registry's output fields - velocity, angular_velocity, radius, fiber -
// and fiber_direction) with its bonds as line cells
// (bond_tensile_stress, bond_shear_stress, their peaks over the run and
// over the output interval (docs/dem.md, "Bond stress peaks"), broken,
// fiber, piece, fiber_direction). Each rank passes its owned particles and
// the bonds they own; a bond's line id is its bond id. `piece` and
// `piece_length` are the fiber each particle is in now that broken bonds
// split fibers (fiber_pieces.hpp): the smallest gid of the piece and its
// length. The fiber direction is the sum of the fiber's bond vectors (its
// end-to-end vector, bonds running in gid order), added in bond-id order.
// Both are computed by each fiber's home rank (fiber_homes.hpp), never from
// every particle gathered, and are bitwise rank-independent.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fiber_homes.hpp"
#include "snapshot_fields.hpp"
#include "sphdem/io/io.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

template <int D>
class DemSnapshotBuffers {
 public:
  // Collective (pieces and directions at the fibers' homes). The slots must be current
  // (DemDomain::store_state).
  DemSnapshotBuffers(const DemParticles<D>& ps, const Comm& comm) {
    const OwnedFiberState<D> state = owned_fiber_state(ps, comm);
    std::vector<std::size_t> owned(ps.n_owned);
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      owned[i] = i;
      id_.push_back(ps.gid[i]);
      for (int k = 0; k < D; ++k) position_.push_back(ps.x[i][k]);
    }
    fields_ = registry_output_fields(ps, owned, [](const char*) { return true; });
    OutputField direction{"fiber_direction", "1", D, {}};
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      for (int k = 0; k < D; ++k) direction.data.push_back(state.direction[i][k]);
    fields_.push_back(std::move(direction));
    OutputField piece{"piece", "1", 1, {}}, length{"piece_length", "m", 1, {}};
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      piece.data.push_back(static_cast<double>(state.piece[i]));
      length.data.push_back(state.length[i]);
    }
    fields_.push_back(std::move(piece));
    fields_.push_back(std::move(length));
    pack_bonds(ps, state);
  }

  ParticleSetView view() const {
    ParticleSetView v;
    v.name = "dem";
    v.n_local = id_.size();
    v.id = id_.data();
    v.dimension = D;
    v.position = position_.data();
    for (const OutputField& f : fields_)
      v.fields.push_back({f.name, f.units, f.components, f.data.data()});
    v.has_lines = true;
    v.lines.n_local = line_id_.size();
    v.lines.id = line_id_.data();
    v.lines.nodes = nodes_.data();
    v.lines.fields = {{"bond_tensile_stress", "Pa", 1, sigma_.data()},
                      {"bond_shear_stress", "Pa", 1, tau_.data()},
                      {"bond_tensile_stress_max", "Pa", 1, sigma_run_.data()},
                      {"bond_shear_stress_max", "Pa", 1, tau_run_.data()},
                      {"bond_tensile_stress_interval_max", "Pa", 1, sigma_interval_.data()},
                      {"bond_shear_stress_interval_max", "Pa", 1, tau_interval_.data()},
                      {"broken", "1", 1, broken_.data()},
                      {"fiber", "1", 1, line_fiber_.data()},
                      {"piece", "1", 1, line_piece_.data()},
                      {"fiber_direction", "1", D, direction_.data()}};
    return v;
  }

 private:
  void pack_bonds(const DemParticles<D>& ps, const OwnedFiberState<D>& state) {
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      for (std::size_t s = 0; s < ps.bonds[i].size(); ++s) {
        const DemBond<D>& b = ps.bonds[i][s];
        if (b.partner < 0) continue;
        const BondPeak& peak = ps.bond_peaks[i][s];
        line_id_.push_back(b.id);
        nodes_.insert(nodes_.end(), {ps.gid[i], b.partner});
        sigma_.push_back(b.sigma);
        tau_.push_back(b.tau);
        sigma_run_.push_back(peak.sigma_run);
        tau_run_.push_back(peak.tau_run);
        sigma_interval_.push_back(peak.sigma_interval);
        tau_interval_.push_back(peak.tau_interval);
        line_piece_.push_back(static_cast<double>(state.piece[i]));
        broken_.push_back(b.broken ? 1.0 : 0.0);
        line_fiber_.push_back(static_cast<double>(ps.fiber[i]));
        for (int k = 0; k < D; ++k) direction_.push_back(state.direction[i][k]);
      }
    }
  }

  std::vector<std::int64_t> id_, line_id_, nodes_;
  std::vector<double> position_;
  std::vector<OutputField> fields_;  // per particle
  std::vector<double> sigma_, tau_, broken_, line_fiber_, direction_;
  std::vector<double> sigma_run_, tau_run_, sigma_interval_, tau_interval_, line_piece_;
};

}  // namespace sphdem
