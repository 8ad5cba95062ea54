#pragma once
// Fibers as bonded DEM particles (docs/dem.md): linear
// spring-dashpot contacts with an incremental Coulomb-capped tangential
// spring, Potyondy & Cundall (2004) parallel bonds with breakage, and a
// velocity-Verlet step for translation and rotation. The pair kernels live
// in src/dem/terms/, one per header; the loops are in src/dem/dem_pair_list.cpp, dem_forces.cpp and
// dem_stable_step.cpp. Nothing here knows about ranks.
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

// Units: SI. In 2D every quantity is per unit depth (thickness t, 1 m by
// default): masses kg/m, forces N/m, stiffnesses N/m/m.
template <int D>
struct DemParams {
  // Contacts (docs/validation.md section 2).
  double kn = 0;                  // normal contact stiffness [N/m]
  double kt_over_kn = 2.0 / 7.0;  // tangential / normal contact stiffness
  double restitution = 0.9;       // normal restitution e, sets the damping per pair
  double friction = 0.3;          // Coulomb coefficient mu
  // Parallel bonds (docs/validation.md section 6).
  double youngs_modulus = 0;  // E [Pa]: kbar_n = E / (R1 + R2) [Pa/m]
  double kbar_star = 0.25;    // kbar_n / kbar_s (paper: 0.25)
  double lambda = 1.0;        // bond radius multiplier, Rbar = lambda min(R1, R2)
  double tensile_strength = std::numeric_limits<double>::infinity();  // sigma_c [Pa]
  double shear_strength = std::numeric_limits<double>::infinity();    // tau_c [Pa]
  double thickness = 1.0;  // 2D depth t [m] (bond area 2 Rbar t)
  // Body force and damping.
  Vec<D> gravity = Vec<D>::Zero();  // [m/s^2]
  double global_damping = 0;        // [1/s]: F -= gamma m v, T -= gamma I omega
  double dt_safety = 0.2;           // dt = dt_safety * min sqrt(m/k) (stable_dem_dt)
  // Bond sub-cycling (docs/dem.md, "Bond sub-cycling"): the bonds advance in
  // inner steps of at most bond_dt within each step, everything else
  // (contacts, walls, drag, body and external forces) at the step.
  bool subcycle_bonds = false;
  double bond_dt = 0;  // [s] the inner step's bound (stable_dem_dt), set by the driver
  // Implicit bonds (docs/dem.md, "Implicit bonds"; with subcycle_bonds, whose
  // outer step it keeps): the bonds of each fiber solved together in one step
  // instead of inner steps. chain_reach [m]: the farthest two particles of a
  // fiber can be apart (set by the driver; the DEM halo covers it, so that
  // every rank holding a fiber's particle holds the whole fiber).
  bool implicit_bonds = false;
  double chain_reach = 0;
  // Exponential drag (docs/physics.md "Exponential drag"): the resin's drag
  // and torque are no forces; each kick relaxes v towards drag_velocity
  // (and omega towards resin_spin) by the exact exponential instead.
  bool exponential_drag = false;
  // The decomposed run's pair-list skin may grow to this many r_min where
  // the decomposition's cells leave room (DemDomain): a wider skin rebuilds
  // less often for a few more candidate pairs; results do not depend on it.
  double max_skin = 1.0;
};

// The contact stiffness of docs/dem.md: a fraction of the bond's axial
// stiffness kbar_n A for two equal particles of radius r (paper: 0.01).
template <int D>
double contact_stiffness_from_bond(const DemParams<D>& p, double r, double fraction = 0.01);

