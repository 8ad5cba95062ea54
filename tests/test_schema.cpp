// The key schema (docs/case-file.md): every key used in inputs/ is in it,
// the checkpoint identity generated from it keeps the old lines, and the
// effective case (overrides applied) loads back to the same case.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/io/checkpoint.hpp"

namespace sphdem {
namespace {

constexpr const char* kMinimal = R"(dimension: 2
resin:
  density: 900
  viscosity: 0.1
  sound_speed: 60
numerics:
  spacing: 3.0e-4
  end_time: 0.12
mold:
  shapes:
    - box: {min: [0, 0], max: [0.03, 0.03]}
fill:
  - box: {min: [0, 0], max: [0.03, 0.02]}
)";

// The key paths of a YAML tree, list items of mappings as [] (the schema's
// spelling); lists of scalars or lists are values, not keys.
void key_paths(const YAML::Node& n, const std::string& prefix, std::vector<std::string>& out) {
  if (n.IsMap()) {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string key = (prefix.empty() ? "" : prefix + ".") + it->first.Scalar();
      out.push_back(key);
      key_paths(it->second, key, out);
    }
  } else if (n.IsSequence()) {
    for (const YAML::Node& item : n)
      if (item.IsMap()) key_paths(item, prefix + "[]", out);
  }
}

std::vector<std::string> keys_not_in_schema(const YAML::Node& root) {
  const std::vector<std::string> schema = case_key_paths();
  const std::set<std::string> known(schema.begin(), schema.end());
  std::vector<std::string> used, unknown;
  key_paths(root, "", used);
  for (const std::string& k : used)
    if (!known.count(k)) unknown.push_back(k);
  return unknown;
}

std::vector<std::string> input_files() {
  std::vector<std::string> files;
  const std::filesystem::path inputs = std::filesystem::path(SPHDEM_SOURCE_DIR) / "inputs";
  // inputs/materials/ holds material files (resin.material), not cases.
  for (const auto& e : std::filesystem::recursive_directory_iterator(inputs))
    if (e.path().extension() == ".yaml" && e.path().parent_path().filename() != "materials")
      files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(Schema, EveryKeyUsedInInputsIsInTheSchema) {
  const std::vector<std::string> files = input_files();
  ASSERT_GE(files.size(), 10u);
  for (const std::string& f : files) {
    EXPECT_EQ(keys_not_in_schema(YAML::LoadFile(f)), std::vector<std::string>{}) << f;
    EXPECT_NO_THROW(load_case(f)) << f;
  }
}

TEST(Schema, AnUnknownKeyIsReported) {
  const YAML::Node root =
      YAML::Load(std::string(kMinimal) + "moving_walls:\n  - name: p\n    regoin: {box: {}}\n");
  EXPECT_EQ(keys_not_in_schema(root),
            (std::vector<std::string>{"moving_walls[].regoin", "moving_walls[].regoin.box"}));
}

TEST(Schema, KeysListsEveryPathWithItsDefault) {
  const std::string text = keys_text();
  for (const std::string& path : case_key_paths())
    EXPECT_NE(text.find("\n" + path + " "), std::string::npos) << path;
  EXPECT_NE(text.find("fibers.void_fraction_min"), std::string::npos);
  const std::string page = case_file_markdown();
  EXPECT_EQ(page.rfind("# Case files\n", 0), 0u);
  EXPECT_NE(page.find("| `void_fraction_in_continuity` | boolean |  | true |"), std::string::npos)
      << "the fibers table shows the default of FiberSettings";
}

// The identity of a resin-only case has exactly the lines of the
// hand-written list it replaced, so older checkpoints are still accepted.
TEST(Schema, IdentityOfAResinCaseKeepsTheOldLines) {
  std::vector<std::string> id = case_identity(load_case_from_string(kMinimal, "tank.yaml"));
  std::sort(id.begin(), id.end());
  std::vector<std::string> old{"name = tank",
                               "dimension = 2",
                               "resin.density = 900",
                               "resin.viscosity = 0.1",
                               "resin.sound_speed = 60",
                               "resin.gamma = 7",
                               "numerics.spacing = 0.0003",
                               "numerics.h_over_spacing = 1.2",
                               "numerics.cfl = 0.25",
                               "numerics.force_factor = 0.25",
                               "numerics.viscous_factor = 0.125",
                               "numerics.fixed_dt = none",
                               "numerics.viscosity_model = morris",
                               "numerics.lattice_correction = true",
                               "numerics.artificial_viscosity = 0",
                               "numerics.delta_sph = 0",
                               "numerics.anti_clump = true",
                               "numerics.anti_clump_epsilon = 0.2",
                               "numerics.anti_clump_exponent = 4",
                               "numerics.neighbor_skin = 0.15",
                               "mold.wall_layers = 3",
                               "mold.shapes[0] = box [0, 0, 0] [0.03, 0.03, 0]",
                               "fill[0] = box [0, 0, 0] [0.03, 0.02, 0]",
                               "body_force = [0, 0, 0]",
                               "initial_velocity = [0, 0, 0]",
                               "periodic = false false false",
                               "domain = default"};
  std::sort(old.begin(), old.end());
  EXPECT_EQ(id, old);
  EXPECT_EQ(case_identity(load_case_from_string(kMinimal, "tank.yaml")).front(), "name = tank");
}

TEST(Schema, IdentityHasTheCouplingKeysOfTheFibers) {
  const Case c = load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/validation/coupled_box.yaml",
                           {"fibers.void_fraction_min=0.5"});
  const std::string id = case_identity_text(c);
  EXPECT_NE(id.find("fibers.void_fraction_min = 0.5\n"), std::string::npos) << id;
  EXPECT_NE(id.find("fibers.void_fraction_in_continuity = true\n"), std::string::npos) << id;
  EXPECT_EQ(id.find("output."), std::string::npos) << "output keys may change on restart";
  EXPECT_EQ(id.find("numerics.end_time"), std::string::npos);
}

