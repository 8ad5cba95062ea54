#pragma once
// When a run writes a snapshot: every `output.every_steps` steps and/or each
// time simulated time passes a multiple of `output.every_time` (a step that
// jumps over several multiples writes once). Shared by the SPH and the
// DEM-only step loops.
#include <algorithm>
#include <cmath>
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
      // A few passes at most: the app refuses an interval shorter than the
      // step (src/app/output_interval.hpp). Far behind (an interval far
      // below the step, as 1e-300 s), one multiplication instead of the
      // chain of additions, which would take for ever.
      // (Rounded, the product may not pass `time`: then just past it.)
      if ((time - next_t_) / every_t_ > kMaxCatchUp)
        next_t_ = std::max((std::floor(time / every_t_) + 1) * every_t_,
                           std::nextafter(time * (1 + 1e-12), HUGE_VAL));
      while (next_t_ <= time * (1 + 1e-12)) next_t_ += every_t_;
    }
    return out;
  }

 private:
  static constexpr double kMaxCatchUp = 1e6;
  double every_t_;
  std::int64_t every_s_;
  double next_t_;
};

}  // namespace sphdem
