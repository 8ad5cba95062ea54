// 2D walls (docs/dem.md, "Walls"): a disk against segments whose ends push
// only when flagged (a seam, an end another segment owns), and the mold's
// outline turned into segments (dem_walls_from_case<2>): one owner per
// convex corner, none at seams and concave corners.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dem_wall_helpers.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/solver/dem_run.hpp"

namespace sphdem {
namespace {

constexpr double kKn = 1e3, kR = 0.1;

// The wall force on one disk at rest at x (kn delta along the push) and
// the number of walls it touches.
Vec<2> wall_force(const std::vector<DemWall<2>>& walls, const Vec<2>& x, int* contacts = nullptr,
                  double r = kR) {
  return testing::wall_force<2>(walls, x, kKn, r, contacts);
}

DemWall<2> segment(double x0, double x1, int ends) {
  DemWall<2> w = DemWall<2>::segment(Vec<2>(x0, 0), Vec<2>(x1, 0));
  w.edges = ends;
  return w;
}

TEST(DemSegmentWall, UnflaggedEndsDoNotPush) {
  // End b unflagged: nothing beyond it; end a still pushes from its point.
  const std::vector<DemWall<2>> one{segment(0, 1, DemWall<2>::kEndA)};
  EXPECT_EQ(wall_force(one, Vec<2>(1.05, 0.05)).norm(), 0.0);
  const Vec<2> f = wall_force(one, Vec<2>(-0.05, 0.05));
  const double d = 0.05 * std::sqrt(2.0);
  EXPECT_NEAR(f[0], -kKn * (kR - d) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(f[1], kKn * (kR - d) / std::sqrt(2.0), 1e-12);
  // Two pieces of one straight wall meeting at a seam, the seam's ends
  // unflagged: a disk near or exactly on it meets one face. (With both
  // ends pushing, the disk beside the seam would feel a second, slanted
  // contact from the neighbour's end, and exactly on it two faces.)
  const std::vector<DemWall<2>> seam{segment(0, 1, DemWall<2>::kEndA),
                                     segment(1, 2, DemWall<2>::kEndB)};
  for (const double x : {0.97, 0.999, 1.0, 1.001, 1.03}) {
    int n = 0;
    const Vec<2> g = wall_force(seam, Vec<2>(x, 0.06), &n);
    EXPECT_EQ(n, 1) << "x = " << x;
    EXPECT_NEAR(g[0], 0.0, 1e-12) << "x = " << x;
    EXPECT_NEAR(g[1], kKn * 0.04, 1e-12) << "x = " << x;
  }
  const std::vector<DemWall<2>> all_ends{segment(0, 1, DemWall<2>::kAllEdges),
                                         segment(1, 2, DemWall<2>::kAllEdges)};
  int n = 0;
  wall_force(all_ends, Vec<2>(1.03, 0.06), &n);
  EXPECT_EQ(n, 2) << "the old behaviour, for contrast";
}

// A 12 x 6 bath with a 6 x 6 nozzle standing on it (lengths in mm).
const std::string kCase = R"(dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 50}
numerics: {spacing: 5.0e-4, end_time: 1.0e-3}
mold:
  shapes:
    - box: {min: [-0.006, 0.0], max: [0.006, 0.006]}
    - box: {min: [-0.003, 0.006], max: [0.003, 0.012]}
fibers:
  count: 4
  diameter: 2.5e-4
  density: 2540
  youngs_modulus: 1.0e8
  region: {box: {min: [-0.003, 0.006], max: [0.003, 0.012]}}
moving_walls:
  - name: piston
    region: {box: {min: [-0.003, 0.012], max: [0.003, 0.0125]}}
    velocity_table: [[0, 0, -1]]
)";

TEST(DemMoldWalls2D, OneOwnerPerConvexCorner) {
  const Case c = load_case_from_string(kCase, "mold2d.yaml");
  std::vector<int> owner;
  const std::vector<DemWall<2>> walls = dem_walls_from_case<2>(c, owner);
  double length = 0;
  int flagged = 0;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const DemWall<2>& w = walls[k];
    if (owner[k] >= 0) {
      EXPECT_EQ(w.edges & 3, 3) << "a piston's segment keeps its ends";
      continue;
    }
    length += (w.end - w.point).norm();
    for (int e = 0; e < 2; ++e) {
      if (!(w.edges & (e == 0 ? DemWall<2>::kEndA : DemWall<2>::kEndB))) continue;
      ++flagged;
      const Vec<2> v = e == 0 ? w.point : w.end;
      // Only the rims (+-3, 6) are convex; the bath's and the nozzle's
      // corners are concave.
      EXPECT_NEAR(std::abs(v[0]), 0.003, 1e-12) << "flagged end at " << v.transpose();
      EXPECT_NEAR(v[1], 0.006, 1e-12) << "flagged end at " << v.transpose();
    }
  }
  // Floor 12, sides 6 + 6, ceiling 3 + 3 beside the opening, nozzle sides
  // 6 + 6 and top 6.
  EXPECT_NEAR(length, 0.048, 1e-12);
  EXPECT_EQ(flagged, 2) << "each rim vertex owned by exactly one segment";
  // Disks of radius 0.1 mm at the right rim (3, 6) mm, the solid beyond it
  // at x > 3, y > 6: in the nozzle beside its wall, in the bath under the
  // ceiling, and rounding the corner. Each meets one wall: the face, the
  // face, and the rim's owner along the diagonal (the other segment's end
  // is unflagged; an end behind its own line never pushes).
  const double r = 1e-4, o = 0.05e-3, kn = kKn;
  struct Probe {
    Vec<2> x, force;
  };
  const double diag = kn * (r - o * std::sqrt(2.0)) / std::sqrt(2.0);
  for (const Probe& p : {Probe{Vec<2>(0.003 - o, 0.006 + o), Vec<2>(-kn * (r - o), 0)},
                         Probe{Vec<2>(0.003 + o, 0.006 - o), Vec<2>(0, -kn * (r - o))},
                         Probe{Vec<2>(0.003 - o, 0.006 - o), Vec<2>(-diag, -diag)}}) {
    int n = 0;
    const Vec<2> f = wall_force(walls, p.x, &n, r);
    EXPECT_EQ(n, 1) << "at " << p.x.transpose();
    EXPECT_LT((f - p.force).norm(), 1e-9 * kn * r)
        << "at " << p.x.transpose() << ": " << f.transpose();
  }
}

}  // namespace
}  // namespace sphdem
