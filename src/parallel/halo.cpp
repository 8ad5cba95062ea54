// Ghost plan and forward exchanges (docs/parallel.md, "Halo").
#include "sphdem/parallel/halo.hpp"

#include "exchange.hpp"
#include "ghost_fields.hpp"
#include "ghost_targets.hpp"

namespace sphdem {

template <int D>
void Halo<D>::build(const Decomposition<D>& dec, SphParticles<D>& ps, double range) {
  comm_ = dec.comm().raw();
  const auto ranks = static_cast<std::size_t>(dec.comm().size());
  detail::build_ghosts<D>(dec, ps, range, plan_, send_buf_, recv_buf_);
  build_wall_plan(ps, ranks);
}

// The wall ghosts' sub-plan. Both sides select the wall particles of each
// message in message order, so sender and receiver agree without talking.
template <int D>
void Halo<D>::build_wall_plan(const SphParticles<D>& ps, std::size_t ranks) {
  std::vector<std::int64_t> send_counts(ranks, 0), recv_counts(ranks, 0);
  GhostPlan<D>& w = wall_plan_;
  w.send_index.clear();
  w.send_shift.clear();
  w.recv_slot.clear();
  const GhostPlan<D>& all = plan_;
  for (std::size_t k = 0; k < all.send.ranks.size(); ++k) {
    for (std::size_t e = all.send.offsets[k]; e < all.send.offsets[k + 1]; ++e) {
      if (ps.kind[all.send_index[e]] != Kind::Wall) continue;
      w.send_index.push_back(all.send_index[e]);
      w.send_shift.push_back(all.send_shift[e]);
      ++send_counts[static_cast<std::size_t>(all.send.ranks[k])];
    }
  }
  for (std::size_t k = 0; k < all.recv.ranks.size(); ++k) {
    for (std::size_t e = all.recv.offsets[k]; e < all.recv.offsets[k + 1]; ++e) {
      if (ps.kind[ps.n_owned + e] != Kind::Wall) continue;
      w.recv_slot.push_back(ps.n_owned + e);
      ++recv_counts[static_cast<std::size_t>(all.recv.ranks[k])];
    }
  }
  w.send = detail::route_from_counts(send_counts);
  w.recv = detail::route_from_counts(recv_counts);
}

template <int D>
void Halo<D>::forward(SphParticles<D>& ps, SphGroup group) {
  const GhostPlan<D>& plan = group == SphGroup::WallState ? wall_plan_ : plan_;
  detail::forward_groups<D>(comm_, plan, ps, group_bit(group), send_buf_, recv_buf_);
}

template class Halo<2>;
template class Halo<3>;

}  // namespace sphdem
