// Case-file loader: valid cases, defaults, --set overrides, and one test per
// way a case file can be wrong (each error must name file, line and key).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"

namespace sphdem {
namespace {

constexpr const char* kFile = "case.yaml";

// The smallest valid case; the comments give the line numbers the error
// tests below expect.
constexpr std::string_view kMinimal = R"(dimension: 2                 # 1
resin:                       # 2
  density: 900               # 3
  viscosity: 0.1             # 4
  sound_speed: 60            # 5
numerics:                    # 6
  spacing: 3.0e-4            # 7
  end_time: 0.12             # 8
mold:                        # 9
  shapes:                    # 10
    - box: {min: [0, 0], max: [0.03, 0.03]}    # 11
fill:                        # 12
  - box: {min: [0, 0], max: [0.03, 0.02]}      # 13
)";

// The paper's plate case with every key spelled out.
constexpr std::string_view kFull = R"(
name: plate
dimension: 2
resin:
  density: 900
  viscosity: 0.1
  sound_speed: 60
  gamma: 7
numerics:
  spacing: 3.0e-4
  h_over_spacing: 1.2
  cfl: 0.3
  force_factor: 0.2
  viscous_factor: 0.1
  fixed_dt: 2.0e-7
  end_time: 0.12
  viscosity_model: none
  artificial_viscosity: 0.02
  delta_sph: 0.1
  anti_clump: false
  anti_clump_epsilon: 0.3
  anti_clump_exponent: 6
  neighbor_skin: 0.12
mold:
  wall_layers: 4
  shapes:
    - box: {min: [-0.015, 0.03], max: [0.015, 0.06]}                            # bath
    - polygon: [[-0.015, 0.03], [0.015, 0.03], [0.003, 0.005], [-0.003, 0.005]]  # nozzle
    - box: {min: [-0.003, 0.0], max: [0.003, 0.005]}                            # gate
    - box: {min: [-0.04, -0.004], max: [0.04, 0.0]}                             # plate
fill:
  - box: {min: [-0.015, 0.03], max: [0.015, 0.06]}
moving_walls:
  - name: piston
    region: {box: {min: [-0.016, 0.06], max: [0.016, 0.062]}}
    velocity_table: [[0.0, 0.0, -1.0], [0.02, 0.0, -0.5], [0.12, 0.0, -0.15]]
    pressure_limit: 2.0e5
    pressure_relax_time: 2.0e-3
sliding_walls:
  - name: lid
    region: {polygon: [[-0.04, -0.005], [0.04, -0.005], [0.04, -0.004], [-0.04, -0.004]]}
    velocity: [1.0e-3, 0]
body_force: [0, -9.81]
periodic: [x]
domain: {min: [-0.04, -0.005], max: [0.04, 0.062]}
output:
  directory: results/plate
  every_time: 1.0e-3
  every_steps: 1000
  fields: [velocity, density, pressure, wall_id]
  progress_every: 50
)";

// `text` with the one occurrence of `from` replaced by `to`.
std::string edit(std::string_view text, std::string_view from, std::string_view to) {
  std::string s(text);
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case";
  EXPECT_EQ(s.find(from, at + 1), std::string::npos) << "test bug: '" << from << "' twice";
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

std::string append(std::string_view text, std::string_view lines) {
  return std::string(text) + std::string(lines);
}

bool contains(std::string_view text, std::string_view part) {
  return text.find(part) != std::string_view::npos;
}

// Loading must fail with an InputError naming file, line and key, whose
// message contains `message`.
void expect_error(const std::string& text, int line, const std::string& key,
                  const std::string& message, const std::vector<std::string>& overrides = {},
                  const std::string& file = kFile) {
  try {
    load_case_from_string(text, kFile, overrides);
    ADD_FAILURE() << "no error; expected " << file << ":" << line << " " << key << ": " << message;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), file) << what;
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), key) << what;
    EXPECT_TRUE(contains(what, line > 0 ? file + ":" + std::to_string(line) + ":" : file + ":"))
        << what;
    if (!key.empty()) {
      EXPECT_TRUE(contains(what, "key '" + key + "'")) << what;
    }
    EXPECT_TRUE(contains(what, message)) << what << "\n  expected to contain: " << message;
  }
}

// --- valid cases -----------------------------------------------------------

