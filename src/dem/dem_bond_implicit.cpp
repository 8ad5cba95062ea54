// Implicit bonds (docs/dem.md, "Implicit bonds"): the bonded clusters
// (chains) of the owned particles and one banded linear solve per chain per
// step for the trapezoidal rule's drift velocity (Newmark 1959, J. Eng.
// Mech. Div. ASCE 85, 67: the average-acceleration method).
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "dem_bond_chains.hpp"
#include "dem_kernels.hpp"
#include "sphdem/dem/dem_profile.hpp"

namespace sphdem::dem_detail {

namespace {

template <int D>
constexpr int kDof = D == 2 ? 3 : 6;  // per particle: position, then rotation

// Symmetric positive definite matrix of half-bandwidth w in band storage
// (row r holds columns r - w .. r), factorised in place (Cholesky).
class BandSpd {
 public:
  void reset(int n, int w) {
    n_ = n;
    w_ = w;
    a_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(w + 1), 0.0);
  }
  int size() const { return n_; }
  int width() const { return w_; }
  // Entry (r, c), r >= c, r - c <= w.
  double& at(int r, int c) {
    return a_[static_cast<std::size_t>(r) * static_cast<std::size_t>(w_ + 1) +
              static_cast<std::size_t>(r - c)];
  }
  // Row and column k replaced by the identity, b keeping A x = b for the
  // others with x_k = value (a prescribed unknown).
  void prescribe(int k, double value, std::vector<double>& b) {
    for (int c = std::max(0, k - w_); c < k; ++c) {
      b[static_cast<std::size_t>(c)] -= at(k, c) * value;
      at(k, c) = 0;
    }
    for (int r = k + 1; r <= std::min(n_ - 1, k + w_); ++r) {
      b[static_cast<std::size_t>(r)] -= at(r, k) * value;
      at(r, k) = 0;
    }
    at(k, k) = 1;
    b[static_cast<std::size_t>(k)] = value;
  }
  // A = L L^T in place; then b <- A^-1 b.
  void solve(std::vector<double>& b) {
    for (int r = 0; r < n_; ++r) {
      for (int c = std::max(0, r - w_); c <= r; ++c) {
        double s = at(r, c);
        for (int k = std::max(0, r - w_); k < c; ++k) s -= at(r, k) * at(c, k);
        at(r, c) = r == c ? std::sqrt(s) : s / at(c, c);
      }
    }
    for (int r = 0; r < n_; ++r) {
      double s = b[static_cast<std::size_t>(r)];
      for (int k = std::max(0, r - w_); k < r; ++k) s -= at(r, k) * b[static_cast<std::size_t>(k)];
      b[static_cast<std::size_t>(r)] = s / at(r, r);
    }
    for (int r = n_ - 1; r >= 0; --r) {
      double s = b[static_cast<std::size_t>(r)];
      for (int k = r + 1; k <= std::min(n_ - 1, r + w_); ++k)
        s -= at(k, r) * b[static_cast<std::size_t>(k)];
      b[static_cast<std::size_t>(r)] = s / at(r, r);
    }
  }

