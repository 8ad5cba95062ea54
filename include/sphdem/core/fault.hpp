#pragma once
// Where the run is, for the message of a one-rank failure, and the fault
// injection hook of the tests (docs/architecture.md, "Errors"). No MPI here:
// callers pass their rank.
#include <cstdint>
#include <optional>

namespace sphdem {

// The step the run loop is computing (or writing the output of); -1 while
// the run is set up. Set by drive_run (src/solver/run_loop.hpp).
void set_current_step(std::int64_t step);
std::int64_t current_step();

// Testing hook: SPHDEM_INJECT_FAULT=RANK:STEP:KIND makes rank RANK fail
// on its own, as a real one-rank failure would:
//   input       loading the case file (STEP is ignored): an InputError
//   simulation  after step STEP: a SimulationError (as a DEM list overflow)
//   runtime     after step STEP: a std::runtime_error
//   hdf5        writing the snapshot of step STEP: a failing HDF5 call
enum class FaultKind { Input, Simulation, Runtime, Hdf5 };

struct InjectedFault {
  int rank = 0;
  std::int64_t step = 0;
  FaultKind kind = FaultKind::Input;
};

// The fault the environment asks for (read once); nullopt when unset.
// Throws InputError naming SPHDEM_INJECT_FAULT for a malformed value.
std::optional<InjectedFault> injected_fault();

// True when the environment asks for a fault of `kind` on `rank` at `step`
// (any step for FaultKind::Input).
bool fault_due(FaultKind kind, int rank, std::int64_t step);

// Throws the injected fault of the case file's loading when due.
void inject_load_fault(int rank, const char* case_file);
// Throws the injected fault after step `step` (simulation, runtime) when due.
void inject_step_fault(int rank, std::int64_t step);

}  // namespace sphdem
