#pragma once
// Point-to-point plumbing shared by migration and the halo: who talks to
// whom (a Route per direction) and one exchange call for any element type.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "sphdem/parallel/decomposition.hpp"

namespace sphdem::detail {

using Route = MessageRoute;

// The ranks with a nonzero count (counts has one entry per rank), in rank
// order, so every message layout is deterministic.
Route route_from_counts(const std::vector<std::int64_t>& counts);

// MPI_Alltoall: given how many elements this rank sends to each rank,
// returns how many it receives from each.
std::vector<std::int64_t> transpose_counts(MPI_Comm comm, const std::vector<std::int64_t>& send);

// Sends the elements of `send` to its ranks and receives those of `recv`
// (nonblocking pairs, then one wait). An element is `per` values of the
// predefined type `base` (e.g. a particle's 2D+1 doubles, or a record of
// bytes), so no derived datatype is built per call. Messages to self go
// through MPI too: one code path whatever the rank count.
void exchange(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
              void* recv_buf, MPI_Datatype base, std::size_t per);

// exchange(), and the largest `vote` over every rank of comm in the same
// wait: each rank sends its vote to every other rank beside the elements,
// so a few ranks synchronise once where exchange() and an allreduce
// synchronise twice. Above kVoteMessageRanks ranks (n^2 small messages)
// the vote is an allreduce after the exchange. The maximum is exact: the
// same value either way.
constexpr int kVoteMessageRanks = 8;
double exchange_max(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
                    void* recv_buf, MPI_Datatype base, std::size_t per, double vote);

}  // namespace sphdem::detail
