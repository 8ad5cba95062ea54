// Shapes, particle filling, moving walls and the periodic halo.
#include <gtest/gtest.h>

#include "sphdem/config/config.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/geometry/walls.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/parallel/halo.hpp"

namespace sphdem {
namespace {

Shape polygon(std::vector<std::array<double, 2>> v) {
  Shape s;
  s.type = Shape::Type::Polygon;
  s.vertices = std::move(v);
  return s;
}

TEST(Shapes, PolygonContainsAndDistance) {
  const Shape tri = polygon({{0, 0}, {4, 0}, {0, 3}});
  EXPECT_TRUE(shape_contains<2>(tri, Vec<2>(1, 1)));
  EXPECT_FALSE(shape_contains<2>(tri, Vec<2>(3, 3)));
  EXPECT_DOUBLE_EQ(shape_distance<2>(tri, Vec<2>(1, 1)), 0.0);
  EXPECT_NEAR(shape_distance<2>(tri, Vec<2>(2, -1)), 1.0, 1e-15);
  // Distance to the hypotenuse 3x + 4y = 12 from (4, 3): |12 + 12 - 12| / 5.
  EXPECT_NEAR(shape_distance<2>(tri, Vec<2>(4, 3)), 12.0 / 5.0, 1e-14);
  EXPECT_TRUE(shape_contains<2>(tri, Vec<2>(2, -1e-10), 1e-9)) << "within tolerance of an edge";
}

TEST(Shapes, BoxDistance3D) {
  Shape b;
  b.lo = {0, 0, 0};
  b.hi = {1, 1, 1};
  EXPECT_NEAR(shape_distance<3>(b, Vec<3>(2, 2, 0.5)), std::sqrt(2.0), 1e-15);
  EXPECT_TRUE(shape_contains<3>(b, Vec<3>(0.5, 0.5, 0.5)));
}

const char* kBox = R"(
dimension: 2
resin: {density: 1000, viscosity: 0.001, sound_speed: 10}
numerics: {spacing: 0.1, end_time: 1}
mold: {wall_layers: 3, shapes: [{box: {min: [0, 0], max: [1, 1]}}]}
fill: [{box: {min: [0, 0], max: [1, 0.5]}}]
moving_walls:
  - name: lid
    region: {box: {min: [0, 1], max: [1, 1.5]}}
    velocity_table: [[0, 0, -1], [1, 0, -3]]
)";

std::size_t lid_count(const SphParticles<2>& ps) {
  std::size_t lid = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    EXPECT_EQ(ps.gid[i], static_cast<std::int64_t>(i));
    if (ps.kind[i] == Kind::Wall && ps.wall[i] == 0) ++lid;
  }
  return lid;
}

TEST(Filling, CountsAndWallLayers) {
  // h = 1.5 dp: the support 2h = 3 dp holds all 3 layers.
  const Case c = load_case_from_string(kBox, "box.yaml", {"numerics.h_over_spacing=1.5"});
  EXPECT_EQ(wall_layers_made(c), 3);
  SphParticles<2> ps;
  const InitialCounts n = build_initial_particles<2>(c, ps);
  EXPECT_EQ(n.fluid, 50u);  // 10 x 5 lattice nodes
  // 3 layers around a 10 x 10 cavity, less the outermost corner node of each
  // corner: it lies 3.5 dp from the cavity, beyond the layers' 3 dp reach
  // (and beyond any resin particle's 3 dp support).
  EXPECT_EQ(n.wall, 16u * 16u - 100u - 4u);
  EXPECT_EQ(lid_count(ps), 30u) << "3 layers x 10 nodes above the cavity belong to the lid";
}

