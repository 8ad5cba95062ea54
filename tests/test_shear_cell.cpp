// A fiber in a periodic shear cell (issue 12 part 3,
// inputs/validation/shear_cell.yaml): the loader accepts fibers with a
// periodic axis, the resin starts from the linear profile, the flow carries
// the fiber across the periodic face with its bonds intact (the pair list
// bonds the nearest image), and N ranks give bitwise the run of one.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
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
  double stretch = 0;           // largest |bond length / length0 - 1| seen
  double x_min = 1, x_max = 0;  // the fiber's particles' extreme x over the run
};

// [s]: every particle has crossed x = 6 mm by then (the last at 0.0225 s),
// past 0.0235 s, where the cell blew up before the pair list took the
// mutually nearest copies of a bond (docs/physics.md "Shear cells").
constexpr double kEnd = 0.026;

State run(const Comm& comm) {
  const Case c = testing::load_input("validation/shear_cell.yaml");
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  State st;
  double stretch = 0, x_min = 1, x_max = 0;
  while (sim.time() < kEnd) {
    sim.advance(1);
    const auto& f = sim.dem()->particles();
    for (std::size_t i = 0; i < f.n_owned; ++i) {
      x_min = std::min(x_min, f.x[i][0]);
      x_max = std::max(x_max, f.x[i][0]);
      for (const DemBond<2>& b : f.bonds[i]) {
        if (b.partner < 0) continue;
        // The nearest copy is the bonded one (a periodic image or the owned one).
        double len = -1;
        for (std::size_t k = 0; k < f.size(); ++k) {
          const double d = (f.x[k] - f.x[i]).norm();
          if (f.gid[k] == b.partner && (len < 0 || d < len)) len = d;
        }
        if (len >= 0) stretch = std::max(stretch, std::abs(len / b.length0 - 1));
      }
    }
  }
  st.stretch = comm.max(stretch);
  st.x_min = comm.min(x_min);
  st.x_max = comm.max(x_max);
  const auto& ps = sim.particles();
  std::vector<Row> resin, fibers;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    resin.push_back({ps.gid[i], {ps.x[i][0], ps.x[i][1], ps.v[i][0], ps.v[i][1], ps.rho[i], 0}});
  }
  const auto& f = sim.dem()->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i) {
    fibers.push_back(
        {f.gid[i], {f.x[i][0], f.x[i][1], f.v[i][0], f.v[i][1], f.omega[i][0], f.bonds[i][0].fn}});
  }
  st.resin = testing_mpi::gather_rows(comm, resin);
  st.fibers = testing_mpi::gather_rows(comm, fibers);
  return st;
}

TEST(ShearCell, FiberCrossesThePeriodicFaceIntact) {
  const Comm world;
  State ref;
  if (world.root()) ref = run(Comm(MPI_COMM_SELF));
  testing_mpi::wait_for_root(world);
  if (world.size() > 1) {
    const State got = run(world);
    if (!world.root()) return;
    EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.resin, got.resin), 0u)
        << "resin differs from the 1-rank run";
    EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.fibers, got.fibers), 0u)
        << "fibers differ from the 1-rank run";
  }
  if (!world.root()) return;
  ASSERT_EQ(ref.fibers.size(), 4u);
  // Crossed: particles seen at both ends of the period, and the whole
  // fiber across the face at the end.
  EXPECT_LT(ref.x_min, 0.0005);
  EXPECT_GT(ref.x_max, 0.005);
  for (const Row& r : ref.fibers) EXPECT_LT(r.value[0], 0.002);
  // Every particle inside the period (up to the drift since the last
  // rebuild, where positions wrap), and the bonds barely strained.
  for (const Row& r : ref.fibers) {
    EXPECT_GT(r.value[0], -0.0003);
    EXPECT_LT(r.value[0], 0.0063);
  }
  EXPECT_LT(ref.stretch, 0.01);
}

}  // namespace
}  // namespace sphdem
