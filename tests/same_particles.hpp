#pragma once
// Two runs' owned particles, matched by global id, hold the same bits:
// resin and wall particles their density, pressure, position and velocity,
// fiber particles their position and velocity (ASSERTs inside, so the
// first difference ends the comparison).
#include <gtest/gtest.h>

#include <cstdint>
#include <map>

#include "sphdem/particles/dem_particles.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem::testing {

// Returns the resin particles compared.
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

// Returns the fiber particles compared.
template <int D>
int expect_same_particles(const DemParticles<D>& fa, const DemParticles<D>& fb) {
  int compared = 0;
  [&] {
    ASSERT_EQ(fa.n_owned, fb.n_owned);
    std::map<std::int64_t, std::size_t> at;
    for (std::size_t i = 0; i < fb.n_owned; ++i) at[fb.gid[i]] = i;
    for (std::size_t i = 0; i < fa.n_owned; ++i) {
      const auto j = at.find(fa.gid[i]);
      ASSERT_NE(j, at.end()) << "fiber particle " << fa.gid[i] << " only in the first run";
      for (int d = 0; d < D; ++d) {
        ASSERT_EQ(fa.x[i][d], fb.x[j->second][d]) << "fiber particle " << fa.gid[i];
        ASSERT_EQ(fa.v[i][d], fb.v[j->second][d]) << "fiber particle " << fa.gid[i];
      }
      ++compared;
    }
  }();
  return compared;
}

}  // namespace sphdem::testing
