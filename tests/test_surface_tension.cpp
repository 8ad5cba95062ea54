// Surface tension (issue 18 part 3): the continuum surface force of
// src/sph/terms/surface_tension.hpp. Unit checks on a lattice disc (the
// normal, the curvature, the force against a direct sum), and the input
// errors. The droplet validations (Laplace pressure in 2D and 3D, Lamb's
// period) are in test_droplet.cpp (label validation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "../src/sph/terms/surface_tension.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/solver/solver.hpp"
#include "sphdem/sph/sph.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

constexpr double kDp = 1.0e-4;
constexpr double kRadius = 16 * kDp;  // the disc's nodes lie within it

using testing::quiet;

SphParams disc_params(double h_over_dp) {
  SphParams sp;
  sp.spacing = kDp;
  sp.h = h_over_dp * kDp;
  sp.rho0 = 1000;
  sp.c0 = 10;
  sp.grad_scale = gradient_lattice_correction(2, h_over_dp);
  sp.anti_clump = false;
  sp.surface_tension = 0.07;
  return sp;
}

// The lattice nodes (offset by half a spacing) inside a circle of kRadius,
// at rest density: pressure 0, so the surface force is the only one.
SphParticles<2> lattice_disc() {
  SphParticles<2> ps;
  std::int64_t id = 0;
  const int n = 20;
  for (int i = -n; i < n; ++i)
    for (int j = -n; j < n; ++j) {
      const Vec<2> x((i + 0.5) * kDp, (j + 0.5) * kDp);
      if (x.norm() < kRadius)
        ps.push_owned(id++, Kind::Fluid, -1, 1000 * kDp * kDp, x, Vec<2>::Zero(), 1000);
    }
  return ps;
}

// A disc of concentric rings (radius R - (k + 1/2) dp, spacing dp along
// each): a smooth surface of radius R, unlike the staircase of a lattice.
SphParticles<2> ring_disc() {
  SphParticles<2> ps;
  std::int64_t id = 0;
  for (int k = 0; k < 16; ++k) {
    const double r = kRadius - (k + 0.5) * kDp;
    const int n = std::max(1, static_cast<int>(std::lround(2 * std::numbers::pi * r / kDp)));
    for (int m = 0; m < n; ++m) {
      const double a = 2 * std::numbers::pi * (m + 0.5 * (k % 2)) / n;
      ps.push_owned(id++, Kind::Fluid, -1, 1000 * kDp * kDp,
                    Vec<2>(r * std::cos(a), r * std::sin(a)), Vec<2>::Zero(), 1000);
    }
  }
  return ps;
}

// The particles with a normal are the outer rings: their normal is the
// radial one within 0.01, their curvature that of the surface, 1 / R,
// within 10 % each and 5 % on average: the renormalisation over the
// neighbours that have a normal and over the tangent (without it kappa is
// ~2 / R) and the move to the surface (without it the second ring gives
// 1 / (R - 1.5 dp), 10 % high). The bulk has no normal. (The few particles
// of the innermost rings are not a disc's lattice and are left out.)
TEST(SurfaceTension, NormalAndCurvatureOfADisc) {
  SphParticles<2> ps = ring_disc();
  const SphParams sp = disc_params(1.5);
  NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  std::vector<SphGroup> forwarded;
  compute_fluid_passes<2>(sp, nl, ps, [&](SphGroup g) { forwarded.push_back(g); });
  EXPECT_EQ(forwarded, (std::vector<SphGroup>{SphGroup::SurfaceNormal, SphGroup::Curvature}));
  int with_normal = 0;
  double sum = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const double r = ps.x[i].norm();
    if (r < 4 * kDp) continue;
    if (r < kRadius - 4 * kDp) {
      EXPECT_EQ(ps.csf_normal[i], Vec<2>::Zero()) << "bulk particle at r = " << r;
      EXPECT_EQ(ps.curvature[i], 0.0);
    }
    if (ps.csf_normal[i] == Vec<2>::Zero()) continue;
    ++with_normal;
    EXPECT_GT(ps.csf_normal[i].dot(ps.x[i] / r), 0.99) << r;
    EXPECT_NEAR(ps.curvature[i] * kRadius, 1.0, 0.10) << "at r = " << r / kDp << " dp";
    sum += ps.curvature[i] * kRadius;
  }
  std::printf("[          ] %d particles with a normal: mean curvature %.4f of 1/R\n", with_normal,
              sum / with_normal);
  EXPECT_GT(with_normal, 150);
  EXPECT_NEAR(sum / with_normal, 1.0, 0.05);
}

