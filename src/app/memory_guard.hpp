#pragma once
// Refusing a case too big for the machine before building it (defect 3 of
// issue 15, issue 14 part 4; docs/case-file.md, "Size estimate";
// docs/scaling.md, "Memory per rank").
#include <optional>
#include <string>

#include "sphdem/config/case.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/case_size.hpp"

namespace sphdem::app {

// "16G", "512M", "2048K", "1T" or a number of bytes; InputError naming
// `option` (the command line's --max-memory, --memory-per-rank) otherwise.
double parse_memory_size(const std::string& text, const std::string& option = "--max-memory");

// MemAvailable of /proc/meminfo, in bytes; nullopt where it cannot be read.
std::optional<double> available_memory();

// What the guard measures the estimate against.
struct MemoryLimits {
  std::optional<double> node;      // --max-memory: all the ranks on one node
  std::optional<double> per_rank;  // --memory-per-rank: one rank
  // --ranks: the rank count to estimate for (default: the communicator's).
  std::optional<int> ranks;
};

// The ranks that share a node's memory at `ranks` ranks: the ranks of this
// communicator on this node when it is the run's; for a rank count this
// process only estimates for, as many as this node has cores (at most
// `ranks`): a job fills its nodes.
int local_ranks(const Comm& comm, int ranks);

// Collective. The estimate at the rank count of `limits` (default: this
// communicator's); throws InputError on every rank, naming the key that
// dominates, the rank count and the estimate, when a rank needs more than
// its share: --memory-per-rank, else --max-memory or the node's
// MemAvailable divided by the local ranks (each rank its own node's).
CaseSize check_case_fits(const Case& c, const Comm& comm, const MemoryLimits& limits);

}  // namespace sphdem::app
