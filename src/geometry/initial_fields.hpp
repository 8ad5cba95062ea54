#pragma once
// The case's initial_fields (docs/case-file.md): expressions of x, y, z
// evaluated at the resin particles of their fill regions.
#include <cstddef>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Sets v and rho of resin particle i (i < fill_of.size(), which holds the
// index of the fill shape each was made in). Throws InputError at the
// expression's key and line when it is not finite at some particle.
template <int D>
void apply_initial_fields(const Case& c, const std::vector<std::size_t>& fill_of,
                          SphParticles<D>& ps);

}  // namespace sphdem
