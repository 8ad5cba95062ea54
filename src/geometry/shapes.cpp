#include <algorithm>
#include <cmath>
#include <limits>

#include "sphdem/geometry/geometry.hpp"

namespace sphdem {

namespace {

double segment_distance(const std::array<double, 2>& a, const std::array<double, 2>& b, double px,
                        double py) {
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0 ? ((px - a[0]) * ex + (py - a[1]) * ey) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double dx = px - (a[0] + t * ex), dy = py - (a[1] + t * ey);
  return std::sqrt(dx * dx + dy * dy);
}

// Even-odd crossing test, strict interior.
bool polygon_inside(const std::vector<std::array<double, 2>>& v, double px, double py) {
  bool inside = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    const bool crosses = (v[i][1] > py) != (v[j][1] > py);
    if (crosses) {
      const double xc = v[j][0] + (py - v[j][1]) * (v[i][0] - v[j][0]) / (v[i][1] - v[j][1]);
      if (px < xc) inside = !inside;
    }
  }
  return inside;
}

double polygon_boundary_distance(const std::vector<std::array<double, 2>>& v, double px,
                                 double py) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    d = std::min(d, segment_distance(v[j], v[i], px, py));
  }
  return d;
}

}  // namespace

template <int D>
bool shape_contains(const Shape& s, const Vec<D>& p, double tol) {
  if (s.type == Shape::Type::Box) {
    for (int k = 0; k < D; ++k) {
      if (p[k] < s.lo[k] - tol || p[k] > s.hi[k] + tol) return false;
    }
    return true;
  }
  if constexpr (D == 2) {
    if (polygon_inside(s.vertices, p[0], p[1])) return true;
    return tol > 0 && polygon_boundary_distance(s.vertices, p[0], p[1]) <= tol;
  }
  return false;
}

template <int D>
double shape_distance(const Shape& s, const Vec<D>& p) {
  if (s.type == Shape::Type::Box) {
    double d2 = 0;
    for (int k = 0; k < D; ++k) {
      const double e = std::max({s.lo[k] - p[k], 0.0, p[k] - s.hi[k]});
      d2 += e * e;
    }
    return std::sqrt(d2);
  }
  if constexpr (D == 2) {
    if (polygon_inside(s.vertices, p[0], p[1])) return 0.0;
    return polygon_boundary_distance(s.vertices, p[0], p[1]);
  }
  return std::numeric_limits<double>::infinity();
}

template <int D>
bool union_contains(const std::vector<Shape>& shapes, const Vec<D>& p, double tol) {
  return std::any_of(shapes.begin(), shapes.end(),
                     [&](const Shape& s) { return shape_contains<D>(s, p, tol); });
}

template <int D>
double union_distance(const std::vector<Shape>& shapes, const Vec<D>& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Shape& s : shapes) d = std::min(d, shape_distance<D>(s, p));
  return d;
}

template <int D>
Box<D> mold_bounds(const Case& c) {
  Box<D> b;
  b.lo.setConstant(std::numeric_limits<double>::infinity());
  b.hi.setConstant(-std::numeric_limits<double>::infinity());
  for (const Shape& s : c.mold.shapes) {
    if (s.type == Shape::Type::Box) {
      for (int k = 0; k < D; ++k) {
        b.lo[k] = std::min(b.lo[k], s.lo[k]);
        b.hi[k] = std::max(b.hi[k], s.hi[k]);
      }
    } else {
      for (const auto& v : s.vertices) {
        for (int k = 0; k < std::min(D, 2); ++k) {
          b.lo[k] = std::min(b.lo[k], v[k]);
          b.hi[k] = std::max(b.hi[k], v[k]);
        }
      }
    }
  }
  return b;
}

template <int D>
Box<D> simulation_domain(const Case& c) {
  Box<D> b = mold_bounds<D>(c);
  const double margin = (c.mold.wall_layers + 1) * c.numerics.spacing;
  for (int k = 0; k < D; ++k) {
    if (c.domain_lo)
      b.lo[k] = (*c.domain_lo)[k];
    else
      b.lo[k] -= margin;
    if (c.domain_hi)
      b.hi[k] = (*c.domain_hi)[k];
    else
      b.hi[k] += margin;
  }
  return b;
}

double wall_band(const Case& c) {
  return std::min(c.mold.wall_layers * c.numerics.spacing, 2.0 * c.h());
}

int wall_layers_made(const Case& c) {
  // The fill's tolerance (1e-9 spacings, filling.cpp) keeps a layer that
  // lies on the band's edge.
  const double layers = std::floor(wall_band(c) / c.numerics.spacing + 0.5 + 1e-9);
  return static_cast<int>(std::min(static_cast<double>(c.mold.wall_layers), layers));
}

#define SPHDEM_INSTANTIATE(D)                                                        \
  template bool shape_contains<D>(const Shape&, const Vec<D>&, double);              \
  template double shape_distance<D>(const Shape&, const Vec<D>&);                    \
  template bool union_contains<D>(const std::vector<Shape>&, const Vec<D>&, double); \
  template double union_distance<D>(const std::vector<Shape>&, const Vec<D>&);       \
  template Box<D> mold_bounds<D>(const Case&);                                       \
  template Box<D> simulation_domain<D>(const Case&);
SPHDEM_INSTANTIATE(2)
SPHDEM_INSTANTIATE(3)
#undef SPHDEM_INSTANTIATE

}  // namespace sphdem
