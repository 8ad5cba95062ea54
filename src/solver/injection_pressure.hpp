#pragma once
// The injection pressure time series (docs/physics.md "Injection
// pressure"): <output>/<case>_injection_pressure.csv, one row per moving
// wall at every snapshot. The pressure is the wall's face pressure, the
// force the resin exerts on its face over the face's area (the mean of the
// extrapolated pressures of its wall particles that touch resin, summed in
// global-id order, so it is the same at every rank count).
#include <cstdint>
#include <string>
#include <vector>

#include "sphdem/geometry/walls.hpp"

namespace sphdem {

// Rank 0 only. first_of_run: drop the rows at or after `step` (a restart
// continues the series; a fresh run starts it over) and write the header.
void append_injection_pressure(const std::string& dir, const std::string& case_name,
                               std::int64_t step, double time, const std::vector<WallMotion>& walls,
                               bool first_of_run);

}  // namespace sphdem