// h = 1.2 dp (the default): the third layer lies 2.5 dp behind the wall
// face, beyond the support 2h = 2.4 dp of a resin particle on the face, so
// it is not made; the corner nodes 1.5 dp along both axes (2.12 dp from
// the cavity) are within the support and are made, which two layers
// (mold.wall_layers: 2, a reach of 2 dp) would drop.
TEST(Filling, WallLayersTrimmedToTheSupport) {
  const Case c = load_case_from_string(kBox, "box.yaml");
  EXPECT_DOUBLE_EQ(wall_band(c), 2.4 * 0.1);
  EXPECT_EQ(wall_layers_made(c), 2);
  SphParticles<2> ps;
  const InitialCounts n = build_initial_particles<2>(c, ps);
  EXPECT_EQ(n.fluid, 50u);
  EXPECT_EQ(n.wall, 14u * 14u - 100u) << "2 full layers, corners included";
  EXPECT_EQ(lid_count(ps), 20u) << "2 layers x 10 nodes above the cavity";
  // Every wall particle made is within the support of some point of the cavity.
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (ps.kind[i] != Kind::Wall) continue;
    EXPECT_LE(union_distance<2>(c.mold.shapes, ps.x[i]), wall_band(c) + 1e-12);
  }
  // Fewer layers than the support needs are kept as asked.
  const Case one = load_case_from_string(kBox, "box.yaml", {"mold.wall_layers=1"});
  EXPECT_EQ(wall_layers_made(one), 1);
  EXPECT_DOUBLE_EQ(wall_band(one), 0.1);
}

TEST(MovingWalls, TableAndPressureLimit) {
  const Case c = load_case_from_string(kBox, "box.yaml");
  std::vector<WallMotion> w = make_wall_motions(c);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_DOUBLE_EQ(w[0].velocity(0.5)[1], -2.0);
  EXPECT_DOUBLE_EQ(w[0].velocity(5.0)[1], -3.0) << "constant after the last row";
  EXPECT_DOUBLE_EQ(w[0].acceleration(0.5)[1], -2.0);
  w[0].pressure_limit = 1000;
  w[0].relax_time = 1e-3;
  update_wall_controllers(w, {2000.0}, 1e-4);  // 100 % over the limit for 0.1 tau
  EXPECT_NEAR(w[0].scale, 0.9, 1e-12);
  update_wall_controllers(w, {0.0}, 1.0);  // far below: back to the table, no further
  EXPECT_DOUBLE_EQ(w[0].scale, 1.0);
}

TEST(Halo, PeriodicImagesIncludingCorners) {
  SphParticles<2> ps;
  ps.push_owned(0, Kind::Fluid, -1, 1, Vec<2>(0.05, 0.05), Vec<2>::Zero(), 1);  // corner
  ps.push_owned(1, Kind::Fluid, -1, 1, Vec<2>(0.5, 0.5), Vec<2>::Zero(), 1);    // interior
  ps.push_owned(2, Kind::Fluid, -1, 1, Vec<2>(1.02, 0.5), Vec<2>::Zero(), 1);   // outside: wraps
  Box<2> dom{Vec<2>(0, 0), Vec<2>(1, 1)};
  const std::array<bool, 3> periodic{true, true, false};
  // One rank: every image is a message to itself, as at any rank count.
  const Comm self(MPI_COMM_SELF);
  const Decomposition<2> dec(self, dom, periodic, 0.1);
  wrap_periodic<2>(ps, dom, periodic);
  EXPECT_NEAR(ps.x[2][0], 0.02, 1e-15) << "wrapped into the box";
  Halo<2> halo;
  halo.build(dec, ps, 0.1);
  EXPECT_EQ(ps.n_owned, 3u);
  // Corner particle: 3 images; wrapped particle near x = 0: 1 image.
  ASSERT_EQ(halo.size(), 4u);
  EXPECT_EQ(ps.size(), 7u);
  ps.v[0] = Vec<2>(3, 4);
  halo.forward(ps, SphGroup::State);
  int copies = 0;
  for (std::size_t g = ps.n_owned; g < ps.size(); ++g) {
    if (ps.gid[g] == 0) {
      ++copies;
      EXPECT_EQ(ps.v[g], Vec<2>(3, 4));
    }
  }
  EXPECT_EQ(copies, 3);
}

}  // namespace
}  // namespace sphdem
