#pragma once
// When a run writes a snapshot: every `output.every_steps` steps and/or each
// time simulated time passes a multiple of `output.every_time` (a step that
// jumps over several multiples writes once). Shared by the SPH and the
// DEM-only step loops.
#include <cstdint>

#include "sphdem/config/case.hpp"

namespace sphdem {

class OutputCadence {
 public:
  OutputCadence(const Output& out, double start_time)
      : every_t_(out.every_time.value_or(0.0)),
        every_s_(out.every_steps.value_or(0)),
        next_t_(start_time + every_t_) {}

  // True when the state after `step` at `time` is due for output.
  bool due(std::int64_t step, double time) {
    bool out = every_s_ > 0 && step % every_s_ == 0;
    if (every_t_ > 0 && time >= next_t_ * (1 - 1e-12)) {
      out = true;
      while (next_t_ <= time * (1 + 1e-12)) next_t_ += every_t_;
    }
    return out;
  }

 private:
  double every_t_;
  std::int64_t every_s_;
  double next_t_;
};

}  // namespace sphdem
