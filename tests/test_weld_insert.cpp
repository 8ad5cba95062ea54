// A weld line where two melt fronts meet behind an insert (issue 18 part 5,
// docs/paper-comparison.md section 12 "Two fronts meet behind an insert"):
// inputs/insert_melt_front.yaml (the melt plate's physics in a 12 mm channel
// fed by a piston, a 6 x 4 mm insert on its centre line) at 1 mm, four
// particles across each passage. The front splits at the insert; once both
// streams have passed its back face they turn into its shadow and meet on
// the centre line: weld-line events there, and none anywhere before that
// (so the test fails whether the detector fires too early, in the wrong
// place or not at all). The case vents at the channel's far end only, so
// air closed in against the insert would be listed: no pocket may appear
// before the streams meet or outside the shadow (at 1 mm the one behind the
// insert reaches a spacing^2 only at 14 ms, after this run). 2 ranks give
// the 1-rank run bitwise.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
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
// The insert: x 19-25 mm, y -2 to 2 mm; the channel's walls at y = +-6 mm.
constexpr double kFace = 19 * kMm, kBack = 25 * kMm, kHalf = 2 * kMm;
constexpr double kDp = 1 * kMm;
constexpr double kEndTime = 0.0115;
constexpr double kChunk = 2.5e-4;  // s between the stream and event checks

using Row = testing::ResinRow<5>;  // x, y, v_x, v_y, weld_line

struct InsertRun {
  std::vector<Row> rows;           // per resin particle at the end
  std::vector<FrontEvent> events;  // all of the run, in time order
  double passed = -1;              // s: both streams beyond the back face
};

InsertRun run_insert(const Comm& comm) {
  const Case c = testing::load_input("insert_melt_front.yaml",
                                     {"numerics.spacing=1e-3", "numerics.end_time=0.0115"});
  Simulation<2> sim(c, comm, quiet());
  InsertRun run;
  for (double t = kChunk; t < kEndTime + 0.5 * kChunk; t += kChunk) {
    testing::run_until(sim, t);
    const std::vector<FrontEvent> events = sim.front_events();
    run.events.insert(run.events.end(), events.begin(), events.end());
    const SphParticles<2>& ps = sim.particles();
    double upper = -1, lower = -1;  // the streams' leads beside the insert
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] != Kind::Fluid) continue;
      if (ps.x[i][1] > kHalf) upper = std::max(upper, ps.x[i][0]);
      if (ps.x[i][1] < -kHalf) lower = std::max(lower, ps.x[i][0]);
    }
    if (run.passed < 0 && std::min(comm.max(upper), comm.max(lower)) > kBack) run.passed = t;
  }
  const SphParticles<2>& ps = sim.particles();
  run.rows = testing::gather_resin_rows<5>(comm, ps, [&](std::size_t i, double* v) {
    v[0] = ps.x[i][0];
    v[1] = ps.x[i][1];
    v[2] = ps.v[i][0];
    v[3] = ps.v[i][1];
    v[4] = ps.weld_line[i];
  });
  return run;
}

bool in_shadow(const FrontEvent& e) {
  return e.x[0] > kBack && std::abs(e.x[1]) < kHalf;
}

TEST(WeldInsert, TheStreamsWeldInTheInsertsShadowAndNowhereElse) {
  const InsertRun run = run_insert(Comm(MPI_COMM_SELF));
  std::printf("[          ] both streams past the insert at %.4f s\n", run.passed);
  ASSERT_GT(run.passed, 0.0) << "the streams must pass the insert within the run";
  std::size_t wake = 0, pockets = 0;
  double first_weld = 1e300;
  for (const FrontEvent& e : run.events)
    if (e.kind == FrontEvent::Kind::WeldLine) first_weld = std::min(first_weld, e.time);
  for (const FrontEvent& e : run.events) {
    if (e.kind == FrontEvent::Kind::TrappedAir) {
      // Only the air the streams close in against the insert (it does not
      // vent; the channel's far end does): none before they meet.
      ++pockets;
      EXPECT_TRUE(in_shadow(e)) << "a pocket outside the insert's shadow at t = " << e.time;
      EXPECT_GE(e.time, first_weld) << "a pocket before the streams met";
      continue;
    }
    std::printf("[          ] weld at %.4f s, (%.2f, %.2f) mm\n", e.time, e.x[0] / kMm,
                e.x[1] / kMm);
    EXPECT_TRUE(in_shadow(e)) << "a weld outside the insert's shadow at t = " << e.time;
    EXPECT_GE(e.time, run.passed - kChunk) << "a weld before both streams passed the insert";
    // The case is symmetric about y = 0: the streams meet on the centre line.
    EXPECT_LT(std::abs(e.x[1]), kDp) << "a weld off the centre line";
    wake += in_shadow(e);
  }
  std::printf("[          ] %zu weld events in the shadow, %zu trapped-air rows\n", wake, pockets);
  EXPECT_GE(wake, 2u) << "the streams must weld behind the insert";
  std::size_t flagged = 0;
  for (const Row& r : run.rows) flagged += r.value[4] != 0;
  EXPECT_EQ(flagged, wake);
}

TEST(WeldInsertRanks, SameAtEveryRankCount) {
  InsertRun ref;
  if (world().root()) ref = run_insert(Comm(MPI_COMM_SELF));
  testing_mpi::wait_for_root(world());
  const InsertRun got = run_insert(world());
  if (!world().root()) return;
  EXPECT_EQ(testing_mpi::bitwise_mismatches(ref.rows, got.rows), 0u);
  ASSERT_EQ(ref.events.size(), got.events.size());
  for (std::size_t k = 0; k < ref.events.size(); ++k) {
    EXPECT_EQ(std::memcmp(&ref.events[k].x, &got.events[k].x, sizeof ref.events[k].x), 0);
    EXPECT_EQ(ref.events[k].time, got.events[k].time);
  }
  EXPECT_EQ(ref.passed, got.passed);
}

}  // namespace
}  // namespace sphdem
