// DEM on any number of ranks (issue 4, docs/parallel.md "DEM particles"):
// fibers that straddle rank borders, collide across them, migrate with
// their bonds and contact histories, and (in one test) break. Each test runs
// at the rank count the binary was started with and compares the gathered
// state with rank 0 running the same system alone on MPI_COMM_SELF: the
// gather formulation (dem.hpp) makes them bitwise identical; they need
// several ranks and check that bonds and contacts crossed rank borders
// (tests/dem.cmake leaves them out at one rank). The serial DemSystem path
// must agree with a 1-rank DemDomain too (run at one rank only).
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/dem/dem_fibers.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/dem_halo.hpp"
#include "sphdem/solver/dem_domain.hpp"

namespace sphdem {
namespace {

constexpr double kR = 1.25e-4;  // the paper's fiber particle radius [m]

// Soft fibers (E = 1 MPa) so that a few thousand sub-steps move them by
// millimetres: across rank borders, into each other and into the walls.
template <int D>
DemSystem<D> make_system(int fibers, double tensile_strength) {
  DemSystem<D> sys;
  sys.params.youngs_modulus = 1e6;
  sys.params.kn = contact_stiffness_from_bond(sys.params, kR, 1.0);
  sys.params.restitution = 0.7;
  sys.params.friction = 0.4;
  sys.params.tensile_strength = tensile_strength;
  sys.params.gravity = Vec<D>::Zero();
  sys.params.gravity[1] = -200.0;
  FiberSpec<D> spec;
  spec.count = fibers;
  spec.radius = kR;
  spec.density = 2540;
  spec.lo = Vec<D>::Constant(0.0);
  spec.hi = Vec<D>::Constant(6e-3);
  spec.seed = 7;
  place_fibers(spec, sys);
  sys.walls = box_walls<D>(spec.lo, spec.hi);
  // Random velocities up to 1.5 m/s (deterministic), spins included.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (std::size_t i = 0; i < sys.particles.n_owned; ++i) {
    for (int k = 0; k < D; ++k) sys.particles.v[i][k] = u(rng);
    sys.particles.omega[i].setConstant(0.1 * u(rng) / kR);
  }
  return sys;
}

struct Row {
  std::int64_t gid = 0;
  double value[16] = {};  // x, v, omega, bond sigma of slot 0, broken, its peaks
};

template <int D>
std::vector<Row> gather(const Comm& comm, const DemParticles<D>& ps) {
  std::vector<Row> mine;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    Row r;
    r.gid = ps.gid[i];
    int k = 0;
    for (int d = 0; d < D; ++d) r.value[k++] = ps.x[i][d];
    for (int d = 0; d < D; ++d) r.value[k++] = ps.v[i][d];
    for (int d = 0; d < ps.omega[i].size(); ++d) r.value[k++] = ps.omega[i][d];
    r.value[k++] = ps.bonds[i][0].sigma;
    r.value[k++] = ps.bonds[i][0].broken ? 1.0 : 0.0;
    const BondPeak& peak = ps.bond_peaks[i][0];
    for (double v : {peak.sigma_run, peak.tau_run, peak.sigma_interval, peak.tau_interval})
      r.value[k++] = v;
    mine.push_back(r);
  }
  return testing_mpi::gather_rows(comm, mine);
}

void expect_identical(const std::vector<Row>& ref, const std::vector<Row>& got) {
  ASSERT_EQ(ref.size(), got.size());
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref, got), 0u)
      << "DEM particles differing from the 1-rank run";
}

// What happened across rank borders during a run (summed over ranks).
struct Crossings {
  std::int64_t bonds_to_ghosts = 0;     // owned bonds whose partner is a ghost
  std::int64_t contacts_to_ghosts = 0;  // owned contact histories with a ghost partner
  std::int64_t broken = 0;
};

template <int D>
void count_crossings(const DemParticles<D>& ps, Crossings& c) {
  std::vector<std::int64_t> ghosts(ps.gid.begin() + static_cast<std::ptrdiff_t>(ps.n_owned),
                                   ps.gid.end());
  std::sort(ghosts.begin(), ghosts.end());
  const auto is_ghost = [&](std::int64_t g) {
    return std::binary_search(ghosts.begin(), ghosts.end(), g);
  };
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    for (const auto& b : ps.bonds[i])
      if (b.partner >= 0 && !b.broken && is_ghost(b.partner)) ++c.bonds_to_ghosts;
    for (const auto& k : ps.contacts[i])
      if (k.partner >= 0 && is_ghost(k.partner)) ++c.contacts_to_ghosts;
  }
}

template <int D>
struct RunResult {
  std::vector<Row> rows;
  Crossings crossings;
  std::int64_t rebuilds = 0;
};

