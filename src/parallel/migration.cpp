// Periodic wrap and particle migration (docs/parallel.md).
#include <cmath>

#include "exchange.hpp"
#include "pack.hpp"
#include "sphdem/decomposition.hpp"
#include "sphdem/dem_particles.hpp"

namespace sphdem {

template <int D>
void wrap_periodic(SphParticles<D>& ps, const Box<D>& box, const std::array<bool, 3>& periodic) {
  for (int k = 0; k < D; ++k) {
    if (!periodic[static_cast<std::size_t>(k)]) continue;
    const double len = box.hi[k] - box.lo[k];
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      double& x = ps.x[i][k];
      if (x < box.lo[k] || x >= box.hi[k]) x -= len * std::floor((x - box.lo[k]) / len);
    }
  }
}

namespace {

// Leaving particles grouped by destination rank (in local order within a
// group) and the count per rank; `stay` gets the particles this rank keeps.
struct Departures {
  std::vector<std::size_t> leave;
  std::vector<std::int64_t> counts;
  std::vector<std::size_t> stay;
};

template <int D, class P>
Departures sort_departures(const Decomposition<D>& dec, const P& ps) {
  const int me = dec.comm().rank();
  Departures d;
  d.counts.assign(static_cast<std::size_t>(dec.comm().size()), 0);
  std::vector<int> dest(ps.n_owned);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    dest[i] = dec.owner(ps.x[i]);
    if (dest[i] == me)
      d.stay.push_back(i);
    else
      ++d.counts[static_cast<std::size_t>(dest[i])];
  }
  std::vector<std::size_t> next(d.counts.size() + 1, 0);
  for (std::size_t r = 0; r < d.counts.size(); ++r) {
    next[r + 1] = next[r] + static_cast<std::size_t>(d.counts[r]);
  }
  d.leave.resize(next.back());
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (dest[i] != me) d.leave[next[static_cast<std::size_t>(dest[i])]++] = i;
  }
  return d;
}

}  // namespace

template <int D, class P>
MigrationCounts migrate(const Decomposition<D>& dec, P& ps) {
  ps.clear_ghosts();
  const auto want = [](FieldPolicy p) { return p.migrate; };
  const Departures d = sort_departures(dec, ps);
  const MPI_Comm comm = dec.comm().raw();
  const detail::Route send = detail::route_from_counts(d.counts);
  const detail::Route recv = detail::route_from_counts(detail::transpose_counts(comm, d.counts));

  std::vector<char> out;
  detail::pack_records(ps, d.leave, want, out);
  const std::size_t rec = detail::record_bytes(ps, want);
  std::vector<char> in(recv.total() * rec);
  detail::exchange(comm, send, out.data(), recv, in.data(), MPI_BYTE, rec);

  ps.permute_owned(d.stay);
  const std::size_t kept = d.stay.size();
  ps.resize(kept + recv.total());
  detail::unpack_records(ps, kept, recv.total(), want, in.data());
  ps.n_owned = ps.size();
  return {d.leave.size(), recv.total()};
}

template void wrap_periodic<2>(SphParticles<2>&, const Box<2>&, const std::array<bool, 3>&);
template void wrap_periodic<3>(SphParticles<3>&, const Box<3>&, const std::array<bool, 3>&);
template MigrationCounts migrate<2>(const Decomposition<2>&, SphParticles<2>&);
template MigrationCounts migrate<3>(const Decomposition<3>&, SphParticles<3>&);
template MigrationCounts migrate<2>(const Decomposition<2>&, DemParticles<2>&);
template MigrationCounts migrate<3>(const Decomposition<3>&, DemParticles<3>&);

}  // namespace sphdem
