// The sphdem command line: `sphdem run case.yaml`, `sphdem check case.yaml`,
// `sphdem partition case.yaml --ranks 64,256`, `sphdem keys [--markdown]`,
// `sphdem scaling case.yaml --ranks 1,2,4 --steps N` (no MPI: it launches runs).
// Exit status (include/sphdem/core/errors.hpp, docs/architecture.md "Errors"):
// 0 success, 2 bad input (nothing written), 3 the simulation failed (last
// state written when every rank saw the failure), 1 anything else.
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string_view>

#include "commands.hpp"
#include "fault_handler.hpp"
#include "scaling_command.hpp"
#include "sphdem/core/errors.hpp"

int main(int argc, char** argv) {
  // A scaling study starts its runs with mpiexec/srun, which an MPI process
  // (an Open MPI singleton) cannot: it never initialises MPI.
  if (argc > 1 && std::string_view(argv[1]) == "scaling")
    return sphdem::app::scaling_main(argc, argv);
  MPI_Init(&argc, &argv);
  sphdem::app::install_fault_handler();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 0;
  // Only the collective errors are caught: every rank throws them together,
  // so every rank can leave MPI cleanly. Nothing else is caught, on purpose:
  // a one-rank failure goes to the fault handler (fault_handler.hpp), which
  // aborts the job before the stack unwinds.
  try {
    status = sphdem::app::dispatch(argc, argv);
  } catch (const sphdem::InputError& e) {
    if (rank == 0) std::cerr << "sphdem: error: " << e.what() << "\n";
    status = sphdem::kExitInput;
  } catch (const sphdem::CollectiveSimulationError& e) {
    if (rank == 0) std::cerr << "sphdem: simulation failed: " << e.what() << "\n";
    status = sphdem::kExitSimulation;
  } catch (const sphdem::CollectiveIoError& e) {
    if (rank == 0) std::cerr << "sphdem: output failed: " << e.what() << "\n";
    status = sphdem::kExitOther;
  }
  MPI_Finalize();
  return status;
}
