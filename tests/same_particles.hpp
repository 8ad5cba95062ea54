#pragma once
// Two runs' owned particles, matched by global id, hold the same bits:
// density, pressure, position and velocity (ASSERTs inside, so the first
// difference ends the comparison). Returns the resin particles compared.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>

#include "sphdem/particles/particles.hpp"

namespace sphdem::testing {

template <int D>
int expect_same_particles(const SphParticles<D>& pa, const SphParticles<D>& pb) {
  int fluid = 0;
  [&] {
    ASSERT_EQ(pa.n_owned, pb.n_owned);
    std::map<std::int64_t, std::size_t> at;
    for (std::size_t i = 0; i < pb.n_owned; ++i) at[pb.gid[i]] = i;
    for (std::size_t i = 0; i < pa.n_owned; ++i) {
      const auto j = at.find(pa.gid[i]);
      ASSERT_NE(j, at.end()) << "id " << pa.gid[i] << " only in the first run";
      ASSERT_EQ(pa.rho[i], pb.rho[j->second]) << "id " << pa.gid[i];
      ASSERT_EQ(pa.p[i], pb.p[j->second]) << "id " << pa.gid[i];
      for (int d = 0; d < D; ++d) {
        ASSERT_EQ(pa.x[i][d], pb.x[j->second][d]) << "id " << pa.gid[i];
        ASSERT_EQ(pa.v[i][d], pb.v[j->second][d]) << "id " << pa.gid[i];
      }
      fluid += pa.kind[i] == Kind::Fluid;
    }
  }();
  return fluid;
}

}  // namespace sphdem::testing
