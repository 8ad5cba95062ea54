// Fields only when used (issue 19's memory target, docs/performance.md
// "Memory per particle"): a dropped registry field holds no memory and
// every registry function skips it; checkpoints keep its column (zeros), so
// their format does not depend on the options; a run holds exactly the
// fields its options read or write (drop_unused_fields).
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphdem/io/checkpoint.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/sph.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

// The optional fields (src/sph/fluid_rates.cpp, drop_unused_fields).
const std::vector<std::string> kOptional = {"wall_to_surface",
                                            "temperature",
                                            "dtemp",
                                            "temp_half",
                                            "frozen",
                                            "weld_line",
                                            "shear_rate",
                                            "viscosity",
                                            "free_surface",
                                            "surface_normal",
                                            "position_divergence",
                                            "shifting_gradient",
                                            "colour",
                                            "csf_normal",
                                            "curvature",
                                            "visc_u",
                                            "visc_free",
                                            "visc_acc"};

template <int D>
std::vector<std::string> held(const SphParticles<D>& ps) {
  std::vector<std::string> names;
  ps.for_each_field([&](const char* name, const auto&, FieldPolicy) { names.emplace_back(name); });
  return names;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

SphParticles<2> three(SphParticles<2> ps) {
  for (int i = 0; i < 3; ++i) {
    const double d = i;
    ps.push_owned(i, i == 2 ? Kind::Wall : Kind::Fluid, -1, 1.0 + d, Vec<2>(d, 2 * d),
                  Vec<2>(-d, 0.5), 1000 + d);
  }
  return ps;
}

TEST(DropField, RegistryFunctionsSkipADroppedField) {
  SphParticles<2> ps;
  ps.drop_field("temperature");
  ps.drop_field("visc_u");
  EXPECT_FALSE(ps.has_field("temperature"));
  EXPECT_FALSE(ps.has_field("visc_u"));
  EXPECT_TRUE(ps.has_field("x"));
  EXPECT_THROW(ps.drop_field("no_such_field"), std::logic_error);
  EXPECT_THROW((void)ps.has_field("no_such_field"), std::logic_error);
  ps = three(std::move(ps));
  ps.resize(5);  // two ghosts
  ps.copy_particle(4, 1);
  ps.zero_particle(3);
  ps.permute_owned({2, 0, 1});
  EXPECT_TRUE(ps.temperature.empty());
  EXPECT_TRUE(ps.visc_u.empty());
  EXPECT_EQ(ps.temperature.capacity(), 0u);
  EXPECT_EQ(ps.rho.size(), 5u);
  EXPECT_EQ(ps.x[4], Vec<2>(1, 2));
  EXPECT_EQ(ps.gid[0], 2);
  const std::vector<std::string> names = held(ps);
  EXPECT_FALSE(contains(names, "temperature"));
  EXPECT_FALSE(contains(names, "visc_u"));
  EXPECT_TRUE(contains(names, "rho"));
  // Messages (migration, halo) and the set-up's reserve count only held fields.
  const auto all = [](FieldPolicy) { return true; };
  EXPECT_EQ(record_bytes(ps, all) + sizeof(double) + sizeof(Vec<2>),
            record_bytes(SphParticles<2>(), all));
  std::size_t declared = 0;
  ps.for_each_declared_field([&](const char*, const auto&, FieldPolicy) { ++declared; });
  EXPECT_EQ(declared, held(SphParticles<2>()).size());
}

TEST(DropField, CheckpointsKeepTheColumnsOfDroppedFields) {
  SphParticles<2> lean_empty;
  lean_empty.drop_field("viscosity");
  lean_empty.drop_field("wall_to_surface");
  const SphParticles<2> lean = three(lean_empty);
  SphParticles<2> full = three(SphParticles<2>());
  full.viscosity[1] = 7.0;
  const std::vector<CheckpointColumn> lean_cols = checkpoint_columns(lean);
  const std::vector<CheckpointColumn> full_cols = checkpoint_columns(full);
  ASSERT_EQ(lean_cols.size(), full_cols.size());
  for (std::size_t k = 0; k < lean_cols.size(); ++k) {
    EXPECT_EQ(lean_cols[k].name, full_cols[k].name);
    EXPECT_EQ(lean_cols[k].data.size(), full_cols[k].data.size()) << lean_cols[k].name;
    if (lean_cols[k].name == "viscosity") {
      EXPECT_TRUE(std::all_of(lean_cols[k].data.begin(), lean_cols[k].data.end(),
                              [](char b) { return b == 0; }));
    }
  }
  // A lean container reads past the column; a full one reads the zeros.
  SphParticles<2> a = lean_empty;
  assign_checkpoint_columns(a, full_cols, 3, "full.h5");
  EXPECT_TRUE(a.viscosity.empty());
  EXPECT_EQ(a.x, full.x);
  EXPECT_EQ(a.rho, full.rho);
  SphParticles<2> b;
  assign_checkpoint_columns(b, lean_cols, 3, "lean.h5");
  EXPECT_EQ(b.viscosity, std::vector<double>(3, 0.0));
  EXPECT_EQ(b.x, lean.x);
}

template <int D>
std::vector<std::string> used_by(const Case& c) {
  SphParticles<D> ps;
  drop_unused_fields<D>(make_sph_params(c), any_slip_wall(c), ps);
  std::vector<std::string> optional;
  for (const std::string& f : kOptional)
    if (ps.has_field(f)) optional.push_back(f);
  return optional;
}

using Names = std::vector<std::string>;

TEST(FieldUse, EachOptionBringsItsFields) {
  using testing::load_input;
  // Newtonian, isothermal, no-slip, no anti-clump: none.
  EXPECT_EQ(used_by<2>(load_input("validation/poiseuille.yaml")), Names{});
  // The anti-clump term reads the free-surface flag (its pass runs).
  EXPECT_EQ(used_by<2>(load_input("validation/poiseuille.yaml", {"numerics.anti_clump=true"})),
            Names{"free_surface"});
  EXPECT_EQ(used_by<2>(load_input("validation/poiseuille_navier_slip.yaml")),
            Names{"wall_to_surface"});
  EXPECT_EQ(used_by<2>(load_input("validation/poiseuille_power_law.yaml")),
            (Names{"shear_rate", "viscosity"}));
  EXPECT_EQ(used_by<2>(load_input("validation/couette_implicit.yaml")),
            (Names{"visc_u", "visc_free", "visc_acc"}));
  const Names thermal = used_by<2>(load_input("validation/couette_heating.yaml"));
  for (const char* f : {"wall_to_surface", "temperature", "dtemp", "temp_half", "frozen"})
    EXPECT_TRUE(contains(thermal, f)) << f;
  const Names droplet = used_by<2>(load_input("validation/droplet_2d.yaml"));
  for (const char* f : {"wall_to_surface", "colour", "csf_normal", "curvature"})
    EXPECT_TRUE(contains(droplet, f)) << f;
  const Names weld = used_by<2>(load_input("validation/weld_line.yaml"));
  for (const char* f : {"weld_line", "free_surface", "surface_normal"})
    EXPECT_TRUE(contains(weld, f)) << f;
  // Naming a field in output.fields holds it (and runs its pass).
  EXPECT_EQ(used_by<2>(load_input("validation/poiseuille.yaml",
                                  {"output.fields=[velocity, position_divergence, temperature]"})),
            (Names{"temperature", "free_surface", "position_divergence"}));
}

// A run holds only its fields from the set-up on, and steps with them dropped.
TEST(FieldUse, ARunHoldsOnlyItsFields) {
  const Case c = testing::load_input("validation/poiseuille.yaml");
  const Comm comm(MPI_COMM_SELF);
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  sim.advance(20);
  const SphParticles<2>& ps = sim.particles();
  for (const std::string& f : kOptional) EXPECT_FALSE(ps.has_field(f)) << f;
  EXPECT_EQ(ps.temperature.capacity(), 0u);
  EXPECT_EQ(ps.visc_u.capacity(), 0u);
  EXPECT_GT(ps.n_owned, 0u);
  for (std::size_t i = 0; i < ps.n_owned; ++i) ASSERT_TRUE(ps.x[i].allFinite());
}

}  // namespace
}  // namespace sphdem
