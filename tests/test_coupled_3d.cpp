// A 3D coupled resin + fiber run (inputs/validation/coupled_box_3d.yaml) on
// N ranks against rank 0 alone: resin (gid, x, v, rho) and fibers (gid, x,
// v, omega) bitwise identical, with fibers straddling rank borders and
// touching the mold's rectangle walls (docs/dem.md, "Walls").
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

struct Row {
  std::int64_t gid = 0;
  double value[10] = {};
};

struct State {
  std::vector<Row> resin, fibers;
  std::int64_t ghost_fibers = 0, wall_touches = 0;
};

Row row(std::int64_t gid, const Vec<3>& x, const Vec<3>& v, const Vec<3>& w, double s) {
  return {gid, {x[0], x[1], x[2], v[0], v[1], v[2], w[0], w[1], w[2], s}};
}

State run(const Comm& comm, std::int64_t steps) {
  const Case c =
      testing::load_input("validation/coupled_box_3d.yaml",
                          {"parallel.balance_every=20", "parallel.imbalance_threshold=0.001"});
  RunOptions opt;
  opt.write_output = false;
  Simulation<3> sim(c, comm, opt);
  State st;
  for (std::int64_t s = 0; s < steps; ++s) {
    sim.advance(1);
    const DemParticles<3>& f = sim.dem()->particles();
    st.ghost_fibers += static_cast<std::int64_t>(f.size() - f.n_owned);
    for (std::size_t i = 0; i < f.n_owned; ++i)
      for (const auto& w : f.wall_contacts[i]) st.wall_touches += w.partner != DemContact<3>::kNone;
  }
  const auto& ps = sim.particles();
  std::vector<Row> resin, fibers;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] == Kind::Fluid)
      resin.push_back(row(ps.gid[i], ps.x[i], ps.v[i], Vec<3>::Zero(), ps.rho[i]));
  }
  const DemParticles<3>& f = sim.dem()->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i)
    fibers.push_back(row(f.gid[i], f.x[i], f.v[i], f.omega[i], f.bonds[i][0].sigma));
  st.resin = testing_mpi::gather_rows(comm, resin);
  st.fibers = testing_mpi::gather_rows(comm, fibers);
  st.ghost_fibers = comm.sum(st.ghost_fibers);
  st.wall_touches = comm.sum(st.wall_touches);
  return st;
}

TEST(Coupled3D, RankIndependent) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  constexpr std::int64_t kSteps = 200;
  State ref;
  if (world.root()) ref = run(Comm(MPI_COMM_SELF), kSteps);
  testing_mpi::wait_for_root(world);
  const State got = run(world, kSteps);
  if (!world.root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.resin, got.resin), 0u)
      << "resin differs from the 1-rank run";
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.fibers, got.fibers), 0u)
      << "fibers differ from the 1-rank run";
  EXPECT_EQ(got.resin.size(), 2600u);
  EXPECT_EQ(got.fibers.size(), 48u);
  EXPECT_GT(got.wall_touches, 0) << "no fiber touched a wall";
  EXPECT_GT(got.ghost_fibers, 0) << "no fiber near a rank border";
}

}  // namespace
}  // namespace sphdem