TEST(Config, FullCaseLoads) {
  const Case c = load_case_from_string(std::string(kFull), kFile);
  EXPECT_EQ(c.name, "plate");
  EXPECT_EQ(c.dimension, 2);
  EXPECT_EQ(c.resin.density, 900);
  EXPECT_EQ(c.resin.viscosity, 0.1);
  EXPECT_EQ(c.resin.sound_speed, 60);
  EXPECT_EQ(c.resin.gamma, 7);
  EXPECT_EQ(c.numerics.spacing, 3.0e-4);
  EXPECT_EQ(c.numerics.cfl, 0.3);
  EXPECT_EQ(c.numerics.force_factor, 0.2);
  EXPECT_EQ(c.numerics.viscous_factor, 0.1);
  ASSERT_TRUE(c.numerics.fixed_dt.has_value());
  EXPECT_EQ(*c.numerics.fixed_dt, 2.0e-7);
  EXPECT_EQ(c.numerics.end_time, 0.12);
  EXPECT_EQ(c.numerics.viscosity_model, ViscosityModel::None);
  EXPECT_EQ(c.numerics.artificial_viscosity, 0.02);
  EXPECT_EQ(c.numerics.delta_sph, 0.1);
  EXPECT_FALSE(c.numerics.anti_clump);
  EXPECT_EQ(c.numerics.anti_clump_epsilon, 0.3);
  EXPECT_EQ(c.numerics.anti_clump_exponent, 6);
  EXPECT_EQ(c.numerics.neighbor_skin, 0.12);
  EXPECT_DOUBLE_EQ(c.h(), 3.6e-4);
  EXPECT_EQ(c.mold.wall_layers, 4);
  ASSERT_EQ(c.mold.shapes.size(), 4u);
  EXPECT_EQ(c.mold.shapes[1].type, Shape::Type::Polygon);
  ASSERT_EQ(c.mold.shapes[1].vertices.size(), 4u);
  EXPECT_EQ(c.mold.shapes[1].vertices[2][0], 0.003);
  EXPECT_EQ(c.mold.shapes[1].key, "mold.shapes[1]");
  EXPECT_EQ(c.mold.shapes[1].line, 28);
  EXPECT_EQ(c.mold.shapes[3].type, Shape::Type::Box);
  EXPECT_EQ(c.mold.shapes[3].lo, (Vec3a{-0.04, -0.004, 0}));
  EXPECT_EQ(c.mold.shapes[3].hi, (Vec3a{0.04, 0.0, 0}));
  ASSERT_EQ(c.fill.size(), 1u);
  EXPECT_EQ(c.fill[0].key, "fill[0]");
}

TEST(Config, FullCaseWallsAndOutput) {
  const Case c = load_case_from_string(std::string(kFull), kFile);
  ASSERT_EQ(c.moving_walls.size(), 1u);
  const MovingWall& piston = c.moving_walls[0];
  EXPECT_EQ(piston.name, "piston");
  EXPECT_EQ(piston.region.lo, (Vec3a{-0.016, 0.06, 0}));
  EXPECT_EQ(piston.velocity.time, (std::vector<double>{0.0, 0.02, 0.12}));
  ASSERT_EQ(piston.velocity.velocity.size(), 3u);
  EXPECT_EQ(piston.velocity.velocity[1], (Vec3a{0.0, -0.5, 0}));
  EXPECT_EQ(piston.pressure_limit, 2.0e5);
  EXPECT_EQ(piston.pressure_relax_time, 2.0e-3);
  ASSERT_EQ(c.sliding_walls.size(), 1u);
  EXPECT_EQ(c.sliding_walls[0].name, "lid");
  EXPECT_EQ(c.sliding_walls[0].region.type, Shape::Type::Polygon);
  EXPECT_EQ(c.sliding_walls[0].velocity, (Vec3a{1.0e-3, 0, 0}));
  EXPECT_EQ(c.body_force, (Vec3a{0, -9.81, 0}));
  EXPECT_EQ(c.periodic, (std::array<bool, 3>{true, false, false}));
  ASSERT_TRUE(c.domain_lo && c.domain_hi);
  EXPECT_EQ(*c.domain_hi, (Vec3a{0.04, 0.062, 0}));
  EXPECT_EQ(c.output.directory, "results/plate");
  EXPECT_EQ(c.output.every_time, 1.0e-3);
  EXPECT_EQ(c.output.every_steps, 1000);
  EXPECT_EQ(c.output.fields,
            (std::vector<std::string>{"velocity", "density", "pressure", "wall_id"}));
  EXPECT_EQ(c.output.progress_every, 50);
  // Its table (15 mm to 0.02 s, then 32.5 mm to 0.12 s) runs the piston
  // through the 30 mm bath: the one warning.
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_TRUE(contains(c.warnings[0], "moving wall 'piston' (line ")) << c.warnings[0];
  EXPECT_TRUE(contains(c.warnings[0], "0.0475 m")) << c.warnings[0];
  EXPECT_EQ(c.source_text, kFull);
  EXPECT_EQ(c.source_file, kFile);
}

