// Ghost plan and forward exchanges (docs/parallel.md, "Halo").
#include "sphdem/halo.hpp"

#include <algorithm>
#include <cmath>

#include "exchange.hpp"
#include "pack.hpp"

namespace sphdem {

namespace {

template <int D>
struct Target {
  int rank;
  Vec<D> shift;
};

// Distance from x (in cell c along axis k) to the neighbor cell at offset o.
template <int D>
double gap(const CellGrid<D>& g, const Vec<D>& x, int k, long c, long o) {
  if (o < 0) return std::max(0.0, x[k] - g.lower(k, c));
  if (o > 0) return std::max(0.0, g.lower(k, c + 1) - x[k]);
  return 0.0;
}

// The neighbor cell at offset o of cell c, wrapped across periodic faces
// (shift: what the copy's position gains), or -1 outside a closed face.
template <int D>
long offset_cell(const CellGrid<D>& g, const typename CellGrid<D>::Coords& c,
                 const std::array<long, 3>& o, Vec<D>& shift) {
  typename CellGrid<D>::Coords m = c;
  shift.setZero();
  for (int k = 0; k < D; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    m[uk] = c[uk] + o[uk];
    if (m[uk] >= 0 && m[uk] < g.dims()[uk]) continue;
    if (!g.periodic(k)) return -1;
    const bool below = m[uk] < 0;
    m[uk] += below ? g.dims()[uk] : -g.dims()[uk];
    shift[k] = below ? g.length(k) : -g.length(k);
  }
  return g.index(m);
}

// Every (rank, shift) that needs a copy of the owned particle at x: the
// owners of the neighbor cells within `range` of x, except this rank
// without a shift (the particle itself).
template <int D>
void ghost_targets(const Decomposition<D>& dec, const Vec<D>& x, double range,
                   std::vector<Target<D>>& out) {
  out.clear();
  const CellGrid<D>& g = dec.grid();
  const auto c = g.coords(x);
  // A hair wider than the neighbor search (which keeps r^2 < range^2), so
  // rounding in the cell bounds can only add a ghost, never lose one.
  const double r2 = range * range * (1.0 + 1e-9);
  const long z = D == 3 ? 1 : 0;
  for (long oz = -z; oz <= z; ++oz)
    for (long oy = -1; oy <= 1; ++oy)
      for (long ox = -1; ox <= 1; ++ox) {
        const std::array<long, 3> o{ox, oy, oz};
        if (ox == 0 && oy == 0 && oz == 0) continue;
        double d2 = 0.0;
        for (int k = 0; k < D; ++k) {
          const double d =
              gap<D>(g, x, k, c[static_cast<std::size_t>(k)], o[static_cast<std::size_t>(k)]);
          d2 += d * d;
        }
        if (d2 >= r2) continue;
        Target<D> t{0, Vec<D>::Zero()};
        const long cell = offset_cell<D>(g, c, o, t.shift);
        if (cell < 0) continue;
        t.rank = dec.owner_of_cell(cell);
        if (t.rank == dec.comm().rank() && t.shift.isZero(0.0)) continue;
        const auto same = [&](const Target<D>& u) {
          return u.rank == t.rank && u.shift == t.shift;
        };
        if (std::none_of(out.begin(), out.end(), same)) out.push_back(t);
      }
}

}  // namespace

template <int D>
void Halo<D>::build(const Decomposition<D>& dec, SphParticles<D>& ps, double range) {
  ps.clear_ghosts();
  comm_ = dec.comm().raw();
  const auto ranks = static_cast<std::size_t>(dec.comm().size());

  // Copies grouped by destination rank (counting sort keeps local order).
  std::vector<std::pair<int, std::size_t>> copies;  // rank, owned index
  std::vector<Vec<D>> shifts;
  std::vector<Target<D>> targets;
  std::vector<std::int64_t> counts(ranks, 0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    ghost_targets<D>(dec, ps.x[i], range, targets);
    for (const Target<D>& t : targets) {
      copies.emplace_back(t.rank, i);
      shifts.push_back(t.shift);
      ++counts[static_cast<std::size_t>(t.rank)];
    }
  }
  send_ = detail::route_from_counts(counts);
  recv_ = detail::route_from_counts(detail::transpose_counts(comm_, counts));
  std::vector<std::size_t> next(ranks + 1, 0);
  for (std::size_t r = 0; r < ranks; ++r)
    next[r + 1] = next[r] + static_cast<std::size_t>(counts[r]);
  send_index_.assign(copies.size(), 0);
  send_shift_.assign(copies.size(), Vec<D>::Zero());
  for (std::size_t k = 0; k < copies.size(); ++k) {
    const std::size_t at = next[static_cast<std::size_t>(copies[k].first)]++;
    send_index_[at] = copies[k].second;
    send_shift_[at] = shifts[k];
  }

  // Every ghost field once (the constants are never sent again).
  const auto want = [](FieldPolicy p) { return p.ghost; };
  std::vector<char> out;
  detail::pack_records(ps, send_index_, want, out);
  const std::size_t rec = detail::record_bytes(ps, want);
  std::vector<char> in(recv_.total() * rec);
  detail::exchange(comm_, send_, out.data(), recv_, in.data(), MPI_BYTE, rec);
  const std::size_t n_own = ps.n_owned;
  ps.resize(n_own + recv_.total());
  detail::unpack_records(ps, n_own, recv_.total(), want, in.data());
  ps.n_owned = n_own;

  build_wall_plan(ps, ranks);
  update_state(ps);  // applies the periodic shifts
}

// The wall ghosts' sub-plan. Both sides select the wall particles of each
// message in message order, so sender and receiver agree without talking.
template <int D>
void Halo<D>::build_wall_plan(const SphParticles<D>& ps, std::size_t ranks) {
  std::vector<std::int64_t> send_counts(ranks, 0), recv_counts(ranks, 0);
  wall_send_index_.clear();
  wall_recv_slot_.clear();
  for (std::size_t k = 0; k < send_.ranks.size(); ++k) {
    for (std::size_t e = send_.offsets[k]; e < send_.offsets[k + 1]; ++e) {
      if (ps.kind[send_index_[e]] != Kind::Wall) continue;
      wall_send_index_.push_back(send_index_[e]);
      ++send_counts[static_cast<std::size_t>(send_.ranks[k])];
    }
  }
  for (std::size_t k = 0; k < recv_.ranks.size(); ++k) {
    for (std::size_t e = recv_.offsets[k]; e < recv_.offsets[k + 1]; ++e) {
      if (ps.kind[ps.n_owned + e] != Kind::Wall) continue;
      wall_recv_slot_.push_back(ps.n_owned + e);
      ++recv_counts[static_cast<std::size_t>(recv_.ranks[k])];
    }
  }
  wall_send_ = detail::route_from_counts(send_counts);
  wall_recv_ = detail::route_from_counts(recv_counts);
}

template <int D>
void Halo<D>::update_state(SphParticles<D>& ps) {
  constexpr int per = 2 * D + 1;
  send_buf_.resize(send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t e = 0; e < send_index_.size(); ++e, b += per) {
    const std::size_t s = send_index_[e];
    const Vec<D> x = ps.x[s] + send_shift_[e];
    for (int k = 0; k < D; ++k) b[k] = x[k];
    for (int k = 0; k < D; ++k) b[D + k] = ps.v[s][k];
    b[2 * D] = ps.rho[s];
  }
  recv_buf_.resize(recv_.total() * per);
  detail::exchange(comm_, send_, send_buf_.data(), recv_, recv_buf_.data(), MPI_DOUBLE, per);
  const double* r = recv_buf_.data();
  for (std::size_t g = ps.n_owned; g < ps.n_owned + recv_.total(); ++g, r += per) {
    for (int k = 0; k < D; ++k) ps.x[g][k] = r[k];
    for (int k = 0; k < D; ++k) ps.v[g][k] = r[D + k];
    ps.rho[g] = r[2 * D];
  }
}

template <int D>
void Halo<D>::update_wall_state(SphParticles<D>& ps) {
  constexpr int per = D + 2;
  send_buf_.resize(wall_send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t s : wall_send_index_) {
    b[0] = ps.p[s];
    b[1] = ps.rho[s];
    for (int k = 0; k < D; ++k) b[2 + k] = ps.vwall[s][k];
    b += per;
  }
  recv_buf_.resize(wall_recv_slot_.size() * per);
  detail::exchange(comm_, wall_send_, send_buf_.data(), wall_recv_, recv_buf_.data(), MPI_DOUBLE,
                   per);
  const double* r = recv_buf_.data();
  for (std::size_t g : wall_recv_slot_) {
    ps.p[g] = r[0];
    ps.rho[g] = r[1];
    for (int k = 0; k < D; ++k) ps.vwall[g][k] = r[2 + k];
    r += per;
  }
}

template class Halo<2>;
template class Halo<3>;

}  // namespace sphdem
