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

// Calls same(i, j) for every owned particle i of a, j of b with the same
// global id, after ASSERTing the same count; stops at the first fatal
// failure of the test (an ASSERT in `same`, or an id only in a).
template <class Particles, class Same>
void for_each_same_id(const Particles& a, const Particles& b, const char* what, Same same) {
  ASSERT_EQ(a.n_owned, b.n_owned) << what;
  std::map<std::int64_t, std::size_t> at;
  for (std::size_t i = 0; i < b.n_owned; ++i) at[b.gid[i]] = i;
  for (std::size_t i = 0; i < a.n_owned; ++i) {
    const auto j = at.find(a.gid[i]);
    ASSERT_NE(j, at.end()) << what << " " << a.gid[i] << " only in the first run";
    same(i, j->second);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// Returns the resin particles compared.
template <int D>
int expect_same_particles(const SphParticles<D>& pa, const SphParticles<D>& pb) {
  int fluid = 0;
  for_each_same_id(pa, pb, "id", [&](std::size_t i, std::size_t j) {
    ASSERT_EQ(pa.rho[i], pb.rho[j]) << "id " << pa.gid[i];
    ASSERT_EQ(pa.p[i], pb.p[j]) << "id " << pa.gid[i];
    for (int d = 0; d < D; ++d) {
      ASSERT_EQ(pa.x[i][d], pb.x[j][d]) << "id " << pa.gid[i];
      ASSERT_EQ(pa.v[i][d], pb.v[j][d]) << "id " << pa.gid[i];
    }
    fluid += pa.kind[i] == Kind::Fluid;
  });
  return fluid;
}

// Returns the fiber particles compared.
template <int D>
int expect_same_particles(const DemParticles<D>& fa, const DemParticles<D>& fb) {
  int compared = 0;
  for_each_same_id(fa, fb, "fiber particle", [&](std::size_t i, std::size_t j) {
    for (int d = 0; d < D; ++d) {
      ASSERT_EQ(fa.x[i][d], fb.x[j][d]) << "fiber particle " << fa.gid[i];
      ASSERT_EQ(fa.v[i][d], fb.v[j][d]) << "fiber particle " << fa.gid[i];
    }
    ++compared;
  });
  return compared;
}

}  // namespace sphdem::testing
