#pragma once
// Structure-of-arrays storage for DEM particles (disks in 2D, spheres in
// 3D), with the field registry (field_registry.hpp, as the SPH particles
// in particles.hpp). Owned particles first, [0, n_owned), ghosts after
// (docs/parallel.md, "DEM particles").
//
// Owner rule (docs/dem.md): the state of a bond and the
// tangential history of a contact between particles a and b live on the
// particle with the SMALLER global id, keyed by the partner's global id.
// They sit in that particle's fixed-size slots, so they migrate, go to
// ghosts at each halo build and checkpoint with it. Wall contacts are the
// particle's own, in separate slots keyed by wall_key(w) < 0.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross()
#include <array>
#include <cstdint>
#include <vector>

#include "sphdem/particles/particles.hpp"

namespace sphdem {

// Angular quantities: a scalar (rotation about z) in 2D, a vector in 3D.
template <int D>
using Rot = Eigen::Matrix<double, D == 2 ? 1 : 3, 1>;

// omega x r: the velocity of an arm r on a body spinning at omega.
template <int D>
inline Vec<D> cross(const Rot<D>& w, const Vec<D>& r) {
  if constexpr (D == 2) {
    return Vec<D>(-w[0] * r[1], w[0] * r[0]);
  } else {
    return w.cross(r);
  }
}

// r x f: the moment of a force f applied at arm r.
template <int D>
inline Rot<D> moment(const Vec<D>& r, const Vec<D>& f) {
  if constexpr (D == 2) {
    Rot<D> m;
    m[0] = r[0] * f[1] - r[1] * f[0];
    return m;
  } else {
    return r.cross(f);
  }
}

// One parallel bond (Potyondy & Cundall 2004), stored on its owner.
// Sign convention: the forces and moments are those acting on the
// PARTNER (larger gid); the owner receives the opposite. fn is
// compression-positive.
template <int D>
struct DemBond {
  std::int64_t partner = -1;   // partner's global id, -1 = empty slot
  std::int64_t id = -1;        // bond id, dense over all bonds (output line cells)
  bool broken = false;         // broken for good (the slot is kept for output)
  double rbar = 0;             // bond radius lambda * min(R1, R2) [m]
  double length0 = 0;          // centre distance at creation [m]
  double fn = 0;               // normal force, compression-positive [N] (2D: N/m)
  Vec<D> fs = Vec<D>::Zero();  // shear force, in the contact plane [N]
  Rot<D> mb = Rot<D>::Zero();  // bending moment [N m] (2D: the only moment)
  double mt = 0;               // twisting moment about n [N m] (3D only)
  double sigma = 0;            // max tensile stress on the periphery [Pa]
  double tau = 0;              // max shear stress [Pa]
};

// The largest stresses one bond has seen (docs/dem.md, "Bond stress
// peaks"), taken at every evaluation of the bond, i.e. every DEM sub-step
// (the stress that broke it included): over the whole run and over the
// current output interval (reset after each snapshot). Kept beside the bond
// slots, not in DemBond, so that the bond record of older checkpoints keeps
// its size.
struct BondPeak {
  double sigma_run = 0;       // max tensile stress since t = 0 [Pa]
  double tau_run = 0;         // max shear stress since t = 0 [Pa]
  double sigma_interval = 0;  // max tensile stress since the last snapshot [Pa]
  double tau_interval = 0;    // max shear stress since the last snapshot [Pa]
  void record(double sigma, double tau) {
    sigma_run = sigma > sigma_run ? sigma : sigma_run;
    tau_run = tau > tau_run ? tau : tau_run;
    sigma_interval = sigma > sigma_interval ? sigma : sigma_interval;
    tau_interval = tau > tau_interval ? tau : tau_interval;
  }
  void start_interval() { sigma_interval = tau_interval = 0; }
};

// Tangential history of one contact, stored on its owner.
template <int D>
struct DemContact {
  std::int64_t partner = kNone;  // partner gid (>= 0) or wall_key(w) (< -1)
  Vec<D> xi = Vec<D>::Zero();    // tangential spring elongation [m]
  static constexpr std::int64_t kNone = -1;
};

// History key of wall w (never a particle gid, never kNone).
inline std::int64_t wall_key(int w) {
  return -2 - static_cast<std::int64_t>(w);
}

// Slots per particle. A particle owns the bonds to partners with larger
// gids: in a chain numbered in order that is one, two covers any chain.
inline constexpr int kMaxBonds = 2;
// Contacts owned: equal disks touch at most 6 others (spheres 12), of
// which the owner holds those with larger gids, plus walls.
template <int D>
inline constexpr int kMaxContacts = D == 2 ? 8 : 16;

// Walls touched at once: a corner of the mold is two (three in 3D).
template <int D>
inline constexpr int kMaxWallContacts = D == 2 ? 4 : 6;

template <int D>
using BondSlots = std::array<DemBond<D>, kMaxBonds>;
using BondPeakSlots = std::array<BondPeak, kMaxBonds>;  // one per bond slot
template <int D>
using ContactSlots = std::array<DemContact<D>, kMaxContacts<D>>;
template <int D>
using WallContactSlots = std::array<DemContact<D>, kMaxWallContacts<D>>;

// Flags of DemParticles::fixed.
enum DemFixed : std::uint8_t { kFree = 0, kFixedMotion = 1 };

// The fibers' per-step ghost exchanges (DemHalo::forward): State between
// DEM sub-steps, Coupling at the coupling pass (docs/parallel.md, "DEM
// particles").
enum class DemGroup : std::uint8_t { State = 0, Coupling = 1 };

// The DEM field registry (field_registry.hpp): X(type, member, policy).
// Bond and contact slots go to ghosts so that a rank holding the partner as
// owned can evaluate the same pair from the same state (gather), and travel
// and checkpoint with their owner.
#define SPHDEM_DEM_FIELDS(X)                                                                     \
  /* Identity and constants. */                                                                  \
  X(std::int64_t, gid, kGhost | kMigrate | kCheckpoint)                                          \
  X(std::int32_t, fiber,                                                                         \
    kGhost | kMigrate | kCheckpoint | output_as("fiber", "1")) /* -1 = loose */                  \
  /* kFixedMotion: v and omega prescribed (clamps, pullers) */                                   \
  X(std::uint8_t, fixed, kGhost | kMigrate | kCheckpoint)                                        \
  X(double, radius, kGhost | kMigrate | kCheckpoint | output_as("radius", "m"))                  \
  X(double, mass, kGhost | kMigrate | kCheckpoint)    /* [kg] (2D: per unit depth, kg/m) */      \
  X(double, inertia, kGhost | kMigrate | kCheckpoint) /* [kg m^2] (2D: per unit depth) */        \
  /* State. */                                                                                   \
  X(Vec<D>, x, kGhost | in_group(DemGroup::State) | kShifted | kMigrate | kCheckpoint) /* [m] */ \
  X(Vec<D>, v,                                                                                   \
    kGhost | in_group(DemGroup::State) | kMigrate | kCheckpoint | output_as("velocity", "m/s"))  \
  X(Rot<D>, omega,                                                                               \
    kGhost | in_group(DemGroup::State) | kMigrate | kCheckpoint |                                \
        output_as("angular_velocity", "rad/s"))                                                  \
  /* Forces of the last evaluation (velocity Verlet's first kick reads them). */                 \
  X(Vec<D>, force, kMigrate | kCheckpoint)  /* [N] */                                            \
  X(Rot<D>, torque, kMigrate | kCheckpoint) /* [N m] */                                          \
  X(Vec<D>, f_ext, kMigrate | kCheckpoint)  /* external force held over the sub-steps [N] */     \
  /* The resin's drag (docs/physics.md "Coupling"): F = drag_coeff */                            \
  /* (drag_velocity - v), coefficient K V_f [kg/s] and Shepard resin velocity */                 \
  /* [m/s] held from the last coupling pass; the impulse [N s] it gave since */                  \
  /* then goes back to the resin at the next pass. */                                            \
  X(double, drag_coeff, kMigrate | kCheckpoint | in_group(DemGroup::Coupling))                   \
  X(Vec<D>, drag_velocity, kMigrate | kCheckpoint)                                               \
  X(Vec<D>, drag_force, kMigrate | kCheckpoint) /* of the last force evaluation [N] */           \
  X(Vec<D>, drag_impulse, kMigrate | kCheckpoint)                                                \
  /* Exponential drag: the resin mass the particle exchanges with [kg] */                        \
  /* (2D: per depth); drag_velocity then moves by -impulse / this. */                            \
  X(double, drag_parcel_mass, kMigrate | kCheckpoint)                                            \
  /* The resin's hydrodynamic torque (docs/physics.md "Hydrodynamic torque"): */                 \
  /* T = torque_coeff (resin_spin - omega), the rotational friction [N m s] and */               \
  /* half the resin's vorticity at x_f [rad/s] held from the last coupling */                    \
  /* pass; the angular impulse [N m s] goes back to the resin at the next. */                    \
  X(double, torque_coeff, kMigrate | kCheckpoint)                                                \
  X(Rot<D>, resin_spin, kMigrate | kCheckpoint)                                                  \
  X(Rot<D>, hydro_torque, kMigrate | kCheckpoint) /* of the last force evaluation [N m] */       \
  X(Rot<D>, torque_impulse, kMigrate | kCheckpoint)                                              \
  /* Owned interaction state (owner rule above). */                                              \
  X(BondSlots<D>, bonds, kGhost | kMigrate | kCheckpoint)                                        \
  /* Peaks of the owned bonds, slot by slot (ghosts' copies are scratch). */                     \
  X(BondPeakSlots, bond_peaks, kMigrate | kCheckpoint)                                           \
  X(ContactSlots<D>, contacts, kGhost | kMigrate | kCheckpoint)                                  \
  X(WallContactSlots<D>, wall_contacts, kMigrate | kCheckpoint)                                  \
  /* The coupling pass's results (coupling_loops.hpp), recomputed every */                       \
  /* pass: Shepard sum S_f (0: no resin near, no drag) and the drag */                           \
  /* impulse of the last step / dt [N], which the resin on other ranks */                        \
  /* needs from the ghosts, the clipped void fraction and the Shepard */                         \
  /* resin velocity [m/s] at x_f. */                                                             \
  X(double, shepard_sum, in_group(DemGroup::Coupling))                                           \
  X(Vec<D>, mean_drag, in_group(DemGroup::Coupling))                                             \
  /* The torque's reaction (coupling_loops.hpp): resin neighbour r gets */                       \
  /* V_r W_fr torque_lever x (x_r - x_f - resin_offset), resin_offset the */                     \
  /* weighted centroid of the neighbours from x_f [m]. */                                        \
  X(Rot<D>, torque_lever, in_group(DemGroup::Coupling))                                          \
  X(Vec<D>, resin_offset, in_group(DemGroup::Coupling))                                          \
  X(double, void_fraction, kLocal)                                                               \
  X(Vec<D>, resin_velocity, kLocal)                                                              \
  /* The resin's temperature at x_f [K], the same Shepard filter (resin.thermal; */              \
  /* the fibers' own heat capacity is neglected, docs/physics.md "Temperature"). */              \
  X(double, resin_temperature, output_as("resin_temperature", "K"))

template <int D>
struct DemParticles {
  std::size_t n_owned = 0;

  SPHDEM_FIELD_REGISTRY(SPHDEM_DEM_FIELDS)

  std::size_t size() const { return x.size(); }
  std::size_t n_ghost() const { return size() - n_owned; }

  void clear_ghosts() { resize(n_owned); }
  // Room for n particles in every field: a generator that knows its count
  // appends without moving the fields again and again (push_owned).
  void reserve(std::size_t n) {
    for_each_field([n](const char*, auto& field, FieldPolicy) { field.reserve(n); });
  }
  void permute_owned(const std::vector<std::size_t>& order) { permute_owned_fields(*this, order); }

  // Appends one owned particle at rest (only valid while there are no
  // ghosts). Mass and inertia of a disk of depth `thickness` (2D) or a
  // sphere (3D) of the given density.
  std::size_t push_owned(std::int64_t id, std::int32_t fiber_id, const Vec<D>& pos, double r,
                         double density, double thickness = 1.0);
};

}  // namespace sphdem
