// The field registry (include/sphdem/particles/field_registry.hpp, docs/architecture.md
// "Adding a field"): a field's one registry line decides whether it goes to
// the ghosts at the halo build, in which per-step exchange group it is
// refreshed (and whether it gains the periodic shift), whether it migrates,
// is checkpointed and can be written to snapshots. A test-only registry
// with one field per combination goes through the generic machinery that
// the SPH and DEM particles use (build_ghosts, forward, migrate,
// checkpoint_columns, snapshot fields) at any rank count; the real
// registries' group sizes, output names and checkpoint columns are pinned.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "../src/parallel/ghost_targets.hpp"
#include "../src/parallel/migrate.hpp"
#include "../src/solver/snapshot_fields.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/parallel/partition_report.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {
namespace {

enum class TestGroup : std::uint8_t { A = 0, B = 1 };

// One field per behaviour; x is the position (the halo and migration read it).
#define TEST_FIELDS(X)                                                              \
  X(std::int64_t, gid, kGhost | kMigrate | kCheckpoint)                             \
  X(Vec<2>, x, kGhost | in_group(TestGroup::A) | kShifted | kMigrate | kCheckpoint) \
  X(double, built, kGhost)                /* at the build only */                   \
  X(double, in_a, in_group(TestGroup::A)) /* group A only */                        \
  X(Vec<2>, in_b, in_group(TestGroup::B)) /* a vector, not a position */            \
  X(double, moves, kMigrate)                                                        \
  X(std::int32_t, saved, kCheckpoint | output_as("saved", "1"))                     \
  X(double, local, kLocal)

struct TestParticles {
  std::size_t n_owned = 0;
  SPHDEM_FIELD_REGISTRY(TEST_FIELDS)
  std::size_t size() const { return x.size(); }
  void clear_ghosts() { resize(n_owned); }
  void permute_owned(const std::vector<std::size_t>& order) { permute_owned_fields(*this, order); }
};

// 40 particles on two rows of a periodic unit square: x = (k + 0.5) / 20.
Vec<2> home(std::int64_t gid) {
  return Vec<2>((static_cast<double>(gid % 20) + 0.5) / 20, gid < 20 ? 0.3 : 0.7);
}

// Distinct values per particle and field.
double value(std::int64_t gid, double field) {
  return 1000.0 * field + static_cast<double>(gid);
}

TestParticles all_particles() {
  TestParticles ps;
  ps.resize(40);
  ps.n_owned = 40;
  for (std::int64_t g = 0; g < 40; ++g) {
    const auto i = static_cast<std::size_t>(g);
    ps.gid[i] = g;
    ps.x[i] = home(g);
    ps.built[i] = value(g, 1);
    ps.in_a[i] = value(g, 2);
    ps.in_b[i] = Vec<2>(value(g, 3), -value(g, 3));
    ps.moves[i] = value(g, 4);
    ps.saved[i] = static_cast<std::int32_t>(g + 7);
    ps.local[i] = value(g, 5);
  }
  return ps;
}

// Periodic along x, split between the ranks (uniform work in every cell).
Decomposition<2> decomposition(const Comm& comm) {
  const Box<2> box{Vec<2>(0, 0), Vec<2>(1, 1)};
  Decomposition<2> dec(comm, box, {true, false, false}, 0.1);
  dec.partition(std::vector<std::int64_t>(static_cast<std::size_t>(dec.blocks()), 1), true);
  return dec;
}

TEST(FieldRegistry, PoliciesSelectTheFields) {
  TestParticles ps = all_particles();
  const auto bytes = [&](auto want) { return record_bytes(ps, want); };
  EXPECT_EQ(bytes([](FieldPolicy p) { return p.ghost; }), 8u + 16u + 8u);
  EXPECT_EQ(bytes([](FieldPolicy p) { return p.migrate; }), 8u + 16u + 8u);
  EXPECT_EQ(bytes([](FieldPolicy p) { return p.in(group_bit(TestGroup::A)); }), 16u + 8u);
  EXPECT_EQ(bytes([](FieldPolicy p) { return p.in(group_bit(TestGroup::B)); }), 16u);

  std::vector<std::string> columns;
  for (const CheckpointColumn& c : checkpoint_columns(ps)) columns.push_back(c.name);
  EXPECT_EQ(columns, (std::vector<std::string>{"gid", "x", "saved"}));

  const std::vector<OutputField> out =
      registry_output_fields(ps, {3, 5}, [](const char*) { return true; });
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].name, "saved");
  EXPECT_EQ(out[0].units, "1");
  EXPECT_EQ(out[0].data, (std::vector<double>{10, 12}));
}

