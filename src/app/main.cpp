// The sphdem command line: `sphdem run case.yaml`, `sphdem check case.yaml`,
// `sphdem partition case.yaml --ranks 64,256`, `sphdem keys [--markdown]`.
// Exit status: 0 success, 2 bad input (nothing written), 3 the simulation
// failed (last state written), 1 anything else.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "sphdem/errors.hpp"

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 0;
  try {
    status = sphdem::app::dispatch(argc, argv);
  } catch (const sphdem::InputError& e) {
    if (rank == 0) std::cerr << "sphdem: error: " << e.what() << "\n";
    status = 2;
  } catch (const sphdem::SimulationError& e) {
    if (rank == 0) std::cerr << "sphdem: simulation failed: " << e.what() << "\n";
    status = 3;
  } catch (const std::exception& e) {
    std::cerr << "sphdem: error (rank " << rank << "): " << e.what() << "\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return status;
}
