// Fiber pieces and directions computed at the fibers' home ranks
// (src/solver/fiber_homes.hpp, docs/checkpoint.md "At scale") against the
// version they replace, which gathered every particle and bond on every
// rank (kept here as the reference): bitwise the same piece ids, lengths
// and directions, at 1-4 ranks, with fibers split over ranks, broken bonds,
// loose particles and bond partners beyond the halo; and the same as one
// rank holding everything. A bond joining two fibers is refused.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <vector>

#include "../src/solver/fiber_homes.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/dem/dem_fibers.hpp"
#include "sphdem/parallel/ordered_sum.hpp"

namespace sphdem {
namespace {

// The gathered version (before fiber_homes.hpp): every rank gathers every
// particle and intact bond, and every fiber's bond vectors.
template <int D>
OwnedFiberState<D> gathered_fiber_state(const DemParticles<D>& ps, const Comm& comm) {
  std::int64_t n_fibers = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    n_fibers = std::max<std::int64_t>(n_fibers, ps.fiber[i] + 1);
  n_fibers = comm.max(n_fibers);
  std::vector<std::pair<std::int64_t, std::size_t>> index;
  for (std::size_t i = 0; i < ps.size(); ++i) index.emplace_back(ps.gid[i], i);
  std::sort(index.begin(), index.end());
  std::vector<OrderedTerm> terms, particles, bonds;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    particles.push_back({ps.gid[i], ps.fiber[i], ps.radius[i]});
    for (const DemBond<D>& b : ps.bonds[i]) {
      if (b.partner >= 0 && !b.broken) bonds.push_back({ps.gid[i], b.partner, 0.0});
      if (ps.fiber[i] < 0 || b.partner < 0) continue;
      const auto it =
          std::lower_bound(index.begin(), index.end(), std::make_pair(b.partner, std::size_t{0}));
      if (it == index.end() || it->first != b.partner) continue;
      const Vec<D> d = ps.x[it->second] - ps.x[i];
      for (int k = 0; k < D; ++k) terms.push_back({b.id, ps.fiber[i] * D + k, d[k]});
    }
  }
  const std::vector<KeySum> sums =
      ordered_sums(comm, terms, static_cast<std::size_t>(n_fibers * D));
  FiberPieceInput all;
  for (const OrderedTerm& t : gather_terms(comm, particles)) {
    all.gid.push_back(t.order);
    all.fiber.push_back(static_cast<std::int32_t>(t.key));
    all.radius.push_back(t.value);
  }
  for (const OrderedTerm& t : gather_terms(comm, bonds)) all.bonds.emplace_back(t.order, t.key);
  const FiberPieces global = fiber_pieces(all);
  OwnedFiberState<D> out;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const auto row = static_cast<std::size_t>(
        std::lower_bound(all.gid.begin(), all.gid.end(), ps.gid[i]) - all.gid.begin());
    out.piece.push_back(global.piece[row]);
    out.length.push_back(global.length[row]);
    Vec<D> d = Vec<D>::Zero();
    if (ps.fiber[i] >= 0) {
      for (int k = 0; k < D; ++k) d[k] = sums[static_cast<std::size_t>(ps.fiber[i] * D + k)].sum;
      d = fiber_homes_detail::unit_headless<D>(d);
    }
    out.direction.push_back(d);
  }
  return out;
}

// 60 fibers of 5 to 7 particles in a 2D or 3D box, every 4th bond broken,
// radii varying per fiber (lengths are sums of unequal numbers), and a few
// loose particles (fiber -1).
template <int D>
DemParticles<D> fibers() {
  DemSystem<D> sys;
  for (int batch = 0; batch < 3; ++batch) {
    FiberSpec<D> s;
    s.count = 20;
    s.particles_per_fiber = 5 + batch;
    s.radius = 1e-3 * (1.0 + 0.37 * batch);
    s.lo = Vec<D>::Constant(0.0);
    s.hi = Vec<D>::Constant(0.2);
    s.seed = 7 + static_cast<std::uint64_t>(batch);
    place_fibers(s, sys);
  }
  DemParticles<D> ps = sys.particles;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    for (DemBond<D>& b : ps.bonds[i])
      if (b.partner >= 0 && b.id % 4 == 1) b.broken = true;
  const std::size_t n = ps.n_owned;
  for (int k = 0; k < 3; ++k)
    ps.push_owned(static_cast<std::int64_t>(n) + k, -1, Vec<D>::Constant(0.3 + 0.01 * k), 1e-3,
                  2500);
  return ps;
}

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int world_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

