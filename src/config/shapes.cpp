#include "shapes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace sphdem::config {

namespace {

constexpr int kEdgeSegments = 8;  // samples per edge in point_outside
constexpr const char* kAxis[] = {"x", "y", "z"};

using Point2 = std::array<double, 2>;

// Sign of the turn a -> b -> c (cross product), 0 when collinear.
double orientation(const Point2& a, const Point2& b, const Point2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

bool on_segment(const Point2& a, const Point2& b, const Point2& p) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
         std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
}

// Segments ab and cd share a point (touching counts).
bool segments_meet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const double o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

// The first pair of edges (i, j) of a polygon that cross or touch other
// than at their shared vertex; a simple polygon has none (the filling's
// inside test and the mold's wall outline assume one).
std::optional<std::pair<std::size_t, std::size_t>> crossing_edges(const std::vector<Point2>& v) {
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const Point2 &a = v[i], &b = v[(i + 1) % n], &c = v[j], &d = v[(j + 1) % n];
      if (adjacent) {
        // Neighbours share one vertex; they must not fold back onto each other.
        const Point2& shared = j == i + 1 ? b : a;
        const Point2& p = j == i + 1 ? a : b;
        const Point2& q = j == i + 1 ? d : c;
        const bool repeated = p == shared || q == shared;
        const bool folds = orientation(p, shared, q) == 0 &&
                           (on_segment(p, shared, q) || on_segment(shared, q, p));
        if (repeated || folds) return std::pair{i, j};
        continue;
      }
      if (segments_meet(a, b, c, d)) return std::pair{i, j};
    }
  }
  return std::nullopt;
}

// The self-intersection test is quadratic in the vertex count.
constexpr std::size_t kMaxPolygonVertices = 10000;

std::vector<std::array<double, 2>> read_polygon(const Value& v, int dim) {
  if (dim != 2) v.fail("polygons are 2D only; use a box in 3D");
  const std::vector<Value> items = v.list();
  if (items.size() < 3) v.fail(fmt::format("needs at least 3 vertices, got {}", items.size()));
  if (items.size() > kMaxPolygonVertices)
    v.fail(fmt::format("has {} vertices; at most {}", items.size(), kMaxPolygonVertices));
  std::vector<std::array<double, 2>> vertices;
  for (const Value& item : items) {
    const Vec3a p = item.vector(2);
    vertices.push_back({p[0], p[1]});
  }
  // Shoelace area against the bounding box, so the test is scale-free.
  double area2 = 0, size = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const auto& a = vertices[i];
    const auto& b = vertices[(i + 1) % vertices.size()];
    area2 += a[0] * b[1] - b[0] * a[1];
    size = std::max({size, std::abs(a[0] - b[0]), std::abs(a[1] - b[1])});
  }
  if (!(std::abs(area2) > 1e-12 * size * size)) v.fail("polygon is degenerate (zero area)");
  if (const auto e = crossing_edges(vertices)) {
    const auto edge = [&](std::size_t k) {
      return fmt::format("[{}, {}]-[{}, {}]", vertices[k][0], vertices[k][1],
                         vertices[(k + 1) % vertices.size()][0],
                         vertices[(k + 1) % vertices.size()][1]);
    };
    v.fail(fmt::format("polygon intersects itself: edge {} {} meets edge {} {}", e->first,
                       edge(e->first), e->second, edge(e->second)));
  }
  return vertices;
}

// Bounding box of a set of shapes.
std::pair<Vec3a, Vec3a> bounds(const std::vector<Shape>& shapes) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3a lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  auto grow = [&](const Vec3a& p) {
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  };
  for (const Shape& s : shapes) {
    if (s.type == Shape::Type::Box) {
      grow(s.lo);
      grow(s.hi);
    }
    for (const auto& v : s.vertices) grow({v[0], v[1], 0.0});
  }
  return {lo, hi};
}

double segment_distance(const Vec3a& p, const std::array<double, 2>& a,
                        const std::array<double, 2>& b) {
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey);
}

// Crossing-number test; points within `tol` of an edge count as inside.
bool inside_polygon(const Vec3a& p, const std::vector<std::array<double, 2>>& v, double tol) {
  bool inside = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if (segment_distance(p, v[j], v[i]) <= tol) return true;
    const bool straddles = (v[i][1] > p[1]) != (v[j][1] > p[1]);
    if (straddles &&
        p[0] < v[j][0] + (v[i][0] - v[j][0]) * (p[1] - v[j][1]) / (v[i][1] - v[j][1])) {
      inside = !inside;
    }
  }
  return inside;
}

bool inside_shape(const Vec3a& p, const Shape& s, int dim, double tol) {
  if (s.type == Shape::Type::Polygon) return inside_polygon(p, s.vertices, tol);
  for (int d = 0; d < dim; ++d)
    if (p[d] < s.lo[d] - tol || p[d] > s.hi[d] + tol) return false;
  return true;
}

