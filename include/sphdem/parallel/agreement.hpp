#pragma once
// Agreeing on a failure after a phase every rank runs on its own (reading
// the case file): one allreduce and one broadcast, so that either every
// rank goes on or every rank stops with the same error (docs/architecture.md,
// "Errors"). The phase itself must not communicate.
#include <optional>
#include <string>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

struct RankFailure {
  int rank = 0;         // the lowest rank that failed
  std::string message;  // its error message
};

// Collective. `error`: this rank's failure, if any. Returns the lowest
// failing rank and its message on every rank; nullopt when none failed.
std::optional<RankFailure> first_failure(const Comm& comm, const std::optional<std::string>& error);

}  // namespace sphdem