// The bulk filter (kBulkColour): a particle inside the resin pushed 0.3 dp
// toward its neighbour has a colour gradient above Morris's threshold and a
// colour above 1 (both summed here by hand); it gets no normal and no
// curvature, so no surface force. Its neighbours on the far side, with a
// colour below 1, may keep theirs, but the disc's surface rows are as
// before (NormalAndCurvatureOfADisc).
TEST(SurfaceTension, NoNormalInAClumpInsideTheResin) {
  SphParticles<2> ps = lattice_disc();
  const SphParams sp = disc_params(1.5);
  std::size_t c = 0;  // the particle nearest the centre
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.x[i].norm() < ps.x[c].norm()) c = i;
  ps.x[c][0] += 0.3 * kDp;
  NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  compute_fluid_passes<2>(sp, nl, ps, [](SphGroup) {});
  const WendlandC2<2> kernel(sp.h);
  Vec<2> g = Vec<2>::Zero();
  double colour = 0;
  for (std::size_t j = 0; j < ps.n_owned; ++j) {
    const Vec<2> xij = ps.x[c] - ps.x[j];
    const double r = xij.norm();
    if (r >= 2 * sp.h) continue;
    colour += ps.mass[j] / ps.rho[j] * kernel.w(r);
    if (j != c) g += ps.mass[j] / ps.rho[j] * kernel.f(r) * sp.grad_scale * xij;
  }
  std::printf("[          ] clumped particle: colour %.4f, |g| h %.3f\n", colour, g.norm() * sp.h);
  EXPECT_NEAR(ps.colour[c], colour, 1e-12);
  ASSERT_GE(colour, terms::kBulkColour);
  ASSERT_GE(g.norm() * sp.h, terms::kNormalThreshold);
  EXPECT_EQ(ps.csf_normal[c], Vec<2>::Zero());
  EXPECT_EQ(ps.curvature[c], 0.0);
}

// The pair loop's bracket -2 sigma kappa_i / (rho_i rho_j) gives
// a_i = 2 sigma kappa_i / rho_i sum_j V_j grad W_ij: compared with that sum
// done here, particle by particle (every other term is zero at rest density).
TEST(SurfaceTension, ForceIsTwiceSigmaKappaTimesTheColourGradient) {
  SphParticles<2> ps = lattice_disc();
  const SphParams sp = disc_params(1.5);
  NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
  nl.build(ps);
  compute_fluid_passes<2>(sp, nl, ps, [](SphGroup) {});
  compute_fluid_rates<2>(sp, nl, ps);
  const WendlandC2<2> kernel(sp.h);
  double a_max = 0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) a_max = std::max(a_max, ps.a[i].norm());
  ASSERT_GT(a_max, 0.0);
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    Vec<2> g = Vec<2>::Zero();
    for (std::size_t j = 0; j < ps.n_owned; ++j) {
      const Vec<2> xij = ps.x[i] - ps.x[j];
      const double r = xij.norm();
      if (j == i || r >= 2 * sp.h) continue;
      g += ps.mass[j] / ps.rho[j] * kernel.f(r) * sp.grad_scale * xij;
    }
    const Vec<2> want = 2 * sp.surface_tension * ps.curvature[i] / ps.rho[i] * g;
    EXPECT_NEAR((ps.a[i] - want).norm(), 0.0, 1e-9 * a_max) << i;
    // Inward on the ring (the curvature is positive there).
    if (ps.csf_normal[i] != Vec<2>::Zero() && ps.curvature[i] > 0) {
      EXPECT_LE(ps.a[i].dot(ps.x[i]), 0.0) << i;
    }
  }
}

