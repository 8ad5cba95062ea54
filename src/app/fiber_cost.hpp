#pragma once
// The cost of the fibers' stiffness, for `sphdem check` (docs/dem.md, "Bond
// sub-cycling"): how many bond sub-steps each resin step takes, a warning
// when explicit bonds make that large, and a refusal naming
// fibers.youngs_modulus when the DEM alone would run for more than a day.
#include <cstdint>
#include <ostream>

#include "sphdem/config/case.hpp"

namespace sphdem::app {

struct FiberCost {
  double bond_substeps = 0;   // bond evaluations per resin step
  double outer_substeps = 0;  // contact/drag sub-steps per resin step
  double dem_seconds = 0;     // estimated DEM time on one core [s]
};

// dem_particles fiber particles, resin steps of resin_dt to end_time, DEM
// sub-steps of outer_dt and bond steps of bond_dt (equal when explicit).
FiberCost fiber_cost(const Case& c, double resin_dt, double outer_dt, double bond_dt,
                     std::int64_t dem_particles);

// Prints the estimate; warns when explicit bonds take more than
// kExplicitWarnSubsteps sub-steps per resin step; throws InputError at
// fibers.youngs_modulus when dem_seconds exceeds a day.
void check_fiber_cost(const Case& c, const FiberCost& cost, std::ostream& out);

}  // namespace sphdem::app