// A rigid wall: a plane (one-sided, particles on the side of `normal`;
// particles more than a radius behind it are not seen), a segment [a, b]
// (two-sided: a line segment in 2D, a thin rod in 3D; its ends push from
// their point when flagged in `edges`, kEndA and kEndB, else the segment's
// reach ends there, as for a rectangle's edges; a mold segment has a
// `normal` into the mold, and its ends then push only in front of it), or,
// in 3D, a
// rectangle: the corner `point`, two orthogonal edges `u` and `v`, the unit
// `normal` into the domain. A rectangle is the face of a solid behind it:
// within its footprint it pushes along `normal` (one-sided, as the plane);
// beyond an edge, and only in front of its plane, it pushes from the closest
// point of the edge or corner, for the edges flagged in `edges` (bit 0: the
// edge at point, along v; bit 1: the one at point + u; bit 2: at point,
// along u; bit 3: at point + v). An unflagged edge ends the rectangle's
// reach there: a coplanar neighbour (a seam), or an edge that another wall
// owns (docs/dem.md, "Walls"). Every wall translates at `velocity` (a
// piston).
template <int D>
struct DemWall {
  enum class Type { Plane, Segment, Rect };
  static constexpr int kAllEdges = 0xF;
  static constexpr int kEndA = 1, kEndB = 2;  // Segment: the ends at point and at end
  Type type = Type::Plane;
  Vec<D> point = Vec<D>::Zero();   // Plane: a point on it; Segment: end a; Rect: a corner
  Vec<D> normal = Vec<D>::Zero();  // Plane, Rect (and mold segments): unit normal inward
  Vec<D> end = Vec<D>::Zero();     // Segment: end b; Rect: the opposite corner point + u + v
  Vec<D> u = Vec<D>::Zero(), v = Vec<D>::Zero();  // Rect: the edges from point
  int edges = kAllEdges;  // Rect: edges that push (bits above); Segment: ends that push
  Vec<D> velocity = Vec<D>::Zero();

  static DemWall plane(const Vec<D>& p, const Vec<D>& n, const Vec<D>& vel = Vec<D>::Zero());
  static DemWall segment(const Vec<D>& a, const Vec<D>& b, const Vec<D>& vel = Vec<D>::Zero());
  // u and v orthogonal; the normal is +-(u x v), the sign of `inward`.
  static DemWall rect(const Vec<D>& corner, const Vec<D>& u, const Vec<D>& v, const Vec<D>& inward,
                      int edges = kAllEdges, const Vec<D>& vel = Vec<D>::Zero()) requires(D == 3);
};

// The 2 D inward planes of the box [lo, hi].
template <int D>
std::vector<DemWall<D>> box_walls(const Vec<D>& lo, const Vec<D>& hi);

// The pair list of the DEM loops (docs/dem.md, "Pairs"). Built from the
// slots at a rebuild, it holds every pair (a, b), gid a < gid b, with at
// least one owned particle, that is bonded or within R_a + R_b + skin; the
// contact history travels in the pair between rebuilds and goes back to the
// owner's slots at dem_store_pair_state. Bond state is updated in place in
// the smaller gid's slots (a ghost's copy on the rank of the larger gid:
// both ranks compute the same update from the same inputs).
template <int D>
struct DemPair {
  std::int32_t a = 0, b = 0;  // local indices, gid[a] < gid[b]
  std::int8_t bond = -1;      // slot in a's bonds, -1 = none
  // Touching (or bonded) at the last evaluation: f, ta, tb hold its force.
  // A contact built from a stored history is active (f, ta, tb zero until
  // evaluated), so that its history goes back to the slots until then.
  bool active = false;
  double cn = 0, ct = 0;                            // contact damping for the pair's effective mass
  Vec<D> xi = Vec<D>::Zero();                       // tangential spring of the contact
  Vec<D> f = Vec<D>::Zero();                        // force on b (a receives -f)
  Rot<D> ta = Rot<D>::Zero(), tb = Rot<D>::Zero();  // torques on a and b
};

