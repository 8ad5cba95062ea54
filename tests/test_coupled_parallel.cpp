// A coupled resin + fiber run on N ranks against rank 0 alone (issue 5,
// docs/parallel.md): resin (gid, x, v, rho) and fibers (gid, x, v, omega)
// bitwise identical, with fibers straddling rank borders and re-partitions
// on the way. The coupling passes sum in global-id order and the DEM ghosts
// carry what the resin on another rank needs (drag, S_f).
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

struct Row {
  std::int64_t gid = 0;
  double value[6] = {};
};

struct State {
  std::vector<Row> resin, fibers;
  std::int64_t ghost_fibers = 0, repartitions = 0;
};

State run(const Comm& comm, std::int64_t steps, const std::string& drag = "explicit") {
  // Frequent re-partitions: the fibers must follow the resin's new map.
  const Case c =
      testing::load_input("validation/coupled_box.yaml",
                          {"parallel.balance_every=20", "parallel.imbalance_threshold=0.001",
                           "fibers.drag_integration=" + drag});
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
  st.resin = testing_mpi::gather_rows(comm, resin);
  st.fibers = testing_mpi::gather_rows(comm, fibers);
  st.ghost_fibers = comm.sum(ghosts);
  st.repartitions = sim.repartitions();
  return st;
}

TEST(CoupledParallel, RankIndependent) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  const std::int64_t kSteps = std::getenv("KSTEPS") ? std::atoll(std::getenv("KSTEPS")) : 400;
  State ref;
  if (world.root()) ref = run(Comm(MPI_COMM_SELF), kSteps);
  testing_mpi::wait_for_root(world);
  const State got = run(world, kSteps);
  if (!world.root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.resin, got.resin), 0u)
      << "resin differs from the 1-rank run";
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.fibers, got.fibers), 0u)
      << "fibers differ from the 1-rank run";
  EXPECT_EQ(got.fibers.size(), 120u);
  EXPECT_GT(got.ghost_fibers, 0) << "no fiber near a rank border";
  EXPECT_GT(got.repartitions, 0) << "no re-partition happened";
}

// The same with the exponential drag (docs/physics.md "Exponential drag"):
// the parcel's mass comes from the resin and fibers within the kernel, which
// every rank holding the fiber particle sees alike.
TEST(CoupledParallel, ExponentialDragRankIndependent) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  const std::int64_t kSteps = 200;
  State ref;
  if (world.root()) ref = run(Comm(MPI_COMM_SELF), kSteps, "exponential");
  testing_mpi::wait_for_root(world);
  const State got = run(world, kSteps, "exponential");
  if (!world.root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.resin, got.resin), 0u)
      << "resin differs from the 1-rank run";
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.fibers, got.fibers), 0u)
      << "fibers differ from the 1-rank run";
  EXPECT_GT(got.ghost_fibers, 0) << "no fiber near a rank border";
  EXPECT_GT(got.repartitions, 0) << "no re-partition happened";
}

}  // namespace
}  // namespace sphdem