 private:
  int n_ = 0, w_ = 0;
  std::vector<double> a_;
};

// The parallel bond's stiffness for increments (dx_i, dtheta_i, dx_j,
// dtheta_j) at the current geometry: K = B^T W B, B the strains of the
// incremental law (terms/parallel_bond.hpp): the change of length (kbar_n
// A), the contact points' slip in the bond's plane (kbar_s A; arms a_i, a_j
// to the contact point), in 3D the twist (kbar_s J), and the relative
// rotation across the axis (kbar_n I). Plain loops: small, and the same
// operations in the same order wherever it runs.
template <int D>
struct BondStiffness {
  static constexpr int kN = 2 * kDof<D>;
  static constexpr int kRows = D == 2 ? 3 : 8;
  std::array<std::array<double, kN>, kN> k{};
};

template <int D>
BondStiffness<D> bond_stiffness(const terms::BondLaw& law, const Vec<D>& n, double a_i,
                                double a_j) {
  constexpr int rows = BondStiffness<D>::kRows, cols = BondStiffness<D>::kN;
  std::array<std::array<double, cols>, rows> B{};
  std::array<double, rows> w{};
  if constexpr (D == 2) {
    const double t0 = -n[1], t1 = n[0];
    B[0] = {-n[0], -n[1], 0, n[0], n[1], 0};  // change of length
    B[1] = {-t0, -t1, -a_i, t0, t1, -a_j};    // slip across the axis
    B[2] = {0, 0, -1, 0, 0, 1};               // relative rotation
    w = {law.kn * law.s.area, law.ks * law.s.area, law.kn * law.s.inertia};
  } else {
    // P = I - n n^T (the bond's plane), N v = n x v.
    double P[3][3], N[3][3] = {{0, -n[2], n[1]}, {n[2], 0, -n[0]}, {-n[1], n[0], 0}};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) P[r][c] = (r == c ? 1.0 : 0.0) - n[r] * n[c];
    for (int c = 0; c < 3; ++c) {
      B[0][c] = -n[c];  // change of length
      B[0][6 + c] = n[c];
      B[4][3 + c] = -n[c];  // twist
      B[4][9 + c] = n[c];
      for (int r = 0; r < 3; ++r) {
        B[1 + r][c] = -P[r][c];  // slip in the plane
        B[1 + r][3 + c] = a_i * N[r][c];
        B[1 + r][6 + c] = P[r][c];
        B[1 + r][9 + c] = a_j * N[r][c];
        B[5 + r][3 + c] = -P[r][c];  // rotation across the axis
        B[5 + r][9 + c] = P[r][c];
      }
    }
    const double ka = law.ks * law.s.area, kb = law.kn * law.s.inertia;
    w = {law.kn * law.s.area, ka, ka, ka, law.ks * law.s.polar, kb, kb, kb};
  }
  BondStiffness<D> out;
  for (int r = 0; r < rows; ++r)
    for (int a = 0; a < cols; ++a) {
      if (B[r][a] == 0) continue;
      const double wb = w[r] * B[r][a];
      for (int c = 0; c < cols; ++c) out.k[a][c] += wb * B[r][c];
    }
  return out;
}

}  // namespace