// Migration carries exactly the kMigrate fields; the build copies the
// kGhost fields with shifted positions; forward(A) refreshes the fields of
// group A only, shifting the position; forward(B) those of group B, with
// no shift.
TEST(FieldRegistry, GhostsAndMigrationFollowThePolicies) {
  const Comm world(MPI_COMM_WORLD);
  const Decomposition<2> dec = decomposition(world);
  TestParticles ps = all_particles();
  dec.keep_owned(ps);

  // Every particle moves by half the period and to the other row: at two
  // ranks, however they split the square, some change rank.
  const auto moved_x = [](std::int64_t g) {
    Vec<2> x = home(g);
    x[0] += 0.5;
    if (x[0] >= 1) x[0] -= 1;
    x[1] = 1 - x[1];
    return x;
  };
  for (std::size_t i = 0; i < ps.n_owned; ++i) ps.x[i] = moved_x(ps.gid[i]);
  const MigrationCounts moved = migrate<2>(dec, ps);
  if (world.size() > 1) {
    EXPECT_GT(world.sum(static_cast<std::int64_t>(moved.received)), 0);
  }
  EXPECT_EQ(world.sum(static_cast<std::int64_t>(ps.n_owned)), 40);
  const std::size_t kept = ps.n_owned - moved.received;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    const std::int64_t g = ps.gid[i];
    EXPECT_EQ(dec.owner(ps.x[i]), world.rank());
    EXPECT_EQ(ps.moves[i], value(g, 4));
    // Not migrating: a kept particle keeps its value, an arrival does not
    // bring it (its slot holds whatever was there).
    if (i < kept) {
      EXPECT_EQ(ps.built[i], value(g, 1));
      EXPECT_EQ(ps.local[i], value(g, 5));
      EXPECT_EQ(ps.saved[i], g + 7);
    } else {
      EXPECT_NE(ps.built[i], value(g, 1));
      EXPECT_NE(ps.local[i], value(g, 5));
      EXPECT_NE(ps.saved[i], g + 7);
    }
  }

  // The build: kGhost fields, positions shifted; the rest stays zero.
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    ps.built[i] = value(ps.gid[i], 1);
    ps.in_a[i] = value(ps.gid[i], 2);
    ps.in_b[i] = Vec<2>(value(ps.gid[i], 3), -value(ps.gid[i], 3));
  }
  GhostPlan<2> plan;
  std::vector<char> send_buf, recv_buf;
  detail::build_ghosts<2>(dec, ps, 0.1, plan, send_buf, recv_buf);
  ASSERT_GT(ps.size(), ps.n_owned);
  const auto owner_x = moved_x;
  // The owner's position plus 0 or +-1 along x, bit for bit.
  const auto shifted_ok = [&](std::size_t i) {
    const Vec<2> o = owner_x(ps.gid[i]);
    const Vec<2> d = ps.x[i] - o;
    return d[1] == 0 &&
           (d[0] == 0 || ps.x[i] == Vec<2>(o[0] + 1, o[1]) || ps.x[i] == Vec<2>(o[0] - 1, o[1]));
  };
  std::int64_t crossed = 0;
  for (std::size_t i = ps.n_owned; i < ps.size(); ++i) {
    const std::int64_t g = ps.gid[i];
    EXPECT_TRUE(shifted_ok(i)) << "ghost of " << g;
    if (ps.x[i] != owner_x(g)) ++crossed;
    EXPECT_EQ(ps.built[i], value(g, 1));
    EXPECT_EQ(ps.in_a[i], 0.0);
    EXPECT_EQ(ps.moves[i], 0.0);
    EXPECT_EQ(ps.saved[i], 0);
    EXPECT_EQ(ps.local[i], 0.0);
  }
  EXPECT_GT(world.sum(crossed), 0) << "no copy crossed the periodic face";

  // New owner values everywhere; forward(A) brings x and in_a only.
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    ps.built[i] = -1;
    ps.in_a[i] = value(ps.gid[i], 6);
    ps.moves[i] = -2;
  }
  detail::forward_groups<2>(world.raw(), plan, ps, group_bit(TestGroup::A), send_buf, recv_buf);
  for (std::size_t i = ps.n_owned; i < ps.size(); ++i) {
    const std::int64_t g = ps.gid[i];
    EXPECT_TRUE(shifted_ok(i)) << "ghost of " << g;
    EXPECT_EQ(ps.in_a[i], value(g, 6));
    EXPECT_EQ(ps.built[i], value(g, 1)) << "not in group A";
    EXPECT_EQ(ps.moves[i], 0.0);
  }

  // forward(B): the vector arrives unshifted, across the face too.
  detail::forward_groups<2>(world.raw(), plan, ps, group_bit(TestGroup::B), send_buf, recv_buf);
  for (std::size_t i = ps.n_owned; i < ps.size(); ++i) {
    const std::int64_t g = ps.gid[i];
    EXPECT_EQ(ps.in_b[i], Vec<2>(value(g, 3), -value(g, 3)));
    EXPECT_EQ(ps.in_a[i], value(g, 6));
  }
}

