#pragma once
// A run that cannot make progress is refused before it starts: an output
// interval shorter than the step would ask for more than one snapshot per
// step (output.every_time = 1e-300 made the snapshot cadence's catch-up
// loop spin for ever, deaf to stop signals).
#include "sphdem/config/case.hpp"

namespace sphdem::app {

// The step a resin run starts with, estimated as `sphdem check` does (at
// Mach 0.1, |v| = 0.1 c0): CFL, force and viscous limits.
double estimated_resin_dt(const Case& c);

// Throws InputError naming output.every_time (file and line, or --set)
// when the user set it below `dt_estimate`. Checkpoint intervals need no
// check: every_steps is at least 1 and every_minutes is looked at once per
// step, so neither can ask for more than one checkpoint per step.
void check_output_interval(const Case& c, double dt_estimate);

}  // namespace sphdem::app
