#pragma once
// Optional wall-clock breakdown of the DEM sub-step for bench/bench_dem
// (docs/performance.md, "DEM"). Off by default: then each timed section
// costs one predictable branch. Not thread-safe (one DEM stepper per
// process, which is how the library runs DEM).
#include <chrono>

namespace sphdem::dem_detail {

struct DemProfile {
  bool enabled = false;
  // Seconds, accumulated over the run.
  double pairs = 0;       // evaluate every pair (contacts, bonds) into per-pair results
  double gather = 0;      // each owned particle sums its pairs, body and external forces
  double walls = 0;       // wall contacts of the owned particles
  double kick_drift = 0;  // the two half kicks and the drift
  double halo = 0;        // ghost state update between rebuilds (bond sub-cycling's inner steps)
  double collective = 0;  // the rebuild vote with the ghost update it rides on (waiting included)
  double rebuild = 0;     // store state, migration, ghost build, pair list build
  double rebuild_pairs = 0;    // of which the pair-list build
  double rebuild_migrate = 0;  // of which the migration (or dropping the ghosts)
  double rebuild_ghosts = 0;   // of which the ghost build
  double chains = 0;           // implicit bonds: the chains' linear solves
  void reset() { *this = DemProfile{enabled}; }
};

DemProfile& dem_profile();

// Adds the time from construction to destruction to `slot` when enabled.
class DemTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit DemTimer(double& slot) : slot_(dem_profile().enabled ? &slot : nullptr) {
    if (slot_) t0_ = Clock::now();
  }
  ~DemTimer() { stop(); }
  void stop() {
    if (slot_) slot_[0] += std::chrono::duration<double>(Clock::now() - t0_).count();
    slot_ = nullptr;
  }
  DemTimer(const DemTimer&) = delete;
  DemTimer& operator=(const DemTimer&) = delete;

 private:
  double* slot_;
  Clock::time_point t0_;
};

}  // namespace sphdem::dem_detail
