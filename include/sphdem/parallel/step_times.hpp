#pragma once
// Each rank's busy time per step, and what the ranks lose waiting for each
// other step by step (docs/parallel.md, "Per-step times"). A step's busy
// time is its wall time less the idle phases (PhaseTimers::idle: halo,
// migration, rebalance, I/O, wait). The steps are folded across ranks in
// blocks: one allreduce (max) every `block` steps gives each step's slowest
// rank, and each rank sums its lag behind it. A steady imbalance makes the
// same rank slowest at every step; step-to-step changes of speed (a CPU
// whose clock moves, a rank whose particles bunch for a while) make the
// lag larger than the imbalance of the totals, and no re-partition removes
// that part.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

class StepTimes {
 public:
  // 8 kB of pending steps per rank between folds.
  static constexpr std::size_t kDefaultBlock = 1024;
  explicit StepTimes(std::size_t block = kDefaultBlock);

  // Local: one step's busy time [s] (negative clamps to zero).
  void record(double busy_seconds);
  // True when a block is pending: fold() now (every rank records the same
  // steps, so every rank sees it at the same step).
  bool block_full() const { return pending_.size() >= block_; }
  // Collective: one allreduce (max) of the pending steps, whatever their
  // number (also none: every rank must call it the same number of times).
  void fold(const Comm& comm);
  // Zeroes everything (a run's start).
  void reset();

  // This rank's statistics over the folded steps. The quantiles come from
  // a histogram of 128 logarithmic bins per decade (1e-8 s to 1e4 s, 12 kB):
  // each is the bin's geometric centre, within 0.91 % of the exact quantile,
  // clamped to the smallest and largest step.
  struct Summary {
    std::int64_t steps = 0;
    double busy = 0;                                      // the sum of the steps' busy times [s]
    double mean = 0, p10 = 0, p50 = 0, p90 = 0, max = 0;  // per step [s]
    double lag = 0;  // sum over the steps of (slowest rank's busy time - this rank's) [s]
  };
  Summary summary() const;

  static constexpr int kBinsPerDecade = 128;
  static constexpr int kDecades = 12;
  static constexpr double kLowest = 1e-8;  // seconds: the first bin's lower edge

 private:
  double quantile(double q) const;

  std::size_t block_;
  std::vector<double> pending_, slowest_;
  std::array<std::int64_t, kBinsPerDecade * kDecades + 2> histogram_{};  // under, bins, over
  std::int64_t steps_ = 0;
  double busy_ = 0, max_ = 0, min_ = 0, lag_ = 0;
};

}  // namespace sphdem