TEST(Config, DefaultsApply) {
  const Case c = load_case_from_string(std::string(kMinimal), "cases/minimal.yaml");
  EXPECT_EQ(c.name, "minimal");  // the file stem
  EXPECT_EQ(c.resin.gamma, 7.0);
  EXPECT_EQ(c.numerics.h_over_spacing, 1.2);
  EXPECT_EQ(c.numerics.cfl, 0.25);
  EXPECT_EQ(c.numerics.force_factor, 0.25);
  EXPECT_EQ(c.numerics.viscous_factor, 0.125);
  EXPECT_FALSE(c.numerics.fixed_dt.has_value());
  EXPECT_EQ(c.numerics.viscosity_model, ViscosityModel::Morris);
  EXPECT_EQ(c.numerics.delta_sph, 0.0);
  EXPECT_TRUE(c.numerics.anti_clump);
  EXPECT_EQ(c.numerics.anti_clump_exponent, 4);
  EXPECT_EQ(c.numerics.neighbor_skin, 0.15);
  EXPECT_EQ(c.mold.wall_layers, 3);
  EXPECT_EQ(c.mold.shapes[0].line, 11);
  EXPECT_TRUE(c.moving_walls.empty());
  EXPECT_TRUE(c.sliding_walls.empty());
  EXPECT_EQ(c.body_force, (Vec3a{0, 0, 0}));
  EXPECT_EQ(c.periodic, (std::array<bool, 3>{false, false, false}));
  EXPECT_FALSE(c.domain_lo.has_value());
  EXPECT_EQ(c.output.directory, "out/minimal");
  ASSERT_TRUE(c.output.every_time.has_value());
  EXPECT_DOUBLE_EQ(*c.output.every_time, 0.12 / 100);
  EXPECT_FALSE(c.output.every_steps.has_value());
  EXPECT_EQ(c.output.fields, (std::vector<std::string>{"velocity", "density", "pressure"}));
  EXPECT_EQ(c.output.progress_every, 100);
}

TEST(Config, ThreeDimensionalCase) {
  const std::string text = R"(dimension: 3
resin: {density: 900, viscosity: 0.1, sound_speed: 60}
numerics: {spacing: 1.0e-3, end_time: 0.1}
mold:
  shapes:
    - box: {min: [0, 0, 0], max: [0.01, 0.01, 0.01]}
fill:
  - box: {min: [0, 0, 0], max: [0.01, 0.01, 0.005]}
body_force: [0, 0, -9.81]
periodic: [x, z]
domain: {min: [0, 0, 0], max: [0.01, 0.01, 0.01]}
)";
  const Case c = load_case_from_string(text, kFile);
  EXPECT_EQ(c.dimension, 3);
  EXPECT_EQ(c.fill[0].hi, (Vec3a{0.01, 0.01, 0.005}));
  EXPECT_EQ(c.body_force, (Vec3a{0, 0, -9.81}));
  EXPECT_EQ(c.periodic, (std::array<bool, 3>{true, false, true}));
}

TEST(Config, SoundSpeedFromMachAndReferenceVelocity) {
  const Case c = load_case_from_string(
      edit(kMinimal, "sound_speed: 60", "mach: 0.05\n  reference_velocity: 2"), kFile);
  EXPECT_DOUBLE_EQ(c.resin.sound_speed, 40.0);
}

TEST(Config, FillMaySpanSeveralMoldShapes) {
  // Two boxes side by side; the fill covers both and touches the boundary.
  const Case c = load_case_from_string(edit(kMinimal, "- box: {min: [0, 0], max: [0.03, 0.03]}",
                                            "- box: {min: [0, 0], max: [0.01, 0.03]}\n"
                                            "    - box: {min: [0.01, 0], max: [0.03, 0.03]}"),
                                       kFile);
  EXPECT_EQ(c.mold.shapes.size(), 2u);
}

