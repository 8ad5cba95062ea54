// The 3D mold cases' coarse variants (inputs/plate_3d_fibers_coarse.yaml,
// inputs/ribbed_part_fibers_coarse.yaml, docs/performance.md "3D molds"):
// N ranks bitwise equal to rank 0 alone (resin and fibers), the resin's ids
// conserved (no particle lost or made), and every fiber particle inside the
// cavity (the union of the mold's boxes) after the run.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

struct Row {
  std::int64_t gid = 0;
  double value[7] = {};
};

struct State {
  std::vector<Row> resin, fibers;
  std::vector<std::int64_t> resin_ids_at_start;
  std::int64_t fibers_outside = 0, ghost_fibers = 0;
};

Row row(std::int64_t gid, const Vec<3>& x, const Vec<3>& v, double s) {
  return {gid, {x[0], x[1], x[2], v[0], v[1], v[2], s}};
}

std::vector<std::int64_t> resin_ids(const Comm& comm, const SphParticles<3>& ps) {
  std::vector<Row> mine;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.kind[i] == Kind::Fluid) mine.push_back({ps.gid[i], {}});
  std::vector<std::int64_t> ids;
  for (const Row& r : testing_mpi::gather_rows(comm, mine)) ids.push_back(r.gid);
  return ids;
}

State run(const std::string& input, const Comm& comm, std::int64_t steps) {
  const Case c = testing::load_input(input);
  RunOptions opt;
  opt.write_output = false;
  Simulation<3> sim(c, comm, opt);
  State st;
  st.resin_ids_at_start = resin_ids(comm, sim.particles());
  for (std::int64_t s = 0; s < steps; ++s) {
    sim.advance(1);
    const DemParticles<3>& f = sim.dem()->particles();
    st.ghost_fibers += static_cast<std::int64_t>(f.size() - f.n_owned);
  }
  const auto& ps = sim.particles();
  std::vector<Row> resin, fibers;
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.kind[i] == Kind::Fluid) resin.push_back(row(ps.gid[i], ps.x[i], ps.v[i], ps.rho[i]));
  const DemParticles<3>& f = sim.dem()->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i) {
    fibers.push_back(row(f.gid[i], f.x[i], f.v[i], f.bonds[i][0].sigma));
    st.fibers_outside += !union_contains<3>(c.mold.shapes, f.x[i]);
  }
  st.resin = testing_mpi::gather_rows(comm, resin);
  st.fibers = testing_mpi::gather_rows(comm, fibers);
  st.fibers_outside = comm.sum(st.fibers_outside);
  st.ghost_fibers = comm.sum(st.ghost_fibers);
  return st;
}

void check_case(const std::string& input, std::int64_t steps, std::size_t fiber_particles) {
  const Comm world;
  ASSERT_GT(world.size(), 1) << "a comparison with one rank needs several ranks";
  State ref;
  if (world.root()) ref = run(input, Comm(MPI_COMM_SELF), steps);
  testing_mpi::wait_for_root(world);
  const State got = run(input, world, steps);
  if (!world.root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.resin, got.resin), 0u)
      << input << ": resin differs from the 1-rank run";
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.fibers, got.fibers), 0u)
      << input << ": fibers differ from the 1-rank run";
  std::vector<std::int64_t> ids_now;
  for (const Row& r : got.resin) ids_now.push_back(r.gid);
  EXPECT_EQ(ids_now, got.resin_ids_at_start) << input << ": resin particles lost or made";
  EXPECT_FALSE(ids_now.empty());
  EXPECT_EQ(got.fibers.size(), fiber_particles) << input << ": fiber particles lost or made";
  EXPECT_EQ(got.fibers_outside, 0) << input << ": fiber particles outside the cavity";
  EXPECT_EQ(ref.fibers_outside, 0) << input << ": fiber particles outside the cavity (1 rank)";
  EXPECT_GT(got.ghost_fibers, 0) << input << ": no fiber near a rank border";
}

TEST(Mold3D, PlateCoarseRankIndependent) {
  check_case("plate_3d_fibers_coarse.yaml", 25, 100 * 4);
}

TEST(Mold3D, RibbedPartCoarseRankIndependent) {
  check_case("ribbed_part_fibers_coarse.yaml", 25, 60 * 4);
}

}  // namespace
}  // namespace sphdem