// The system on `comm`, decomposed by DEM particles per cell.
// rebuild_twice: two rebuilds after every 100 sub-steps, the second before
// any force evaluation (as a coupled restart does): the results must not
// change.
template <int D>
RunResult<D> run_domain(const Comm& comm, int fibers, double strength, std::int64_t steps,
                        bool rebuild_twice = false) {
  DemSystem<D> sys = make_system<D>(fibers, strength);
  const double dt = sys.stable_dt();
  Box<D> box{Vec<D>::Constant(-1e-3), Vec<D>::Constant(7e-3)};
  Decomposition<D> dec(comm, box, {false, false, false}, DemDomain<D>::reach(kR, kR));
  std::vector<std::int64_t> work(static_cast<std::size_t>(dec.blocks()), 0);
  for (std::size_t i = 0; i < sys.particles.n_owned; ++i)
    ++work[static_cast<std::size_t>(dec.block_of(sys.particles.x[i]))];
  dec.partition(work, true);
  DemDomain<D> dom(dec, sys.params, sys.walls, std::move(sys.particles));
  RunResult<D> r;
  Crossings local;
  for (std::int64_t s = 0; s < steps; s += 100) {
    dom.advance(100, dt);
    dom.store_state();
    count_crossings(dom.particles(), local);
    if (rebuild_twice) {
      dom.rebuild();
      dom.rebuild();
    }
  }
  r.crossings.bonds_to_ghosts = comm.sum(local.bonds_to_ghosts);
  r.crossings.contacts_to_ghosts = comm.sum(local.contacts_to_ghosts);
  std::int64_t broken = 0;
  for (std::size_t i = 0; i < dom.particles().n_owned; ++i)
    for (const auto& b : dom.particles().bonds[i]) broken += b.partner >= 0 && b.broken;
  r.crossings.broken = comm.sum(broken);
  r.rebuilds = dom.rebuilds();
  r.rows = gather<D>(comm, dom.particles());
  return r;
}

template <int D>
void expect_rank_independent(int fibers, double strength, std::int64_t steps, bool expect_breaks) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  RunResult<D> ref;
  if (world.root()) ref = run_domain<D>(Comm(MPI_COMM_SELF), fibers, strength, steps);
  testing_mpi::wait_for_root(world);
  const RunResult<D> got = run_domain<D>(world, fibers, strength, steps);
  if (!world.root()) return;
  std::printf(
      "D=%d ranks %d: %lld rebuilds, %lld broken, %lld bond and %lld contact samples "
      "across ranks\n",
      D, world.size(), static_cast<long long>(got.rebuilds),
      static_cast<long long>(got.crossings.broken),
      static_cast<long long>(got.crossings.bonds_to_ghosts),
      static_cast<long long>(got.crossings.contacts_to_ghosts));
  expect_identical(ref.rows, got.rows);
  EXPECT_EQ(ref.rebuilds, got.rebuilds);  // rebuilds are global decisions
  EXPECT_GT(got.rebuilds, 3);             // particles moved, migrated
  EXPECT_EQ(ref.crossings.broken, got.crossings.broken);
  if (expect_breaks) {
    EXPECT_GT(got.crossings.broken, 0);
  }
  EXPECT_GT(got.crossings.bonds_to_ghosts, 0) << "no fiber straddled a rank border";
  EXPECT_GT(got.crossings.contacts_to_ghosts, 0) << "no collision across a rank border";
}

TEST(DemParallel, FibersAcrossRanks2D) {
  expect_rank_independent<2>(60, 1e12, 3000, false);
}

TEST(DemParallel, BreakingFibersAcrossRanks2D) {
  expect_rank_independent<2>(60, 1e5, 3000, true);
}

TEST(DemParallel, FibersAcrossRanks3D) {
  expect_rank_independent<3>(300, 1e12, 2000, false);
}

// The serial driver (DemSystem, used by the validation tests) and a 1-rank
// DemDomain run the same arithmetic.
// The sub-step's rebuild vote rides on the ghost update (DemHalo::
// forward_max): every rank gets the largest vote, also a rank that sends
// no ghost to anyone, and a NaN on one rank reaches every rank (so all
// take the same decision).
TEST(DemParallel, HaloVoteAcrossRanks) {
  const Comm comm;
  const Box<2> box{Vec<2>::Constant(0.0), Vec<2>::Constant(1.0)};
  Decomposition<2> dec(comm, box, {false, false, false}, 0.1);
  std::vector<std::int64_t> work(static_cast<std::size_t>(dec.blocks()), 1);
  dec.partition(work, true);
  DemParticles<2> ps;  // no particle: no ghost travels
  DemHalo<2> halo;
  halo.build(dec, ps, 0.1);
  const int n = comm.size(), me = comm.rank();
  EXPECT_EQ(halo.forward_max(ps, DemGroup::State, 1.5 * (me + 1)), 1.5 * n);
  EXPECT_EQ(halo.forward_max(ps, DemGroup::State, -1.0 * me), 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(halo.forward_max(ps, DemGroup::State, me == n - 1 ? nan : 1.0)));
}

TEST(DemParallel, SerialDriverMatchesDomain) {
  const Comm self(MPI_COMM_SELF);
  DemSystem<2> sys = make_system<2>(30, 1e12);
  const double dt = sys.stable_dt();
  for (int s = 0; s < 1500; ++s) sys.step(dt);
  const RunResult<2> dom = run_domain<2>(self, 30, 1e12, 1500);
  expect_identical(gather<2>(self, sys.particles), dom.rows);
}

// A rebuild stores the pairs' contact histories back into the slots and
// reads them again; one that comes before any force evaluation since the
// last (a coupled restart rebuilds twice) must keep them too. It dropped
// them before issue 15 (defect 2): the trajectories then differed.
TEST(DemParallel, RebuildBeforeEvaluationKeepsContactHistory) {
  const Comm self(MPI_COMM_SELF);
  const RunResult<2> plain = run_domain<2>(self, 30, 1e12, 1500);
  const RunResult<2> twice = run_domain<2>(self, 30, 1e12, 1500, /*rebuild_twice=*/true);
  EXPECT_GT(twice.rebuilds, plain.rebuilds + 20);
  expect_identical(plain.rows, twice.rows);
}

}  // namespace
}  // namespace sphdem