TEST(Schema, SettingsKnowTheirDefaults) {
  const Case c = load_case_from_string(kMinimal, "tank.yaml", {"numerics.cfl=0.2"});
  auto find = [&](const std::string& key) {
    for (const Setting& s : case_settings(c))
      if (s.key == key) return s;
    ADD_FAILURE() << key << " not among the settings";
    return Setting{};
  };
  EXPECT_FALSE(find("numerics.cfl").is_default);
  EXPECT_EQ(find("numerics.cfl").value, "0.2");
  EXPECT_TRUE(find("numerics.force_factor").is_default);
  EXPECT_FALSE(find("resin.density").is_default) << "required keys have no default";
}

// load(effective case) == load(original + overrides), in every key.
TEST(Schema, EffectiveCaseLoadsBackToTheSameCase) {
  const std::vector<std::string> sets{"numerics.cfl=0.2", "output.every_steps=7",
                                      "mold.shapes[0].box.max=[0.04, 0.03]",
                                      "output.directory=\"out dir\""};
  const Case c = load_case_from_string(kMinimal, "cases/tank.yaml", sets);
  const std::string yaml = effective_case_yaml(c);
  EXPECT_NE(yaml.find("cfl: 0.2"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("name: tank"), std::string::npos) << "the default name made explicit";
  EXPECT_NE(yaml.find("# --set numerics.cfl=0.2"), std::string::npos) << yaml;
  const Case back = load_case_from_string(yaml, "elsewhere/case.yaml");
  EXPECT_EQ(case_identity(back), case_identity(c));
  std::vector<std::string> a, b;
  for (const Setting& s : case_settings(c)) a.push_back(s.key + " = " + s.value);
  for (const Setting& s : case_settings(back)) b.push_back(s.key + " = " + s.value);
  EXPECT_EQ(a, b);
  EXPECT_EQ(back.output.directory, "out dir");
  EXPECT_EQ(effective_case_yaml(back).substr(effective_case_yaml(back).find("name:")),
            yaml.substr(yaml.find("name:")))
      << "a second round gives the same text";
}

// A quoted scalar stays quoted: '7' is a string to the loader, and would
// turn into a number if the quotes were lost.
TEST(Schema, EffectiveCaseKeepsQuotes) {
  const Case c = load_case_from_string(std::string(kMinimal) + "name: '7'\n", "tank.yaml");
  const std::string yaml = effective_case_yaml(c);
  EXPECT_NE(yaml.find("name: \"7\""), std::string::npos) << yaml;
  EXPECT_EQ(YAML::Load(yaml)["name"].Tag(), "!");
}

}  // namespace
}  // namespace sphdem
