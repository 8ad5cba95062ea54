// 3D walls (docs/dem.md, "Walls"): a sphere against a rectangle (face, edge,
// corner, reach, unflagged edges, sliding off an edge), the wall history
// dropped at a pair-list build without candidate walls, the walls' state in
// a checkpoint, and a 3D mold of boxes turned into rectangles
// (dem_walls_from_case<3>): the boundary of the union, inward normals, one
// owner per rim edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "../src/solver/dem_checkpoint.hpp"
#include "dem_wall_helpers.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/solver/dem_run.hpp"

namespace sphdem {
namespace {

constexpr double kKn = 1e3, kR = 0.1;

// The wall force on one sphere at rest at x (kn delta along the push).
Vec<3> wall_force(const std::vector<DemWall<3>>& walls, const Vec<3>& x, int* contacts = nullptr) {
  return testing::wall_force<3>(walls, x, kKn, kR, contacts);
}

void expect_vec(const Vec<3>& got, const Vec<3>& want, const char* what) {
  EXPECT_LT((got - want).norm(), 1e-12 * std::max(1.0, want.norm()))
      << what << ": got " << got.transpose() << ", want " << want.transpose();
}

// The unit-depth 2 x 1 rectangle z = 0, facing +z.
DemWall<3> floor_rect(int edges = DemWall<3>::kAllEdges) {
  return DemWall<3>::rect(Vec<3>::Zero(), Vec<3>(2, 0, 0), Vec<3>(0, 1, 0), Vec<3>(0, 0, 1), edges);
}

TEST(DemRectWall, Geometry) {
  const DemWall<3> w =
      DemWall<3>::rect(Vec<3>(0, 0, 1), Vec<3>(0, 1, 0), Vec<3>(2, 0, 0), Vec<3>(0, 0, -3));
  expect_vec(w.normal, Vec<3>(0, 0, -1), "normal follows the inward hint");
  expect_vec(w.end, Vec<3>(2, 1, 1), "end is the opposite corner");
}

TEST(DemRectWall, FaceEdgeCornerAndReach) {
  const std::vector<DemWall<3>> walls{floor_rect()};
  // Face: overlap 0.04 along +z, also half a radius behind the face (one-sided).
  expect_vec(wall_force(walls, Vec<3>(0.5, 0.5, 0.06)), Vec<3>(0, 0, kKn * 0.04), "face");
  expect_vec(wall_force(walls, Vec<3>(0.5, 0.5, -0.03)), Vec<3>(0, 0, kKn * 0.13), "behind");
  // Edge x = 2: closest point (2, 0.5, 0), distance 0.06 sqrt 2, along (1, 0, 1)/sqrt 2.
  const double de = 0.06 * std::sqrt(2.0);
  expect_vec(wall_force(walls, Vec<3>(2.06, 0.5, 0.06)),
             Vec<3>(kKn * (kR - de) / std::sqrt(2.0) * Vec<3>(1, 0, 1)), "edge");
  // Corner (2, 1, 0): along (1, 1, 1)/sqrt 3.
  const double dc = 0.05 * std::sqrt(3.0);
  expect_vec(wall_force(walls, Vec<3>(2.05, 1.05, 0.05)),
             Vec<3>(kKn * (kR - dc) / std::sqrt(3.0) * Vec<3>(1, 1, 1)), "corner");
  // Out of reach: past the edge, at exactly a radius, too far behind, and
  // beyond an edge behind the plane (the solid's side is another wall's).
  expect_vec(wall_force(walls, Vec<3>(2.08, 0.5, 0.08)), Vec<3>::Zero(), "past the edge");
  expect_vec(wall_force(walls, Vec<3>(0.5, 0.5, kR)), Vec<3>::Zero(), "at a radius");
  expect_vec(wall_force(walls, Vec<3>(0.5, 0.5, -0.12)), Vec<3>::Zero(), "far behind");
  expect_vec(wall_force(walls, Vec<3>(2.05, 0.5, -0.05)), Vec<3>::Zero(), "behind the edge");
}

TEST(DemRectWall, UnflaggedEdgesDoNotPush) {
  // Edge x = 2 is bit 1 (at point + u); the others still push.
  const std::vector<DemWall<3>> walls{floor_rect(DemWall<3>::kAllEdges & ~2)};
  expect_vec(wall_force(walls, Vec<3>(2.06, 0.5, 0.06)), Vec<3>::Zero(), "edge x = 2");
  expect_vec(wall_force(walls, Vec<3>(2.05, 1.05, 0.05)), Vec<3>::Zero(), "corner on it");
  EXPECT_GT(wall_force(walls, Vec<3>(-0.06, 0.5, 0.06)).norm(), 0.0) << "edge x = 0";
  EXPECT_GT(wall_force(walls, Vec<3>(1.0, 1.06, 0.06)).norm(), 0.0) << "edge y = 1";
  // Two coplanar rectangles meeting at a seam, its edges unflagged: a sphere
  // near the seam feels exactly the face, from one of them.
  const std::vector<DemWall<3>> seam{
      DemWall<3>::rect(Vec<3>::Zero(), Vec<3>(1, 0, 0), Vec<3>(0, 1, 0), Vec<3>(0, 0, 1), 0xF & ~2),
      DemWall<3>::rect(Vec<3>(1, 0, 0), Vec<3>(1, 0, 0), Vec<3>(0, 1, 0), Vec<3>(0, 0, 1),
                       0xF & ~1)};
  for (const double x : {0.97, 0.999, 1.0, 1.001, 1.03}) {
    int n = 0;
    expect_vec(wall_force(seam, Vec<3>(x, 0.5, 0.06), &n), Vec<3>(0, 0, kKn * 0.04), "seam");
    EXPECT_EQ(n, 1) << "x = " << x;
  }
}

// A sphere sliding along x over the rectangle under gravity, frictionless:
// held by the face, then by the edge, the push turning smoothly from +z
// toward +x as it tips over; then it falls past the edge, the contact ends.
TEST(DemRectWall, SlidesOffTheEdge) {
  DemSystem<3> sys;
  sys.params.kn = 1e5;
  sys.params.friction = 0;
  sys.params.gravity = Vec<3>(0, 0, -10);
  sys.walls.push_back(floor_rect());
  sys.add_particle(Vec<3>(1.7, 0.5, kR), kR, 1000);
  const double mg = 10 * sys.particles.mass[0];
  sys.particles.x[0][2] = kR - mg / sys.params.kn;  // resting overlap
  sys.particles.v[0] = Vec<3>(0.5, 0, 0);
  sys.invalidate_forces();
  const double dt = sys.stable_dt();
  Vec<3> last = Vec<3>(0, 0, mg);
  double max_jump = 0, max_push_x = 0, max_bump = 0;
  bool back = false;
  for (int k = 0; k < 3000 && sys.particles.x[0][2] > -2 * kR; ++k) {
    sys.step(dt);
    const Vec<3> f = sys.particles.force[0] + Vec<3>(0, 0, mg);  // the wall's push
    max_jump = std::max(max_jump, (f - last).norm());
    max_push_x = std::max(max_push_x, f[0]);
    if (sys.particles.x[0][0] < 2.0) max_bump = std::max(max_bump, std::abs(f[2] - mg));
    back = back || sys.particles.v[0][0] <= 0;
    last = f;
  }
  EXPECT_LT(max_bump, 1e-9 * mg) << "the face holds the sphere at rest height";
  // Measured 0.048 m g: the contact spring's own swing as the support turns;
  // a doubled or lost contact would jump by m g.
  EXPECT_LT(max_jump, 0.1 * mg) << "the push is continuous over the edge";
  EXPECT_GT(max_push_x, 0.05 * mg) << "the edge pushes outward";
  EXPECT_FALSE(back) << "nothing pushed the sphere back";
  EXPECT_LT(sys.particles.x[0][2], -kR) << "it fell past the edge";
  EXPECT_GT(sys.particles.x[0][0], 2.0);
  EXPECT_EQ(sys.particles.wall_contacts[0][0].partner, DemContact<3>::kNone);
}

// A particle with no wall within reach at a pair-list build has its wall
// history dropped there (dem_build_wall_lists), and the force loops skip it
// without reading its slots; one whose wall is still a candidate keeps its
// history until a force evaluation finds it apart (docs/dem.md, "Walls").
TEST(DemRectWall, HistoryDroppedAtTheBuildOnlyWithoutCandidates) {
  DemParams<3> p;
  p.kn = kKn;
  const std::vector<DemWall<3>> walls{floor_rect()};
  const auto slots_used = [](const DemParticles<3>& ps, std::size_t i) {
    int n = 0;
    for (const auto& c : ps.wall_contacts[i]) n += c.partner != DemContact<3>::kNone;
    return n;
  };
  DemParticles<3> ps;
  ps.push_owned(0, -1, Vec<3>(0.5, 0.5, 0.06), kR, 1000, 1.0);  // touching the face
  ps.push_owned(1, -1, Vec<3>(1.5, 0.5, 0.06), kR, 1000, 1.0);  // touching the face
  // Sliding: a tangential spring too.
  ps.v[0] = ps.v[1] = Vec<3>(0.3, 0, 0);
  DemWorkspace<3> ws;
  dem_build_pairs(p, walls, ps, ws);
  compute_dem_forces(p, 1e-3, walls, ps, ws);
  ASSERT_EQ(slots_used(ps, 0), 1);
  ASSERT_EQ(slots_used(ps, 1), 1);
  EXPECT_EQ(ps.wall_contacts[0][0].partner, wall_key(0));
  EXPECT_GT(ps.wall_contacts[0][0].xi.norm(), 0.0);
  // Particle 0 goes far beyond R + skin, particle 1 just beyond R but
  // within R + skin (skin: a quarter of R here).
  ps.x[0] = Vec<3>(0.5, 0.5, 0.5);
  ps.x[1] = Vec<3>(1.5, 0.5, kR + 0.2 * ws.skin);
  ASSERT_GT(ws.skin, 0.0);
  dem_build_pairs(p, walls, ps, ws);
  EXPECT_EQ(ws.wall_start[1] - ws.wall_start[0], 0) << "no candidate wall for particle 0";
  EXPECT_EQ(ws.wall_start[2] - ws.wall_start[1], 1) << "the floor is particle 1's candidate";
  EXPECT_EQ(slots_used(ps, 0), 0) << "history dropped at the build";
  EXPECT_EQ(slots_used(ps, 1), 1) << "history kept until a force evaluation";
  compute_dem_forces(p, 1e-3, walls, ps, ws);
  EXPECT_EQ(slots_used(ps, 1), 0) << "the evaluation found it apart";
  // No wall force on either: the forces of the same state without walls.
  DemParticles<3> alone = ps;
  DemWorkspace<3> ws_alone;
  const std::vector<DemWall<3>> none;
  dem_build_pairs(p, none, alone, ws_alone);
  compute_dem_forces(p, 1e-3, none, alone, ws_alone);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(ps.force[i], alone.force[i]) << "particle " << i;
}

// The state of plane, segment and rectangle walls through a checkpoint;
// another number or type of walls is refused.
TEST(DemRectWall, CheckpointState) {
  std::vector<DemWall<3>> walls{
      DemWall<3>::plane(Vec<3>(0, 0, 1), Vec<3>(0, 0, 1), Vec<3>(1, 2, 3)),
      DemWall<3>::segment(Vec<3>(1, 2, 3), Vec<3>(4, 5, 6)),
      DemWall<3>::rect(Vec<3>(1, 1, 1), Vec<3>(0, 2, 0), Vec<3>(0, 0, 3), Vec<3>(1, 0, 0), 5,
                       Vec<3>(-4, 0, 0))};
  walls[2].point += Vec<3>(-0.5, 0, 0);  // moved: the state is not the factory's
  walls[2].end += Vec<3>(-0.5, 0, 0);
  const std::vector<double> s = dem_wall_state(walls);
  EXPECT_EQ(s.size(), 3u * (1 + 4 * 3) + 2 * 3 + 1);
  std::vector<DemWall<3>> back{DemWall<3>::plane(Vec<3>::Zero(), Vec<3>(1, 0, 0)),
                               DemWall<3>::segment(Vec<3>::Zero(), Vec<3>(1, 0, 0)), floor_rect()};
  ASSERT_TRUE(set_dem_wall_state(back, s));
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const DemWall<3>&a = walls[k], &b = back[k];
    EXPECT_TRUE(a.point == b.point && a.normal == b.normal && a.end == b.end && a.u == b.u &&
                a.v == b.v && a.velocity == b.velocity && a.edges == b.edges)
        << "wall " << k;
  }
  std::vector<DemWall<3>> other{back[0], back[2], back[1]};  // types in another order
  EXPECT_FALSE(set_dem_wall_state(other, s));
  std::vector<DemWall<3>> fewer{back[0], back[1]};
  EXPECT_FALSE(set_dem_wall_state(fewer, s));
  std::vector<double> cut(s.begin(), s.end() - 1);
  EXPECT_FALSE(set_dem_wall_state(back, cut));
}

// A 12 x 12 x 6 bath with a 6 x 6 x 6 nozzle standing on it (the mold of
// inputs/fibers_only_3d.yaml, lengths in mm) and a piston on the nozzle.
constexpr const char* kFile = "mold3d.yaml";
const std::string kCase = R"(dimension: 3                                          # 1
resin: {density: 900, viscosity: 0.1, sound_speed: 50}             # 2
numerics: {spacing: 5.0e-4, end_time: 1.0e-3}                      # 3
mold:                                                              # 4
  shapes:                                                          # 5
    - box: {min: [-0.006, -0.006, 0.0], max: [0.006, 0.006, 0.006]}   # 6
    - box: {min: [-0.003, -0.003, 0.006], max: [0.003, 0.003, 0.012]}   # 7
fibers:                                                            # 8
  count: 10                                                        # 9
  diameter: 4.0e-4                                                 # 10
  density: 2540                                                    # 11
  youngs_modulus: 1.0e8                                            # 12
  region: {box: {min: [-0.003, -0.003, 0.006], max: [0.003, 0.003, 0.012]}}   # 13
moving_walls:                                                      # 14
  - name: piston                                                   # 15
    region: {box: {min: [-0.003, -0.003, 0.012], max: [0.003, 0.003, 0.0125]}}   # 16
    velocity_table: [[0, 0, 0, -1]]                                # 17
)";

