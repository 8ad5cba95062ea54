#include "fiber_cost.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"

namespace sphdem::app {

namespace {

// DEM particle-steps per second on one core, measured on the coupled
// plate (docs/performance.md, "The coupled plate": 39 M/s on 2 ranks).
constexpr double kDemParticleStepsPerSecond = 2e7;
// Beyond this many explicit sub-steps per resin step the bonds, not the
// resin, set the run time (the E = 1e8 paper cases take 30).
constexpr double kExplicitWarnSubsteps = 100;
constexpr double kDay = 86400;

}  // namespace

FiberCost fiber_cost(const Case& c, double resin_dt, double outer_dt, double bond_dt,
                     std::int64_t dem_particles) {
  FiberCost k;
  k.outer_substeps = std::ceil(resin_dt / outer_dt);
  // Implicit bonds: one solve and bond update per outer step.
  k.bond_substeps = c.fibers->implicit_bonds
                        ? k.outer_substeps
                        : k.outer_substeps * std::ceil(resin_dt / k.outer_substeps / bond_dt);
  const double resin_steps = std::ceil(c.numerics.end_time / resin_dt);
  k.dem_seconds = static_cast<double>(dem_particles) * resin_steps * k.bond_substeps /
                  kDemParticleStepsPerSecond;
  return k;
}

void check_fiber_cost(const Case& c, const FiberCost& k, std::ostream& out) {
  const FiberSettings& f = *c.fibers;
  out << fmt::format(
      "  fiber bonds ({}): {:.0f} bond sub-steps per SPH step ({:.0f} contact/drag sub-steps); "
      "DEM alone about {:.0f} s on one core\n",
      f.implicit_bonds   ? "implicit"
      : f.subcycle_bonds ? "subcycled"
                         : "explicit",
      k.bond_substeps, k.outer_substeps, k.dem_seconds);
  if (k.dem_seconds > kDay) {
    throw input_error_at(
        c, "fibers.youngs_modulus",
        fmt::format("E = {:.3g} Pa needs {:.3g} bond sub-steps per SPH step: the DEM alone would "
                    "take about {:.1f} days on one core; lower fibers.youngs_modulus or "
                    "numerics.end_time, or use fewer fibers",
                    f.youngs_modulus, k.bond_substeps, k.dem_seconds / kDay));
  }
  if (!f.subcycle_bonds && k.bond_substeps > kExplicitWarnSubsteps) {
    out << fmt::format(
        "  warning: fibers.youngs_modulus = {:.3g} Pa takes {:.0f} explicit DEM sub-steps per SPH "
        "step; fibers.bond_integration: implicit solves each fiber's bonds once per contact "
        "step (docs/dem.md, \"Implicit bonds\")\n",
        f.youngs_modulus, k.bond_substeps);
  }
}

}  // namespace sphdem::app
