#pragma once
// Sends fields of any registry container (SPH or DEM particles) along a
// ghost plan (docs/parallel.md, "Halo"): the fields a policy test selects,
// in registry order, from the owned source of each copy to its ghost slot,
// a field marked kShifted gaining the copy's periodic shift. The halo build
// sends the kGhost fields this way, and Halo::forward / DemHalo::forward
// the fields of one exchange group, so a field travels as soon as its
// registry line says so.
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "exchange.hpp"
#include "sphdem/parallel/halo.hpp"

namespace sphdem::detail {

// Packs, exchanges and unpacks the fields `want` selects for every copy of
// `plan`. Collective over `comm` (the ranks of the plan's routes; with a
// `vote`, every rank of comm: *vote becomes its largest value over the
// ranks, in the same exchange, exchange_max).
template <int D, class P, class Want>
void send_fields(MPI_Comm comm, const GhostPlan<D>& plan, P& ps, Want want,
                 std::vector<char>& send_buf, std::vector<char>& recv_buf, double* vote = nullptr) {
  const std::size_t rec = record_bytes(ps, want);
  const std::size_t n_send = plan.send_index.size(), n_recv = plan.recv.total();
  send_buf.resize(n_send * rec);
  std::size_t offset = 0;
  ps.for_each_field([&](const char* name, auto& field, FieldPolicy p) {
    if (!want(p)) return;
    using T = typename std::decay_t<decltype(field)>::value_type;
    char* out = send_buf.data() + offset;
    if (p.shifted) {
      if constexpr (std::is_same_v<T, Vec<D>>) {
        for (std::size_t e = 0; e < n_send; ++e) {
          const T shifted = field[plan.send_index[e]] + plan.send_shift[e];
          std::memcpy(out + e * rec, static_cast<const void*>(&shifted), sizeof(T));
        }
      } else {
        throw std::logic_error(std::string("sphdem: field '") + name +
                               "' is marked kShifted but is not a position");
      }
    } else {
      for (std::size_t e = 0; e < n_send; ++e)
        std::memcpy(out + e * rec, static_cast<const void*>(&field[plan.send_index[e]]), sizeof(T));
    }
    offset += sizeof(T);
  });
  recv_buf.resize(n_recv * rec);
  if (vote) {
    *vote = exchange_max(comm, plan.send, send_buf.data(), plan.recv, recv_buf.data(), MPI_BYTE,
                         rec, *vote);
  } else {
    exchange(comm, plan.send, send_buf.data(), plan.recv, recv_buf.data(), MPI_BYTE, rec);
  }
  offset = 0;
  ps.for_each_field([&](const char*, auto& field, FieldPolicy p) {
    if (!want(p)) return;
    using T = typename std::decay_t<decltype(field)>::value_type;
    const char* in = recv_buf.data() + offset;
    for (std::size_t k = 0; k < n_recv; ++k) {
      const std::size_t slot = plan.recv_slot.empty() ? ps.n_owned + k : plan.recv_slot[k];
      std::memcpy(static_cast<void*>(&field[slot]), in + k * rec, sizeof(T));
    }
    offset += sizeof(T);
  });
}

// The fields of the exchange groups in `group_bits` (group_bit(g)).
template <int D, class P>
void forward_groups(MPI_Comm comm, const GhostPlan<D>& plan, P& ps, std::uint32_t group_bits,
                    std::vector<char>& send_buf, std::vector<char>& recv_buf,
                    double* vote = nullptr) {
  send_fields(
      comm, plan, ps, [group_bits](FieldPolicy p) { return p.in(group_bits); }, send_buf, recv_buf,
      vote);
}

}  // namespace sphdem::detail