double area(const DemWall<3>& w) {
  return w.u.cross(w.v).norm();
}

TEST(DemMoldWalls3D, BoundaryOfTheUnion) {
  const Case c = load_case_from_string(kCase, kFile);
  std::vector<int> owner;
  const std::vector<DemWall<3>> walls = dem_walls_from_case<3>(c, owner);
  ASSERT_EQ(owner.size(), walls.size());
  double total = 0, piston = 0;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const DemWall<3>& w = walls[k];
    ASSERT_EQ(w.type, DemWall<3>::Type::Rect);
    EXPECT_NEAR(std::abs(w.u.dot(w.v)), 0.0, 1e-18);
    if (owner[k] >= 0) {
      EXPECT_EQ(owner[k], 0);
      piston += area(w);
      expect_vec(w.normal, Vec<3>(0, 0, -1), "the piston pushes down");
      continue;
    }
    total += area(w);
    // Inward normal: the mold just in front of the centre, not behind it.
    const Vec<3> mid = w.point + 0.5 * (w.u + w.v);
    EXPECT_TRUE(union_contains<3>(c.mold.shapes, Vec<3>(mid + 1e-7 * w.normal), 0.0)) << k;
    EXPECT_FALSE(union_contains<3>(c.mold.shapes, Vec<3>(mid - 1e-7 * w.normal), 0.0)) << k;
    // Nothing on the opening between bath and nozzle (z = 6, |x|, |y| < 3).
    if (std::abs(w.normal[2]) == 1 && std::abs(w.point[2] - 0.006) < 1e-12) {
      const Vec<3> lo = w.point.cwiseMin(w.end), hi = w.point.cwiseMax(w.end);
      const double ox = std::max(0.0, std::min(hi[0], 0.003) - std::max(lo[0], -0.003));
      const double oy = std::max(0.0, std::min(hi[1], 0.003) - std::max(lo[1], -0.003));
      EXPECT_EQ(ox * oy, 0.0) << "wall " << k << " covers part of the opening";
    }
  }
  // By hand: bath 2 (12 x 12) + 4 (12 x 6), nozzle 6 (6 x 6), less the
  // 6 x 6 opening on both: 720 mm^2.
  EXPECT_NEAR(total, 720e-6, 1e-15);
  EXPECT_NEAR(piston, 36e-6, 1e-15);
  // Merged: the floor, 4 bath sides, the ceiling's frame (4 pieces), 4
  // nozzle sides, its top; the piston's face.
  EXPECT_EQ(walls.size(), 15u);
}

