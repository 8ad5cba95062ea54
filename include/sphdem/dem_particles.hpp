#pragma once
// Structure-of-arrays storage for DEM particles (disks in 2D, spheres in
// 3D), with the field registry of STYLE habit 1 (same FieldPolicy as the
// SPH particles, particles.hpp). Owned particles first, [0, n_owned),
// ghosts after (docs/parallel.md, "DEM particles").
//
// Owner rule (STYLE habit 4, docs/dem.md): the state of a bond and the
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

#include "sphdem/particles.hpp"

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
template <int D>
using ContactSlots = std::array<DemContact<D>, kMaxContacts<D>>;
template <int D>
using WallContactSlots = std::array<DemContact<D>, kMaxWallContacts<D>>;

// Flags of DemParticles::fixed.
enum DemFixed : std::uint8_t { kFree = 0, kFixedMotion = 1 };

template <int D>
struct DemParticles {
  std::size_t n_owned = 0;

  // Identity and constants.
  std::vector<std::int64_t> gid;    // global id
  std::vector<std::int32_t> fiber;  // fiber id, -1 = loose particle
  std::vector<std::uint8_t> fixed;  // kFixedMotion: v and omega prescribed (clamps, pullers)
  std::vector<double> radius;       // [m]
  std::vector<double> mass;         // [kg] (2D: per unit depth, kg/m)
  std::vector<double> inertia;      // moment of inertia [kg m^2] (2D: per unit depth)
  // State.
  std::vector<Vec<D>> x;      // position [m]
  std::vector<Vec<D>> v;      // velocity [m/s]
  std::vector<Rot<D>> omega;  // angular velocity [rad/s]
  // Forces of the last evaluation (velocity Verlet's first kick reads them).
  std::vector<Vec<D>> force;   // [N]
  std::vector<Rot<D>> torque;  // [N m]
  // External force held over the DEM sub-steps.
  std::vector<Vec<D>> f_ext;  // [N]
  // The resin's drag (docs/physics.md "Coupling"): F = drag_coeff
  // (drag_velocity - v), coefficient K V_f and Shepard resin velocity held
  // from the last coupling pass; the impulse it gave since then goes back
  // to the resin at the next pass.
  std::vector<double> drag_coeff;     // [kg/s]
  std::vector<Vec<D>> drag_velocity;  // [m/s]
  std::vector<Vec<D>> drag_force;     // of the last force evaluation [N]
  std::vector<Vec<D>> drag_impulse;   // since the last coupling pass [N s]
  // Owned interaction state (owner rule above).
  std::vector<BondSlots<D>> bonds;
  std::vector<ContactSlots<D>> contacts;
  std::vector<WallContactSlots<D>> wall_contacts;

  std::size_t size() const { return x.size(); }
  std::size_t n_ghost() const { return size() - n_owned; }

  // The registry: f(name, vector, policy) for every per-particle field.
  // Bond and contact slots go to ghosts so that a rank holding the partner
  // as owned can evaluate the same pair from the same state (gather), and
  // travel and checkpoint with their owner.
  template <class F>
  void for_each_field(F&& f) {
    f("gid", gid, FieldPolicy{true, true, true});
    f("fiber", fiber, FieldPolicy{true, true, true});
    f("fixed", fixed, FieldPolicy{true, true, true});
    f("radius", radius, FieldPolicy{true, true, true});
    f("mass", mass, FieldPolicy{true, true, true});
    f("inertia", inertia, FieldPolicy{true, true, true});
    f("x", x, FieldPolicy{true, true, true});
    f("v", v, FieldPolicy{true, true, true});
    f("omega", omega, FieldPolicy{true, true, true});
    f("force", force, FieldPolicy{false, true, true});
    f("torque", torque, FieldPolicy{false, true, true});
    f("f_ext", f_ext, FieldPolicy{false, true, true});
    f("drag_coeff", drag_coeff, FieldPolicy{false, true, true});
    f("drag_velocity", drag_velocity, FieldPolicy{false, true, true});
    f("drag_force", drag_force, FieldPolicy{false, true, true});
    f("drag_impulse", drag_impulse, FieldPolicy{false, true, true});
    f("bonds", bonds, FieldPolicy{true, true, true});
    f("contacts", contacts, FieldPolicy{true, true, true});
    f("wall_contacts", wall_contacts, FieldPolicy{false, true, true});
  }

  void resize(std::size_t n) {
    for_each_field([n](const char*, auto& field, FieldPolicy) { field.resize(n); });
  }
  void clear_ghosts() { resize(n_owned); }
  void permute_owned(const std::vector<std::size_t>& order) { permute_owned_fields(*this, order); }

  // Appends one owned particle at rest (only valid while there are no
  // ghosts). Mass and inertia of a disk of depth `thickness` (2D) or a
  // sphere (3D) of the given density.
  std::size_t push_owned(std::int64_t id, std::int32_t fiber_id, const Vec<D>& pos, double r,
                         double density, double thickness = 1.0);
};

}  // namespace sphdem
