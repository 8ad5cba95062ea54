// The `fibers:` case-file section and the DEM-only run's set-up
// (docs/case-file.md, docs/dem.md): reading, errors with file:line:key,
// walls from the mold, and the generator's failure as an InputError.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/dem_run.hpp"

namespace sphdem {
namespace {

constexpr const char* kFile = "fibers.yaml";

// A bath with fibers and a piston, no resin; comments give line numbers.
constexpr std::string_view kCase = R"(dimension: 2                 # 1
resin: {density: 900, viscosity: 0.1, sound_speed: 50}   # 2
numerics: {spacing: 3.0e-4, end_time: 1.0e-3}            # 3
mold:                        # 4
  shapes:                    # 5
    - box: {min: [-0.015, 0.03], max: [0.015, 0.06]}     # 6
fibers:                      # 7
  count: 175                 # 8
  diameter: 2.5e-4           # 9
  density: 2540              # 10
  youngs_modulus: 7.2e10     # 11
  region: {box: {min: [-0.015, 0.03], max: [0.015, 0.06]}}   # 12
moving_walls:                # 13
  - name: piston             # 14
    region: {box: {min: [-0.015, 0.06], max: [0.015, 0.0615]}}   # 15
    velocity_table: [[0, 0, -1]]                                  # 16
)";

std::string edit(std::string_view from, std::string_view to) {
  std::string s(kCase);
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

void expect_error(const std::string& text, int line, const std::string& key,
                  const std::string& message) {
  try {
    const Case c = load_case_from_string(text, kFile);
    const Comm comm;
    RunOptions opt;
    opt.write_output = false;
    DemRun<2> run(c, comm, opt);
    ADD_FAILURE() << "no error; expected " << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kFile) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(CaseFibers, DefaultsAndWalls) {
  const Case c = load_case_from_string(std::string(kCase), kFile);
  ASSERT_TRUE(c.fibers.has_value());
  EXPECT_TRUE(c.fill.empty());
  EXPECT_EQ(c.fibers->count, 175);
  EXPECT_EQ(c.fibers->particles_per_fiber, 4);
  EXPECT_DOUBLE_EQ(c.fibers->stiffness_ratio, 0.25);
  EXPECT_DOUBLE_EQ(c.fibers->contact_stiffness_fraction, 0.01);
  EXPECT_FALSE(c.fibers->angle.has_value());  // random
  EXPECT_FALSE(c.fibers->tensile_strength.has_value());
  std::vector<int> owner;
  const auto walls = dem_walls_from_case<2>(c, owner);
  ASSERT_EQ(walls.size(), 5u);  // the bath's 4 edges, the piston's face
  EXPECT_EQ(owner.back(), 0);
  EXPECT_DOUBLE_EQ(walls.back().point[1], 0.06);
  EXPECT_DOUBLE_EQ(walls.back().end[1], 0.06);
}

TEST(CaseFibers, RunSetUp) {
  const Case c =
      load_case_from_string(edit("  count: 175", "  count: 175\n  orientation: 90"), kFile);
  const Comm comm;
  RunOptions opt;
  opt.write_output = false;
  DemRun<2> run(c, comm, opt);
  EXPECT_EQ(run.dem().global_count(), 700);
  EXPECT_NEAR(run.placement().fraction, 0.0382, 1e-4);
  EXPECT_GT(run.dt(), 1e-9);
  EXPECT_LT(run.dt(), 2e-9);
  // Vertical fibers: a bond joins particles of the same x.
  const DemParticles<2>& ps = run.dem().particles();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    for (const DemBond<2>& b : ps.bonds[i]) {
      if (b.partner < 0) continue;
      for (std::size_t j = 0; j < ps.size(); ++j)
        if (ps.gid[j] == b.partner) {
          EXPECT_NEAR(ps.x[i][0], ps.x[j][0], 1e-12);
        }
    }
  }
  run.advance(10);
  EXPECT_EQ(run.step(), 10);
}

TEST(CaseFibers, Errors) {
  expect_error(edit("  count: 175", "  count: 175\n  colour: red"), 9, "fibers.colour",
               "unknown key");
  expect_error(edit("  count: 175", "  count: 0"), 8, "fibers.count", "must be at least 1");
  expect_error(edit("  count: 175", "  area_fraction: 1.5"), 8, "fibers.area_fraction",
               "must be in (0, 1)");
  expect_error(edit("  count: 175", "  count: 1\n  area_fraction: 0.1"), 9, "fibers.area_fraction",
               "not both");
  expect_error(edit("  diameter: 2.5e-4", "  diameter: -1"), 9, "fibers.diameter",
               "must be in [1e-09, 1]");
  expect_error(edit("  count: 175", "  count: 175\n  orientation: sideways"), 9,
               "fibers.orientation", "expected a number");
  expect_error(edit("max: [0.015, 0.06]}}   # 12", "max: [0.015, 0.07]}}"), 12, "fibers.region",
               "outside the mold");
  expect_error(edit("dimension: 2                 # 1",
                    "dimension: 2\nperiodic: [x]\n"
                    "domain: {min: [-0.015, 0.03], max: [0.015, 0.0615]}"),
               9, "fibers", "periodic axes need `fill`");
  expect_error(edit("  count: 175", "  count: 175\n  void_fraction_min: 1.5"), 9,
               "fibers.void_fraction_min", "");
  // The generator's failure, at the key that asked for too much.
  expect_error(edit("  count: 175", "  area_fraction: 0.6"), 8, "fibers.area_fraction",
               "could not place");
  expect_error(edit("  count: 175", "  count: 20000"), 8, "fibers.count", "could not place");
  // A fiber longer than the region (50 mm in the 30 mm bath): refused at once.
  expect_error(edit("  count: 175", "  count: 1\n  particles_per_fiber: 200"), 8, "fibers.count",
               "cannot lie in the region");
  // A seeded bend (docs/dem.md "Seeded bend"): a sagitta in [0, 0.25) of the
  // length, and a chain that can bend.
  expect_error(edit("  count: 175", "  count: 175\n  initial_bend: -0.01"), 9,
               "fibers.initial_bend", "must be in [0, 0.25)");
  expect_error(edit("  count: 175", "  count: 175\n  initial_bend: 0.25"), 9, "fibers.initial_bend",
               "must be in [0, 0.25)");
  expect_error(edit("  count: 175", "  count: 175\n  particles_per_fiber: 2\n  initial_bend: 0.01"),
               10, "fibers.initial_bend", "at least 3 particles");
}

TEST(CaseFibers, NeitherFillNorFibers) {
  std::string s(kCase);
  s = s.substr(0, s.find("fibers:")) + s.substr(s.find("moving_walls:"));
  try {
    load_case_from_string(s, kFile);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kFile);
    EXPECT_EQ(e.key(), "fill");
    EXPECT_NE(std::string(e.what()).find("or fibers:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sphdem
