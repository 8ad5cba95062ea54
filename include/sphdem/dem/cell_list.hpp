#pragma once
// A cell list over the DEM particles, rebuilt every sub-step (DEM particles
// are few, and a rebuild is a counting sort, linear in their number).
// Cells are at least `cell` wide (the largest contact distance, 2 R_max),
// so every touching pair sits in the same or adjacent cells. The grid spans
// the particles' bounding box; past a cell budget of 16 per particle the
// cells grow, so a particle far away cannot blow up the memory.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sphdem/core/errors.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem::dem_detail {

template <int D>
class CellList {
 public:
  void build(const std::vector<Vec<D>>& x, std::size_t n, double cell,
             std::vector<std::int32_t>& start, std::vector<std::int32_t>& items) {
    lo_ = Vec<D>::Zero();
    Vec<D> hi = Vec<D>::Zero();
    if (n > 0) {
      lo_ = x[0];
      hi = x[0];
      for (std::size_t i = 1; i < n; ++i) {
        lo_ = lo_.cwiseMin(x[i]);
        hi = hi.cwiseMax(x[i]);
      }
    }
    // A NaN or an infinity (a blown-up particle) would size the grid from
    // garbage: stop with the solver's error instead (exit 3, state written).
    if (!lo_.allFinite() || !hi.allFinite())
      throw SimulationError("a particle position is not finite (the DEM or coupling blew up)");
    // A particle flung astronomically far (a blow-up that stayed finite)
    // would overflow the cell counts below.
    for (int d = 0; d < D; ++d) {
      if ((hi[d] - lo_[d]) / std::max(cell, 1e-300) > 1e12)
        throw SimulationError("a DEM particle is far outside the domain (the DEM blew up)");
    }
    const double budget = 16.0 * static_cast<double>(n) + 64.0;
    cell_ = std::max(cell, 1e-300);
    for (;;) {
      double total = 1;
      for (int d = 0; d < D; ++d) {
        dims_[d] = static_cast<std::int64_t>((hi[d] - lo_[d]) / cell_) + 1;
        total *= static_cast<double>(dims_[d]);
      }
      if (total <= budget) break;
      cell_ *= 2.0;
    }
    std::int64_t ncell = 1;
    for (int d = 0; d < D; ++d) ncell *= dims_[d];
    start.assign(static_cast<std::size_t>(ncell) + 1, 0);
    items.resize(n);
    for (std::size_t i = 0; i < n; ++i) ++start[cell_of(x[i]) + 1];
    for (std::int64_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) items[fill[cell_of(x[i])]++] = static_cast<std::int32_t>(i);
    start_ = &start;
    items_ = &items;
  }

  // Calls f(j) for every particle in the cells around position p.
  template <class F>
  void for_each_near(const Vec<D>& p, F&& f) const {
    std::array<std::int64_t, 3> c{0, 0, 0};
    for (int d = 0; d < D; ++d) c[d] = coord(p, d);
    const std::int64_t zlo = D == 3 ? c[2] - 1 : 0, zhi = D == 3 ? c[2] + 1 : 0;
    for (std::int64_t cz = zlo; cz <= zhi; ++cz) {
      if (D == 3 && (cz < 0 || cz >= dims_[2])) continue;
      for (std::int64_t cy = c[1] - 1; cy <= c[1] + 1; ++cy) {
        if (cy < 0 || cy >= dims_[1]) continue;
        for (std::int64_t cx = c[0] - 1; cx <= c[0] + 1; ++cx) {
          if (cx < 0 || cx >= dims_[0]) continue;
          const std::int64_t k = cx + dims_[0] * (cy + dims_[1] * cz);
          for (std::int32_t s = (*start_)[k]; s < (*start_)[k + 1]; ++s) f((*items_)[s]);
        }
      }
    }
  }

  // Calls f(i, j) once for every unordered pair of particles i != j whose
  // cells are the same or adjacent: the pairs for_each_near finds from
  // both ends, each found once. Per cell, the pairs inside it (j after i
  // in the cell's items), then with each of the cells after it in the
  // linear order among its neighbours (13 in 3D, 4 in 2D): half the cells
  // and candidates of calling for_each_near for every particle.
  template <class F>
  void for_each_pair(F&& f) const {
    const std::vector<std::int32_t>& start = *start_;
    const std::vector<std::int32_t>& items = *items_;
    const std::int64_t nz = D == 3 ? dims_[2] : 1;
    for (std::int64_t cz = 0; cz < nz; ++cz)
      for (std::int64_t cy = 0; cy < dims_[1]; ++cy)
        for (std::int64_t cx = 0; cx < dims_[0]; ++cx) {
          const std::int64_t k = cx + dims_[0] * (cy + dims_[1] * cz);
          const std::int32_t s0 = start[k], s1 = start[k + 1];
          if (s0 == s1) continue;
          for (std::int32_t a = s0; a < s1; ++a)
            for (std::int32_t b = a + 1; b < s1; ++b) f(items[a], items[b]);
          for (std::int64_t dz = 0; dz <= (D == 3 ? 1 : 0); ++dz)
            for (std::int64_t dy = dz > 0 ? -1 : 0; dy <= 1; ++dy)
              for (std::int64_t dx = dz > 0 || dy > 0 ? -1 : 1; dx <= 1; ++dx) {
                const std::int64_t x = cx + dx, y = cy + dy, z = cz + dz;
                if (x < 0 || x >= dims_[0] || y < 0 || y >= dims_[1] || z >= nz) continue;
                const std::int64_t m = x + dims_[0] * (y + dims_[1] * z);
                const std::int32_t t0 = start[m], t1 = start[m + 1];
                for (std::int32_t a = s0; a < s1; ++a)
                  for (std::int32_t b = t0; b < t1; ++b) f(items[a], items[b]);
              }
        }
  }

 private:
  std::int64_t coord(const Vec<D>& p, int d) const {
    const auto c = static_cast<std::int64_t>(std::floor((p[d] - lo_[d]) / cell_));
    return std::clamp<std::int64_t>(c, 0, dims_[d] - 1);
  }
  std::int64_t cell_of(const Vec<D>& p) const {
    std::int64_t k = 0;
    for (int d = D - 1; d >= 0; --d) k = k * dims_[d] + coord(p, d);
    return k;
  }

  Vec<D> lo_ = Vec<D>::Zero();
  double cell_ = 1;
  std::array<std::int64_t, 3> dims_{1, 1, 1};
  const std::vector<std::int32_t>* start_ = nullptr;
  const std::vector<std::int32_t>* items_ = nullptr;
};

}  // namespace sphdem::dem_detail
