// The neighbour lists' storage (issue 19, docs/performance.md "16-bit
// neighbour lists"): 16-bit offsets from the particle's own index where
// they fit, 32-bit indices for a list with a neighbour farther off, every
// list 32-bit when those hold more than a quarter of the pairs. Whatever
// the storage, each list is what a brute-force search gives: every
// particle within the cut-off (walls: resin only), in global-id order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "listed_rows.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particles.hpp"

#include "../src/neighbor/cell_candidates.hpp"

namespace sphdem {
namespace {

using testing::listed;

void add(SphParticles<2>& ps, std::int64_t gid, Kind kind, Vec<2> x) {
  ps.push_owned(gid, kind, -1, 1.0, x, Vec<2>::Zero(), 1000.0);
}

// Particle i's list by brute force.
template <int D>
std::vector<std::int32_t> brute(const SphParticles<D>& ps, std::size_t i, double rc) {
  std::vector<std::int32_t> l;
  for (std::size_t j = 0; j < ps.size(); ++j) {
    if (j == i || (ps.kind[i] == Kind::Wall && ps.kind[j] == Kind::Wall)) continue;
    if ((ps.x[i] - ps.x[j]).squaredNorm() < rc * rc) l.push_back(static_cast<std::int32_t>(j));
  }
  std::sort(l.begin(), l.end(), [&](std::int32_t a, std::int32_t b) {
    if (ps.gid[a] != ps.gid[b]) return ps.gid[a] < ps.gid[b];
    return std::lexicographical_compare(ps.x[a].begin(), ps.x[a].end(), ps.x[b].begin(),
                                        ps.x[b].end());
  });
  return l;
}

void expect_rows(const SphParticles<2>& ps, const NeighborList<2>& nl,
                 const std::vector<std::size_t>& rows) {
  for (const std::size_t i : rows) EXPECT_EQ(listed(nl, i), brute(ps, i, nl.cutoff())) << i;
}

// A 200 x 200 lattice (spacing 1, cut-off 1.5: 8 neighbours, offsets up
// to 201) in row order, walls on the first row.
SphParticles<2> lattice() {
  SphParticles<2> ps;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      add(ps, 200 * y + x, y == 0 ? Kind::Wall : Kind::Fluid, Vec<2>(x, y));
  return ps;
}

// 600 owned particles (every fifth a wall) at random in a 10 x 10 box and
// 50 ghosts, half of them images of owned particles (the same gid); gids
// from `first`; sorted by cell as a rebuild does.
SphParticles<2> random_cloud(unsigned seed, std::int64_t first) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  SphParticles<2> ps;
  for (int k = 0; k < 600; ++k)
    add(ps, first + k, k % 5 == 0 ? Kind::Wall : Kind::Fluid, {u(rng), u(rng)});
  ps.resize(650);
  for (std::size_t g = 600; g < 650; ++g) {
    ps.gid[g] = first + static_cast<std::int64_t>(g % 2 == 0 ? g - 600 : g);
    ps.kind[g] = g % 3 == 0 ? Kind::Wall : Kind::Fluid;
    ps.x[g] = Vec<2>(u(rng), u(rng));
  }
  sort_by_cell<2>(ps, 1.2);
  return ps;
}

// Every owned particle's row against brute force.
void expect_all_rows(const SphParticles<2>& ps, const NeighborList<2>& nl) {
  std::vector<std::size_t> all(ps.n_owned);
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  expect_rows(ps, nl, all);
}

TEST(NeighborStorage, RandomCloudWithGhostsMatchesBruteForce) {
  const SphParticles<2> ps = random_cloud(7, 0);
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  expect_all_rows(ps, nl);
  EXPECT_EQ(nl.wide_pairs(), 0u);  // 650 particles: every offset fits
  EXPECT_FALSE(nl.all_wide());
}

// The owned particles whose list names a ghost, kept by the build for the
// free-surface flag's second run (src/sph/fluid_rates.cpp): exactly those,
// in index order, and none once the ghosts are gone.
TEST(NeighborStorage, GhostListersAreTheListsNamingAGhost) {
  SphParticles<2> ps = random_cloud(11, 0);
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  std::vector<std::uint32_t> expected;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const std::vector<std::int32_t> l = brute(ps, i, nl.cutoff());
    if (std::any_of(l.begin(), l.end(),
                    [&](std::int32_t j) { return static_cast<std::size_t>(j) >= ps.n_owned; }))
      expected.push_back(static_cast<std::uint32_t>(i));
  }
  // 50 ghosts in a 10 x 10 box, cut-off 1.2: most lists name one, not all.
  EXPECT_GT(expected.size(), 10u);
  EXPECT_LT(expected.size(), ps.n_owned);
  EXPECT_EQ(nl.ghost_listers(), expected);
  ps.clear_ghosts();  // no list names a ghost now
  nl.build(ps);
  EXPECT_TRUE(nl.ghost_listers().empty());
}

