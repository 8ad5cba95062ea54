// The DEM walls of a case's mold and moving walls (mold_walls.hpp,
// docs/dem.md "Walls"): only the parts of the shapes' boundaries that bound
// the union of the shapes (fibers pass from one shape into a touching one),
// in 2D as segments, in 3D as rectangles.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/geometry/mold_walls.hpp"

namespace sphdem {

namespace {

// Corners of a 2D shape in order (a box as a rectangle).
std::vector<Vec<2>> outline(const Shape& s) {
  if (s.type == Shape::Type::Box)
    return {Vec<2>(s.lo[0], s.lo[1]), Vec<2>(s.hi[0], s.lo[1]), Vec<2>(s.hi[0], s.hi[1]),
            Vec<2>(s.lo[0], s.hi[1])};
  std::vector<Vec<2>> out;
  for (const auto& v : s.vertices) out.emplace_back(v[0], v[1]);
  return out;
}

// The mold's size, for tolerances: its largest coordinate.
double mold_size(const Case& c) {
  double size = 0;
  for (const Shape& s : c.mold.shapes) {
    if (s.type == Shape::Type::Box) {
      for (int k = 0; k < c.dimension; ++k)
        size = std::max({size, std::abs(s.lo[static_cast<std::size_t>(k)]),
                         std::abs(s.hi[static_cast<std::size_t>(k)])});
    } else {
      for (const Vec<2>& p : outline(s)) size = std::max(size, p.cwiseAbs().maxCoeff());
    }
  }
  return size;
}

[[noreturn]] void no_touch(const Case& c, std::size_t w) {
  throw InputError(c.source_file, c.moving_walls[w].line, fmt::format("moving_walls[{}].region", w),
                   "no edge of the region touches the mold, so the wall cannot push fibers");
}

// Which ends of the mold's segments push (DemWall kEndA / kEndB), so that a
// particle meets one wall where two segments meet, as the 3D rectangles'
// edges do: at a seam (the next piece of the same straight boundary) no
// end pushes, the faces cover it; at a concave corner neither, the two
// faces hold the particle; at a convex one (the rim where a nozzle meets
// the bath: resin just beyond the vertex between the two segments) the
// segment listed first owns the vertex. A free end keeps pushing.
void flag_segment_ends(const Case& c, std::vector<DemWall<2>>& walls, double tol) {
  const double probe = 1e3 * tol;
  auto end_of = [](const DemWall<2>& w, int e) { return e == 0 ? w.point : w.end; };
  auto into = [&](const DemWall<2>& w, int e) {  // unit direction from end e along w
    return Vec<2>((end_of(w, 1 - e) - end_of(w, e)).normalized());
  };
  std::vector<int> flags(walls.size(), DemWall<2>::kEndA | DemWall<2>::kEndB);
  for (std::size_t i = 0; i < walls.size(); ++i) {
    for (int e = 0; e < 2; ++e) {
      const Vec<2> v = end_of(walls[i], e);
      const Vec<2> ui = into(walls[i], e);
      bool push = true;
      for (std::size_t j = 0; j < walls.size() && push; ++j) {
        for (int f = 0; f < 2 && j != i; ++f) {
          if ((end_of(walls[j], f) - v).norm() >= tol) continue;
          const Vec<2> uj = into(walls[j], f);
          const bool seam = ui.dot(uj) < -1 + 1e-9;
          const bool convex =
              !seam && union_contains<2>(c.mold.shapes, Vec<2>(v - probe * (ui + uj)), 0.0);
          if (seam || !convex || j < i) push = false;
        }
      }
      if (!push) flags[i] &= ~(e == 0 ? DemWall<2>::kEndA : DemWall<2>::kEndB);
    }
  }
  for (std::size_t i = 0; i < walls.size(); ++i) walls[i].edges = flags[i];
}

std::vector<DemWall<2>> walls_2d(const Case& c, std::vector<int>& wall_owner) {
  std::vector<DemWall<2>> walls;
  const double tol = 1e-9 * mold_size(c);
  // Moving walls: the edges of the region that touch the mold.
  auto add_touching = [&](const Shape& s, int owner) {
    const std::vector<Vec<2>> p = outline(s);
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Vec<2>& a = p[k];
      const Vec<2>& b = p[(k + 1) % p.size()];
      if (!union_contains<2>(c.mold.shapes, Vec<2>(0.5 * (a + b)), tol)) continue;
      walls.push_back(DemWall<2>::segment(a, b));
      wall_owner.push_back(owner);
    }
  };
  // The mold: only the parts of its shapes' edges on the boundary of their
  // union (where two shapes meet, as the bath and the nozzle do, fibers
  // pass). An edge is cut at every vertex of the mold lying on it; a piece
  // is boundary when resin is on exactly one side of its midpoint.
  std::vector<Vec<2>> vertices;
  for (const Shape& s : c.mold.shapes)
    for (const Vec<2>& v : outline(s)) vertices.push_back(v);
  auto add_boundary = [&](const Shape& s) {
    const std::vector<Vec<2>> p = outline(s);
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Vec<2>& a = p[k];
      const Vec<2>& b = p[(k + 1) % p.size()];
      const Vec<2> ab = b - a;
      const double len = ab.norm();
      const Vec<2> normal(-ab[1] / len, ab[0] / len);
      std::vector<double> cuts{0.0, 1.0};
      for (const Vec<2>& v : vertices) {
        const double t = (v - a).dot(ab) / (len * len);
        if (t > 0 && t < 1 && std::abs((v - a).dot(normal)) < tol) cuts.push_back(t);
      }
      std::sort(cuts.begin(), cuts.end());
      const double probe = 1e3 * tol;
      for (std::size_t m = 0; m + 1 < cuts.size(); ++m) {
        if (cuts[m + 1] - cuts[m] < 1e-12) continue;
        const Vec<2> mid = a + 0.5 * (cuts[m] + cuts[m + 1]) * ab;
        const bool left = union_contains<2>(c.mold.shapes, Vec<2>(mid + probe * normal), 0.0);
        const bool right = union_contains<2>(c.mold.shapes, Vec<2>(mid - probe * normal), 0.0);
        if (left == right) continue;
        const Vec<2> p0 = a + cuts[m] * ab, p1 = a + cuts[m + 1] * ab;
        const auto same = [&](const DemWall<2>& w) {  // shapes sharing an outer edge
          return ((w.point - p0).norm() < tol && (w.end - p1).norm() < tol) ||
                 ((w.point - p1).norm() < tol && (w.end - p0).norm() < tol);
        };
        if (std::any_of(walls.begin(), walls.end(), same)) continue;
        walls.push_back(DemWall<2>::segment(p0, p1));
        walls.back().normal = left ? normal : Vec<2>(-normal);  // into the mold
        wall_owner.push_back(-1);
      }
    }
  };
  for (const Shape& s : c.mold.shapes) add_boundary(s);
  flag_segment_ends(c, walls, tol);
  for (std::size_t w = 0; w < c.moving_walls.size(); ++w) {
    const std::size_t before = walls.size();
    add_touching(c.moving_walls[w].region, static_cast<int>(w));
    if (walls.size() == before) no_touch(c, w);
  }
  return walls;
}