TEST(Config, HighMachIsAWarningNotAnError) {
  const Case c = load_case_from_string(append(kMinimal, R"(moving_walls:
  - name: piston
    region: {box: {min: [0, 0.03], max: [0.03, 0.031]}}
    velocity_table: [[0, 0, -10]]
)"),
                                       kFile);
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_TRUE(contains(c.warnings[0], "Mach number 0.167")) << c.warnings[0];
}

// A velocity table whose stroke by end_time carries the piston's face
// through the mold and out of it is a warning naming the wall, its line and
// the stroke. By hand: 0.5 -> 0.25 m/s over 0.02 s (7.5 mm), then 0.25 m/s
// for 0.1 s (25 mm): 32.5 mm from y = 0.02, through the bottom at 0. At half
// the speed (16.25 mm) it stays in the mold: no warning.
TEST(Config, PistonStrokeBeyondTheMoldIsAWarning) {
  const char* piston = R"(moving_walls:
  - name: piston
    region: {box: {min: [0, 0.02], max: [0.03, 0.021]}}
    velocity_table: [[0, 0, -0.5], [0.02, 0, -0.25]]
)";
  const Case c = load_case_from_string(append(kMinimal, piston), kFile);
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_TRUE(contains(c.warnings[0], "moving wall 'piston' (line ")) << c.warnings[0];
  EXPECT_TRUE(contains(c.warnings[0], "0.0325 m")) << c.warnings[0];
  const Case slow =
      load_case_from_string(append(kMinimal, edit(piston, "[[0, 0, -0.5], [0.02, 0, -0.25]]",
                                                  "[[0, 0, -0.25], [0.02, 0, -0.125]]")),
                            kFile);
  EXPECT_TRUE(slow.warnings.empty()) << slow.warnings[0];
}

TEST(Config, LoadCaseReadsAFile) {
  const std::string path = ::testing::TempDir() + "sphdem_test_config_tank.yaml";
  {
    std::ofstream out(path);
    out << kMinimal;
  }
  const Case c = load_case(path, {"numerics.cfl=0.2"});
  std::remove(path.c_str());
  EXPECT_EQ(c.name, "sphdem_test_config_tank");
  EXPECT_EQ(c.source_file, path);
  EXPECT_EQ(c.source_text, kMinimal);
  EXPECT_EQ(c.numerics.cfl, 0.2);
}

// The complete example in docs/case-file.md (its last yaml block) loads.
TEST(Config, DocumentedExampleLoads) {
  std::ifstream in(std::string(SPHDEM_SOURCE_DIR) + "/docs/case-file.md");
  ASSERT_TRUE(in) << "docs/case-file.md not found";
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t start = doc.rfind("```yaml\n");
  ASSERT_NE(start, std::string::npos);
  const std::size_t end = doc.find("```", start + 8);
  ASSERT_NE(end, std::string::npos);
  const Case c = load_case_from_string(doc.substr(start + 8, end - start - 8), "plate.yaml");
  EXPECT_EQ(c.name, "plate");
  EXPECT_EQ(c.mold.shapes.size(), 4u);
  EXPECT_EQ(c.moving_walls.at(0).velocity.time.size(), 3u);
  EXPECT_TRUE(c.warnings.empty());
}

// --- --set overrides ---------------------------------------------------------

TEST(Config, OverrideNumberListAndBool) {
  const Case c = load_case_from_string(
      std::string(kMinimal), kFile,
      {"numerics.spacing=1e-3", "body_force=[0, -9.81]", "numerics.anti_clump=false",
       "periodic=[x]", "domain={min: [0, 0], max: [0.03, 0.03]}", "name=tank"});
  EXPECT_EQ(c.numerics.spacing, 1e-3);
  EXPECT_EQ(c.body_force, (Vec3a{0, -9.81, 0}));
  EXPECT_FALSE(c.numerics.anti_clump);
  EXPECT_TRUE(c.periodic[0]);
  EXPECT_EQ(c.name, "tank");
  EXPECT_EQ(c.output.directory, "out/tank");
}