// The lists with an offset past 16 bits (the four lattice particles around
// particle 40,000 and its own) are kept 32-bit, the others 16-bit.
TEST(NeighborStorage, FarNeighbourKeepsThatListWide) {
  SphParticles<2> ps = lattice();
  add(ps, 40000, Kind::Fluid, Vec<2>(0.5, 0.5));  // among particles 0, 1, 200, 201
  NeighborList<2> nl(1.0, 0.5);
  nl.build(ps);
  EXPECT_FALSE(nl.all_wide());
  std::size_t far = 0;
  for (const std::size_t i : {0, 1, 200, 201, 40000}) far += nl.end(i) - nl.begin(i);
  EXPECT_EQ(nl.wide_pairs(), far);
  EXPECT_EQ(far, 3u + 4 + 6 + 9 + 4);  // walls 0 and 1 list resin only
  expect_rows(ps, nl, {0, 1, 2, 199, 200, 201, 202, 20100, 39799, 39998, 39999, 40000});
  EXPECT_EQ(listed(nl, 0).back(), 40000);  // the last gid
}

// Every list with a far neighbour: all 32-bit; then a layout that fits
// 16 bits again (a rebuild of the same list converts back).
TEST(NeighborStorage, MostlyFarListsAreAllWideAndBack) {
  const int half = 35000;
  SphParticles<2> ps;
  for (int k = 0; k < 2 * half; ++k)  // k and k + half side by side, 10 apart from the next
    add(ps, k, Kind::Fluid, Vec<2>(10.0 * (k % half), k < half ? 0.0 : 0.5));
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  EXPECT_TRUE(nl.all_wide());
  EXPECT_EQ(nl.total_pairs(), static_cast<std::size_t>(2 * half));
  EXPECT_EQ(nl.wide_pairs(), nl.total_pairs());
  expect_rows(ps, nl, {0, 1, 17, 34999, 35000, 35001, 69999});
  EXPECT_EQ(listed(nl, 3), std::vector<std::int32_t>{3 + half});

  for (int k = 0; k < 2 * half; ++k)  // pairs (2m, 2m + 1) side by side
    ps.x[static_cast<std::size_t>(k)] = Vec<2>(10.0 * (k / 2), 0.5 * (k % 2));
  nl.build(ps);
  EXPECT_FALSE(nl.all_wide());
  EXPECT_EQ(nl.wide_pairs(), 0u);
  expect_rows(ps, nl, {0, 1, 2, 3, 34999, 35000, 69998, 69999});

  for (int k = 0; k < 2 * half; ++k)  // and far apart again: 16-bit first, then converted
    ps.x[static_cast<std::size_t>(k)] = Vec<2>(10.0 * (k % half), k < half ? 0.0 : 0.5);
  nl.build(ps);
  EXPECT_TRUE(nl.all_wide());
  expect_rows(ps, nl, {0, 5, 34999, 35000, 69999});
}

// Fifty far lists among 40,000 16-bit ones: each as the brute force gives.
TEST(NeighborStorage, ManyFarListsAmongNarrowOnes) {
  SphParticles<2> ps = lattice();
  for (int k = 0; k < 50; ++k)  // far-indexed particles beside the lattice's first rows
    add(ps, 40000 + k, Kind::Fluid, Vec<2>(4.0 * k + 0.5, 0.5));
  NeighborList<2> mixed(1.0, 0.5);
  mixed.build(ps);
  ASSERT_FALSE(mixed.all_wide());
  ASSERT_GT(mixed.wide_pairs(), 0u);
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < ps.n_owned; i += 97) rows.push_back(i);
  for (std::size_t i = 40000; i < ps.n_owned; ++i) rows.push_back(i);
  for (std::size_t i = 0; i < 200; i += 4) rows.push_back(i);
  expect_rows(ps, mixed, rows);
}