// An L of two overlapping boxes (extruded along y, lengths in m): A = [0, 2]
// x [0, 1] x [0, 1], B = [1, 2] x [0, 1] x [0, 3], B's foot inside A. By
// hand: the L's outline 10 times its depth 1, plus twice its area 4: 18. The
// inner corner (x = 1, z = 1) is a convex edge of the solid, 1 long, owned
// by B's face x = 1 (the smaller axis), not by A's top z = 1.
TEST(DemMoldWalls3D, OverlappingBoxesL) {
  const std::string text = R"(dimension: 3
resin: {density: 900, viscosity: 0.1, sound_speed: 50}
numerics: {spacing: 0.1, end_time: 1.0}
mold:
  shapes:
    - box: {min: [0, 0, 0], max: [2, 1, 1]}
    - box: {min: [1, 0, 0], max: [2, 1, 3]}
fibers: {count: 1, diameter: 0.1, density: 1000, youngs_modulus: 1.0e6,
         region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}}
)";
  const Case c = load_case_from_string(text, kFile);
  std::vector<int> owner;
  const std::vector<DemWall<3>> walls = dem_walls_from_case<3>(c, owner);
  double total = 0, flagged = 0;
  for (const DemWall<3>& w : walls) {
    total += area(w);
    const Vec<3> mid = w.point + 0.5 * (w.u + w.v);
    EXPECT_TRUE(union_contains<3>(c.mold.shapes, Vec<3>(mid + 1e-6 * w.normal), 0.0));
    EXPECT_FALSE(union_contains<3>(c.mold.shapes, Vec<3>(mid - 1e-6 * w.normal), 0.0));
    for (int e = 0; e < 4; ++e) {
      if (!(w.edges & (1 << e))) continue;
      flagged += (e < 2 ? w.v : w.u).norm();
      EXPECT_NEAR(w.normal[0], 1.0, 1e-15) << "owned by the face x = 1, facing B";
      EXPECT_NEAR(w.point[0], 1.0, 1e-15);
    }
  }
  EXPECT_NEAR(total, 18.0, 1e-12);
  EXPECT_NEAR(flagged, 1.0, 1e-12);
  EXPECT_EQ(walls.size(), 10u);  // the L's 6 sides (its outline), 2 + 2 in front and back
}

