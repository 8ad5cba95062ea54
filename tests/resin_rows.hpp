#pragma once
// Shared by the flow-front tests (test_front, test_ambient_pressure,
// test_melt_front, test_weld_insert): one row per owned resin particle,
// its gid and N values that the caller picks, gathered on rank 0 in gid
// order for the bitwise rank comparisons of mpi_test_helpers.hpp.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem::testing {

template <int N>
struct ResinRow {
  std::int64_t gid = 0;
  double value[N] = {};
};

// fill(i, value) writes particle i's N values; empty on ranks other than 0.
template <int N, int D, class Fill>
std::vector<ResinRow<N>> gather_resin_rows(const Comm& comm, const SphParticles<D>& ps,
                                           Fill&& fill) {
  std::vector<ResinRow<N>> mine;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    ResinRow<N> r;
    r.gid = ps.gid[i];
    fill(i, r.value);
    mine.push_back(r);
  }
  return testing_mpi::gather_rows(comm, mine);
}

}  // namespace sphdem::testing
