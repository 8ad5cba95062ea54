// The lists a 3D step's sums walk (include/sphdem/neighbor/support_lists.hpp,
// docs/performance.md "The support lists"): the build's lists cut to the
// pairs within a radius, each list in its order and storage, cut again once
// the box of the particles' moves since the cut reaches the margin; and runs
// that walk them hold the same bits as runs that walk the build's lists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "listed_rows.hpp"
#include "same_particles.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/neighbor/support_lists.hpp"
#include "sphdem/particles/particles.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::listed;

using testing::quiet;
using testing::world;

// Every owned particle's kept list is its full list's entries closer than
// radius (or at a distance that is not a number), in the same order.
// Returns the pairs kept.
template <int D>
std::size_t expect_cut(const SphParticles<D>& ps, const NeighborList<D>& full,
                       const NeighborList<D>& kept, double radius) {
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    std::vector<std::int32_t> want;
    for (const std::int32_t j : listed(full, i)) {
      const double r2 = (ps.x[i] - ps.x[static_cast<std::size_t>(j)]).squaredNorm();
      if (!(r2 >= radius * radius)) want.push_back(j);
    }
    EXPECT_EQ(listed(kept, i), want) << i;
    pairs += want.size();
  }
  EXPECT_EQ(kept.total_pairs(), pairs);
  return pairs;
}

// A random cloud of `owned` particles (every fifth a wall) and 10 % more
// ghosts, half of them images of owned particles, sorted by cell.
template <int D>
SphParticles<D> cloud(unsigned seed, int owned, double side) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, side);
  const auto at = [&] {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = u(rng);
    return x;
  };
  SphParticles<D> ps;
  for (int k = 0; k < owned; ++k)
    ps.push_owned(k, k % 5 == 0 ? Kind::Wall : Kind::Fluid, -1, 1.0, at(), Vec<D>::Zero(), 1000.0);
  const auto n = static_cast<std::size_t>(owned);
  ps.resize(n + n / 10);
  for (std::size_t g = n; g < ps.size(); ++g) {
    ps.gid[g] = static_cast<std::int64_t>(g % 2 == 0 ? g - n : g);
    ps.kind[g] = g % 3 == 0 ? Kind::Wall : Kind::Fluid;
    ps.x[g] = at();
  }
  sort_by_cell<D>(ps, 1.3);
  return ps;
}

TEST(SupportLists, CutIsTheFullListsPairsWithinTheRadius2d) {
  const SphParticles<2> ps = cloud<2>(3, 2000, 20.0);
  NeighborList<2> full(1.0, 0.3), kept(0.0, 0.0);
  full.build(ps);
  kept.keep_within(full, ps, 1.0);
  const std::size_t pairs = expect_cut(ps, full, kept, 1.0);
  EXPECT_GT(pairs, 5000u);
  EXPECT_LT(pairs, full.total_pairs());  // some pairs were cut
  EXPECT_EQ(kept.wide_pairs(), 0u);
}

TEST(SupportLists, CutIsTheFullListsPairsWithinTheRadius3d) {
  const SphParticles<3> ps = cloud<3>(4, 3000, 9.0);
  NeighborList<3> full(1.0, 0.3), kept(0.0, 0.0);
  full.build(ps);
  for (const double radius : {1.0, 0.5, 1.3}) {  // the last keeps every pair
    kept.keep_within(full, ps, radius * radius);
    const std::size_t pairs = expect_cut(ps, full, kept, radius);
    EXPECT_GT(pairs, 1000u);
    if (radius < 1.3) {
      EXPECT_LT(pairs, full.total_pairs());
    }
  }
  EXPECT_EQ(kept.total_pairs(), full.total_pairs());
}

// A 200 x 200 lattice of spacing 1 in row order (offsets up to 201) and 50
// particles far off in index beside its first rows: their lists and those
// naming them are 32-bit, the rest 16-bit. A cut at 1.1 keeps the four
// nearest of the lattice's eight listed neighbours, each list in its storage.
TEST(SupportLists, CutKeepsEachListsStorage) {
  SphParticles<2> ps;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      ps.push_owned(200 * y + x, y == 0 ? Kind::Wall : Kind::Fluid, -1, 1.0, Vec<2>(x, y),
                    Vec<2>::Zero(), 1000.0);
  for (int k = 0; k < 50; ++k)
    ps.push_owned(40000 + k, Kind::Fluid, -1, 1.0, Vec<2>(4.0 * k + 0.5, 0.5), Vec<2>::Zero(),
                  1000.0);
  NeighborList<2> full(1.0, 0.5), kept(0.0, 0.0);
  full.build(ps);
  ASSERT_FALSE(full.all_wide());
  ASSERT_GT(full.wide_pairs(), 0u);
  kept.keep_within(full, ps, 1.1 * 1.1);
  EXPECT_FALSE(kept.all_wide());
  expect_cut(ps, full, kept, 1.1);
  EXPECT_EQ(listed(kept, 20100), (std::vector<std::int32_t>{19900, 20099, 20101, 20300}));
  // The far particles' lists (32-bit) keep the lattice nodes within 1.1:
  // all four around (4k + 0.5, 0.5).
  EXPECT_EQ(listed(kept, 40000), (std::vector<std::int32_t>{0, 1, 200, 201}));
  EXPECT_GT(kept.wide_pairs(), 0u);
  EXPECT_LT(kept.wide_pairs(), full.wide_pairs());

  // Every list far: all 32-bit, and so is the cut.
  const int half = 35000;
  SphParticles<2> far;
  for (int k = 0; k < 2 * half; ++k)
    far.push_owned(k, Kind::Fluid, -1, 1.0, Vec<2>(10.0 * (k % half), k < half ? 0.0 : 0.5),
                   Vec<2>::Zero(), 1000.0);
  far.x[5] = Vec<2>(10.0 * 5, 0.3);  // 0.3 from 5 + half's 0.5: only that pair within 0.25
  NeighborList<2> far_full(1.0, 0.2);
  far_full.build(far);
  ASSERT_TRUE(far_full.all_wide());
  kept.keep_within(far_full, far, 0.25 * 0.25);
  EXPECT_TRUE(kept.all_wide());
  expect_cut(far, far_full, kept, 0.25);
  EXPECT_EQ(kept.total_pairs(), 2u);
  EXPECT_EQ(kept.wide_pairs(), 2u);
}