TEST(Config, OverrideListIndexNewSectionAndRemoval) {
  const Case c = load_case_from_string(
      edit(kMinimal, "end_time: 0.12", "end_time: 0.12\n  fixed_dt: 1.0e-6"), kFile,
      {"mold.shapes[0].box.max=[0.04, 0.03]", "output.every_steps=10", "numerics.fixed_dt=~"});
  EXPECT_EQ(c.mold.shapes[0].hi, (Vec3a{0.04, 0.03, 0}));
  EXPECT_EQ(c.mold.shapes[0].line, 12);  // the shape itself still comes from the file
  EXPECT_EQ(c.output.every_steps, 10);
  EXPECT_FALSE(c.numerics.fixed_dt.has_value());
}

TEST(Config, OverrideIsValidated) {
  expect_error(std::string(kMinimal), 0, "resin.density", "must be positive, got -1",
               {"resin.density=-1"}, "--set");
}

TEST(Config, OverrideWithBadValueIsReportedAsSet) {
  expect_error(std::string(kMinimal), 0, "resin.density", "expected a number, got 'abc'",
               {"resin.density=abc"}, "--set");
}

TEST(Config, OverrideUnknownKeyIsReportedAsSet) {
  expect_error(std::string(kMinimal), 0, "resn", "unknown key (did you mean 'resin'?)",
               {"resn.density=1"}, "--set");
}

TEST(Config, OverrideUnparsableValue) {
  expect_error(std::string(kMinimal), 0, "periodic", "cannot parse value '[x'", {"periodic=[x"},
               "--set");
}

TEST(Config, OverrideWithoutEquals) {
  expect_error(std::string(kMinimal), 0, "numerics.spacing", "expected key=value",
               {"numerics.spacing"}, "--set");
}

TEST(Config, OverrideThroughANonMap) {
  expect_error(std::string(kMinimal), 0, "resin.density.value", "'resin.density' is not a mapping",
               {"resin.density.value=3"}, "--set");
}

TEST(Config, OverrideIndexOutOfRange) {
  expect_error(std::string(kMinimal), 0, "fill[3]", "index out of range", {"fill[3]={}"}, "--set");
}

TEST(Config, OverrideMalformedPath) {
  expect_error(std::string(kMinimal), 0, "numerics..spacing", "malformed key path",
               {"numerics..spacing=1"}, "--set");
}

// --- bad input: one edit of the minimal case each ----------------------------

struct BadEdit {
  const char* name;
  const char* from;  // unique text in kMinimal
  const char* to;    // what replaces it (may add lines after `from`'s)
  int line;
  const char* key;
  const char* message;
};

void PrintTo(const BadEdit& b, std::ostream* os) {
  *os << b.name;
}

class ConfigBadEdit : public ::testing::TestWithParam<BadEdit> {};

TEST_P(ConfigBadEdit, NamesFileLineAndKey) {
  const BadEdit& b = GetParam();
  expect_error(edit(kMinimal, b.from, b.to), b.line, b.key, b.message);
}