// The 3D mold (a union of boxes) on the grid of every box's coordinates:
// each plane x_a = z through a box face is cut into cells; a cell is a wall
// when resin is on exactly one side of its centre (label +1 / -1: the
// inward normal along +e_a / -e_a). An edge of a cell pushes (DemWall
// `edges`) only where the solid behind the cell ends in a convex edge that
// particles can reach from both sides (the rim where a nozzle meets the
// bath): resin on both sides just beyond it. The other wall through that
// line (perpendicular, its own cell edge the same segment) sees the same,
// so the one with the smaller normal axis owns the edge. Seams between
// coplanar cells, and edges into a concave corner, do not push: the
// neighbouring face does. Coplanar cells of equal label are then merged
// into rectangles whose every side has one edge flag.
class MoldGrid3 {
 public:
  MoldGrid3(const Case& c, double tol) : c_(c), probe_(1e3 * tol) {
    for (int a = 0; a < 3; ++a) {
      std::vector<double>& v = coords_[static_cast<std::size_t>(a)];
      for (const Shape& s : c.mold.shapes)
        v.insert(v.end(), {s.lo[static_cast<std::size_t>(a)], s.hi[static_cast<std::size_t>(a)]});
      std::sort(v.begin(), v.end());
      std::vector<double> merged;
      for (double x : v)
        if (merged.empty() || x - merged.back() > tol) merged.push_back(x);
      v = merged;
    }
  }

  void add_walls(std::vector<DemWall<3>>& walls) const {
    for (int a = 0; a < 3; ++a)
      for (double z : coords_[static_cast<std::size_t>(a)]) add_plane(a, z, walls);
  }

