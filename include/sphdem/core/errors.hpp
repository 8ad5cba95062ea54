#pragma once
// The error classes of sphdem and the exit status each ends a run with
// (docs/architecture.md, "Errors"). Errors are collective (every rank
// throws the same one at the same point) or one-rank (thrown where one rank
// found a problem the others do not know about):
//  - InputError, exit 2: a bad case file, command line or checkpoint.
//    Collective: every rank reads the same input and so throws the same
//    error (the app agrees on the case file's loading, src/app/commands.cpp);
//    the app prints it once (rank 0) and every rank exits before anything is
//    written.
//  - CollectiveSimulationError, exit 3: the run cannot continue and every
//    rank knows it (a health check after an allreduce). The run loop writes
//    the last state, then the app exits.
//  - SimulationError, exit 3, and any other exception, exit 1: thrown on one
//    rank (a DEM cell list or pair list overflowing, an HDF5 call failing).
//    The app never catches them: the job is aborted (MPI_Abort) with the
//    class's status before the stack unwinds, since unwinding would run
//    destructors that are collective (closing an HDF5 file) while the other
//    ranks wait in another collective (src/app/fault_handler.cpp).
//  - CollectiveIoError, exit 1: a snapshot, checkpoint or restart read failed
//    on some rank. Collective: the I/O paths agree on failure after every
//    HDF5 call that can fail (src/io/io_agreement.hpp), so every rank throws
//    it at the same point, and the app prints it once and exits cleanly.
#include <stdexcept>
#include <string>

namespace sphdem {

// Exit statuses of `sphdem` (0: success).
constexpr int kExitOther = 1;
constexpr int kExitInput = 2;
constexpr int kExitSimulation = 3;

// `s` with control characters and bytes that are not UTF-8 written as \xNN:
// a case file of binary junk must not echo raw bytes to the terminal.
std::string printable(const std::string& s);

// Its message is "file:line: key 'k': what", made printable.
class InputError : public std::runtime_error {
 public:
  // file: the case file (or "--set"), line: 1-based (0 when unknown),
  // key: dotted path of the offending key.
  InputError(std::string file, int line, std::string key, const std::string& what);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

// Thrown where one rank finds that the run cannot continue.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown by every rank together: the decision followed a reduction over
// the ranks, so all of them reach it at the same step.
class CollectiveSimulationError : public SimulationError {
 public:
  using SimulationError::SimulationError;
};

// Thrown by every rank together when a collective write or read failed on
// at least one rank; names the file, the first failing rank and its cause.
class CollectiveIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The exit status an exception ends the run with (kExit*).
int exit_status_of(const std::exception& e);

}  // namespace sphdem