const BadEdit kBadEdits[] = {
    {"UnknownKeySuggests", "density: 900", "densty: 900", 3, "resin.densty",
     "unknown key (did you mean 'density'?)"},
    {"UnknownKeyListsChoices", "spacing: 3.0e-4", "foo: 1\n  spacing: 3.0e-4", 7, "numerics.foo",
     "unknown key (expected one of: spacing, h_over_spacing"},
    {"DuplicateKey", "viscosity: 0.1", "density: 0.1", 4, "resin.density", "duplicate key"},
    {"NumberExpected", "density: 900", "density: abc", 3, "resin.density",
     "expected a number, got 'abc'"},
    {"QuotedNumber", "density: 900", "density: '900'", 3, "resin.density",
     "expected a number, got the quoted string '900'"},
    {"NumberNotList", "spacing: 3.0e-4", "spacing: [1, 2]", 7, "numerics.spacing",
     "expected a number, got a list"},
    {"NumberNotNull", "spacing: 3.0e-4", "spacing:", 7, "numerics.spacing",
     "expected a number, got nothing"},
    {"NotFinite", "spacing: 3.0e-4", "spacing: .inf", 7, "numerics.spacing",
     "expected a number, got '.inf'"},
    {"MapExpected", "- box: {min: [0, 0], max: [0.03, 0.02]}", "- box: [0, 0]", 13, "fill[0].box",
     "expected a mapping, got a list"},
    {"ListExpected", "- box: {min: [0, 0], max: [0.03, 0.02]}", "{box: {}}", 12, "fill",
     "expected a list, got a mapping"},
    {"IntegerExpected", "dimension: 2", "dimension: 2.5", 1, "dimension",
     "expected an integer, got '2.5'"},
    {"BadDimension", "dimension: 2", "dimension: 4", 1, "dimension", "must be 2 or 3, got 4"},
    {"MissingRequiredKey", "viscosity: 0.1", "gamma: 7", 2, "resin.viscosity",
     "missing required key"},
    {"MissingSection", "numerics:", "numerix:", 6, "numerix",
     "unknown key (did you mean 'numerics'?)"},
    {"NegativeDensity", "density: 900", "density: -3", 3, "resin.density",
     "must be positive, got -3"},
    {"ZeroSoundSpeed", "sound_speed: 60", "sound_speed: 0", 5, "resin.sound_speed",
     "must be positive, got 0"},
    {"NegativeViscosity", "viscosity: 0.1", "viscosity: -0.1", 4, "resin.viscosity",
     "must be zero or positive, got -0.1"},
    {"ZeroSpacing", "spacing: 3.0e-4", "spacing: 0", 7, "numerics.spacing",
     "must be positive, got 0"},
    {"NegativeEndTime", "end_time: 0.12", "end_time: -1", 8, "numerics.end_time",
     "must be positive, got -1"},
    {"CflOutOfRange", "end_time: 0.12", "end_time: 0.12\n  cfl: 1.5", 9, "numerics.cfl",
     "must be in (0, 1], got 1.5"},
    {"HOverSpacingOutOfRange", "spacing: 3.0e-4", "spacing: 3.0e-4\n  h_over_spacing: 0.5", 8,
     "numerics.h_over_spacing", "must be in [1, 3], got 0.5"},
    {"SkinOutOfRange", "spacing: 3.0e-4", "spacing: 3.0e-4\n  neighbor_skin: 1", 8,
     "numerics.neighbor_skin", "must be in [0, 1), got 1"},
    {"BadBool", "spacing: 3.0e-4", "spacing: 3.0e-4\n  anti_clump: maybe", 8, "numerics.anti_clump",
     "expected true or false, got 'maybe'"},
    {"ExponentTooSmall", "spacing: 3.0e-4", "spacing: 3.0e-4\n  anti_clump_exponent: 0", 8,
     "numerics.anti_clump_exponent", "must be at least 1, got 0"},
    {"UnknownViscosityModel", "spacing: 3.0e-4", "spacing: 3.0e-4\n  viscosity_model: moris", 8,
     "numerics.viscosity_model", "unknown value 'moris' (did you mean 'morris'?)"},
    {"WallLayersNotInteger", "  shapes:", "  wall_layers: 2.5\n  shapes:", 10, "mold.wall_layers",
     "expected an integer, got '2.5'"},
    {"SoundSpeedAndMach", "sound_speed: 60", "sound_speed: 60\n  mach: 0.1", 6, "resin.mach",
     "either sound_speed or mach with reference_velocity, not both"},
    {"NoSoundSpeed", "sound_speed: 60", "gamma: 7", 2, "resin.sound_speed",
     "missing required key (give sound_speed, or both mach and reference_velocity)"},
    {"MachWithoutReferenceVelocity", "sound_speed: 60", "mach: 0.1", 2, "resin.reference_velocity",
     "missing required key (needed with mach)"},
    {"VectorTooLong", "min: [0, 0], max: [0.03, 0.02]", "min: [0, 0, 0], max: [0.03, 0.02]", 13,
     "fill[0].box.min", "expected 2 numbers (dimension 2), got 3"},
    {"VectorElementNotNumber", "min: [0, 0], max: [0.03, 0.02]", "min: [0, y], max: [0.03, 0.02]",
     13, "fill[0].box.min[1]", "expected a number, got 'y'"},
    {"BoxMinNotBelowMax", "max: [0.03, 0.02]", "max: [0.03, 0]", 13, "fill[0].box.max",
     "must be greater than min along y"},
    {"ShapeWithoutType", "- box: {min: [0, 0], max: [0.03, 0.02]}", "- {}", 13, "fill[0]",
     "expected exactly one of 'polygon' or 'box'"},
    {"EmptyShapeList", "- box: {min: [0, 0], max: [0.03, 0.02]}", "[]", 12, "fill",
     "needs at least one shape"},
    {"PolygonTooFewVertices", "- box: {min: [0, 0], max: [0.03, 0.02]}",
     "- polygon: [[0, 0], [0.01, 0]]", 13, "fill[0].polygon", "needs at least 3 vertices, got 2"},
    {"DegeneratePolygon", "- box: {min: [0, 0], max: [0.03, 0.02]}",
     "- polygon: [[0, 0], [0.01, 0.01], [0.02, 0.02]]", 13, "fill[0].polygon",
     "polygon is degenerate (zero area)"},
    {"FillOutsideMold", "max: [0.03, 0.02]", "max: [0.03, 0.05]", 13, "fill[0]",
     "fill region lies outside the mold (point (0, 0.05) is outside)"},
    {"FillPolygonOutsideMold", "- box: {min: [0, 0], max: [0.03, 0.02]}",
     "- polygon: [[0, 0], [0.04, 0], [0, 0.02]]", 13, "fill[0]",
     "fill region lies outside the mold (point (0.035, 0) is outside)"},
    {"UnstableFixedDtCfl", "end_time: 0.12", "end_time: 0.12\n  fixed_dt: 2.0e-6", 9,
     "numerics.fixed_dt", "2.0e-6 s exceeds the stable limit cfl*h/c0 = 1.5e-06 s"},
    {"EndTimeBeforeFixedDt", "end_time: 0.12", "end_time: 1.0e-7\n  fixed_dt: 2.0e-7", 8,
     "numerics.end_time", "must be greater than numerics.fixed_dt (2.0e-7 s)"},
};

