#pragma once
// The seeded bend of a placed fiber (`fibers.initial_bend`, issue 12 part
// 5; docs/dem.md "Seeded bend"): a straight chain bent into a half-sine
// arc, a stressed perturbation of the straight fiber (its rest state stays
// straight), so that the buckling instability has a seed.
#include <vector>

#include "sphdem/dem/dem.hpp"

namespace sphdem {

// The arc of a chain of n touching particles of radius r whose centres
// have a sagitta of `sagitta` x the fiber length 2 r n. The chain's
// tangent angle at particle k is theta0 cos(pi k / (n - 1)) (a half-sine in
// the arc length, zero curvature at the free ends), each bond's chord
// keeps the pitch 2 r and lies at the tangent angle of its middle, and
// theta0 is found by bisection for the sagitta (0 <= sagitta < 0.25 is
// reachable at every n >= 3).
struct FiberBend {
  std::vector<double> along;   // centre k along the end-to-end axis, from the middle [m]
  std::vector<double> across;  // centre k's distance from that axis, towards the bend [m]
  std::vector<double> turn;    // bond k: particle k + 1's rotation minus particle k's [rad]
};

FiberBend fiber_bend(int n, double radius, double sagitta);

// The direction the fiber of axis u bends towards: 2D, u turned by +90
// degrees; 3D, e_z x u normalised (horizontal; for a fiber in the x-y
// plane, its plane), e_x for a fiber along z.
template <int D>
Vec<D> bend_direction(const Vec<D>& u);

// The loads of bond k of the bent chain (u its axis): the bending moment
// that bending the straight chain gave it, M_b = -kbar_n I turn, about
// u x bend_direction(u) (2D: the scalar); no shear or normal force (the
// chords keep the pitch). The moments then relax through the bonds' own
// law: a free fiber left alone straightens.
template <int D>
void preload_bent_bond(const DemParams<D>& p, double radius, double turn, const Vec<D>& u,
                       DemBond<D>& b);

}  // namespace sphdem
