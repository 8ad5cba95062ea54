// Per-step busy times and the lag behind each step's slowest rank
// (docs/parallel.md, "Per-step times"): quantiles from the histogram, the
// lag folded across ranks in blocks, and the imbalance of the totals that
// report_timings adds. Runs at 1-3 ranks: every expected value is written
// for any rank count.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/step_times.hpp"
#include "sphdem/parallel/timers.hpp"

using namespace sphdem;

namespace {

// timings.csv as rows of name -> value.
std::vector<std::map<std::string, double>> read_csv(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string n; std::getline(header, n, ',');) names.push_back(n);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::map<std::string, double> row;
    std::size_t c = 0;
    for (std::string v; std::getline(fields, v, ','); ++c) row[names.at(c)] = std::stod(v);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST(StepTimes, QuantilesWithinTheBinWidth) {
  const Comm world;
  StepTimes t(64);  // 1000 steps: 15 full blocks and a partial one
  for (int s = 1; s <= 1000; ++s) {
    t.record(1e-3 * s);
    if (t.block_full()) t.fold(world);
  }
  t.fold(world);
  const StepTimes::Summary s = t.summary();
  EXPECT_EQ(s.steps, 1000);
  EXPECT_NEAR(s.busy, 500.5, 1e-9);
  EXPECT_NEAR(s.mean, 0.5005, 1e-12);
  EXPECT_DOUBLE_EQ(s.max, 1.0);
  // The bins are 10^(1/128) = 1.018 wide: the centre is within 10^(1/256) = 1.00904.
  EXPECT_NEAR(s.p10, 0.100, 0.0091 * 0.100);
  EXPECT_NEAR(s.p50, 0.500, 0.0091 * 0.500);
  EXPECT_NEAR(s.p90, 0.900, 0.0091 * 0.900);
  EXPECT_EQ(s.lag, 0.0) << "every rank recorded the same steps";
}

TEST(StepTimes, ExtremesAndEmptyRuns) {
  const Comm world;
  StepTimes none;
  none.fold(world);
  EXPECT_EQ(none.summary().steps, 0);
  EXPECT_EQ(none.summary().p50, 0.0);
  // Below and above the histogram's range, and a negative (clamped) step.
  StepTimes t(8);
  for (double v : {1e-12, -1.0, 5e5, 2e-3}) t.record(v);
  t.fold(world);
  const StepTimes::Summary s = t.summary();
  EXPECT_EQ(s.steps, 4);
  EXPECT_EQ(s.max, 5e5);
  EXPECT_EQ(s.p10, 0.0) << "the smallest step, clamped from -1";
  EXPECT_EQ(s.p90, 5e5) << "the overflow bin answers the largest step";
  t.reset();
  t.fold(world);
  EXPECT_EQ(t.summary().steps, 0);
}

// Each rank slow in turn: equal totals, no steady imbalance, but each rank
// lags behind the slowest at every step where it is not the slow one.
TEST(StepTimes, LagFollowsTheSlowestRankOfEachStep) {
  const Comm world;
  const int n = world.size();
  StepTimes t(3);  // folds after steps 3, 6, 9 and at the end: blocks of 3 and 1
  const int steps = 10;
  int fast_steps = 0;
  for (int s = 0; s < steps; ++s) {
    const bool slow = (s + world.rank()) % n == 0;
    t.record(slow ? 2e-3 : 1e-3);
    if (!slow) ++fast_steps;
    if (t.block_full()) t.fold(world);
  }
  t.fold(world);
  const StepTimes::Summary s = t.summary();
  EXPECT_EQ(s.steps, steps);
  EXPECT_NEAR(s.lag, 1e-3 * fast_steps, 1e-15);
  if (n == 1) {
    EXPECT_EQ(s.lag, 0.0);
  } else {
    EXPECT_GT(s.lag, 0.0);
  }
}

// report_timings: the per-step columns, the imbalance of the totals, and
// the reading of lag against imbalance.
TEST(StepTimes, ReportSplitsLagIntoImbalanceAndChanges) {
  const Comm world;
  const int n = world.size();
  const std::string dir =
      std::string(SPHDEM_BINARY_DIR) + "/tests/step_times_np" + std::to_string(n);
  if (world.root()) std::filesystem::create_directories(dir);
  world.barrier();
  // Rank r takes (1 + r) ms per step, steadily: lag and imbalance agree.
  StepTimes t;
  for (int s = 0; s < 100; ++s) t.record(1e-3 * (1 + world.rank()));
  t.fold(world);
  PhaseTimers timers;
  const std::string text = report_timings(world, timers, 1.0, t.summary(), nullptr, dir);
  if (!world.root()) return;
  const auto rows = read_csv(dir + "/timings.csv");
  ASSERT_EQ(static_cast<int>(rows.size()), n);
  for (int r = 0; r < n; ++r) {
    const auto& row = rows[static_cast<std::size_t>(r)];
    EXPECT_EQ(row.at("steps"), 100);
    EXPECT_NEAR(row.at("busy"), 0.1 * (1 + r), 1e-9);
    EXPECT_NEAR(row.at("step_mean"), 1e-3 * (1 + r), 1e-9);
    EXPECT_NEAR(row.at("step_max"), 1e-3 * (1 + r), 1e-9);
    EXPECT_NEAR(row.at("step_lag"), 0.1 * (n - 1 - r), 1e-6);
    EXPECT_NEAR(row.at("imbalance"), 0.1 * (n - 1 - r), 1e-6);
    EXPECT_NEAR(row.at("total"), 1.0, 1e-12);
  }
  if (n > 1) {
    // Rank 0, the fastest, lags the most: 100 steps of (n - 1) ms.
    const std::string lag = std::to_string(n - 1);
    EXPECT_NE(text.find("waiting for the step's slowest rank: up to 0." + lag + "00 s (rank 0)"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("of which 0." + lag + "00 s a steady imbalance and 0.000 s step-to-step"),
              std::string::npos)
        << text;
  }
  std::ifstream json(dir + "/timings.json");
  std::stringstream all;
  all << json.rdbuf();
  EXPECT_NE(all.str().find("\"step_lag\": "), std::string::npos);
  EXPECT_NE(all.str().find("\"steps\": 100"), std::string::npos);
}
