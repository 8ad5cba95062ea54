#pragma once
// Refusing a case too big for the machine before building it (defect 3 of
// issue 15; docs/case-file.md, "Size estimate").
#include <optional>
#include <string>

#include "sphdem/config/case.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/case_size.hpp"

namespace sphdem::app {

// "16G", "512M", "2048K", "1T" or a number of bytes; InputError on the
// command line's --max-memory otherwise.
double parse_memory_size(const std::string& text);

// MemAvailable of /proc/meminfo, in bytes; nullopt where it cannot be read.
std::optional<double> available_memory();

// Collective. The estimate at this communicator's rank count; throws
// InputError on every rank, naming the key that dominates, when the ranks
// that share a node need more than `max_memory` bytes (default: the
// node's MemAvailable, each rank its own node's).
CaseSize check_case_fits(const Case& c, const Comm& comm, std::optional<double> max_memory);

}  // namespace sphdem::app