template <int D>
void build_bond_chains(DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const std::size_t n = ps.size();
  const GidIndex<D> index(ps);
  // Every intact bond of every present particle, to its partner's nearest copy.
  struct Edge {
    std::int32_t owner, partner, slot;
  };
  std::vector<Edge> edges;
  std::vector<std::int32_t> deg(n + 1, 0);
  std::vector<std::int64_t> missing(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    for (int s = 0; s < kMaxBonds; ++s) {
      const DemBond<D>& b = ps.bonds[i][static_cast<std::size_t>(s)];
      if (b.partner < 0 || b.broken) continue;
      const std::int32_t j = index.find_nearest(b.partner, ps.x[i], ps);
      if (j < 0) {
        missing[i] = b.partner;
        continue;
      }
      edges.push_back({static_cast<std::int32_t>(i), j, s});
      ++deg[i + 1];
      ++deg[static_cast<std::size_t>(j) + 1];
    }
  }
  for (std::size_t i = 0; i < n; ++i) deg[i + 1] += deg[i];
  std::vector<std::int32_t> adj(static_cast<std::size_t>(deg[n])), fill(deg.begin(), deg.end() - 1);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    adj[static_cast<std::size_t>(fill[static_cast<std::size_t>(edges[e].owner)]++)] =
        static_cast<std::int32_t>(e);
    adj[static_cast<std::size_t>(fill[static_cast<std::size_t>(edges[e].partner)]++)] =
        static_cast<std::int32_t>(e);
  }
  ws.chain_start.assign(1, 0);
  ws.chain_items.clear();
  ws.bond_start.assign(1, 0);
  ws.chain_bonds.clear();
  ws.chain_band.clear();
  std::vector<std::int32_t> pos(n, -1);
  std::vector<std::int32_t> members;
  std::vector<std::int32_t> chain_edges;
  for (std::size_t seed = 0; seed < ps.n_owned; ++seed) {
    if (pos[seed] >= 0 || deg[seed + 1] == deg[seed]) continue;  // done, or no bond
    members.assign(1, static_cast<std::int32_t>(seed));
    chain_edges.clear();
    pos[seed] = 0;
    for (std::size_t k = 0; k < members.size(); ++k) {
      const auto m = static_cast<std::size_t>(members[k]);
      if (missing[m] >= 0) {
        throw SimulationError(fmt::format(
            "DEM particle {}: its bond partner {} is not on this rank, so its fiber is not whole "
            "here (fibers.bond_integration: implicit needs each fiber within the DEM halo; "
            "docs/dem.md, \"Implicit bonds\")",
            ps.gid[m], missing[m]));
      }
      for (std::int32_t a = deg[m]; a < deg[m + 1]; ++a) {
        const Edge& e = edges[static_cast<std::size_t>(adj[static_cast<std::size_t>(a)])];
        if (e.owner == members[k]) chain_edges.push_back(adj[static_cast<std::size_t>(a)]);
        const std::int32_t other = e.owner == members[k] ? e.partner : e.owner;
        if (pos[static_cast<std::size_t>(other)] >= 0) continue;
        pos[static_cast<std::size_t>(other)] = 0;
        members.push_back(other);
      }
    }
    // Gid order (a periodic image after its original, by local index).
    std::sort(members.begin(), members.end(), [&](std::int32_t x, std::int32_t y) {
      return std::make_tuple(ps.gid[static_cast<std::size_t>(x)], x) <
             std::make_tuple(ps.gid[static_cast<std::size_t>(y)], y);
    });
    for (std::size_t k = 0; k < members.size(); ++k)
      pos[static_cast<std::size_t>(members[k])] = static_cast<std::int32_t>(k);
    std::sort(chain_edges.begin(), chain_edges.end(), [&](std::int32_t x, std::int32_t y) {
      const Edge &ex = edges[static_cast<std::size_t>(x)], &ey = edges[static_cast<std::size_t>(y)];
      return std::make_tuple(pos[static_cast<std::size_t>(ex.owner)],
                             pos[static_cast<std::size_t>(ex.partner)], ex.slot) <
             std::make_tuple(pos[static_cast<std::size_t>(ey.owner)],
                             pos[static_cast<std::size_t>(ey.partner)], ey.slot);
    });
    std::int32_t band = 0;
    for (const std::int32_t ce : chain_edges) {
      const Edge& e = edges[static_cast<std::size_t>(ce)];
      typename DemWorkspace<D>::ChainBond cb;
      cb.a = pos[static_cast<std::size_t>(e.owner)];
      cb.b = pos[static_cast<std::size_t>(e.partner)];
      cb.owner = e.owner;
      cb.partner = e.partner;
      cb.slot = e.slot;
      band = std::max(band, std::abs(cb.a - cb.b));
      ws.chain_bonds.push_back(cb);
    }
    ws.chain_items.insert(ws.chain_items.end(), members.begin(), members.end());
    ws.chain_start.push_back(static_cast<std::int32_t>(ws.chain_items.size()));
    ws.bond_start.push_back(static_cast<std::int32_t>(ws.chain_bonds.size()));
    ws.chain_band.push_back(band);
  }
  ws.chains_valid = true;
}

