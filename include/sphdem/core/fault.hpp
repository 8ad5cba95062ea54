#pragma once
// Where the run is, for the message of a one-rank failure, and the fault
// injection hook of the tests (docs/architecture.md, "Errors"). No MPI here:
// callers pass their rank.
#include <cstdint>
#include <optional>
#include <string>

namespace sphdem {

// The step the run loop is computing (or writing the output of); -1 while
// the run is set up. Set by drive_run (src/solver/run_loop.hpp).
void set_current_step(std::int64_t step);
std::int64_t current_step();

// Testing hook: SPHDEM_INJECT_FAULT=RANK:STEP:KIND makes rank RANK fail
// on its own, as a real one-rank failure would:
//   input             loading the case file (STEP is ignored): an InputError
//   simulation        after step STEP: a SimulationError (as a DEM list overflow)
//   runtime           after step STEP: a std::runtime_error
//   snapshot_write    an HDF5 dataset write failing inside the collective write
//                     of the snapshot of step STEP (`hdf5` is the same)
//   checkpoint_write  the same inside the checkpoint written after step STEP
//   restart_read      an HDF5 dataset read failing inside a restart's
//                     collective read of a checkpoint (STEP is ignored)
//   enospc            from step STEP on, every dataset write of a snapshot or
//                     checkpoint fails with "No space left on device", as on
//                     a full disk
enum class FaultKind {
  Input,
  Simulation,
  Runtime,
  SnapshotWrite,
  CheckpointWrite,
  RestartRead,
  Enospc
};

struct InjectedFault {
  int rank = 0;
  std::int64_t step = 0;
  FaultKind kind = FaultKind::Input;
};

// The fault the environment asks for (read once); nullopt when unset.
// Throws InputError naming SPHDEM_INJECT_FAULT for a malformed value.
std::optional<InjectedFault> injected_fault();

// True when the environment asks for a fault of `kind` on `rank` at `step`
// (any step for Input and RestartRead, from STEP on for Enospc).
bool fault_due(FaultKind kind, int rank, std::int64_t step);

// Throws the injected fault of the case file's loading when due.
void inject_load_fault(int rank, const char* case_file);
// Throws the injected I/O fault of `kind` (SnapshotWrite, CheckpointWrite,
// RestartRead) when due, or Enospc for the writes, as the std::runtime_error
// a failing HDF5 call on `path` gives.
void inject_io_fault(FaultKind kind, int rank, std::int64_t step, const std::string& path);
// Throws the injected fault after step `step` (simulation, runtime) when due.
void inject_step_fault(int rank, std::int64_t step);

}  // namespace sphdem