// Two images of one particle (a period shorter than two cut-offs: the same
// gid twice in a list) are ordered by position, not by index: the later
// index sits first here. With every gid below 2^32 the build sorts packed
// 64-bit keys and orders such ties afterwards; with a larger gid it sorts
// (gid, position) directly; both give the brute force's order.
TEST(NeighborStorage, ImagesOfOneParticleAreOrderedByPosition) {
  for (const std::int64_t base : {std::int64_t{0}, std::int64_t{1} << 40}) {
    SphParticles<2> ps;
    add(ps, base + 5, Kind::Fluid, Vec<2>(0.0, 0.0));
    add(ps, base + 3, Kind::Fluid, Vec<2>(0.3, 0.1));
    add(ps, base + 9, Kind::Fluid, Vec<2>(-0.2, 0.4));
    ps.resize(6);  // ghosts: two images of gid base + 7 and one of base + 3
    const std::array<std::pair<std::int64_t, Vec<2>>, 3> ghosts{{{base + 7, Vec<2>(0.5, 0.2)},
                                                                 {base + 7, Vec<2>(-0.6, -0.1)},
                                                                 {base + 3, Vec<2>(0.1, -0.7)}}};
    for (std::size_t g = 0; g < ghosts.size(); ++g) {
      ps.gid[3 + g] = ghosts[g].first;
      ps.kind[3 + g] = Kind::Fluid;
      ps.x[3 + g] = ghosts[g].second;
    }
    NeighborList<2> nl(1.0, 0.0);
    nl.build(ps);
    expect_rows(ps, nl, {0, 1, 2});
    // Particle 0 lists gid 3 (the image at x = 0.1 before the owned one at
    // 0.3), 7 (the image at x = -0.6 before the one at 0.5) and 9.
    EXPECT_EQ(listed(nl, 0), (std::vector<std::int32_t>{5, 1, 4, 3, 2}));
  }
}

// The random cloud with gids past 32 bits: the build's other sort.
TEST(NeighborStorage, GidsPast32BitsMatchBruteForce) {
  // Gids around 3 * 2^33, all past 32 bits.
  const SphParticles<2> ps = random_cloud(11, (std::int64_t{3} << 33) - 300);
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  expect_all_rows(ps, nl);
}

// The candidates' sort, every size on both sides of the counted limit
// (kCountedKeys) and past it: std::sort's order. Keys as the build makes
// them (gid << 32 | index), in random order, with gids near 2^32 too.
TEST(NeighborStorage, SortKeysOfEverySizeIsStdSort) {
  std::mt19937_64 rng(11);
  std::vector<std::uint64_t> spare;
  for (std::size_t m = 0; m <= 2 * neighbor_detail::kCountedKeys + 3; ++m) {
    std::vector<std::uint64_t> key(m);
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint64_t gid = m % 2 == 0 ? rng() % 5000 : 0xffffffffULL - rng() % 5000;
      key[k] = gid << 32 | static_cast<std::uint32_t>(k);
    }
    std::vector<std::uint64_t> expected = key;
    std::sort(expected.begin(), expected.end());
    neighbor_detail::sort_keys(key.data(), m, spare);
    EXPECT_EQ(key, expected) << m << " keys";
  }
}

#if defined(SPHDEM_CANDIDATES_AVX512)
// The sorting network (src/neighbor/bitonic_keys.hpp) sorts any keys, not
// only the build's distinct ones: every size up to its 128, with repeated
// keys, with keys equal to its padding (2^64 - 1) and with keys already in
// order or reversed, std::sort's order.
TEST(NeighborStorage, SortingNetworkOfEverySizeIsStdSort) {
  std::mt19937_64 rng(5);
  for (std::size_t m = 0; m <= neighbor_detail::bitonic::kMaxKeys; ++m) {
    for (int shape = 0; shape < 4; ++shape) {
      std::vector<std::uint64_t> key(m);
      for (std::size_t k = 0; k < m; ++k) {
        if (shape == 0) key[k] = rng() % 7;  // many repeats
        if (shape == 1) key[k] = rng() % 3 == 0 ? ~std::uint64_t{0} : rng();
        if (shape == 2) key[k] = k;
        if (shape == 3) key[k] = (m - k) << 40;
      }
      std::vector<std::uint64_t> expected = key;
      std::sort(expected.begin(), expected.end());
      neighbor_detail::bitonic::sort(key.data(), m);
      EXPECT_EQ(key, expected) << m << " keys, shape " << shape;
    }
  }
}
#endif

