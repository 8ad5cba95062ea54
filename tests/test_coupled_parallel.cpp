// A coupled resin + fiber run on N ranks against rank 0 alone (issue 5,
// docs/parallel.md): resin (gid, x, v, rho) and fibers (gid, x, v, omega)
// bitwise identical, with fibers straddling rank borders and re-partitions
// on the way. The coupling passes sum in global-id order and the DEM ghosts
// carry what the resin on another rank needs (drag, S_f).
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "sphdem/comm.hpp"
#include "sphdem/config.hpp"
#include "sphdem/solver.hpp"

namespace sphdem {
namespace {

constexpr const char* kCase = R"(dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 50}
numerics: {spacing: 3.0e-4, end_time: 1.0, delta_sph: 0.1}
mold:
  shapes:
    - box: {min: [0, 0], max: [0.015, 0.009]}
fill:
  - box: {min: [0, 0], max: [0.015, 0.006]}
fibers:
  count: 30
  diameter: 2.5e-4
  density: 2540
  youngs_modulus: 1.0e8
  tensile_strength: 2.0e9
  region: {box: {min: [0.001, 0.001], max: [0.014, 0.005]}}
body_force: [0, -2000]
initial_velocity: [0.5, 0.2]
parallel: {balance_every: 20, imbalance_threshold: 0.001}
)";

struct Row {
  std::int64_t gid = 0;
  double value[6] = {};
};

std::vector<Row> gather(const Comm& comm, const std::vector<Row>& mine) {
  const int bytes = static_cast<int>(mine.size() * sizeof(Row));
  std::vector<int> counts(static_cast<std::size_t>(comm.size())), displs(counts.size(), 0);
  MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw());
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<Row> all(
      comm.root() ? static_cast<std::size_t>(displs.back() + counts.back()) / sizeof(Row) : 0);
  MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, 0,
              comm.raw());
  std::sort(all.begin(), all.end(), [](const Row& a, const Row& b) { return a.gid < b.gid; });
  return all;
}

struct State {
  std::vector<Row> resin, fibers;
  std::int64_t ghost_fibers = 0, repartitions = 0;
};

State run(const Comm& comm, std::int64_t steps) {
  const Case c = load_case_from_string(kCase, "coupled.yaml");
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  std::int64_t ghosts = 0;
  for (std::int64_t s = 0; s < steps; ++s) {
    sim.advance(1);
    const auto& f = sim.dem()->particles();
    ghosts += static_cast<std::int64_t>(f.size() - f.n_owned);
  }
  State st;
  const auto& ps = sim.particles();
  std::vector<Row> resin, fibers;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    resin.push_back({ps.gid[i], {ps.x[i][0], ps.x[i][1], ps.v[i][0], ps.v[i][1], ps.rho[i], 0}});
  }
  const auto& f = sim.dem()->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i) {
    fibers.push_back(
        {f.gid[i],
         {f.x[i][0], f.x[i][1], f.v[i][0], f.v[i][1], f.omega[i][0], f.bonds[i][0].sigma}});
  }
  st.resin = gather(comm, resin);
  st.fibers = gather(comm, fibers);
  st.ghost_fibers = comm.sum(ghosts);
  st.repartitions = sim.repartitions();
  return st;
}

std::size_t mismatches(const std::vector<Row>& a, const std::vector<Row>& b) {
  EXPECT_EQ(a.size(), b.size());
  std::size_t bad = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    EXPECT_EQ(a[i].gid, b[i].gid);
    if (std::memcmp(a[i].value, b[i].value, sizeof a[i].value) != 0) ++bad;
  }
  return bad;
}

TEST(CoupledParallel, RankIndependent) {
  const Comm world;
  const std::int64_t kSteps = std::getenv("KSTEPS") ? std::atoll(std::getenv("KSTEPS")) : 400;
  State ref;
  if (world.root()) ref = run(Comm(MPI_COMM_SELF), kSteps);
  MPI_Request req;
  MPI_Ibarrier(world.raw(), &req);
  for (int done = 0; !done;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const State got = run(world, kSteps);
  if (!world.root()) return;
  EXPECT_EQ(mismatches(ref.resin, got.resin), 0u) << "resin differs from the 1-rank run";
  EXPECT_EQ(mismatches(ref.fibers, got.fibers), 0u) << "fibers differ from the 1-rank run";
  EXPECT_EQ(got.fibers.size(), 120u);
  if (world.size() > 1) {
    EXPECT_GT(got.ghost_fibers, 0) << "no fiber near a rank border";
    EXPECT_GT(got.repartitions, 0) << "no re-partition happened";
  }
}

}  // namespace
}  // namespace sphdem
