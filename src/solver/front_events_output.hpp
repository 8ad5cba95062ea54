#pragma once
// The weld-line and trapped-air list (output.front_events, docs/physics.md
// "Weld lines and trapped air"): <output>/<case>_front_events.csv, columns
// time_s, kind (weld_line or trapped_air), x_m, y_m, z_m, id, size (the
// pocket's area in m^2 in 2D or volume in m^3 in 3D; 0 for a weld line).
#include <string>
#include <vector>

#include "sphdem/sph/front_events.hpp"

namespace sphdem {

// Rank 0 only. first_of_run: keep the rows up to `time` (a restart
// continues the list; a fresh run at time 0 starts it over) and write the
// header.
void append_front_events(const std::string& dir, const std::string& case_name, double time,
                         const std::vector<FrontEvent>& events, bool first_of_run);

}  // namespace sphdem
