#pragma once
// Migration of any registry container (docs/parallel.md, "The step"):
// every owned particle whose cell belongs to another rank goes there with
// every kMigrate field. Instantiated for the SPH and DEM particles in
// migration.cpp; a header so that tests can move a test registry too.
#include <vector>

#include "exchange.hpp"
#include "pack.hpp"
#include "sphdem/parallel/decomposition.hpp"

namespace sphdem {

namespace detail {

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

}  // namespace detail

template <int D, class P>
MigrationCounts migrate(const Decomposition<D>& dec, P& ps) {
  ps.clear_ghosts();
  const auto want = [](FieldPolicy p) { return p.migrate; };
  const detail::Departures d = detail::sort_departures(dec, ps);
  const MPI_Comm comm = dec.comm().raw();
  const detail::Route send = detail::route_from_counts(d.counts);
  const detail::Route recv = detail::route_from_counts(detail::transpose_counts(comm, d.counts));

  std::vector<char> out;
  detail::pack_records(ps, d.leave, want, out);
  const std::size_t rec = record_bytes(ps, want);
  std::vector<char> in(recv.total() * rec);
  detail::exchange(comm, send, out.data(), recv, in.data(), MPI_BYTE, rec);

  ps.permute_owned(d.stay);
  const std::size_t kept = d.stay.size();
  ps.resize(kept + recv.total());
  detail::unpack_records(ps, kept, recv.total(), want, in.data());
  ps.n_owned = ps.size();
  return {d.leave.size(), recv.total()};
}

}  // namespace sphdem