INSTANTIATE_TEST_SUITE_P(Config, ConfigBadEdit, ::testing::ValuesIn(kBadEdits),
                         [](const auto& info) { return std::string(info.param.name); });

// --- bad input: structural cases --------------------------------------------

TEST(Config, UnknownTopLevelKeySuggests) {
  expect_error(append(kMinimal, "bodyforce: [0, -9.81]\n"), 14, "bodyforce",
               "unknown key (did you mean 'body_force'?)");
}

TEST(Config, WrongVectorLength) {
  expect_error(append(kMinimal, "body_force: [0, -9.81, 0]\n"), 14, "body_force",
               "expected 2 numbers (dimension 2), got 3");
}

TEST(Config, PolygonIn3D) {
  const std::string text = R"(dimension: 3
resin: {density: 900, viscosity: 0.1, sound_speed: 60}
numerics: {spacing: 1.0e-3, end_time: 0.1}
mold:
  shapes:
    - box: {min: [0, 0, 0], max: [0.01, 0.01, 0.01]}
    - polygon: [[0, 0], [1, 0], [0, 1]]
fill:
  - box: {min: [0, 0, 0], max: [0.01, 0.01, 0.005]}
)";
  expect_error(text, 7, "mold.shapes[1].polygon", "polygons are 2D only");
}

// An L-shaped mold whose bounding box contains the fill but whose shape
// does not: its top edge crosses the missing quadrant.
TEST(Config, FillOutsideConcaveLShapedMold) {
  const std::string text = edit(
      kMinimal, "    - box: {min: [0, 0], max: [0.03, 0.03]}",
      "    - polygon: [[0, 0], [0.02, 0], [0.02, 0.01], [0.01, 0.01], [0.01, 0.02], [0, 0.02]]");
  expect_error(edit(text, "max: [0.03, 0.02]}", "max: [0.018, 0.018]}"), 13, "fill[0]",
               "fill region lies outside the mold (point (0.01125, 0.018) is outside)");
}

TEST(Config, FillInsideLShapedMoldLoads) {
  const std::string text = edit(
      kMinimal, "    - box: {min: [0, 0], max: [0.03, 0.03]}",
      "    - polygon: [[0, 0], [0.02, 0], [0.02, 0.01], [0.01, 0.01], [0.01, 0.02], [0, 0.02]]");
  EXPECT_NO_THROW(
      load_case_from_string(edit(text, "max: [0.03, 0.02]}", "max: [0.01, 0.02]}"), kFile));
}

