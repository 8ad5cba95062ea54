#pragma once
// Where each rank's run time goes (docs/parallel.md, "Timings"): halo
// exchange, migration, re-partitioning, I/O and waiting in collectives are
// timed where they happen; compute is the rest of the run's wall time, so
// the phases of a rank add up to its total.
#include <array>
#include <chrono>
#include <iosfwd>
#include <string>

#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/step_times.hpp"

namespace sphdem {

// Dem: the fibers' sub-steps (their own exchanges included); Coupling: the
// drag and reaction passes.
enum class Phase { Compute = 0, Halo, Migration, Rebalance, Io, Wait, Dem, Coupling };
inline constexpr int kPhaseCount = 8;

// Wall-clock seconds since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
const char* to_string(Phase p);

class PhaseTimers {
 public:
  using Clock = std::chrono::steady_clock;

  // Zeroes the phases of a run; idle_seconds() keeps counting.
  void reset() { seconds_ = {}; }
  void add(Phase p, double seconds) {
    seconds_[static_cast<std::size_t>(p)] += seconds;
    if (idle(p)) idle_ += seconds;
  }
  // Halo, migration, rebalance, I/O and wait: time a rank spends on other
  // than its own particles' work (waiting for other ranks mostly). The
  // total since construction, across reset(): the balance by measured time
  // takes its busy time as wall time minus this (docs/parallel.md,
  // "Balancing measured time").
  static bool idle(Phase p) {
    return p != Phase::Compute && p != Phase::Dem && p != Phase::Coupling;
  }
  double idle_seconds() const { return idle_; }
  // Measured phases; Compute is derived by split() from the total.
  double measured(Phase p) const { return seconds_[static_cast<std::size_t>(p)]; }
  // The phases of a run that took `total` seconds: compute = total - the others.
  std::array<double, kPhaseCount> split(double total) const;

 private:
  std::array<double, kPhaseCount> seconds_{};
  double idle_ = 0;
};

// Adds the time from construction to destruction to one phase.
class ScopedPhase {
 public:
  ScopedPhase(PhaseTimers& t, Phase p) : t_(t), p_(p), start_(PhaseTimers::Clock::now()) {}
  ~ScopedPhase() {
    t_.add(p_, std::chrono::duration<double>(PhaseTimers::Clock::now() - start_).count());
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseTimers& t_;
  Phase p_;
  PhaseTimers::Clock::time_point start_;
};

// Collective. Gathers every rank's split of a run of `total` seconds and its
// per-step times to rank 0, which prints two tables to `log` (when not null)
// and, when `directory` is not empty, writes <directory>/timings.csv and
// timings.json (one row per rank). Returns the tables' text on rank 0,
// empty elsewhere.
std::string report_timings(const Comm& comm, const PhaseTimers& timers, double total,
                           const StepTimes::Summary& steps, std::ostream* log,
                           const std::string& directory);

}  // namespace sphdem