// A wedge of lattice resin on a floor (three layers of wall particles below
// y = 0) whose free surface is the plane through the origin that meets the
// floor at theta, the resin on its left. The floor's contact angle is theta.
SphParticles<2> wedge_on_floor(double theta_deg) {
  const double th = theta_deg * std::numbers::pi / 180.0;
  const Vec<2> n_theta(std::sin(th), std::cos(th));  // the surface's outward normal
  SphParticles<2> ps;
  std::int64_t id = 0;
  for (int i = -20; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const Vec<2> x((i + 0.5) * kDp, (j + 0.5) * kDp);
      if (x.dot(n_theta) < 0.0)
        ps.push_owned(id++, Kind::Fluid, -1, 1000 * kDp * kDp, x, Vec<2>::Zero(), 1000);
    }
  for (int i = -24; i < 16; ++i)
    for (int k = 0; k < 3; ++k) {
      const double depth = (k + 0.5) * kDp;
      ps.push_owned(id++, Kind::Wall, -1, 1000 * kDp * kDp, Vec<2>((i + 0.5) * kDp, -depth),
                    Vec<2>::Zero(), 1000);
      ps.wall_to_surface[ps.size() - 1] = Vec<2>(0.0, depth);
    }
  return ps;
}

// The angle in degrees between two unit vectors.
double degrees_between(const Vec<2>& a, const Vec<2>& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// The cause of the 120 degree defect (docs/physics.md "Surface tension",
// near-wall normals): the colour counts the wall particles as resin, so the
// colour gradient of a surface particle next to the floor sees a resin that
// fills the floor below the contact line, and its normal tilts away from
// the floor, by about 30 degrees at 120 on the floor row. With the wall's
// correction the floor row's surface particle (half a spacing above the
// wall, blend 1 - d / 2h = 0.83) takes the contact angle's normal within 8
// degrees (measured 5.2 at 120); particles beyond the wall's reach (2h)
// keep their own. Checked against the uncorrected normal summed here by hand.
TEST(SurfaceTension, NearTheWallTheNormalTakesTheContactAngle) {
  for (const double theta : {60.0, 90.0, 120.0}) {
    SphParticles<2> ps = wedge_on_floor(theta);
    SphParams sp = disc_params(1.5);
    sp.contact_angle = {theta};
    NeighborList<2> nl(2.0 * sp.h, 0.2 * sp.h);
    nl.build(ps);
    compute_fluid_passes<2>(sp, nl, ps, [](SphGroup) {});
    const double th = theta * std::numbers::pi / 180.0;
    const Vec<2> n_theta(std::sin(th), std::cos(th));
    // The floor row's outermost resin particle, and the row three rows up
    // (beyond the wall's reach 2h = 3 dp).
    std::size_t edge = 0, high = 0;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] != Kind::Fluid) continue;
      if (ps.x[i][1] < kDp && (ps.kind[edge] != Kind::Fluid || ps.x[i][0] > ps.x[edge][0]))
        edge = i;
      if (std::abs(ps.x[i][1] - 3.5 * kDp) < 0.1 * kDp &&
          (ps.kind[high] != Kind::Fluid || ps.x[i][0] > ps.x[high][0]))
        high = i;
    }
    const WendlandC2<2> kernel(sp.h);
    const auto uncorrected = [&](std::size_t i) {
      Vec<2> g = Vec<2>::Zero();
      for (std::size_t j = 0; j < ps.n_owned; ++j) {
        const Vec<2> xij = ps.x[i] - ps.x[j];
        const double r = xij.norm();
        if (j != i && r < 2 * sp.h) g += ps.mass[j] / ps.rho[j] * kernel.f(r) * sp.grad_scale * xij;
      }
      return Vec<2>(-g / g.norm());
    };
    ASSERT_GT(ps.csf_normal[edge].norm(), 0.5) << theta;
    const double before = degrees_between(uncorrected(edge), n_theta);
    const double after = degrees_between(ps.csf_normal[edge], n_theta);
    std::printf(
        "[          ] theta %.0f: the floor row's surface particle is %.1f degrees off the "
        "contact angle's normal (%.1f uncorrected); three rows up %.1f (its own %.1f)\n",
        theta, after, before, degrees_between(ps.csf_normal[high], n_theta),
        degrees_between(uncorrected(high), n_theta));
    EXPECT_LT(after, 8.0) << theta;
    EXPECT_LT((ps.csf_normal[high] - uncorrected(high)).norm(), 1e-9) << theta;
    if (theta == 120.0) {
      EXPECT_GT(before, 20.0);
    }
  }
}

