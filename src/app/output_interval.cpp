#include "output_interval.hpp"

#include <fmt/format.h>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem::app {

double estimated_resin_dt(const Case& c) {
  const SphParams sp = make_sph_params(c);
  return choose_time_step(c.numerics, sp, 0.1 * sp.c0, 0.0).dt;
}

void check_output_interval(const Case& c, double dt_estimate) {
  const char* key = "output.every_time";
  if (!c.output.every_time || *c.output.every_time >= dt_estimate) return;
  const KeyLocation where = key_location(c, key);
  // The default (end_time / 100) never gets here for long: a run ends at
  // end_time, so it asks for at most 100 snapshots in all.
  if (where.file != "--set" && where.line == 0) return;
  throw InputError(where.file, where.line, key,
                   fmt::format("{:.6g} s is shorter than the estimated time step {:.6g} s: more "
                               "than one snapshot per step; use at least the step, or "
                               "output.every_steps",
                               *c.output.every_time, dt_estimate));
}

}  // namespace sphdem::app
