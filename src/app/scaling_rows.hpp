#pragma once
// The rows of `sphdem scaling` (docs/scaling.md, "Scaling studies of any
// case"): what one run printed and wrote (its banner, its "done" line, its
// timings.csv), and the study's CSV.
#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "sphdem/parallel/timers.hpp"

namespace sphdem::app {

// Particle counts and steps of one run, from its log (the banner of `sphdem
// run` and its "done:" line).
struct RunCounts {
  std::int64_t resin = 0, wall = 0, fibers = 0, dem = 0;
  std::int64_t steps = 0;
  std::int64_t all() const { return resin + wall + dem; }
  // The particles that move and carry the work: resin and fiber particles.
  // Walls are a surface; refining a weak study adds fewer of them per rank.
  std::int64_t moving() const { return resin + dem; }
};

// Throws std::runtime_error when the log lacks the banner or the done line.
RunCounts parse_run_log(const std::string& text);

// Max and mean over ranks of each phase of timings.csv, and of the total;
// the largest lag behind each step's slowest rank and the largest
// imbalance of the totals (docs/parallel.md, "Per-step times"; zero when
// timings.csv has no such columns).
struct PhaseStats {
  int ranks = 0;
  std::array<double, kPhaseCount> max{}, mean{};
  double total_max = 0;
  double step_lag_max = 0, imbalance_max = 0;
};

// Reads <run dir>/timings.csv by its header; throws std::runtime_error when
// it is missing or a phase column is absent.
PhaseStats read_timings(const std::filesystem::path& csv);

struct ScalingRow {
  int ranks = 0;
  double spacing = 0;
  RunCounts counts;
  PhaseStats phases;
  int run = 1;  // which of the repeats (1-based)
  int repeats = 1;
  double wall_seconds() const { return phases.total_max; }
  double particle_steps_per_second() const;
};

// The CSV header and one line per row; efficiency = particle-steps/s per
// rank relative to `base` (T_base P_base / (P T_P) at a fixed case).
void write_scaling_csv(std::ostream& out, const std::vector<ScalingRow>& rows,
                       const ScalingRow& base, bool weak);

// The column names, in order (the test and tools/plot_scaling.py read them).
std::vector<std::string> scaling_csv_columns();

}  // namespace sphdem::app