 private:
  struct Cell {
    int label = 0;  // inward normal sign along the plane's axis, 0: no wall
    int edges = 0;  // DemWall<3>::edges of the cell alone
    bool used = false;
  };

  bool inside(const Vec<3>& p) const { return union_contains<3>(c_.mold.shapes, p, 0.0); }

  const std::vector<double>& axis(int k) const { return coords_[static_cast<std::size_t>(k % 3)]; }

  void add_plane(int a, double z, std::vector<DemWall<3>>& walls) const {
    const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    const std::vector<double>& g1 = axis(b1);
    const std::vector<double>& g2 = axis(b2);
    if (g1.size() < 2 || g2.size() < 2) return;
    const std::size_t n1 = g1.size() - 1, n2 = g2.size() - 1;
    const Vec<3> ea = Vec<3>::Unit(a), e1 = Vec<3>::Unit(b1), e2 = Vec<3>::Unit(b2);
    std::vector<Cell> cells(n1 * n2);
    const auto at = [&](std::size_t i, std::size_t j) -> Cell& { return cells[i * n2 + j]; };
    const auto centre = [&](std::size_t i, std::size_t j) {
      return Vec<3>(z * ea + 0.5 * (g1[i] + g1[i + 1]) * e1 + 0.5 * (g2[j] + g2[j + 1]) * e2);
    };
    for (std::size_t i = 0; i < n1; ++i)
      for (std::size_t j = 0; j < n2; ++j) {
        const Vec<3> m = centre(i, j);
        const bool up = inside(m + probe_ * ea), down = inside(m - probe_ * ea);
        at(i, j).label = up == down ? 0 : (up ? 1 : -1);
      }
    // Edge flags: bit 0 at g1[i] (out of the cell along -e1), bit 1 at
    // g1[i+1] (+e1), bit 2 at g2[j] (-e2), bit 3 at g2[j+1] (+e2).
    for (std::size_t i = 0; i < n1; ++i)
      for (std::size_t j = 0; j < n2; ++j) {
        Cell& cell = at(i, j);
        if (cell.label == 0) continue;
        const Vec<3> n = cell.label * ea, m = centre(i, j);
        const double h1 = 0.5 * (g1[i + 1] - g1[i]), h2 = 0.5 * (g2[j + 1] - g2[j]);
        const std::array<bool, 4> seam{i > 0 && at(i - 1, j).label == cell.label,
                                       i + 1 < n1 && at(i + 1, j).label == cell.label,
                                       j > 0 && at(i, j - 1).label == cell.label,
                                       j + 1 < n2 && at(i, j + 1).label == cell.label};
        const std::array<Vec<3>, 4> out{-e1, e1, -e2, e2};
        const std::array<double, 4> half{h1, h1, h2, h2};
        const std::array<int, 4> out_axis{b1, b1, b2, b2};
        for (std::size_t k = 0; k < 4; ++k) {
          if (seam[k] || out_axis[k] < a) continue;  // a seam, or the other wall owns it
          const Vec<3> q = m + (half[k] + probe_) * out[k];
          if (inside(q + probe_ * n) && inside(q - probe_ * n)) cell.edges |= 1 << k;
        }
      }
    // Greedy merge: rows along e2, then whole rows along e1.
    for (std::size_t i = 0; i < n1; ++i)
      for (std::size_t j = 0; j < n2; ++j) {
        const Cell& first = at(i, j);
        if (first.label == 0 || first.used) continue;
        const auto same = [&](const Cell& x) { return x.label == first.label && !x.used; };
        std::size_t j1 = j;
        while (j1 + 1 < n2 && same(at(i, j1 + 1)) && (at(i, j1 + 1).edges & 3) == (first.edges & 3))
          ++j1;
        const int t0 = first.edges & 4, t1 = at(i, j1).edges & 8;
        std::size_t i1 = i;
        while (i1 + 1 < n1) {
          bool ok = (at(i1 + 1, j).edges & 4) == t0 && (at(i1 + 1, j1).edges & 8) == t1;
          for (std::size_t k = j; k <= j1 && ok; ++k)
            ok = same(at(i1 + 1, k)) && (at(i1 + 1, k).edges & 2) == (at(i1 + 1, j).edges & 2);
          if (!ok) break;
          ++i1;
        }
        for (std::size_t r = i; r <= i1; ++r)
          for (std::size_t k = j; k <= j1; ++k) at(r, k).used = true;
        const int edges = (first.edges & 1) | (at(i1, j).edges & 2) | t0 | t1;
        const Vec<3> corner = z * ea + g1[i] * e1 + g2[j] * e2;
        walls.push_back(DemWall<3>::rect(corner, (g1[i1 + 1] - g1[i]) * e1,
                                         (g2[j1 + 1] - g2[j]) * e2, first.label * ea, edges));
      }
  }

  const Case& c_;
  double probe_;
  std::array<std::vector<double>, 3> coords_;
};

// A moving wall's region box: its faces that touch the mold, pushing out of
// the box; an edge pushes where the mold lies just beyond it.
void add_touching_3d(const Case& c, const Shape& s, double tol, std::vector<DemWall<3>>& walls) {
  const Vec<3> lo(s.lo[0], s.lo[1], s.lo[2]), hi(s.hi[0], s.hi[1], s.hi[2]);
  const double probe = 1e3 * tol;
  for (int a = 0; a < 3; ++a) {
    const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    const Vec<3> e1 = (hi[b1] - lo[b1]) * Vec<3>::Unit(b1),
                 e2 = (hi[b2] - lo[b2]) * Vec<3>::Unit(b2);
    for (int side = 0; side < 2; ++side) {
      Vec<3> corner = lo;
      corner[a] = side ? hi[a] : lo[a];
      const Vec<3> n = (side ? 1.0 : -1.0) * Vec<3>::Unit(a);
      const Vec<3> mid = corner + 0.5 * (e1 + e2);
      if (!union_contains<3>(c.mold.shapes, mid, tol)) continue;
      const std::array<Vec<3>, 4> edge_mid{corner + 0.5 * e2, corner + e1 + 0.5 * e2,
                                           corner + 0.5 * e1, corner + e2 + 0.5 * e1};
      const std::array<Vec<3>, 4> out{-e1.normalized(), e1.normalized(), -e2.normalized(),
                                      e2.normalized()};
      int edges = 0;
      for (std::size_t k = 0; k < 4; ++k)
        if (union_contains<3>(c.mold.shapes, Vec<3>(edge_mid[k] + probe * (out[k] + n)), 0.0))
          edges |= 1 << k;
      walls.push_back(DemWall<3>::rect(corner, e1, e2, n, edges));
    }
  }
}

std::vector<DemWall<3>> walls_3d(const Case& c, std::vector<int>& wall_owner) {
  std::vector<DemWall<3>> walls;
  const double tol = 1e-9 * mold_size(c);
  MoldGrid3(c, tol).add_walls(walls);
  wall_owner.assign(walls.size(), -1);
  for (std::size_t w = 0; w < c.moving_walls.size(); ++w) {
    const std::size_t before = walls.size();
    add_touching_3d(c, c.moving_walls[w].region, tol, walls);
    if (walls.size() == before) no_touch(c, w);
    wall_owner.resize(walls.size(), static_cast<int>(w));
  }
  return walls;
}

}  // namespace

// Whether wall w lies in a face of the domain along a periodic axis: no
// wall there, the resin and the fibers go through (shear cells).
template <int D>
bool on_periodic_face(const Case& c, const DemWall<D>& w, double tol) {
  if (!c.domain_lo || !c.domain_hi) return false;
  for (int k = 0; k < D; ++k) {
    if (!c.periodic[static_cast<std::size_t>(k)]) continue;
    for (const double face : {(*c.domain_lo)[k], (*c.domain_hi)[k]})
      if (std::abs(w.point[k] - face) <= tol && std::abs(w.end[k] - face) <= tol) return true;
  }
  return false;
}

template <int D>
std::vector<DemWall<D>> dem_walls_from_case(const Case& c, std::vector<int>& wall_owner) {
  wall_owner.clear();
  std::vector<DemWall<D>> all;
  if constexpr (D == 2) {
    all = walls_2d(c, wall_owner);
  } else {
    all = walls_3d(c, wall_owner);
  }
  const double tol = 1e-9 * mold_size(c);
  std::vector<DemWall<D>> walls;
  std::vector<int> owner;
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (on_periodic_face<D>(c, all[k], tol)) continue;
    walls.push_back(all[k]);
    owner.push_back(wall_owner[k]);
  }
  wall_owner = owner;
  return walls;
}

template std::vector<DemWall<2>> dem_walls_from_case<2>(const Case&, std::vector<int>&);
template std::vector<DemWall<3>> dem_walls_from_case<3>(const Case&, std::vector<int>&);

}  // namespace sphdem