template <int D>
struct DemWorkspace {
  std::vector<DemPair<D>> pairs;
  // Per owned particle, its pairs in increasing partner gid:
  // adj[adj_start[i] .. adj_start[i+1]), entry 2 k + (1 if i is b).
  std::vector<std::int32_t> adj_start, adj;
  std::vector<Vec<D>> x_ref;  // owned positions at the last build
  double skin = 0;            // set by dem_build_pairs (0: a quarter of R_min)
  bool pairs_valid = false;
  bool forces_valid = false;  // force/torque hold the current state's values
  std::vector<std::int32_t> cell_start, cell_items;
  // Per owned particle, the walls within reach at the build:
  // wall_items[wall_start[i] .. wall_start[i+1]), and the walls' positions then.
  std::vector<std::int32_t> wall_start, wall_items;
  std::vector<Vec<D>> wall_ref;
  // Bond sub-cycling: the bonds' force and torque on each owned particle.
  std::vector<Vec<D>> bond_force;
  std::vector<Rot<D>> bond_torque;
  // The slow forces held over the outer step (for its trapezoid correction).
  std::vector<Vec<D>> held_force, held_drag;
  std::vector<Rot<D>> held_torque, held_hydro_torque;
  // Implicit bonds: each bonded cluster (chain) with an owned particle, its
  // members (local indices) in gid order chain_items[chain_start[c] ..
  // chain_start[c+1]), its bonds chain_bonds[bond_start[c] .. bond_start[c+1])
  // in (gid, partner gid) order; rebuilt after every pair-list build.
  struct ChainBond {
    std::int32_t a = 0, b = 0;  // positions in the chain's member list
    std::int32_t owner = 0;     // local index of the slot's particle (member a or b)
    std::int32_t partner = 0;   // local index of the other particle
    std::int32_t slot = 0;      // in owner's bonds
  };
  std::vector<std::int32_t> chain_start, chain_items, bond_start, chain_band;
  std::vector<ChainBond> chain_bonds;
  std::vector<Vec<D>> v_half;  // the owned velocities of the step's middle
  std::vector<Rot<D>> omega_half;
  bool chains_valid = false;
  bool bond_broke = false;  // a bond broke since the last rebuild vote
  void invalidate() { pairs_valid = forces_valid = chains_valid = false; }
};

// Builds the pair list over owned and ghost particles (the contact history
// read from the slots). Throws SimulationError when an owned particle's
// bond partner is absent (not owned, not a ghost).
// Also lists each owned particle's candidate walls (dem_build_wall_lists),
// dropping the wall history of a particle with none.
template <int D>
void dem_build_pairs(const DemParams<D>& p, const std::vector<DemWall<D>>& walls,
                     DemParticles<D>& ps, DemWorkspace<D>& ws);
template <int D>
void dem_build_wall_lists(const std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
                          DemWorkspace<D>& ws);

// Writes the contact history of the pairs back to the slots of their owned
// owners (call before migration, output and checkpoints).
template <int D>
void dem_store_pair_state(DemParticles<D>& ps, const DemWorkspace<D>& ws);

// Largest squared displacement of an owned particle or a wall since the
// last build; the lists must be rebuilt once it passes (skin / 2)^2.
template <int D>
double dem_max_displacement2(const DemParticles<D>& ps, const std::vector<DemWall<D>>& walls,
                             const DemWorkspace<D>& ws);

// The two halves of a velocity-Verlet sub-step for the parallel driver:
// kick(dt/2) + drift(dt) of the owned particles and the walls, then (after
// the ghosts' state is refreshed) forces at the new positions + kick(dt/2).
template <int D>
void dem_kick_drift(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls,
                    DemParticles<D>& ps);
template <int D>
void dem_force_kick(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                    DemParticles<D>& ps, DemWorkspace<D>& ws);

// Contacts, bonds, body and external forces at the current positions, for
// the owned particles (the pair list must be valid). Incremental springs
// advance by the relative velocities times `dt` (0 for the first
// evaluation). Overwrites force and torque. Each owned particle sums its
// pairs in increasing partner gid, then its walls: the same sum on any
// number of ranks.
template <int D>
void compute_dem_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                        DemParticles<D>& ps, DemWorkspace<D>& ws);

// One serial DEM sub-step of velocity Verlet (kick, drift, forces, kick)
// for translation and rotation; moves the walls and rebuilds the pair list
// when needed. The external force array f_ext is held constant. Throws
// SimulationError when a bond partner is missing or a particle runs out of
// contact slots.
template <int D>
void dem_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps,
              DemWorkspace<D>& ws);

// Bond sub-cycling (docs/dem.md, "Bond sub-cycling"), the pieces of the
// parallel driver's impulse multiple-time-step: the bonds' force and torque
// alone at the current state into ws.bond_force/bond_torque (bond state
// advanced by the half-step velocities times dt, 0 for an evaluation that
// only reads); the slow forces (everything but the intact bonds) into force
// and torque, contact springs advanced by the velocities times dt.
template <int D>
void compute_dem_bond_forces(const DemParams<D>& p, double dt, DemParticles<D>& ps,
                             DemWorkspace<D>& ws);
template <int D>
void compute_dem_slow_forces(const DemParams<D>& p, double dt, const std::vector<DemWall<D>>& walls,
                             DemParticles<D>& ps, DemWorkspace<D>& ws);
