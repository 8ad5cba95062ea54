#include "fault_handler.hpp"

#include <mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sphdem/core/errors.hpp"
#include "sphdem/core/fault.hpp"

namespace sphdem::app {

namespace {

// An exception that no handler catches reaches std::terminate before the
// stack unwinds (GCC and Clang, Itanium C++ ABI; the standard leaves it to
// the implementation, [except.handle]/9): no destructor runs, in particular
// none that closes an HDF5 file collectively on this rank alone.
[[noreturn]] void abort_job() {
  int status = kExitOther;
  std::string cause = "terminated without an exception";
  if (const std::exception_ptr e = std::current_exception()) {
    try {
      std::rethrow_exception(e);
    } catch (const std::exception& ex) {
      status = exit_status_of(ex);
      cause = ex.what();
    } catch (...) {
      cause = "an exception of unknown type";
    }
  }
  int initialized = 0, finalized = 0, rank = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  const bool mpi = initialized && !finalized;
  if (mpi) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::int64_t step = current_step();
  const std::string where = step >= 0 ? "step " + std::to_string(step) : "setting up";
  std::fprintf(stderr, "sphdem: rank %d, %s: %s\n", rank, where.c_str(), cause.c_str());
  std::fflush(stderr);
  if (mpi) MPI_Abort(MPI_COMM_WORLD, status);
  std::_Exit(status);
}

}  // namespace

void install_fault_handler() {
  std::set_terminate(abort_job);
}

}  // namespace sphdem::app
