#pragma once
// The coupled model's stable window, as `sphdem check` reports it
// (docs/physics.md "The stable window"). The drag exchange is explicit on
// both sides: a fiber particle's velocity relaxes at K V_f / m_f over the DEM
// sub-steps, a resin particle's at sum_f (V_r W_fr / S_f) K_f V_f / m_r over
// the resin's steps. The run keeps both steps below those times
// (CouplingModule::stable_dt, FiberModule::limit_substep); this report says
// what that costs, and where the void fraction's clip decides the drag.
#include <iosfwd>

#include "sphdem/config/case.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem {

struct CoupledWindow {
  double fiber_drag_time = 0;      // smallest m_f / (K V_f) of the first pass [s]
  double resin_drag_time = 0;      // 1 / (largest resin drag rate of the first pass) [s]
  double dem_dt = 0;               // the stable DEM step of the fibers' stiffness [s]
  double resin_dt = 0;             // the resin's own step (CFL, force, viscous) [s]
  double fiber_void_fraction = 1;  // unclipped, at the middle particle of a lone straight fiber
  double spacing_at_clip = 0;      // the resin spacing at which that reaches the clip [m]
};

// From the run as built (its first coupling pass) and the resin's own step.
template <int D>
CoupledWindow coupled_window(const Case& c, const Simulation<D>& sim, double resin_dt);

// Unclipped void fraction at the middle particle of a lone straight fiber:
// 1 - V_f sum_j W(|j - m| d) over its n particles (j = 0..n-1, m = n/2).
template <int D>
double lone_fiber_void_fraction(double h, double d, int n);

// The window's lines, with a warning where the drag limits the resin's
// step or the void fraction's clip binds.
void print_coupled_window(const CoupledWindow& w, const Case& c, std::ostream& out);

}  // namespace sphdem
