#pragma once
// The registry of the resin's pair terms: the pair loop (pair_loop.hpp)
// runs the active ones in this order, which is also the order their
// contributions are added (density rate, bracket, viscous factor), so
// moving a term changes results at round-off level. Adding a term: one
// header in terms/ (term_interface.hpp says what it holds), its #include
// and its name in the list (docs/architecture.md, "Adding a physics term").
// SphPasses lists the neighbour-sum preparation passes (pass_loop.hpp), run
// in this order before the pair loop when a term or output.fields needs them.
#include "pass_loop.hpp"
#include "terms/anti_clump.hpp"
#include "terms/artificial_viscosity.hpp"
#include "terms/continuity.hpp"
#include "terms/delta_sph.hpp"
#include "terms/free_surface.hpp"
#include "terms/pressure.hpp"
#include "terms/shear_rate.hpp"
#include "terms/surface_tension.hpp"
#include "terms/viscosity_morris.hpp"
#include "terms/viscosity_variable.hpp"

namespace sphdem::terms {

using SphTerms = TermList<Continuity, DeltaSph, Pressure, ArtificialViscosity, AntiClump,
                          CsfSurfaceTension, MorrisViscosity, VariableViscosity>;

using SphPasses = PassList<ShearRatePass, FreeSurfacePass, SurfaceNormalPass, CurvaturePass>;

}  // namespace sphdem::terms
