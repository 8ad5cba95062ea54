// The real melt's flow front in the plate (issue 18 part 5,
// docs/paper-comparison.md section 12 "The melt's front"):
// inputs/plate_melt_front.yaml (Cross-WLF melt, implicit viscosity with the
// free-surface traction, the atmosphere, sigma = 0.03 N/m, weld lines and
// trapped air on) at a coarse 1 mm spacing, its nozzle and gate filled at
// the start so that the melt enters the plate at once, to 8 ms. The melt
// fills each arm across its whole 4 mm gap behind a front that wets both
// walls within a gap of its tip: no wall left dry (a wall jet or a front
// torn from a wall), no void at a wall. (With the gate filled at the start
// the paper's 0.1 Pa s resin passes these checks too: its jet comes from
// the free fall through the empty nozzle, which this short run skips; so
// the test checks the melt's front, not jet against fountain.) 2 ranks give
// the 1-rank run bitwise.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "resin_rows.hpp"
#include "sphdem/config/config.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;
using testing::world;

constexpr double kMm = 1e-3;
constexpr double kGate = 3 * kMm;  // the gate's half-width
constexpr double kGap = 4 * kMm;   // the plate's gap, walls at y = -4 and 0 mm
constexpr double kEndTime = 0.008;

Case coarse_front(const std::vector<std::string>& extra = {}) {
  std::vector<std::string> sets = {
      "numerics.spacing=1e-3", "numerics.end_time=0.008", "initial_velocity=[0, 0]",
      "fill=[{box: {min: [-0.015, 0.030], max: [0.015, 0.064]}}, "
      "{polygon: [[-0.015, 0.030], [-0.003, 0.005], [0.003, 0.005], [0.015, 0.030]]}, "
      "{box: {min: [-0.003, 0.000], max: [0.003, 0.005]}}]",
      "output.every_time=0.008"};
  sets.insert(sets.end(), extra.begin(), extra.end());
  return testing::load_input("plate_melt_front.yaml", sets);
}

using Row = testing::ResinRow<5>;  // x, y, v_x, v_y, weld_line

std::vector<Row> run_front(const Comm& comm, const std::vector<std::string>& extra = {}) {
  const Case c = coarse_front(extra);
  Simulation<2> sim(c, comm, quiet());
  testing::run_until(sim, kEndTime);
  const SphParticles<2>& ps = sim.particles();
  return testing::gather_resin_rows<5>(comm, ps, [&](std::size_t i, double* v) {
    v[0] = ps.x[i][0];
    v[1] = ps.x[i][1];
    v[2] = ps.v[i][0];
    v[3] = ps.v[i][1];
    v[4] = ps.weld_line[i];
  });
}

// One arm of the plate (side +1: x > the gate, -1: x < -it), distances as
// |x|: the front's tip, its contact with each wall (the largest |x| of the
// resin within one spacing of it) and the bands of one spacing between the
// gate and the nearer contact where a wall is dry.
struct Arm {
  double tip = 0, low = 0, high = 0;
  int dry_bands = 0, bands = 0;
};

Arm arm(const std::vector<Row>& rows, int side, double dp) {
  Arm a;
  std::vector<double> low, high;
  for (const Row& r : rows) {
    const double d = side * r.value[0], y = r.value[1];
    if (y > 0 || y < -kGap || d < kGate) continue;
    a.tip = std::max(a.tip, d);
    if (y < -kGap + dp) low.push_back(d);
    if (y > -dp) high.push_back(d);
  }
  for (double d : low) a.low = std::max(a.low, d);
  for (double d : high) a.high = std::max(a.high, d);
  // A dry stretch counts from two spacings: at 1 mm a wall row laid by the
  // front may miss one particle.
  const auto wet = [dp](const std::vector<double>& at, double b) {
    return std::any_of(at.begin(), at.end(), [&](double d) { return d >= b && d < b + 2 * dp; });
  };
  for (double b = kGate; b + 2 * dp <= std::min(a.low, a.high); b += dp) {
    ++a.bands;
    if (wet(low, b) && wet(high, b)) continue;
    ++a.dry_bands;
    std::printf("  dry: |x| in [%.1f, %.1f) mm at %s\n", b / kMm, (b + 2 * dp) / kMm,
                wet(low, b) ? "y = 0" : (wet(high, b) ? "y = -4 mm" : "both walls"));
  }
  return a;
}

TEST(MeltFront, TheMeltFillsTheArmsBehindAnAttachedFront) {
  const Comm self(MPI_COMM_SELF);
  const std::vector<Row> rows = run_front(self);
  const double dp = 1e-3;
  for (int side : {1, -1}) {
    const Arm a = arm(rows, side, dp);
    std::printf(
        "%s arm: tip %.2f mm, contacts %.2f (y = -4 mm) and %.2f mm (y = 0), "
        "%d of %d bands dry\n",
        side > 0 ? "right" : "left", a.tip / kMm, a.low / kMm, a.high / kMm, a.dry_bands, a.bands);
    EXPECT_GT(a.tip, kGate + 2 * kGap) << "the front must run two gaps into the arm";
    EXPECT_LT(a.tip - a.low, kGap) << "the front must touch the far wall within a gap of its tip";
    EXPECT_LT(a.tip - a.high, kGap)
        << "the front must touch the gate's wall within a gap of its tip";
    EXPECT_EQ(a.dry_bands, 0) << "the arm must be full across its gap behind the front";
  }
}

TEST(MeltFrontRanks, SameAtEveryRankCount) {
  std::vector<Row> ref;
  if (world().root()) {
    const Comm self(MPI_COMM_SELF);
    ref = run_front(self);
  }
  testing_mpi::wait_for_root(world());
  const std::vector<Row> got = run_front(world());
  if (!world().root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref, got), 0u);
}

}  // namespace
}  // namespace sphdem