template <int D>
void solve_bond_chains(const DemParams<D>& p, double dt, DemParticles<D>& ps, DemWorkspace<D>& ws) {
  const DemTimer timer(dem_profile().chains);
  constexpr int q = kDof<D>;
  const std::size_t n_own = ps.n_owned;
  ws.v_half.assign(ps.v.begin(), ps.v.begin() + static_cast<std::ptrdiff_t>(n_own));
  ws.omega_half.assign(ps.omega.begin(), ps.omega.begin() + static_cast<std::ptrdiff_t>(n_own));
  const double c = 0.25 * dt * dt;
  BandSpd a;
  std::vector<double> b;
  const std::size_t n_chains = ws.chain_band.size();
  for (std::size_t ch = 0; ch < n_chains; ++ch) {
    const std::int32_t* item = ws.chain_items.data() + ws.chain_start[ch];
    const int m = ws.chain_start[ch + 1] - ws.chain_start[ch];
    a.reset(m * q, (ws.chain_band[ch] + 1) * q - 1);
    b.assign(static_cast<std::size_t>(m * q), 0.0);
    for (int k = 0; k < m; ++k) {
      const auto i = static_cast<std::size_t>(item[k]);
      for (int d = 0; d < D; ++d) {
        a.at(k * q + d, k * q + d) = ps.mass[i];
        b[static_cast<std::size_t>(k * q + d)] = ps.mass[i] * ps.v[i][d];
      }
      for (int d = 0; d < q - D; ++d) {
        a.at(k * q + D + d, k * q + D + d) = ps.inertia[i];
        b[static_cast<std::size_t>(k * q + D + d)] = ps.inertia[i] * ps.omega[i][d];
      }
    }
    for (std::int32_t e = ws.bond_start[ch]; e < ws.bond_start[ch + 1]; ++e) {
      const auto& cb = ws.chain_bonds[static_cast<std::size_t>(e)];
      const auto i = static_cast<std::size_t>(cb.owner), j = static_cast<std::size_t>(cb.partner);
      const DemBond<D>& bond = ps.bonds[i][static_cast<std::size_t>(cb.slot)];
      if (bond.broken) continue;  // broke in an earlier step, before a rebuild
      const Vec<D> d = ps.x[j] - ps.x[i];
      const double dist = d.norm();
      if (!(dist > 0)) continue;
      const double ri = ps.radius[i], rj = ps.radius[j];
      const double delta = ri + rj - dist;
      const auto k_local = bond_stiffness<D>(bond_law(p, ri, rj, bond.rbar), Vec<D>(d / dist),
                                             ri - 0.5 * delta, rj - 0.5 * delta);
      for (int r = 0; r < 2 * q; ++r) {
        const int gr = (r < q ? cb.a : cb.b) * q + r % q;
        for (int s = 0; s < 2 * q; ++s) {
          const int gs = (s < q ? cb.a : cb.b) * q + s % q;
          if (gr >= gs) a.at(gr, gs) += c * k_local.k[r][s];
        }
      }
    }
    for (int k = 0; k < m; ++k) {
      const auto i = static_cast<std::size_t>(item[k]);
      if (!(ps.fixed[i] & kFixedMotion)) continue;
      for (int d = 0; d < D; ++d) a.prescribe(k * q + d, ps.v[i][d], b);
      for (int d = 0; d < q - D; ++d) a.prescribe(k * q + D + d, ps.omega[i][d], b);
    }
    a.solve(b);
    for (int k = 0; k < m; ++k) {
      const auto i = static_cast<std::size_t>(item[k]);
      if (i >= n_own || (ps.fixed[i] & kFixedMotion)) continue;
      for (int d = 0; d < D; ++d) ps.v[i][d] = b[static_cast<std::size_t>(k * q + d)];
      for (int d = 0; d < q - D; ++d) ps.omega[i][d] = b[static_cast<std::size_t>(k * q + D + d)];
    }
  }
}

template <int D>
void restore_half_velocities(DemParticles<D>& ps, const DemWorkspace<D>& ws) {
  std::copy(ws.v_half.begin(), ws.v_half.end(), ps.v.begin());
  std::copy(ws.omega_half.begin(), ws.omega_half.end(), ps.omega.begin());
}

#define SPHDEM_DEM_INSTANTIATE(D)                                                   \
  template void build_bond_chains<D>(DemParticles<D>&, DemWorkspace<D>&);           \
  template void solve_bond_chains<D>(const DemParams<D>&, double, DemParticles<D>&, \
                                     DemWorkspace<D>&);                             \
  template void restore_half_velocities<D>(DemParticles<D>&, const DemWorkspace<D>&);
SPHDEM_DEM_INSTANTIATE(2)
SPHDEM_DEM_INSTANTIATE(3)
#undef SPHDEM_DEM_INSTANTIATE

}  // namespace sphdem::dem_detail