// The real registries: what a per-step exchange costs, what output.fields
// may name, what a checkpoint holds (old checkpoints stay readable).
// migrate_in_place (the DEM's rebuild) ends with the same particles as
// migrate, each with the same kMigrate fields, and a particle that stays
// keeps every field (moved into a hole or not); with every particle
// moving across the ranks and with all of them crowding to one side (more
// departures than arrivals on one rank, fewer on another).
TEST(FieldRegistry, MigrationInPlaceMatchesMigration) {
  const Comm world(MPI_COMM_WORLD);
  const Decomposition<2> dec = decomposition(world);
  const std::vector<std::function<Vec<2>(std::int64_t)>> moves{
      [](std::int64_t g) {
        Vec<2> x = home(g);
        x[0] = x[0] + 0.5 >= 1 ? x[0] - 0.5 : x[0] + 0.5;
        return x;
      },
      [](std::int64_t g) { return Vec<2>(0.5 * home(g)[0], home(g)[1]); },
      [](std::int64_t g) { return Vec<2>(0.5 + 0.5 * home(g)[0], 1 - home(g)[1]); }};
  for (const auto& moved_x : moves) {
    TestParticles a = all_particles();
    dec.keep_owned(a);
    for (std::size_t i = 0; i < a.n_owned; ++i) {
      a.x[i] = moved_x(a.gid[i]);
      a.local[i] = value(a.gid[i], 6);  // kLocal: only a particle that stays keeps it
    }
    std::vector<std::int64_t> before(a.gid.begin(), a.gid.end());
    std::sort(before.begin(), before.end());
    TestParticles b = a;
    const MigrationCounts ma = migrate<2>(dec, a);
    const MigrationCounts mb = migrate_in_place<2>(dec, b);
    EXPECT_EQ(ma.sent, mb.sent);
    EXPECT_EQ(ma.received, mb.received);
    ASSERT_EQ(a.n_owned, b.n_owned);
    ASSERT_EQ(b.size(), b.n_owned);
    std::vector<std::size_t> by_gid(40, a.n_owned);
    for (std::size_t i = 0; i < a.n_owned; ++i) by_gid[static_cast<std::size_t>(a.gid[i])] = i;
    for (std::size_t i = 0; i < b.n_owned; ++i) {
      const std::int64_t g = b.gid[i];
      const std::size_t j = by_gid[static_cast<std::size_t>(g)];
      ASSERT_LT(j, a.n_owned) << "gid " << g;
      EXPECT_EQ(dec.owner(b.x[i]), world.rank());
      EXPECT_EQ(b.x[i], a.x[j]);
      EXPECT_EQ(b.moves[i], value(g, 4));
      if (std::binary_search(before.begin(), before.end(), g)) {
        EXPECT_EQ(b.built[i], value(g, 1));
        EXPECT_EQ(b.local[i], value(g, 6));
        EXPECT_EQ(b.saved[i], g + 7);
      }
    }
    EXPECT_EQ(world.sum(static_cast<std::int64_t>(b.n_owned)), 40);
  }
}

