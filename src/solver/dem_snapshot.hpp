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
// length, from every rank's particles and intact bonds gathered, so they
// are rank-independent. The fiber direction is the sum of the fiber's
// bond vectors (its end-to-end vector, bonds running in gid order), added
// in bond-id order over all ranks, so it is bitwise rank-independent.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "snapshot_fields.hpp"
#include "sphdem/dem/fiber_pieces.hpp"
#include "sphdem/io/io.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/ordered_sum.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

template <int D>
class DemSnapshotBuffers {
 public:
  // Collective (the fiber directions). The slots must be current
  // (DemDomain::store_state).
  DemSnapshotBuffers(const DemParticles<D>& ps, const Comm& comm) {
    const std::vector<Vec<D>> dir = fiber_directions(ps, comm);
    std::vector<std::size_t> owned(ps.n_owned);
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      owned[i] = i;
      id_.push_back(ps.gid[i]);
      for (int k = 0; k < D; ++k) position_.push_back(ps.x[i][k]);
    }
    fields_ = registry_output_fields(ps, owned, [](const char*) { return true; });
    OutputField direction{"fiber_direction", "1", D, {}};
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      for (int k = 0; k < D; ++k) direction.data.push_back(direction_of(dir, ps.fiber[i])[k]);
    fields_.push_back(std::move(direction));
    const FiberPieces pieces = owned_pieces(ps, comm);
    OutputField piece{"piece", "1", 1, {}}, length{"piece_length", "m", 1, {}};
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      piece.data.push_back(static_cast<double>(pieces.piece[i]));
      length.data.push_back(pieces.length[i]);
    }
    fields_.push_back(std::move(piece));
    fields_.push_back(std::move(length));
    pack_bonds(ps, dir, pieces);
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
  // Unit end-to-end direction of every fiber (by fiber id), its first
  // nonzero component positive (a fiber has no head).
  static std::vector<Vec<D>> fiber_directions(const DemParticles<D>& ps, const Comm& comm) {
    std::int64_t n_fibers = 0;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      n_fibers = std::max<std::int64_t>(n_fibers, ps.fiber[i] + 1);
    n_fibers = comm.max(n_fibers);
    std::vector<std::pair<std::int64_t, std::size_t>> index;  // gid -> local, owned and ghosts
    for (std::size_t i = 0; i < ps.size(); ++i) index.emplace_back(ps.gid[i], i);
    std::sort(index.begin(), index.end());
    std::vector<OrderedTerm> terms;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.fiber[i] < 0) continue;
      for (const DemBond<D>& b : ps.bonds[i]) {
        if (b.partner < 0) continue;
        const auto it =
            std::lower_bound(index.begin(), index.end(), std::make_pair(b.partner, std::size_t{0}));
        if (it == index.end() || it->first != b.partner) continue;  // beyond the halo
        const Vec<D> d = ps.x[it->second] - ps.x[i];
        for (int k = 0; k < D; ++k) terms.push_back({b.id, ps.fiber[i] * D + k, d[k]});
      }
    }
    const std::vector<KeySum> sums =
        ordered_sums(comm, terms, static_cast<std::size_t>(n_fibers * D));
    std::vector<Vec<D>> out(static_cast<std::size_t>(n_fibers), Vec<D>::Zero());
    for (std::size_t f = 0; f < out.size(); ++f) {
      Vec<D> d;
      for (int k = 0; k < D; ++k) d[k] = sums[f * D + static_cast<std::size_t>(k)].sum;
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

  // The piece of every owned particle (in owned order): every rank gathers
  // all particles (order gid, key fiber, value radius) and intact bonds
  // (order owner gid, key partner gid) and finds the same pieces.
  static FiberPieces owned_pieces(const DemParticles<D>& ps, const Comm& comm) {
    std::vector<OrderedTerm> particles, bonds;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      particles.push_back({ps.gid[i], ps.fiber[i], ps.radius[i]});
      for (const DemBond<D>& b : ps.bonds[i])
        if (b.partner >= 0 && !b.broken) bonds.push_back({ps.gid[i], b.partner, 0.0});
    }
    FiberPieceInput all;
    for (const OrderedTerm& t : gather_terms(comm, particles)) {
      all.gid.push_back(t.order);
      all.fiber.push_back(static_cast<std::int32_t>(t.key));
      all.radius.push_back(t.value);
    }
    for (const OrderedTerm& t : gather_terms(comm, bonds)) all.bonds.emplace_back(t.order, t.key);
    const FiberPieces global = fiber_pieces(all);  // rows in gid order
    FiberPieces out;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      const auto it = std::lower_bound(all.gid.begin(), all.gid.end(), ps.gid[i]);
      const auto row = static_cast<std::size_t>(it - all.gid.begin());
      out.piece.push_back(global.piece[row]);
      out.length.push_back(global.length[row]);
    }
    return out;
  }

  static Vec<D> direction_of(const std::vector<Vec<D>>& dir, std::int32_t fiber) {
    return fiber >= 0 && static_cast<std::size_t>(fiber) < dir.size()
               ? dir[static_cast<std::size_t>(fiber)]
               : Vec<D>::Zero();
  }

  void pack_bonds(const DemParticles<D>& ps, const std::vector<Vec<D>>& dir,
                  const FiberPieces& pieces) {
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
        line_piece_.push_back(static_cast<double>(pieces.piece[i]));
        broken_.push_back(b.broken ? 1.0 : 0.0);
        line_fiber_.push_back(static_cast<double>(ps.fiber[i]));
        const Vec<D> d = direction_of(dir, ps.fiber[i]);
        for (int k = 0; k < D; ++k) direction_.push_back(d[k]);
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