// In 2D a cell's particles share one list of candidates, put in list order
// once (src/neighbor/cell_candidates.hpp): up to kCountedKeys of them by a branch-free
// rank sort, more by std::sort. A large cut-off (blocks of about 340
// candidates), a small one (about 4) and a cloud not sorted by cell (a
// cell's particles far apart in memory, its candidates gathered again and
// again) all give the brute force's lists.
TEST(NeighborStorage, SharedCellCandidatesOfEverySizeMatchBruteForce) {
  for (const double support : {0.3, 1.0, 2.0}) {
    const SphParticles<2> ps = random_cloud(5, 0);
    NeighborList<2> nl(support, 0.5 * support);
    nl.build(ps);
    expect_all_rows(ps, nl);
  }
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  SphParticles<2> unsorted;
  for (int k = 0; k < 500; ++k)
    add(unsorted, 499 - k, k % 4 == 0 ? Kind::Wall : Kind::Fluid, {u(rng), u(rng)});
  NeighborList<2> nl(1.0, 0.2);
  nl.build(unsorted);
  expect_all_rows(unsorted, nl);
}

// A particle two million cut-offs from the others (a runaway): the grid
// takes at most 2^20 cells along that axis, each wider than the cut-off,
// not 1.7 million of them; the sort by cell and the lists are still right.
TEST(NeighborStorage, FarParticleCoarsensTheGridListsStayExact) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  SphParticles<2> ps;
  for (int k = 0; k < 400; ++k) add(ps, k, k % 5 == 0 ? Kind::Wall : Kind::Fluid, {u(rng), u(rng)});
  add(ps, 400, Kind::Fluid, Vec<2>(2e6, 5.0));
  add(ps, 401, Kind::Fluid, Vec<2>(2e6 - 0.5, 5.0));  // its one neighbour
  sort_by_cell<2>(ps, 1.2);
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  expect_all_rows(ps, nl);
  std::size_t far = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.gid[i] >= 400) far += nl.end(i) - nl.begin(i);
  EXPECT_EQ(far, 2u);  // the far pair lists each other
}

// Particles spread over 10^7 cut-offs along every axis of a 3D domain: no
// grid of 2^60 cells (its count overflowed a long before), the solver's
// error (exit 3).
TEST(NeighborStorage, GridBeyondInt32CellsIsAClearError) {
  SphParticles<3> ps;
  ps.push_owned(0, Kind::Fluid, -1, 1.0, Vec<3>(0.0, 0.0, 0.0), Vec<3>::Zero(), 1000.0);
  ps.push_owned(1, Kind::Fluid, -1, 1.0, Vec<3>(1e7, 1e7, 1e7), Vec<3>::Zero(), 1000.0);
  NeighborList<3> nl(1.0, 0.2);
  try {
    nl.build(ps);
    ADD_FAILURE() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("neighbour-grid cells"), std::string::npos) << e.what();
  }
}

// The cells are numbered along the owned particles' shortest axis first
// and sort_by_cell puts each slab's walls after its resin (issue 19,
// docs/performance.md "Cells numbered along the short axis first"): a
// particle's neighbours lie close in memory however the domain lies.

// The largest |j - i| over the owned particles' lists.
template <int D>
long widest_offset(const NeighborList<D>& nl, std::size_t n_owned) {
  long widest = 0;
  for (std::size_t i = 0; i < n_owned; ++i) {
    const NeighborRow nb = nl.row(i);
    for (std::size_t n = nl.begin(i); n < nl.end(i); ++n)
      widest = std::max(widest, std::abs(static_cast<long>(nb[n]) - static_cast<long>(i)));
  }
  return widest;
}

// An `along` x `across` lattice of resin (spacing 1), between two rows of
// walls if `walls`, along x or along y, added in a shuffled order.
SphParticles<2> strip(int along, int across, bool along_x, bool walls) {
  std::vector<std::pair<Vec<2>, Kind>> sites;
  const int edge = walls ? 1 : 0;
  for (int a = 0; a < along; ++a)
    for (int c = -edge; c < across + edge; ++c) {
      const Kind kind = c < 0 || c == across ? Kind::Wall : Kind::Fluid;
      sites.push_back({along_x ? Vec<2>(a, c) : Vec<2>(c, a), kind});
    }
  std::shuffle(sites.begin(), sites.end(), std::mt19937(5));
  SphParticles<2> ps;
  for (std::size_t k = 0; k < sites.size(); ++k)
    add(ps, static_cast<std::int64_t>(k), sites[k].second, sites[k].first);
  return ps;
}