// Corners of a box and kEdgeSegments - 1 points inside each of its edges:
// for each axis a, every edge along a (one per corner of the other axes).
std::vector<Vec3a> box_samples(const Shape& s, int dim) {
  std::vector<Vec3a> points;
  for (int a = 0; a < dim; ++a) {
    for (int corner = 0; corner < (1 << dim); ++corner) {
      if (corner & (1 << a)) continue;  // each edge once
      Vec3a p{};
      for (int d = 0; d < dim; ++d) p[d] = (corner & (1 << d)) ? s.hi[d] : s.lo[d];
      for (int k = 0; k <= kEdgeSegments; ++k) {
        p[a] = s.lo[a] + (s.hi[a] - s.lo[a]) * k / kEdgeSegments;
        points.push_back(p);
      }
    }
  }
  return points;
}

std::vector<Vec3a> polygon_samples(const Shape& s) {
  std::vector<Vec3a> points;
  const auto& v = s.vertices;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& a = v[i];
    const auto& b = v[(i + 1) % v.size()];
    for (int k = 0; k < kEdgeSegments; ++k) {
      const double t = static_cast<double>(k) / kEdgeSegments;
      points.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0});
    }
  }
  return points;
}

std::vector<std::string> names(const KeysDoc& doc) {
  std::vector<std::string> n;
  for (const KeyDoc& k : doc.keys) n.push_back(k.name);
  return n;
}

}  // namespace

KeysDoc box_keys_doc() {
  KeysDoc d;
  d.keys.push_back({"min", "vector", "m", "required", "", "the lowest corner", false, {}, false});
  d.keys.push_back({"max",
                    "vector",
                    "m",
                    "required",
                    "> min along every axis",
                    "the highest corner",
                    false,
                    {},
                    false});
  return d;
}

KeysDoc shape_keys_doc() {
  KeysDoc d;
  d.keys.push_back({"polygon",
                    "list of [x, y]",
                    "m",
                    "one of polygon, box",
                    "2D only; at least 3 vertices; non-zero area",
                    "vertices, clockwise or counter-clockwise",
                    false,
                    {},
                    false});
  d.keys.push_back({"box", "mapping", "m", "one of polygon, box", "",
                    "{min: [...], max: [...]}, D numbers each", false,
                    std::make_shared<KeysDoc>(box_keys_doc()), false});
  return d;
}

Shape read_box(const Value& v, int dim) {
  const Map m = v.map(names(box_keys_doc()));
  Shape s;
  s.type = Shape::Type::Box;
  s.lo = m.require("min").vector(dim);
  const Value max = m.require("max");
  s.hi = max.vector(dim);
  for (int d = 0; d < dim; ++d) {
    if (!(s.lo[d] < s.hi[d])) {
      max.fail(fmt::format("must be greater than min along {} (min {}, max {})", kAxis[d], s.lo[d],
                           s.hi[d]));
    }
  }
  s.key = v.key();
  s.line = v.line();
  return s;
}

Shape read_shape(const Value& v, int dim) {
  const Map m = v.map(names(shape_keys_doc()));
  const std::optional<Value> polygon = m.get("polygon");
  const std::optional<Value> box = m.get("box");
  if (polygon.has_value() == box.has_value()) v.fail("expected exactly one of 'polygon' or 'box'");
  Shape s;
  if (polygon) {
    s.type = Shape::Type::Polygon;
    s.vertices = read_polygon(*polygon, dim);
  } else {
    s = read_box(*box, dim);
  }
  s.key = v.key();
  s.line = v.line();
  return s;
}

std::vector<Shape> read_shape_list(const Value& v, int dim) {
  const std::vector<Value> items = v.list();
  if (items.empty()) v.fail("needs at least one shape");
  std::vector<Shape> shapes;
  for (const Value& item : items) shapes.push_back(read_shape(item, dim));
  return shapes;
}

std::optional<Vec3a> point_outside(const Shape& region, const std::vector<Shape>& mold, int dim) {
  const auto [lo, hi] = bounds(mold);
  double size = 0;
  for (int d = 0; d < dim; ++d) size = std::max(size, hi[d] - lo[d]);
  const double tol = 1e-9 * size;
  const std::vector<Vec3a> samples =
      region.type == Shape::Type::Box ? box_samples(region, dim) : polygon_samples(region);
  for (const Vec3a& p : samples) {
    const bool inside = std::any_of(mold.begin(), mold.end(),
                                    [&](const Shape& s) { return inside_shape(p, s, dim, tol); });
    if (!inside) return p;
  }
  return std::nullopt;
}

bool inside_mold(const Vec3a& p, const std::vector<Shape>& mold, int dim) {
  const auto [lo, hi] = bounds(mold);
  double size = 0;
  for (int d = 0; d < dim; ++d) size = std::max(size, hi[d] - lo[d]);
  const double tol = 1e-9 * size;
  return std::any_of(mold.begin(), mold.end(),
                     [&](const Shape& s) { return inside_shape(p, s, dim, tol); });
}

}  // namespace sphdem::config
