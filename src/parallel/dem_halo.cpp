// DEM ghost plan and the per-sub-step state exchange (docs/parallel.md).
#include "sphdem/dem_halo.hpp"

#include "exchange.hpp"
#include "ghost_targets.hpp"

namespace sphdem {

template <int D>
void DemHalo<D>::build(const Decomposition<D>& dec, DemParticles<D>& ps, double range) {
  comm_ = dec.comm().raw();
  bool periodic = false;
  for (int k = 0; k < D; ++k) periodic = periodic || dec.grid().periodic(k);
  if (dec.comm().size() == 1 && !periodic) {
    // No other rank and no periodic image: no ghosts (skips a walk over
    // the neighbor cells of every particle).
    ps.clear_ghosts();
    send_ = MessageRoute{};
    recv_ = MessageRoute{};
    send_index_.clear();
    send_shift_.clear();
    return;
  }
  detail::build_ghosts<D>(dec, ps, range, send_, recv_, send_index_, send_shift_);
  update_state(ps);  // applies the periodic shifts
}

template <int D>
void DemHalo<D>::update_state(DemParticles<D>& ps) {
  constexpr int R = D == 2 ? 1 : 3;
  constexpr int per = 2 * D + R;
  send_buf_.resize(send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t e = 0; e < send_index_.size(); ++e, b += per) {
    const std::size_t s = send_index_[e];
    const Vec<D> x = ps.x[s] + send_shift_[e];
    for (int k = 0; k < D; ++k) b[k] = x[k];
    for (int k = 0; k < D; ++k) b[D + k] = ps.v[s][k];
    for (int k = 0; k < R; ++k) b[2 * D + k] = ps.omega[s][k];
  }
  recv_buf_.resize(recv_.total() * per);
  detail::exchange(comm_, send_, send_buf_.data(), recv_, recv_buf_.data(), MPI_DOUBLE, per);
  const double* r = recv_buf_.data();
  for (std::size_t g = ps.n_owned; g < ps.n_owned + recv_.total(); ++g, r += per) {
    for (int k = 0; k < D; ++k) ps.x[g][k] = r[k];
    for (int k = 0; k < D; ++k) ps.v[g][k] = r[D + k];
    for (int k = 0; k < R; ++k) ps.omega[g][k] = r[2 * D + k];
  }
}

template <int D>
void DemHalo<D>::update_coupling(std::vector<Vec<D>>& drag, std::vector<double>& shepard_sum) {
  const std::size_t n_owned = drag.size() - recv_.total();
  constexpr int per = D + 1;
  send_buf_.resize(send_index_.size() * per);
  double* b = send_buf_.data();
  for (std::size_t e = 0; e < send_index_.size(); ++e, b += per) {
    const std::size_t s = send_index_[e];
    for (int k = 0; k < D; ++k) b[k] = drag[s][k];
    b[D] = shepard_sum[s];
  }
  recv_buf_.resize(recv_.total() * per);
  detail::exchange(comm_, send_, send_buf_.data(), recv_, recv_buf_.data(), MPI_DOUBLE, per);
  const double* r = recv_buf_.data();
  for (std::size_t g = n_owned; g < n_owned + recv_.total(); ++g, r += per) {
    for (int k = 0; k < D; ++k) drag[g][k] = r[k];
    shepard_sum[g] = r[D];
  }
}

template class DemHalo<2>;
template class DemHalo<3>;

}  // namespace sphdem
