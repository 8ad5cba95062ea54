#pragma once
// Moving and sliding walls (docs/physics.md "Walls"). Wall k here is wall index k
// of the particles (moving walls first, then sliding walls, as in the case).
//  - A moving wall translates rigidly with a piecewise-linear velocity table.
//    With a pressure limit it is the ram of a molding machine with V/P
//    switchover: a factor s in [0, 1] scales the table velocity and obeys
//      ds/dt = (P_limit - P_face) / (P_limit * relax_time),
//    so past the limit the piston slows until the resin pressure at its face
//    holds at the limit, and speeds back up (never past the table) below it.
//  - A sliding wall stays in place but its particles carry a tangential
//    velocity (a lid or a belt), which the no-slip condition imposes.
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"

namespace sphdem {

Vec3a table_velocity(const VelocityTable& t, double time);
Vec3a table_acceleration(const VelocityTable& t, double time);

struct WallMotion {
  std::string name;
  bool moves = false;  // false: a sliding wall
  VelocityTable table;
  double pressure_limit = 0;  // 0: none
  double relax_time = 1e-3;
  double adhesion_pressure = 0;  // floor of the extrapolated wall pressure is minus this
  WallSlipLaw slip;              // what the resin sees at this wall
  WallThermalLaw thermal;        // its temperature (resin.thermal)
  Vec3a surface_velocity{};
  double scale = 1.0;        // controller state (part of the checkpoint)
  double face_pressure = 0;  // last measured mean pressure on the face

  Vec3a velocity(double t) const;
  Vec3a acceleration(double t) const;
};

std::vector<WallMotion> make_wall_motions(const Case& c);

// Advances every pressure-limited wall's controller by dt given the mean
// face pressure of each wall (NaN when the wall touches no resin).
void update_wall_controllers(std::vector<WallMotion>& walls, const std::vector<double>& face,
                             double dt);

}  // namespace sphdem