// This rank's share of `all`: particles owned by gid hash (so every fiber
// is split over ranks), then as ghosts the others whose gid passes
// `ghost` (all of them, or some: partners beyond the halo).
template <int D, class Ghost>
DemParticles<D> share(DemParticles<D> all, Ghost ghost) {
  const int p = world_size(), me = world_rank();
  std::vector<std::size_t> mine, ghosts;
  for (std::size_t i = 0; i < all.n_owned; ++i) {
    if (static_cast<int>((all.gid[i] * 7 + 3) % p) == me)
      mine.push_back(i);
    else if (ghost(all.gid[i]))
      ghosts.push_back(i);
  }
  std::vector<std::size_t> order = mine;
  order.insert(order.end(), ghosts.begin(), ghosts.end());
  const std::size_t kept = order.size();
  // permute_owned takes a whole permutation: the rest go last, then are cut.
  std::vector<bool> used(all.n_owned, false);
  for (const std::size_t i : order) used[i] = true;
  for (std::size_t i = 0; i < all.n_owned; ++i)
    if (!used[i]) order.push_back(i);
  all.permute_owned(order);
  all.resize(kept);
  all.n_owned = mine.size();
  return all;
}

template <int D>
void expect_same(const OwnedFiberState<D>& a, const OwnedFiberState<D>& b) {
  ASSERT_EQ(a.piece.size(), b.piece.size());
  for (std::size_t i = 0; i < a.piece.size(); ++i) {
    EXPECT_EQ(a.piece[i], b.piece[i]) << "particle " << i;
    EXPECT_EQ(std::memcmp(&a.length[i], &b.length[i], sizeof(double)), 0) << "particle " << i;
    EXPECT_EQ(std::memcmp(a.direction[i].data(), b.direction[i].data(), sizeof(Vec<D>)), 0)
        << "particle " << i;
  }
}

template <int D>
void check_against_gathered() {
  const Comm world(MPI_COMM_WORLD);
  const DemParticles<D> all = fibers<D>();
  // Every partner visible: the same as one rank holding everything.
  const DemParticles<D> ps = share<D>(all, [](std::int64_t) { return true; });
  const OwnedFiberState<D> homes = owned_fiber_state(ps, world);
  expect_same(homes, gathered_fiber_state(ps, world));
  const OwnedFiberState<D> one = owned_fiber_state(all, Comm(MPI_COMM_SELF));
  OwnedFiberState<D> expected;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const auto j = static_cast<std::size_t>(ps.gid[i]);  // gids are 0..N-1 in order
    expected.piece.push_back(one.piece[j]);
    expected.length.push_back(one.length[j]);
    expected.direction.push_back(one.direction[j]);
  }
  expect_same(homes, expected);
  // The test means something: broken bonds split fibers into more pieces
  // than fibers, of different lengths.
  std::vector<std::int64_t> pieces;
  std::vector<double> lengths;
  for (std::size_t j = 0; j < all.n_owned; ++j) {
    if (all.fiber[j] < 0) continue;
    pieces.push_back(one.piece[j]);
    lengths.push_back(one.length[j]);
  }
  std::sort(pieces.begin(), pieces.end());
  std::sort(lengths.begin(), lengths.end());
  EXPECT_GT(std::unique(pieces.begin(), pieces.end()) - pieces.begin(), 60);
  EXPECT_GT(std::unique(lengths.begin(), lengths.end()) - lengths.begin(), 3);
  // Partners beyond the halo add no term, as before.
  const DemParticles<D> part = share<D>(all, [](std::int64_t g) { return g % 3 != 0; });
  expect_same(owned_fiber_state(part, world), gathered_fiber_state(part, world));
}

TEST(FiberHomes, SameAsGathered2D) {
  check_against_gathered<2>();
}
TEST(FiberHomes, SameAsGathered3D) {
  check_against_gathered<3>();
}

TEST(FiberHomes, BondBetweenFibersIsRefused) {
  DemParticles<2> ps = fibers<2>();
  // Particle 0 (fiber 0) bonded to the first particle of fiber 1 (gid 5).
  for (DemBond<2>& b : ps.bonds[0])
    if (b.partner < 0) {
      b.partner = 5;
      b.id = 100000;
      break;
    }
  EXPECT_THROW(owned_fiber_state(ps, Comm(MPI_COMM_SELF)), std::logic_error);
}

}  // namespace
}  // namespace sphdem