// A U-shaped mold of three boxes: every corner of the fill lies in the
// mold, only the sample points along its top edge fall into the notch.
TEST(Config, FillOutsideConcaveUShapedMoldFoundAlongAnEdge) {
  const std::string text = R"(dimension: 2
resin: {density: 900, viscosity: 0.1, sound_speed: 60}
numerics: {spacing: 1.0e-3, end_time: 0.1}
mold:
  shapes:
    - box: {min: [0, 0], max: [1, 3]}
    - box: {min: [0, 0], max: [3, 1]}
    - box: {min: [2, 0], max: [3, 3]}
fill:
  - box: {min: [0, 0], max: [3, 1]}
  - box: {min: [0.5, 0.5], max: [2.5, 2.5]}
)";
  expect_error(text, 11, "fill[1]", "fill region lies outside the mold (point (1.25, 2.5)");
}

TEST(Config, YamlSyntaxError) {
  expect_error(edit(kMinimal, "density: 900", "density: [900"), 4, "", "YAML syntax error");
}

TEST(Config, EmptyFile) {
  expect_error("# nothing here\n", 1, "", "the case file is empty");
}

// The viscous limit, with the viscosity raised from the command line: the
// error is about fixed_dt, which comes from the file.
TEST(Config, UnstableFixedDtViscousLimit) {
  expect_error(
      edit(kMinimal, "end_time: 0.12", "end_time: 0.12\n  fixed_dt: 1.0e-6"), 9,
      "numerics.fixed_dt",
      "1.0e-6 s exceeds the stable limit viscous_factor*h^2*density/viscosity = 1.458e-07 s",
      {"resin.viscosity=100"});
}

TEST(Config, DuplicateWallName) {
  expect_error(append(kMinimal, R"(moving_walls:
  - name: piston
    region: {box: {min: [0, 0.03], max: [0.03, 0.031]}}
    velocity_table: [[0, 0, -1]]
sliding_walls:
  - name: piston
    region: {box: {min: [0, -0.001], max: [0.03, 0]}}
    velocity: [1, 0]
)"),
               19, "sliding_walls[0].name",
               "duplicate wall name 'piston' (also moving_walls[0].name)");
}

TEST(Config, VelocityTableTimesMustIncrease) {
  expect_error(append(kMinimal, R"(moving_walls:
  - name: piston
    region: {box: {min: [0, 0.03], max: [0.03, 0.031]}}
    velocity_table:
      - [0.0, 0, -1]
      - [0.0, 0, -0.5]
)"),
               19, "moving_walls[0].velocity_table[1][0]", "times must be strictly increasing");
}

TEST(Config, VelocityTableRowLength) {
  expect_error(append(kMinimal, R"(moving_walls:
  - name: piston
    region: {box: {min: [0, 0.03], max: [0.03, 0.031]}}
    velocity_table: [[0.0, -1]]
)"),
               17, "moving_walls[0].velocity_table[0]", "expected 3 numbers [t, velocity]");
}

TEST(Config, PeriodicNeedsDomain) {
  expect_error(append(kMinimal, "periodic: [x]\n"), 1, "domain",
               "missing required key (periodic axes need a domain");
}

TEST(Config, PeriodicAxisMustExist) {
  expect_error(append(kMinimal, "periodic: [z]\ndomain: {min: [0, 0], max: [1, 1]}\n"), 14,
               "periodic[0]", "unknown value 'z' (expected one of: x, y)");
}

TEST(Config, BalanceWeightIsModelOrTime) {
  EXPECT_EQ(load_case_from_string(std::string(kMinimal), "c.yaml").parallel.balance_weight,
            BalanceWeight::Model);
  EXPECT_EQ(load_case_from_string(append(kMinimal, "parallel: {balance_weight: time}\n"), "c.yaml")
                .parallel.balance_weight,
            BalanceWeight::Time);
  expect_error(append(kMinimal, "parallel:\n  balance_weight: speed\n"), 15,
               "parallel.balance_weight", "unknown value 'speed' (expected one of: model, time)");
}

TEST(Config, UnknownOutputField) {
  expect_error(append(kMinimal, "output:\n  fields: [velocty]\n"), 15, "output.fields[0]",
               "unknown value 'velocty' (did you mean 'velocity'?)");
}

TEST(Config, MissingFileCannotBeOpened) {
  try {
    load_case("/nonexistent/dir/case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/dir/case.yaml");
    EXPECT_EQ(e.line(), 0);
    EXPECT_TRUE(contains(e.what(), "cannot open case file")) << e.what();
  }
}

}  // namespace
}  // namespace sphdem