TEST(FieldRegistry, SphAndDemRegistries) {
  EXPECT_EQ(forward_bytes(2, SphGroup::State), 8u * 6);  // x, v, rho, temperature
  EXPECT_EQ(forward_bytes(3, SphGroup::State), 8u * 8);
  EXPECT_EQ(forward_bytes(2, SphGroup::WallState), 8u * 5);  // rho, temperature, p, vwall
  EXPECT_EQ(forward_bytes(3, SphGroup::WallState), 8u * 6);
  EXPECT_EQ(forward_bytes(2, SphGroup::ShearRate), 8u);  // shear_rate, after its pass
  EXPECT_EQ(forward_bytes(3, SphGroup::ShearRate), 8u);
  const auto dem_bytes = [](auto ps, DemGroup g) {
    return record_bytes(ps, [g](FieldPolicy p) { return p.in(group_bit(g)); });
  };
  EXPECT_EQ(dem_bytes(DemParticles<2>(), DemGroup::State), 8u * 5);  // x, v, omega
  EXPECT_EQ(dem_bytes(DemParticles<3>(), DemGroup::State), 8u * 9);
  // shepard_sum, drag_coeff (the resin drag rate), mean_drag, and the
  // hydrodynamic torque's lever and resin offset
  EXPECT_EQ(dem_bytes(DemParticles<2>(), DemGroup::Coupling), 8u * 7);
  EXPECT_EQ(dem_bytes(DemParticles<3>(), DemGroup::Coupling), 8u * 11);
  EXPECT_EQ(sph_output_fields(),
            (std::vector<std::string>{"kind", "wall_id", "velocity", "density", "temperature",
                                      "frozen", "weld_line", "pressure", "acceleration",
                                      "shear_rate", "viscosity", "free_surface", "surface_normal",
                                      "position_divergence", "colour", "csf_normal", "curvature"}));
  std::vector<std::string> sph, dem;
  for (const CheckpointColumn& c : checkpoint_columns(SphParticles<2>{})) sph.push_back(c.name);
  for (const CheckpointColumn& c : checkpoint_columns(DemParticles<2>{})) dem.push_back(c.name);
  EXPECT_EQ(sph, (std::vector<std::string>{"gid", "kind", "wall", "mass", "wall_to_surface", "x",
                                           "v", "rho", "weld_line", "a", "drho", "viscosity"}));
  EXPECT_EQ(dem, (std::vector<std::string>{"gid",
                                           "fiber",
                                           "fixed",
                                           "radius",
                                           "mass",
                                           "inertia",
                                           "x",
                                           "v",
                                           "omega",
                                           "force",
                                           "torque",
                                           "f_ext",
                                           "drag_coeff",
                                           "drag_velocity",
                                           "drag_force",
                                           "drag_impulse",
                                           "drag_parcel_mass",
                                           "torque_coeff",
                                           "resin_spin",
                                           "hydro_torque",
                                           "torque_impulse",
                                           "bonds",
                                           "bond_peaks",
                                           "contacts",
                                           "wall_contacts"}));
}

}  // namespace
}  // namespace sphdem