// ------------------------------------------------------------ input errors

constexpr const char* kCase = R"(name: errors
dimension: 2
resin:
  density: 1000
  viscosity: 0.01
  sound_speed: 5
  surface_tension: 0.05           # 7
numerics:
  spacing: 1.0e-4
  end_time: 0.01
mold:
  shapes:
    - box: {min: [0, 0], max: [2.0e-3, 2.0e-3]}
fill:
  - box: {min: [0, 0], max: [1.0e-3, 1.0e-3]}
)";

void expect_error(const std::string& from, const std::string& to, int line, const std::string& key,
                  const std::string& message, bool build = false) {
  std::string text(kCase);
  if (!from.empty()) text.replace(text.find(from), from.size(), to);
  try {
    const Case c = load_case_from_string(text, "case.yaml");
    const Comm comm;
    if (build) Simulation<2> sim(c, comm, quiet());
    ADD_FAILURE() << "no error; expected case.yaml:" << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "case.yaml") << what;
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), key) << what;
    EXPECT_NE(what.find(message), std::string::npos) << what << "\n  expected: " << message;
  }
}

TEST(SurfaceTensionErrors, NegativeSurfaceTension) {
  expect_error("surface_tension: 0.05", "surface_tension: -0.05", 7, "resin.surface_tension",
               "must be zero or positive, got -0.05");
}

TEST(SurfaceTensionErrors, ContactAngleOutsideZeroTo180) {
  for (const char* angle : {"0", "180", "-10", "200"}) {
    expect_error("    - box: {min: [0, 0], max: [2.0e-3, 2.0e-3]}\n",
                 std::string("    - box: {min: [0, 0], max: [2.0e-3, 2.0e-3]}\n  contact_angle: ") +
                     angle + "\n",
                 14, "mold.contact_angle", "in (0, 180)");
  }
}

// A filled cavity has no free surface: the key is an error at its line.
TEST(SurfaceTensionErrors, NoFreeSurface) {
  expect_error("max: [1.0e-3, 1.0e-3]", "max: [2.0e-3, 2.0e-3]", 7, "resin.surface_tension",
               "no free surface", /*build=*/true);
}

// A partly filled cavity builds; the wall's contact angle reaches the parameters.
TEST(SurfaceTensionErrors, PartlyFilledCavityIsFine) {
  std::string text(kCase);
  const std::string box = "max: [2.0e-3, 2.0e-3]}\n";
  text.replace(text.find(box), box.size(), box + "  contact_angle: 60\n");
  const Case c = load_case_from_string(text, "case.yaml");
  EXPECT_DOUBLE_EQ(*c.mold.contact_angle, 60.0);
  EXPECT_EQ(make_sph_params(c).contact_angle, std::vector<double>{60.0});
  const Comm comm;
  EXPECT_NO_THROW(Simulation<2>(c, comm, quiet()));
}

}  // namespace
}  // namespace sphdem
