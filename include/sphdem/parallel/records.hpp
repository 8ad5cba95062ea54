#pragma once
// Sending small fixed-width integer records to chosen ranks (the
// distributed set-up's row segments, src/solver/distributed_fill.cpp).
#include <cstdint>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

// Collective. Record r is records[r * width, (r + 1) * width) and goes to
// rank dest[r]. Returns the records this rank receives, ordered by source
// rank, each source's in the order it listed them.
std::vector<std::int64_t> route_records(const Comm& comm, const std::vector<int>& dest,
                                        const std::vector<std::int64_t>& records,
                                        std::size_t width);

}  // namespace sphdem
