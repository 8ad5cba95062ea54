#pragma once
// Shared by the fiber rank tests (tests/test_fiber_ranks.cpp,
// tests/test_buckling.cpp): run a coupled shear cell to a time on a
// communicator and gather its resin and fibers, in gid order, to rank 0.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem::testing_fibers {

struct Row {
  std::int64_t gid = 0;
  double value[10] = {};
};

struct Cell {
  std::vector<Row> resin, fibers;  // on rank 0
  double time = 0;
  double phi_start = 0, phi_end = 0;  // fiber 0's end-to-end direction in the x-y plane [rad]
  double least_straightness = 1;      // fiber 0's least end-to-end / contour over the run
  // Fiber 0's sagitta over its length (contour n / (n - 1): fibers.initial_bend's measure).
  double first_bulge = 0;    // at t = 0
  double largest_bulge = 0;  // its largest over the run
};

// Fiber 0's (gids 0..n-1) end-to-end vector, contour length and sagitta
// (its centres' largest distance from the end-to-end line) over its
// length, summed over the ranks (each rank adds its owned particles' share).
template <int D>
void fiber_measure(const Comm& comm, const DemDomain<D>& dem, int n, Vec<D>& end_to_end,
                   double& contour, double& bulge) {
  const auto& f = dem.particles();
  std::vector<double> x(static_cast<std::size_t>(n) * D, 0.0);
  for (std::size_t i = 0; i < f.n_owned; ++i)
    if (f.gid[i] < n)
      for (int a = 0; a < D; ++a) x[static_cast<std::size_t>(f.gid[i]) * D + a] = f.x[i][a];
  MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(x.size()), MPI_DOUBLE, MPI_SUM,
                comm.raw());
  const auto at = [&](int k) {
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = x[static_cast<std::size_t>(k) * D + a];
    return v;
  };
  contour = 0;
  for (int k = 1; k < n; ++k) contour += (at(k) - at(k - 1)).norm();
  end_to_end = at(n - 1) - at(0);
  const Vec<D> axis = end_to_end.normalized();
  bulge = 0;
  for (int k = 1; k + 1 < n; ++k) {
    const Vec<D> d = at(k) - at(0);
    bulge = std::max(bulge, (d - d.dot(axis) * axis).norm() / (contour * n / (n - 1)));
  }
}

// Runs to t_end, or until fiber 0 has turned below phi_stop [rad].
template <int D>
Cell run_cell(const Comm& comm, const std::string& input, const std::vector<std::string>& sets,
              double t_end, double phi_stop = -1e300) {
  const Case c = testing::load_input(input, sets);
  RunOptions opt;
  opt.write_output = false;
  Simulation<D> sim(c, comm, opt);
  const int n = c.fibers->particles_per_fiber;
  Cell cell;
  Vec<D> e;
  double contour = 0, bulge = 0;
  fiber_measure<D>(comm, *sim.dem(), n, e, contour, bulge);
  cell.phi_start = std::atan2(e[1], e[0]);
  cell.first_bulge = cell.largest_bulge = bulge;
  double phi = cell.phi_start;
  while (sim.time() < t_end * (1 - 1e-12) && phi > phi_stop) {
    sim.advance(1);
    fiber_measure<D>(comm, *sim.dem(), n, e, contour, bulge);
    phi += std::remainder(std::atan2(e[1], e[0]) - phi, 2 * std::numbers::pi);
    cell.least_straightness = std::min(cell.least_straightness, e.norm() / contour);
    cell.largest_bulge = std::max(cell.largest_bulge, bulge);
  }
  cell.phi_end = phi;
  cell.time = sim.time();
  const auto& ps = sim.particles();
  std::vector<Row> resin, fibers;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    if (ps.kind[i] != Kind::Fluid) continue;
    Row r{ps.gid[i], {}};
    for (int a = 0; a < D; ++a) {
      r.value[a] = ps.x[i][a];
      r.value[D + a] = ps.v[i][a];
    }
    r.value[2 * D] = ps.rho[i];
    resin.push_back(r);
  }
  const auto& f = sim.dem()->particles();
  for (std::size_t i = 0; i < f.n_owned; ++i) {
    Row r{f.gid[i], {}};
    for (int a = 0; a < D; ++a) {
      r.value[a] = f.x[i][a];
      r.value[D + a] = f.v[i][a];
    }
    for (int a = 0; a < f.omega[i].size(); ++a) r.value[2 * D + a] = f.omega[i][a];
    r.value[9] = f.bonds[i][0].sigma;
    fibers.push_back(r);
  }
  cell.resin = testing_mpi::gather_rows(comm, resin);
  cell.fibers = testing_mpi::gather_rows(comm, fibers);
  return cell;
}

}  // namespace sphdem::testing_fibers