// 400 x 8 along either axis: the neighbours lie within the two lattice
// columns beside a particle's (x first, the old order, put 400 between
// rows of the strip along x). (With walls, a slab's resin lies between a
// particle and its wall neighbours: the next test.)
TEST(NeighborStorage, SortByCellNumbersTheShortAxisFirst) {
  for (const bool along_x : {true, false}) {
    SphParticles<2> ps = strip(400, 8, along_x, false);
    sort_by_cell<2>(ps, 1.2);
    NeighborList<2> nl(1.0, 0.2);
    nl.build(ps);
    EXPECT_LE(widest_offset(nl, ps.n_owned), 60) << "along x: " << along_x;
    const std::vector<std::size_t> some{0, 1, 7, 100, 1999, 3199};
    expect_rows(ps, nl, some);
  }
}

// 6,000 x 6 resin between two wall rows (48,000 particles): a few runs of
// walls (one per slab; a wall in every column of cells made thousands) and
// every list within 16 bits (walls after all the resin put the first
// slabs' walls 36,000 particles off).
TEST(NeighborStorage, SortByCellPutsEachSlabsWallsAfterItsResin) {
  SphParticles<2> ps = strip(6000, 6, true, true);
  sort_by_cell<2>(ps, 1.2);
  std::size_t runs = 0;  // of walls
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    runs += ps.kind[i] == Kind::Wall && (i == 0 || ps.kind[i - 1] != Kind::Wall);
  EXPECT_GE(runs, 2u);
  EXPECT_LE(runs, 12u);
  NeighborList<2> nl(1.0, 0.2);
  nl.build(ps);
  EXPECT_EQ(nl.wide_pairs(), 0u);
  EXPECT_LE(widest_offset(nl, ps.n_owned), 32767);
}

// A 3D plate 40 x 40 x 3, thin along each axis in turn: the neighbours lie
// within three layers of the long axes' cells (x first, the old order, put
// 1,600 between the layers of the plate thin along z).
TEST(NeighborStorage, SortByCellNumbersTheShortAxisFirst3D) {
  for (int thin = 0; thin < 3; ++thin) {
    SphParticles<3> ps;
    std::int64_t gid = 0;
    for (int a = 0; a < 40; ++a)
      for (int b = 0; b < 40; ++b)
        for (int c = 0; c < 3; ++c) {
          Vec<3> x;
          x[thin] = c;
          x[(thin + 1) % 3] = a;
          x[(thin + 2) % 3] = b;
          ps.push_owned(gid++, Kind::Fluid, -1, 1.0, x, Vec<3>::Zero(), 1000.0);
        }
    sort_by_cell<3>(ps, 1.2);
    NeighborList<3> nl(1.0, 0.2);
    nl.build(ps);
    EXPECT_LE(widest_offset(nl, ps.n_owned), 3 * 2 * 40 * 3) << "thin along " << thin;
  }
}

}  // namespace
}  // namespace sphdem

namespace sphdem {
namespace {

// 3D: the search eight candidates at a time where the CPU has AVX-512
// (src/neighbor/neighbor_list.cpp, BinnedCandidates), one at a time
// otherwise. A random cloud in a flat box (y, the short axis, is numbered
// first: the runs of cells go along it), every sixth particle a wall, with
// ghosts, half of them images of owned particles; about 120 neighbours
// each, so that runs end mid-vector. Every row against brute force.
TEST(NeighborStorage, RandomCloud3dWithGhostsMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(0.0, 8.0), uy(0.0, 2.5), uz(0.0, 5.0);
  SphParticles<3> ps;
  for (int k = 0; k < 1500; ++k)
    ps.push_owned(k, k % 6 == 0 ? Kind::Wall : Kind::Fluid, -1, 1.0,
                  Vec<3>(ux(rng), uy(rng), uz(rng)), Vec<3>::Zero(), 1000.0);
  ps.resize(1600);
  for (std::size_t g = 1500; g < 1600; ++g) {
    ps.gid[g] = static_cast<std::int64_t>(g % 2 == 0 ? g - 1500 : g);
    ps.kind[g] = g % 3 == 0 ? Kind::Wall : Kind::Fluid;
    ps.x[g] = Vec<3>(ux(rng), uy(rng), uz(rng));
  }
  NeighborList<3> nl(1.0, 0.2);
  nl.build(ps);
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const std::vector<std::int32_t> got = listed(nl, i);
    EXPECT_EQ(got, brute(ps, i, nl.cutoff())) << i;
    pairs += got.size();
  }
  EXPECT_GT(pairs, 1500U * 60U);  // long rows: many vectors each
}

}  // namespace
}  // namespace sphdem
