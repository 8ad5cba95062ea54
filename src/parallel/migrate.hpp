#pragma once
// Migration of any registry container (docs/parallel.md, "The step"):
// every owned particle whose cell belongs to another rank goes there with
// every kMigrate field. Instantiated for the SPH and DEM particles in
// migration.cpp; a header so that tests can move a test registry too.
#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include "exchange.hpp"
#include "pack.hpp"
#include "sphdem/parallel/decomposition.hpp"

namespace sphdem {

namespace detail {

// Leaving particles grouped by destination rank (in local order within a
// group) and the count per rank; `stay` the particles this rank keeps, when
// asked and some particle leaves (else all stay, in place).
struct Departures {
  std::vector<std::size_t> leave;
  std::vector<std::int64_t> counts;
  std::vector<std::size_t> stay;
};

// One owner lookup per particle: the few that leave are listed with their
// destination as they are found (no scratch per particle at a rebuild,
// where the lists and records of the last step are still held;
// docs/performance.md, "16-bit neighbour lists"), then grouped by rank.
template <int D, class P>
Departures sort_departures(const Decomposition<D>& dec, const P& ps, bool with_stay) {
  const int me = dec.comm().rank();
  Departures d;
  d.counts.assign(static_cast<std::size_t>(dec.comm().size()), 0);
  std::vector<std::pair<std::size_t, int>> leaving;  // (particle, rank), in order
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const int dest = dec.owner(ps.x[i]);
    if (dest == me) continue;
    leaving.emplace_back(i, dest);
    ++d.counts[static_cast<std::size_t>(dest)];
  }
  if (leaving.empty()) return d;
  std::vector<std::size_t> next(d.counts.size() + 1, 0);
  for (std::size_t r = 0; r < d.counts.size(); ++r) {
    next[r + 1] = next[r] + static_cast<std::size_t>(d.counts[r]);
  }
  d.leave.resize(leaving.size());
  for (const auto& [i, dest] : leaving) d.leave[next[static_cast<std::size_t>(dest)]++] = i;
  if (with_stay) {
    d.stay.reserve(ps.n_owned - leaving.size());
    std::size_t k = 0;  // the next leaving particle
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (k < leaving.size() && leaving[k].first == i)
        ++k;
      else
        d.stay.push_back(i);
    }
  }
  return d;
}

// Writes records from `in` to the particles slots[0..n), one after another.
template <class P, class Want>
void unpack_records_to(P& ps, const std::size_t* slots, std::size_t n, Want want, const char* in) {
  const std::size_t rec = record_bytes(ps, want);
  std::size_t offset = 0;
  ps.for_each_field([&](const char*, auto& field, FieldPolicy p) {
    if (!want(p)) return;
    const std::size_t size = sizeof(typename std::decay_t<decltype(field)>::value_type);
    for (std::size_t k = 0; k < n; ++k) {
      std::memcpy(static_cast<void*>(&field[slots[k]]), in + k * rec + offset, size);
    }
    offset += size;
  });
}

}  // namespace detail

template <int D, class P>
MigrationCounts migrate(const Decomposition<D>& dec, P& ps) {
  ps.clear_ghosts();
  const auto want = [](FieldPolicy p) { return p.migrate; };
  const detail::Departures d = detail::sort_departures(dec, ps, true);
  const MPI_Comm comm = dec.comm().raw();
  const detail::Route send = detail::route_from_counts(d.counts);
  const detail::Route recv = detail::route_from_counts(detail::transpose_counts(comm, d.counts));

  std::vector<char> out;
  detail::pack_records(ps, d.leave, want, out);
  const std::size_t rec = record_bytes(ps, want);
  std::vector<char> in(recv.total() * rec);
  detail::exchange(comm, send, out.data(), recv, in.data(), MPI_BYTE, rec);

  const std::size_t kept = ps.n_owned - d.leave.size();
  if (!d.leave.empty()) ps.permute_owned(d.stay);  // else all stay where they are
  ps.resize(kept + recv.total());
  detail::unpack_records(ps, kept, recv.total(), want, in.data());
  ps.n_owned = ps.size();
  return {d.leave.size(), recv.total()};
}

// As migrate, but only the particles that move are copied: arrivals fill
// the slots the departures leave (in increasing slot order), the rest go
// at the end; with fewer arrivals than departures, the last kept particles
// fill the remaining holes. The kept particles' order is not kept.
template <int D, class P>
MigrationCounts migrate_in_place(const Decomposition<D>& dec, P& ps) {
  ps.clear_ghosts();
  const auto want = [](FieldPolicy p) { return p.migrate; };
  const detail::Departures d = detail::sort_departures(dec, ps, false);
  const MPI_Comm comm = dec.comm().raw();
  const detail::Route send = detail::route_from_counts(d.counts);
  const detail::Route recv = detail::route_from_counts(detail::transpose_counts(comm, d.counts));

  thread_local std::vector<char> out, in;
  out.clear();
  detail::pack_records(ps, d.leave, want, out);
  const std::size_t rec = record_bytes(ps, want);
  in.resize(recv.total() * rec);
  detail::exchange(comm, send, out.data(), recv, in.data(), MPI_BYTE, rec);

  // The holes in increasing order (leave is grouped by destination).
  thread_local std::vector<std::size_t> holes;
  holes.assign(d.leave.begin(), d.leave.end());
  std::sort(holes.begin(), holes.end());
  const std::size_t n_old = ps.n_owned, n_leave = holes.size(), n_arrive = recv.total();
  const std::size_t n_new = n_old - n_leave + n_arrive;
  if (n_arrive < n_leave) {
    // The i-th smallest hole is at most n_old - n_leave + i, so the holes
    // left to fill are holes[n_arrive ..) below n_new; their sources are the
    // slots at or past n_new that are no holes, taken from the end.
    std::size_t src = n_old, back = n_leave;  // holes[back ..) lie past src
    for (std::size_t k = n_arrive; k < n_leave && holes[k] < n_new; ++k) {
      for (--src; back > k && holes[back - 1] == src; --src) --back;
      ps.copy_particle(holes[k], src);
    }
  }
  ps.resize(std::max(n_new, n_old));
  thread_local std::vector<std::size_t> slots;
  slots.assign(holes.begin(),
               holes.begin() + static_cast<std::ptrdiff_t>(std::min(n_arrive, n_leave)));
  for (std::size_t k = n_old; k < n_new; ++k) slots.push_back(k);
  detail::unpack_records_to(ps, slots.data(), n_arrive, want, in.data());
  ps.resize(n_new);
  ps.n_owned = n_new;
  return {n_leave, n_arrive};
}

}  // namespace sphdem