// The rim where the nozzle meets the bath's ceiling is a convex edge of
// the solid: one wall pushes from it (total flagged length 4 x 6 mm, all on
// the rim), and a sphere feels one contact near it, from whichever side.
TEST(DemMoldWalls3D, RimEdgeHasOneOwner) {
  const Case c = load_case_from_string(kCase, kFile);
  std::vector<int> owner;
  const std::vector<DemWall<3>> walls = dem_walls_from_case<3>(c, owner);
  double flagged = 0;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    if (owner[k] >= 0) {
      EXPECT_EQ(walls[k].edges, 0) << "the piston's edges slide along the nozzle's walls";
      continue;
    }
    const DemWall<3>& w = walls[k];
    const std::array<std::pair<Vec<3>, Vec<3>>, 4> edge{
        std::pair{w.point, Vec<3>(w.point + w.v)}, std::pair{Vec<3>(w.point + w.u), w.end},
        std::pair{w.point, Vec<3>(w.point + w.u)}, std::pair{Vec<3>(w.point + w.v), w.end}};
    for (std::size_t e = 0; e < 4; ++e) {
      if (!(w.edges & (1 << e))) continue;
      flagged += (edge[e].second - edge[e].first).norm();
      for (const Vec<3>& p : {edge[e].first, edge[e].second}) {
        EXPECT_NEAR(p[2], 0.006, 1e-12) << "wall " << k << " edge " << e;
        EXPECT_NEAR(std::max(std::abs(p[0]), std::abs(p[1])), 0.003, 1e-12);
      }
    }
  }
  EXPECT_NEAR(flagged, 0.024, 1e-12);
  // A sphere of radius kR = 0.1 mm is too big for this test's units: use r.
  DemParams<3> p;
  p.kn = kKn;
  const double r = 2e-4;
  const auto push = [&](const Vec<3>& x, int& n) {
    DemParticles<3> ps;
    ps.push_owned(0, -1, x, r, 2540, 1.0);
    DemWorkspace<3> ws;
    dem_build_pairs(p, walls, ps, ws);
    compute_dem_forces(p, 0.0, walls, ps, ws);
    n = 0;
    for (const auto& s : ps.wall_contacts[0]) n += s.partner != DemContact<3>::kNone;
    return Vec<3>(ps.force[0]);
  };
  int n = 0;
  // Under the opening, 0.1 mm from the rim both ways: the rim alone.
  const double d = 1e-4 * std::sqrt(2.0);
  expect_vec(push(Vec<3>(0.0029, 0, 0.0059), n),
             Vec<3>(kKn * (r - d) / std::sqrt(2.0) * Vec<3>(-1, 0, -1)), "rim");
  EXPECT_EQ(n, 1);
  // Under the ceiling beside the opening: the ceiling alone.
  expect_vec(push(Vec<3>(0.0031, 0, 0.0059), n), Vec<3>(0, 0, -kKn * 1e-4), "ceiling");
  EXPECT_EQ(n, 1);
  // In the nozzle above the ceiling: the nozzle's side alone.
  expect_vec(push(Vec<3>(0.0029, 0, 0.0061), n), Vec<3>(-kKn * 1e-4, 0, 0), "nozzle side");
  EXPECT_EQ(n, 1);
}

TEST(DemMoldWalls3D, PistonTouchingNothingIsAnError) {
  std::string s = kCase;
  const std::string from = "min: [-0.003, -0.003, 0.012], max: [0.003, 0.003, 0.0125]";
  s.replace(s.find(from), from.size(), "min: [-0.003, -0.003, 0.013], max: [0.003, 0.003, 0.014]");
  const Case c = load_case_from_string(s, kFile);
  std::vector<int> owner;
  try {
    dem_walls_from_case<3>(c, owner);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kFile);
    EXPECT_EQ(e.line(), 15);
    EXPECT_EQ(e.key(), "moving_walls[0].region");
    EXPECT_NE(std::string(e.what()).find("touches the mold"), std::string::npos) << e.what();
  }
}

// Fibers with resin in 3D are a valid case now.
TEST(DemMoldWalls3D, CoupledCaseLoads) {
  std::string s = kCase;
  s += "fill:\n  - box: {min: [-0.006, -0.006, 0.0], max: [0.006, 0.006, 0.003]}\n";
  const Case c = load_case_from_string(s, kFile);
  EXPECT_TRUE(c.fibers.has_value());
  EXPECT_EQ(c.fill.size(), 1u);
}

}  // namespace
}  // namespace sphdem
