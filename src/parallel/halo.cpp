// Ghost plan and forward exchanges (docs/parallel.md, "Halo").
#include "sphdem/halo.hpp"

#include <algorithm>
#include <cmath>

#include "exchange.hpp"
#include "ghost_targets.hpp"
#include "pack.hpp"

namespace sphdem {

template <int D>
void Halo<D>::build(const Decomposition<D>& dec, SphParticles<D>& ps, double range) {
  comm_ = dec.comm().raw();
  const auto ranks = static_cast<std::size_t>(dec.comm().size());
  detail::build_ghosts<D>(dec, ps, range, send_, recv_, send_index_, send_shift_);
  build_wall_plan(ps, ranks);
  update_state(ps);  // applies the periodic shifts
}

// The wall ghosts' sub-plan. Both sides select the wall particles of each
// message in message order, so sender and receiver agree without talking.
template <int D>
void Halo<D>::build_wall_plan(const SphParticles<D>& ps, std::size_t ranks) {
  std::vector<std::int64_t> send_counts(ranks, 0), recv_counts(ranks, 0);
  wall_send_index_.clear();
  wall_recv_slot_.clear();
  for (std::size_t k = 0; k < send_.ranks.size(); ++k) {
    for (std::size_t e = send_.offsets[k]; e < send_.offsets[k + 1]; ++e) {
      if (ps.kind[send_index_[e]] != Kind::Wall) continue;
      wall_send_index_.push_back(send_index_[e]);
      ++send_counts[static_cast<std::size_t>(send_.ranks[k])];
    }
  }
  for (std::size_t k = 0; k < recv_.ranks.size(); ++k) {
    for (std::size_t e = recv_.offsets[k]; e < recv_.offsets[k + 1]; ++e) {
      if (ps.kind[ps.n_owned + e] != Kind::Wall) continue;
      wall_recv_slot_.push_back(ps.n_owned + e);
      ++recv_counts[static_cast<std::size_t>(recv_.ranks[k])];
    }
  }
  wall_send_ = detail::route_from_counts(send_counts);
  wall_recv_ = detail::route_from_counts(recv_counts);
}

template <int D>
void Halo<D>::update_state(SphParticles<D>& ps) {
  constexpr int per = 2 * D + 1;
  send_buf_.resize(send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t e = 0; e < send_index_.size(); ++e, b += per) {
    const std::size_t s = send_index_[e];
    const Vec<D> x = ps.x[s] + send_shift_[e];
    for (int k = 0; k < D; ++k) b[k] = x[k];
    for (int k = 0; k < D; ++k) b[D + k] = ps.v[s][k];
    b[2 * D] = ps.rho[s];
  }
  recv_buf_.resize(recv_.total() * per);
  detail::exchange(comm_, send_, send_buf_.data(), recv_, recv_buf_.data(), MPI_DOUBLE, per);
  const double* r = recv_buf_.data();
  for (std::size_t g = ps.n_owned; g < ps.n_owned + recv_.total(); ++g, r += per) {
    for (int k = 0; k < D; ++k) ps.x[g][k] = r[k];
    for (int k = 0; k < D; ++k) ps.v[g][k] = r[D + k];
    ps.rho[g] = r[2 * D];
  }
}

template <int D>
void Halo<D>::update_wall_state(SphParticles<D>& ps) {
  constexpr int per = D + 2;
  send_buf_.resize(wall_send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t s : wall_send_index_) {
    b[0] = ps.p[s];
    b[1] = ps.rho[s];
    for (int k = 0; k < D; ++k) b[2 + k] = ps.vwall[s][k];
    b += per;
  }
  recv_buf_.resize(wall_recv_slot_.size() * per);
  detail::exchange(comm_, wall_send_, send_buf_.data(), wall_recv_, recv_buf_.data(), MPI_DOUBLE,
                   per);
  const double* r = recv_buf_.data();
  for (std::size_t g : wall_recv_slot_) {
    ps.p[g] = r[0];
    ps.rho[g] = r[1];
    for (int k = 0; k < D; ++k) ps.vwall[g][k] = r[2 + k];
    r += per;
  }
}

template class Halo<2>;
template class Halo<3>;

}  // namespace sphdem
