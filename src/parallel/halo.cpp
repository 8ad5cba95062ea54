#include "sphdem/halo.hpp"

#include <cmath>

namespace sphdem {

namespace {

template <int D>
void wrap_into_box(SphParticles<D>& ps, const Box<D>& dom, const std::array<bool, 3>& periodic) {
  for (int k = 0; k < D; ++k) {
    if (!periodic[k]) continue;
    const double len = dom.hi[k] - dom.lo[k];
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      double& x = ps.x[i][k];
      if (x < dom.lo[k] || x >= dom.hi[k]) x -= len * std::floor((x - dom.lo[k]) / len);
    }
  }
}

}  // namespace

template <int D>
void Halo<D>::build(SphParticles<D>& ps, const Box<D>& dom, const std::array<bool, 3>& periodic,
                    double range) {
  ps.clear_ghosts();
  wrap_into_box<D>(ps, dom, periodic);
  src_.clear();
  shift_.clear();
  // Every non-empty subset of the axes along which the particle is near a
  // periodic face gives one image (corners need the diagonal image too).
  constexpr int combos = 1 << D;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    std::array<int, 3> side{0, 0, 0};  // -1 near lo (image at +L), +1 near hi
    bool near = false;
    for (int k = 0; k < D; ++k) {
      if (!periodic[k]) continue;
      if (ps.x[i][k] < dom.lo[k] + range) side[k] = -1;
      else if (ps.x[i][k] >= dom.hi[k] - range) side[k] = 1;
      near = near || side[k] != 0;
    }
    if (!near) continue;
    for (int c = 1; c < combos; ++c) {
      Vec<D> shift = Vec<D>::Zero();
      bool valid = true;
      for (int k = 0; k < D; ++k) {
        if (!(c & (1 << k))) continue;
        if (side[k] == 0) valid = false;
        shift[k] = -side[k] * (dom.hi[k] - dom.lo[k]);
      }
      if (!valid) continue;
      src_.push_back(i);
      shift_.push_back(shift);
    }
  }
  const std::size_t n_own = ps.n_owned;
  ps.resize(n_own + src_.size());
  for (std::size_t k = 0; k < src_.size(); ++k) {
    ps.copy_particle(n_own + k, src_[k]);
    ps.x[n_own + k] += shift_[k];
  }
  ps.n_owned = n_own;
}

template <int D>
void Halo<D>::update_state(SphParticles<D>& ps) const {
  const std::size_t n_own = ps.n_owned;
  for (std::size_t k = 0; k < src_.size(); ++k) {
    const std::size_t s = src_[k], g = n_own + k;
    ps.x[g] = ps.x[s] + shift_[k];
    ps.v[g] = ps.v[s];
    ps.rho[g] = ps.rho[s];
  }
}

template <int D>
void Halo<D>::update_wall_state(SphParticles<D>& ps) const {
  const std::size_t n_own = ps.n_owned;
  for (std::size_t k = 0; k < src_.size(); ++k) {
    const std::size_t s = src_[k], g = n_own + k;
    if (ps.kind[s] != Kind::Wall) continue;
    ps.p[g] = ps.p[s];
    ps.rho[g] = ps.rho[s];
    ps.vwall[g] = ps.vwall[s];
  }
}

template class Halo<2>;
template class Halo<3>;

}  // namespace sphdem
