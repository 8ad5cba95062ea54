// The DEM pair list: bonds and contact candidates (gather order), the walls
// each particle may touch, the rebuild test, pair state back to the slots.
//
// Gather formulation (docs/dem.md, "Pairs"): every pair with an owned
// particle is evaluated once per rank that owns one of its two particles,
// from identical inputs (ghosts are exact copies), into a per-pair result;
// each owned particle then adds its pairs' results in increasing partner
// gid. The sums, and so the trajectories, are bitwise the same on any
// number of ranks, with no reverse communication.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dem_kernels.hpp"
#include "sphdem/dem/cell_list.hpp"
#include "sphdem/dem/dem_profile.hpp"

namespace sphdem {

dem_detail::DemProfile& dem_detail::dem_profile() {
  static DemProfile profile;
  return profile;
}

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
      const std::int32_t j = index.find_nearest(b.partner, ps.x[i], ps);
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
      // Across a periodic face (shear cells) i may be one of several copies
      // of its particle: the bond is the pair of mutually nearest copies.
      // Without this check a copy of i near the face whose partner has no
      // image there bonded to the partner's owned copy a period away, a
      // second bond on the partner that blew up the shear cell
      // (docs/physics.md "Shear cells").
      if (index.find_nearest(ps.gid[i], ps.x[static_cast<std::size_t>(j)], ps) !=
          static_cast<std::int32_t>(i))
        continue;
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
  // Each unordered pair once, then ordered by gid. The order they are found
  // in does not matter: each owned particle sums its pairs by partner gid.
  // The distance test reads the pair from its lower local index, as a walk
  // over particles finding their later neighbours does (the same bits).
  cells.for_each_pair([&](std::int32_t ii, std::int32_t jj) {
    const auto i = static_cast<std::size_t>(std::min(ii, jj));
    const auto j = static_cast<std::size_t>(std::max(ii, jj));
    if ((i >= n_own && j >= n_own) || ps.gid[i] == ps.gid[j]) return;
    const double reach = (ps.radius[i] + skin) + ps.radius[j];
    if ((ps.x[j] - ps.x[i]).squaredNorm() >= reach * reach) return;
    const bool i_first = ps.gid[i] < ps.gid[j];
    const std::size_t a = i_first ? i : j, b = i_first ? j : i;
    if (bond_slot<D>(ps.bonds[a], ps.gid[b]) >= 0) return;  // listed as a bond
    DemPair<D> pr;
    pr.a = static_cast<std::int32_t>(a);
    pr.b = static_cast<std::int32_t>(b);
    // A stored history is a contact that was active at the last evaluation:
    // it stays active, and goes back to the slots, until the next one
    // decides (a rebuild before any evaluation, as at a restart, must not
    // drop it).
    if (const DemContact<D>* c = contact_history<D>(ps.contacts[a], ps.gid[b])) {
      pr.xi = c->xi;
      pr.active = true;
    }
    damping.set(ps, pr);
    ws.pairs.push_back(pr);
  });

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
  ws.chains_valid = false;  // the bond chains index the local order
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
// A particle with no candidate wall has its wall history dropped here: it
// touches no wall until the next build, which its next force evaluation
// would find, dropping the history then (wall_forces). With its slots
// empty the force loops skip it without reading them (docs/dem.md,
// "Walls"): reading every particle's slots was 8 % of the 4800-fiber
// deck's loop (docs/performance.md, "The DEM walls' pass and the bond's
// divisions").
template <int D>
void dem_build_wall_lists(const std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
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
    if (ws.wall_start[i + 1] == ws.wall_start[i]) ps.wall_contacts[i] = WallContactSlots<D>{};
  }
  ws.wall_ref.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) ws.wall_ref[w] = walls[w].point;
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                                  \
  template void dem_build_pairs<D>(const DemParams<D>&, const std::vector<DemWall<D>>&,            \
                                   DemParticles<D>&, DemWorkspace<D>&);                            \
  template void dem_store_pair_state<D>(DemParticles<D>&, const DemWorkspace<D>&);                 \
  template double dem_max_displacement2<D>(const DemParticles<D>&, const std::vector<DemWall<D>>&, \
                                           const DemWorkspace<D>&);                                \
  template void dem_build_wall_lists<D>(const std::vector<DemWall<D>>&, DemParticles<D>&,          \
                                        DemWorkspace<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem
