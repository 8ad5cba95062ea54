#pragma once
// Surface tension as a continuum surface force (Brackbill, Kothe & Zemach
// 1992, JCP 100:335) in SPH form for a single-phase free surface (Morris
// 2000, Int. J. Numer. Meth. Fluids 33:333), docs/physics.md "Surface
// tension". Two neighbour-sum passes (pass_loop.hpp) and one pair term, per
// resin particle i over every neighbour j (resin and wall, V_j = m_j / rho_j,
// grad W_ij = F_ij x_ij, lattice-corrected):
//   1. colour gradient  g_i = sum_j V_j grad W_ij (points into the resin),
//      Shepard colour c_i = sum_j V_j W_ij (i included);
//      unit outward normal n_i = -g_i / |g_i| where |g_i| h >= kNormalThreshold
//      (Morris 2000's filter of unreliable normals) and c_i < kBulkColour (a
//      full support is bulk), else n_i = 0; within 2h of a wall blended
//      toward the contact angle's normal (near_wall_normal);
//   2. curvature  kappa_i = (D - 1) sum_j w_j V_j (n_j - n_i).grad W_ij
//                             / sum_j w_j V_j (-F_ij) (|x_ij|^2 - (x_ij.n_i)^2),
//      w_j = 1 for a neighbour with a normal: the divergence of n renormalised
//      over the neighbours that have one and over the tangent plane (the
//      normal of a level set changes only along it), exact for a normal
//      field of uniform curvature whatever part of the support is missing:
//      the kernel correction near the surface. It is the curvature of the
//      level set through i: moved to the surface with i's depth, estimated
//      from c_i as for a flat surface (CurvaturePass::store). A wall neighbour shows the
//      normal of the contact angle theta (Breinlinger et al. 2013, JCP
//      243:14): n_w cos theta + t sin theta, n_w the wall's unit normal into
//      the resin, t the unit tangent along the wall of i's normal;
//   3. force  f_i = 2 sigma kappa_i g_i: |g| integrates to 1/2 across a
//      single-phase surface (the Shepard colour falls from 1 to 1/2 only),
//      so 2 |g| is the surface delta. As the pair loop's bracket,
//        a_i = -sum_j m_j b_ij F x_ij,   b_ij = -2 sigma kappa_i / (rho_i rho_j).
// The force is not antisymmetric (kappa_i only): momentum is not conserved
// exactly (CSF's known property). Case-file keys: resin.surface_tension,
// contact_angle (mold and walls).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "../record_fields.hpp"

namespace sphdem::terms {

// |g| h below which a normal is unreliable (interior noise).
inline constexpr double kNormalThreshold = 0.05;
// The Shepard colour (walls counted as resin) at and above which a particle
// has no normal: that of a full support. A flat surface gives a normal only
// down to the depth where its colour is 0.990 (|g| h = kNormalThreshold at
// 1.23 h); a particle in a clump inside the resin has a colour above 1 and a
// gradient above the threshold, whose curvature and force opened voids
// (docs/physics.md "Surface tension").
inline constexpr double kBulkColour = 1.0;

namespace field {
// The unit outward normal (0 where unreliable); the neighbour's value.
struct CsfNormal {
  static constexpr bool kVector = true;
  using RelativeTo = void;
  static constexpr const char* name = "csf_normal";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    for (int d = 0; d < D; ++d) out[d] = ps.csf_normal[i][d];
  }
};
// A wall particle's unit normal into the resin (0 for resin).
struct WallNormal {
  static constexpr bool kVector = true;
  using RelativeTo = void;
  static constexpr const char* name = "wall_normal";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    const Vec<D>& s = ps.wall_to_surface[i];
    const double n = s.norm();
    const bool wall = ps.kind[i] != Kind::Fluid && n > 0.0;
    for (int d = 0; d < D; ++d) out[d] = wall ? s[d] / n : 0.0;
  }
};
// cos and sin of a wall particle's contact angle (SphParams::contact_angle
// by wall index + 1); 0 for resin.
struct ContactCos : ScalarField {
  static constexpr const char* name = "contact_cos";
  template <int D>
  static void fill(const SphParams& sp, const SphParticles<D>& ps, std::size_t i, double* out) {
    const bool wall = ps.kind[i] != Kind::Fluid;
    const double deg = wall ? sp.contact_angle[static_cast<std::size_t>(ps.wall[i] + 1)] : 0.0;
    out[0] = wall ? std::cos(deg * std::numbers::pi / 180.0) : 0.0;
  }
};
struct ContactSin : ScalarField {
  static constexpr const char* name = "contact_sin";
  template <int D>
  static void fill(const SphParams& sp, const SphParticles<D>& ps, std::size_t i, double* out) {
    const bool wall = ps.kind[i] != Kind::Fluid;
    const double deg = wall ? sp.contact_angle[static_cast<std::size_t>(ps.wall[i] + 1)] : 0.0;
    out[0] = wall ? std::sin(deg * std::numbers::pi / 180.0) : 0.0;
  }
};
// A wall particle's depth behind the mold's surface, |wall_to_surface| (0 for resin).
struct WallDepth : ScalarField {
  static constexpr const char* name = "wall_depth";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.kind[i] != Kind::Fluid ? ps.wall_to_surface[i].norm() : 0.0;
  }
};
struct Colour : ScalarField {
  static constexpr const char* name = "colour";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.colour[i];
  }
};
struct Curvature : ScalarField {
  static constexpr const char* name = "curvature";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.curvature[i];
  }
};
}  // namespace field

// The Shepard colour c(q) = sum_j V_j W_ij of a particle at depth q h below
// a flat surface of a uniform resin (1/2 at q = 0, 1 from q = 2 on): the
// kernel's mass on the resin's side, tabulated once per dimension.
template <int D>
double flat_surface_colour(double q) {
  constexpr int kN = 256;
  static const std::vector<double> table = [] {
    const WendlandC2<D> kernel(1.0);
    // The kernel's mass on the plane at distance s: its integral over the plane.
    const auto plane = [&](double s) {
      constexpr int kM = 400;
      double sum = 0.0;
      const double reach = std::sqrt(std::max(0.0, 4.0 - s * s));
      for (int m = 0; m < kM; ++m) {
        const double y = (m + 0.5) * reach / kM;
        const double w = kernel.w(std::sqrt(s * s + y * y));
        sum += (D == 2 ? 2.0 * w : 2.0 * std::numbers::pi * y * w) * reach / kM;
      }
      return sum;
    };
    std::vector<double> c(kN + 1);
    c[0] = 0.5;
    for (int k = 0; k < kN; ++k) c[k + 1] = c[k] + plane((k + 0.5) * 2.0 / kN) * 2.0 / kN;
    return c;
  }();
  const double x = std::clamp(q, 0.0, 2.0) * kN / 2.0;
  const int k = std::min(static_cast<int>(x), kN - 1);
  return table[k] + (x - k) * (table[k + 1] - table[k]);
}

// The depth (in h) at which a flat surface gives colour c: the inverse of
// flat_surface_colour by bisection; 0 for c <= 1/2, 2 for c >= its maximum.
template <int D>
double depth_of_colour(double c) {
  double lo = 0.0, hi = 2.0;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (flat_surface_colour<D>(mid) < c ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Pass 1: the Shepard colour and the unit normal.
struct SurfaceNormalPass {
  static constexpr const char* name = "colour";
  static constexpr const char* also_outputs[] = {"csf_normal"};
  using Reads = Fields<field::Pos, field::Vol, field::Fluid, field::WallNormal, field::WallDepth,
                       field::ContactCos, field::ContactSin>;
  using Output = field::Colour;
  static constexpr SphGroup group = SphGroup::SurfaceNormal;
  // g, the colour, and over the wall neighbours: sum V W, sum V W n_w, sum V W cos, sin, distance.
  template <int D>
  static constexpr std::size_t kSums = 2 * D + 5;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.colour;
  }
  // The curvature pass reads its normal.
  static bool needed(const SphParams& sp) { return sp.surface_tension > 0.0; }

  double threshold;  // kNormalThreshold / h
  double kw;         // W = kw t^4 (1 + 2q)
  double reach;      // 2h: beyond it no wall particle is in the support
  template <int D>
  explicit SurfaceNormalPass(const TermContext<D>& c)
      : threshold(kNormalThreshold / c.sp.h), kw(c.kw), reach(2.0 * c.sp.h) {}

  // s[0..D) = g, s[D] = sum_j V_j W_ij; over the wall neighbours: s[D + 1]
  // = sum V W, s[D + 2..2D + 2) = sum V W n_w, s[2D + 2], s[2D + 3] = sum V W
  // cos theta, sin theta, s[2D + 4] = sum V W (i's height above the wall's surface).
  template <class P>
  void pair(const P& p, double* s) const {
    constexpr int D = P::kDim;
    const double v = p.lane(field::Vol{});
    for (int d = 0; d < D; ++d) s[d] = v * p.F * p.lane(field::Pos{}, d);
    const double t2 = p.t * p.t;
    const double vw = v * kw * t2 * t2 * (1.0 + 2.0 * p.q);
    s[D] = vw;
    const double wall = (1.0 - p.lane(field::Fluid{})) * vw;
    s[D + 1] = wall;
    double xn = 0.0;
    for (int d = 0; d < D; ++d) {
      const double n = p.lane(field::WallNormal{}, d);
      s[D + 2 + d] = wall * n;
      xn += p.lane(field::Pos{}, d) * n;
    }
    s[2 * D + 2] = wall * p.lane(field::ContactCos{});
    s[2 * D + 3] = wall * p.lane(field::ContactSin{});
    s[2 * D + 4] = wall * (xn - p.lane(field::WallDepth{}));
  }
  // The colour without i's own part (store adds it).
  template <int D>
  double finish(const double* sums) const {
    return sums[D];
  }
  template <int D>
  void store(const double* sums, SphParticles<D>& ps, std::size_t i) const {
    ps.colour[i] += ps.mass[i] / ps.rho[i] * 16.0 * kw;  // V_i W(0)
    Vec<D> g;
    for (int d = 0; d < D; ++d) g[d] = sums[d];
    const double norm = g.norm();
    // A full support (colour at least kBulkColour) is not at a free surface:
    // its gradient is the disorder of the bulk, not a normal.
    const bool bulk = ps.colour[i] >= kBulkColour;
    Vec<D> n = norm >= threshold && !bulk ? Vec<D>(-g / norm) : Vec<D>::Zero();
    const double cw = sums[D + 1];
    if (cw > 0.0 && n.squaredNorm() > 0.0) n = near_wall_normal<D>(n, sums, cw);
    ps.csf_normal[i] = n;
  }
  template <int D>
  void clear(SphParticles<D>& ps, std::size_t i) const {
    ps.csf_normal[i] = Vec<D>::Zero();
  }
  // Near a wall the colour counts the wall particles as resin, as if the
  // resin filled the wall beyond the contact line: the normal of a surface
  // particle on the floor row tilts away from the wall (about 30 degrees at
  // 120, tests/test_surface_tension.cpp). It is blended toward the contact
  // angle's normal n_w cos theta + t sin theta (t: the normal's part along
  // the wall), fully at the wall's surface and not at all at the wall's
  // reach 2h, linearly in i's height d above the surface (the wall's
  // Shepard means of n_w, cos, sin and d); docs/physics.md "Surface tension".
  template <int D>
  Vec<D> near_wall_normal(const Vec<D>& n, const double* sums, double cw) const {
    Vec<D> nw;
    for (int d = 0; d < D; ++d) nw[d] = sums[D + 2 + d];
    if (nw.norm() == 0.0) return n;
    nw /= nw.norm();
    Vec<D> t = n - n.dot(nw) * nw;
    if (t.norm() > 0.0) t /= t.norm();
    const Vec<D> n_theta = nw * (sums[2 * D + 2] / cw) + t * (sums[2 * D + 3] / cw);
    const double f = std::clamp(1.0 - sums[2 * D + 4] / cw / reach, 0.0, 1.0);
    const Vec<D> m = (1.0 - f) * n + f * n_theta;
    return m.norm() > 0.0 ? Vec<D>(m / m.norm()) : n;
  }
};

// Pass 2: the curvature, the renormalised divergence of the unit normal.
struct CurvaturePass {
  static constexpr const char* name = "curvature";
  using Reads = Fields<field::Pos, field::Vol, field::CsfNormal, field::WallNormal,
                       field::ContactCos, field::ContactSin, field::Fluid>;
  using Output = field::Curvature;
  static constexpr SphGroup group = SphGroup::Curvature;
  template <int D>
  static constexpr std::size_t kSums = 2;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.curvature;
  }

  // s[0] = sum w V (n_j - n_i).F x_ij, s[1] = sum w V (-F) (r^2 - (x_ij.n_i)^2).
  template <class P>
  void pair(const P& p, double* s) const {
    constexpr int D = P::kDim;
    // i's normal, and its part along the wall's plane (walls only).
    double ni[D], nw[D], nin = 0.0, ni2 = 0.0;
    for (int d = 0; d < D; ++d) {
      ni[d] = p.own_value(field::CsfNormal{}, d);
      nw[d] = p.lane(field::WallNormal{}, d);
      nin += ni[d] * nw[d];
      ni2 += ni[d] * ni[d];
    }
    double t[D], t2 = 0.0;
    for (int d = 0; d < D; ++d) {
      t[d] = ni[d] - nin * nw[d];
      t2 += t[d] * t[d];
    }
    const double fluid = p.lane(field::Fluid{});
    // A wall neighbour whose tangent is undefined (i's normal along the wall
    // normal) shows n_w cos theta alone.
    const double inv_t = t2 > 0.0 ? 1.0 / std::sqrt(t2) : 0.0;
    const double cs = p.lane(field::ContactCos{}), sn = p.lane(field::ContactSin{});
    double nj[D], nj2 = 0.0, dot = 0.0, xn = 0.0;
    for (int d = 0; d < D; ++d) {
      const double wall_n = nw[d] * cs + t[d] * inv_t * sn;
      nj[d] = fluid * p.lane(field::CsfNormal{}, d) + (1.0 - fluid) * wall_n;
      nj2 += p.lane(field::CsfNormal{}, d) * p.lane(field::CsfNormal{}, d);
      dot += (nj[d] - ni[d]) * p.lane(field::Pos{}, d);
      xn += ni[d] * p.lane(field::Pos{}, d);
    }
    // Only neighbours with a normal count, and only when i has one (else kappa_i = 0).
    const double w = ni2 * (fluid * nj2 + (1.0 - fluid));
    const double vf = w * p.lane(field::Vol{}) * p.F;
    s[0] = vf * dot;
    s[1] = -vf * (p.r2 - xn * xn);
  }
  template <int D>
  double finish(const double* sums) const {
    return sums[1] > 0.0 ? (D - 1) * sums[0] / sums[1] : 0.0;
  }
  // finish's kappa is that of the level set through particle i, a depth d
  // below the surface: moved to the surface, kappa / (1 + kappa d / (D - 1))
  // (exact for a circle or a sphere), with d from the colour as for a flat
  // surface; the factor is kept within [1/2, 2].
  double h;
  template <int D>
  explicit CurvaturePass(const TermContext<D>& c) : h(c.sp.h) {}
  template <int D>
  void store(const double*, SphParticles<D>& ps, std::size_t i) const {
    const double k = ps.curvature[i];
    const double d = h * depth_of_colour<D>(ps.colour[i]);
    ps.curvature[i] = k * std::clamp(1.0 / (1.0 + k * d / (D - 1)), 0.5, 2.0);
  }
};

// The force, in the pair loop's bracket.
struct CsfSurfaceTension {
  static constexpr const char* name = "surface_tension";
  using Reads = Fields<field::Rho>;
  using OwnReads = Fields<field::Curvature>;
  static constexpr unsigned writes = kBracket;
  static bool active(const SphParams& sp) { return sp.surface_tension > 0.0; }

  double two_sigma;
  template <int D>
  explicit CsfSurfaceTension(const TermContext<D>& c) : two_sigma(2.0 * c.sp.surface_tension) {}

  template <class P>
  void pair(const P& p, PairSums& s) const {
    s.bracket += -two_sigma * p.own_value(field::Curvature{}) /
                 (p.own_value(field::Rho{}) * p.lane(field::Rho{}));
  }
};

}  // namespace sphdem::terms