// x += dt v for the owned particles, walls by their velocity.
template <int D>
void dem_drift(double dt, std::vector<DemWall<D>>& walls, DemParticles<D>& ps);

// One outer step of dt: `inner` velocity-Verlet steps of dt/inner under
// the bonds plus the slow forces held (refresh_ghosts after each drift),
// settle() (the rebuild vote: rebuild or refresh the ghosts), slow forces
// at the new state and their trapezoid correction dt/2 (F_new - F_held)/m. The serial and the
// decomposed drivers differ only in the two hooks.
template <int D>
void dem_subcycled_step(const DemParams<D>& p, double dt, std::int64_t inner,
                        std::vector<DemWall<D>>& walls, DemParticles<D>& ps, DemWorkspace<D>& ws,
                        const std::function<void()>& refresh_ghosts,
                        const std::function<void()>& settle);
// One outer step of dt with implicit bonds (docs/dem.md, "Implicit bonds"):
// half kick under all forces, refresh_ghosts(), the drift velocity u of
// every fiber from its bonds' stiffness (M + dt^2/4 K) u = M v_half (the
// trapezoidal rule, one linear solve per chain), drift by u,
// refresh_ghosts(), the bonds' law over that motion, half kick, settle()
// and the slow forces' trapezoid correction as dem_subcycled_step.
template <int D>
void dem_implicit_step(const DemParams<D>& p, double dt, std::vector<DemWall<D>>& walls,
                       DemParticles<D>& ps, DemWorkspace<D>& ws,
                       const std::function<void()>& refresh_ghosts,
                       const std::function<void()>& settle);
// Inner steps per outer step of dt: ceil(dt / bond_dt), at least 1.
template <int D>
std::int64_t dem_bond_substeps(const DemParams<D>& p, double dt);

// The stable step of everything but the bonds (the contact springs, one
// per particle): the outer step of bond sub-cycling.
template <int D>
double stable_dem_contact_dt(const DemParams<D>& p, const DemParticles<D>& ps);

// The outer step with the bonds kept apart (sub-cycled or implicit), at
// least bond_dt: the contacts' stable step; implicit bonds take
// kImplicitStepsPerContactStep steps in it, to follow the start of a
// fiber's bending vibration (docs/dem.md, "Implicit bonds").
inline constexpr int kImplicitStepsPerContactStep = 2;
template <int D>
double stable_dem_outer_dt(const DemParams<D>& p, const DemParticles<D>& ps);

// dt_safety * min over particles of sqrt(m / k_trans) and sqrt(I / k_rot),
// k summed over the particle's bonds plus one contact (docs/dem.md).
template <int D>
double stable_dem_dt(const DemParams<D>& p, const DemParticles<D>& ps);

// Energies for the tests and diagnostics [J] (2D: J/m).
template <int D>
double dem_kinetic_energy(const DemParticles<D>& ps);
// Elastic energy stored in the bonds and contact springs.
template <int D>
double dem_elastic_energy(const DemParams<D>& p, const std::vector<DemWall<D>>& walls,
                          const DemParticles<D>& ps);

// A DEM-only driver: particles, walls and parameters (tests, fibers_only).
template <int D>
class DemSystem {
 public:
  DemParams<D> params;
  DemParticles<D> particles;
  std::vector<DemWall<D>> walls;

  // Adds a particle at rest; returns its global id (0, 1, 2, ...).
  std::int64_t add_particle(const Vec<D>& x, double radius, double density,
                            std::int32_t fiber = -1);
  // Bonds particles a and b (stored on the smaller gid), unstressed at
  // their current distance.
  void add_bond(std::int64_t a, std::int64_t b);
  std::size_t index_of(std::int64_t gid) const;
  // The bond between a and b (either order), or nullptr.
  const DemBond<D>* bond(std::int64_t a, std::int64_t b) const;

  double stable_dt() const { return stable_dem_dt(params, particles); }
  void step(double dt);
  // Call after changing particles or parameters by hand between steps.
  void invalidate_forces() { ws_.invalidate(); }
  double kinetic_energy() const { return dem_kinetic_energy(particles); }
  double elastic_energy() const { return dem_elastic_energy(params, walls, particles); }
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }

 private:
  DemWorkspace<D> ws_;
  std::int64_t bonds_ = 0;  // bonds made, the next bond id
  double time_ = 0;
  std::int64_t steps_ = 0;
};

}  // namespace sphdem