// A pair whose distance is not a number stays, as the build's list holds it
// (the sums then see what they would see with that list).
TEST(SupportLists, CutKeepsDistancesThatAreNotANumber) {
  SphParticles<3> ps = cloud<3>(5, 800, 6.0);
  NeighborList<3> full(1.0, 0.3), kept(0.0, 0.0);
  full.build(ps);
  ps.x[7][1] = std::numeric_limits<double>::quiet_NaN();
  kept.keep_within(full, ps, 0.5 * 0.5);
  EXPECT_EQ(listed(kept, 7), listed(full, 7));
  expect_cut(ps, full, kept, 0.5);
}

// The lists are cut again at a new build, once the box of the moves since
// the cut has a diagonal of the margin or more, and when a move is not
// finite; not while the particles move together or within the margin.
TEST(SupportLists, CutAgainOnlyPastTheMargin) {
  SphParticles<3> ps = cloud<3>(6, 1500, 8.0);
  NeighborList<3> full(1.0, 0.4);
  full.build(ps);
  SupportLists<3> sl(1.0, 0.1);
  const auto cut_at = [&] {
    return expect_cut(ps, full, sl.lists(full, ps), 1.0 * (1 + 1e-6) + 0.1);
  };
  cut_at();
  EXPECT_EQ(sl.cuts(), 1);
  sl.lists(full, ps);
  EXPECT_EQ(sl.cuts(), 1);
  for (std::size_t i = 0; i < ps.size(); ++i) ps.x[i] += Vec<3>(0.3, -0.2, 0.25);  // together
  sl.lists(full, ps);
  EXPECT_EQ(sl.cuts(), 1);
  ps.x[3][0] += 0.04;              // the box's diagonal: 0.08
  ps.x[ps.size() - 1][0] -= 0.04;  // a ghost
  sl.lists(full, ps);
  EXPECT_EQ(sl.cuts(), 1);
  ps.x[ps.size() - 1][2] -= 0.07;  // sqrt(0.08^2 + 0.07^2) = 0.106
  cut_at();
  EXPECT_EQ(sl.cuts(), 2);
  ps.x[10][1] += std::numeric_limits<double>::infinity();
  sl.lists(full, ps);
  EXPECT_EQ(sl.cuts(), 3);
  ps.x[10][1] = 1.0;
  full.build(ps);
  cut_at();
  EXPECT_EQ(sl.cuts(), 4);
  sl.lists(full, ps);
  EXPECT_EQ(sl.cuts(), 4);
}

// Runs a and b `steps` steps, a on the support lists and b on the build's:
// the same bits, resin and fibers; returns a's cuts.
template <int D>
std::int64_t expect_same_run(const Case& c, int steps) {
  Simulation<D> a(c, world(), quiet());
  a.advance(steps);
  support_lists_on() = false;
  Simulation<D> b(c, world(), quiet());
  b.advance(steps);
  support_lists_on() = true;
  EXPECT_EQ(b.resin()->support_cuts(), 0);
  EXPECT_GT(testing::expect_same_particles<D>(a.particles(), b.particles()), 100);
  EXPECT_EQ(a.dem() == nullptr, b.dem() == nullptr);
  if (a.dem() != nullptr && b.dem() != nullptr) {
    EXPECT_GT(testing::expect_same_particles<D>(a.dem()->particles(), b.dem()->particles()), 0);
  }
  // More cuts than builds: the lists were cut between the builds too.
  EXPECT_GT(a.resin()->support_cuts(), a.resin()->neighbor_builds());
  return a.resin()->support_cuts();
}

// The coarse 3D plate: the piston's jet through the nozzle and the gate,
// the walls' state, anti-clump and delta-SPH, fibers and their coupling.
TEST(SupportLists, Plate3dIsTheSameBitsOnEitherLists) {
  EXPECT_GT(expect_same_run<3>(testing::load_input("plate_3d_fibers_coarse.yaml"), 300), 10);
}

// A 3D tank sloshing: a free surface against the walls.
TEST(SupportLists, Sloshing3dIsTheSameBitsOnEitherLists) {
  EXPECT_GT(expect_same_run<3>(testing::load_input("validation/hydrostatic_3d.yaml",
                                                   {"initial_velocity=[0.3, 0.1, 0]"}),
                               120),
            2);
}

}  // namespace
}  // namespace sphdem
