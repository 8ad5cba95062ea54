// Hostile case files (issue 15, defects 3, 6 and 8): each is refused with an
// InputError naming file, line and key, never a crash, a hang or a silent
// acceptance; and the size estimate that refuses a case too big to build.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/lattice_fill.hpp"
#include "sphdem/solver/case_size.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

constexpr const char* kFile = "case.yaml";

// The smallest valid case; comments give line numbers.
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

constexpr std::string_view kFibers = R"(fibers:                      # 14
  count: 10                  # 15
  diameter: 2.5e-4           # 16
  density: 2540              # 17
  youngs_modulus: 1.0e8      # 18
  region: {box: {min: [0.005, 0.005], max: [0.025, 0.015]}}   # 19
)";

std::string with_fibers(std::string_view extra = "") {
  return std::string(kMinimal) + std::string(kFibers) + std::string(extra);
}

std::string replaced(std::string text, std::string_view from, std::string_view to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the case";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Loading fails with an InputError at file:line, key, with `message` in it.
void expect_error(const std::string& text, int line, const std::string& key,
                  std::string_view message) {
  try {
    load_case_from_string(text, kFile);
    ADD_FAILURE() << "accepted; expected line " << line << " key " << key << ": " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kFile) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(SPHDEM_BINARY_DIR) / "hostile_input";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::string load_error(const std::string& path) {
  try {
    load_case(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Defect 6: a name with '/' would write outside the output directory.
TEST(HostileInput, CaseNameMustBeFileNameSafe) {
  for (const char* name : {"../escape", "a/b", "two words", ".hidden", "tab\there", "-flag"}) {
    expect_error("name: \"" + std::string(name) + "\"\n" + std::string(kMinimal), 1, "name",
                 "not a file-name-safe case name");
  }
  EXPECT_EQ(load_case_from_string("name: plate_v2.1-a+b\n" + std::string(kMinimal), kFile).name,
            "plate_v2.1-a+b");
  // The default, from the file name, is made safe rather than refused.
  EXPECT_EQ(load_case_from_string(std::string(kMinimal), "runs/my case.yaml").name, "my_case");
}

// Defect 8: a polygon whose edges cross is not a shape the filling can use.
TEST(HostileInput, SelfIntersectingPolygonIsRefused) {
  const std::string bowtie =
      replaced(std::string(kMinimal), "    - box: {min: [0, 0], max: [0.03, 0.03]}    # 11",
               "    - polygon: [[0, 0], [0.03, 0.03], [0.03, 0], [0, 0.02]]");
  expect_error(bowtie, 11, "mold.shapes[0].polygon", "polygon intersects itself: edge 0");
  const std::string repeated =
      replaced(std::string(kMinimal), "    - box: {min: [0, 0], max: [0.03, 0.03]}    # 11",
               "    - polygon: [[0, 0], [0.03, 0], [0.03, 0], [0.03, 0.03], [0, 0.03]]");
  expect_error(repeated, 11, "mold.shapes[0].polygon", "polygon intersects itself");
  // A simple concave polygon (an L) is fine.
  const std::string ell = replaced(
      std::string(kMinimal), "    - box: {min: [0, 0], max: [0.03, 0.03]}    # 11",
      "    - polygon: [[0, 0], [0.03, 0], [0.03, 0.03], [0.02, 0.03], [0.02, 0.02], [0, 0.02]]");
  EXPECT_NO_THROW(load_case_from_string(ell, kFile));
}

// Defect 8: non-physical fiber values are bad input, with the key.
TEST(HostileInput, NonPhysicalFiberValuesAreRefused) {
  expect_error(replaced(with_fibers(), "  diameter: 2.5e-4", "  diameter: 1e-300"), 16,
               "fibers.diameter", "must be in [1e-09, 1]");
  expect_error(with_fibers("  dt_safety: 1e-300\n"), 20, "fibers.dt_safety",
               "must be in [0.001, 2)");
  expect_error(with_fibers("  dt_safety: 2\n"), 20, "fibers.dt_safety", "must be in [0.001, 2)");
  // Above the documented stable bound (docs/dem.md): accepted, with a warning.
  const Case warned = load_case_from_string(with_fibers("  dt_safety: 1.5\n"), kFile);
  ASSERT_EQ(warned.warnings.size(), 1u);
  EXPECT_NE(warned.warnings[0].find("fibers.dt_safety = 1.5 is above 1.2"), std::string::npos)
      << warned.warnings[0];
  EXPECT_TRUE(load_case_from_string(with_fibers("  dt_safety: 1.2\n"), kFile).warnings.empty());
}

// Defect 8: a second YAML document would be ignored silently.
TEST(HostileInput, SecondDocumentIsRefused) {
  expect_error(std::string(kMinimal) + "---\nname: other\n", 15, "", "a second YAML document");
  EXPECT_NO_THROW(load_case_from_string("---\n" + std::string(kMinimal), kFile));
}

// Defect 8: directories, devices and huge files are not read.
TEST(HostileInput, OnlyRegularFilesOfModestSizeAreRead) {
  const std::string dir = temp_path("a_directory");
  std::filesystem::create_directories(dir);
  EXPECT_NE(load_error(dir).find("is a directory, not a case file"), std::string::npos);
  EXPECT_NE(load_error("/dev/zero").find("not a regular file"), std::string::npos);
  const std::string huge = temp_path("huge.yaml");
  {
    std::ofstream out(huge, std::ios::binary);
    out << kMinimal;
    out << std::string(17u << 20, '#');
  }
  EXPECT_NE(load_error(huge).find("a case file is at most 16 MiB"), std::string::npos);
  std::filesystem::remove(huge);
  EXPECT_NE(load_error(temp_path("missing.yaml")).find("cannot open case file"), std::string::npos);
}

// Defect 8: the error about a binary file echoes no raw bytes.
TEST(HostileInput, BinaryBytesAreEscapedInErrors) {
  const std::string text = std::string("name: \"\x01\x02\xff\x1b[31m\"\n") + std::string(kMinimal);
  try {
    load_case_from_string(text, kFile);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const char ch : what) {
      const auto c = static_cast<unsigned char>(ch);
      EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "raw byte " << int(c) << " in: " << what;
    }
    EXPECT_NE(what.find("\\x01\\x02\\xff\\x1b[31m"), std::string::npos) << what;
  }
  // Valid UTF-8 stays as it is.
  EXPECT_EQ(printable("r\xc3\xa9sine \x7f"), "r\xc3\xa9sine \\x7f");
  // C1 controls are valid UTF-8 but terminal commands: escaped.
  EXPECT_EQ(printable("a\xc2\x9b"
                      "31m"),
            "a\\xc2\\x9b"
            "31m");
}

// Defect 3: the estimate is made from the geometry, before building.
TEST(HostileInput, SizeEstimateFollowsTheGeometry) {
  const Case c = load_case_from_string(std::string(kMinimal), kFile);
  const CaseSize s = estimate_case_size(c, 1);
  // 0.03 x 0.02 m at 3e-4 m: 6667 resin particles (the lattice: 100 x 66);
  // walls: the band around the 0.03 m square, as deep as the kernel's
  // support 2h = 2.4 dx (less than the 3 layers asked for; wall_band,
  // docs/performance.md "Wall layers trimmed to the support"),
  // (0.03144^2 - 0.03^2) / dx^2 = 983.
  EXPECT_NEAR(s.resin, 6667, 1);
  EXPECT_NEAR(s.walls, 983, 1);
  EXPECT_EQ(s.dem, 0);
  EXPECT_EQ(s.dominant_key, "numerics.spacing");
  EXPECT_GT(s.bytes_per_rank(), 1e6);
  EXPECT_LT(s.bytes_per_rank(), 1e8);
  // Halving the spacing gives four times the resin (2D).
  const CaseSize fine = estimate_case_size(
      load_case_from_string(std::string(kMinimal), kFile, {"numerics.spacing=1.5e-4"}), 1);
  EXPECT_NEAR(fine.resin / s.resin, 4.0, 1e-9);
  // More ranks: less per rank (each rank builds and runs its share).
  EXPECT_LT(estimate_case_size(c, 4).run_bytes, s.run_bytes);
  // The reproducer of defect 3: spacing 1e-6 m is far beyond any node.
  const CaseSize huge = estimate_case_size(
      load_case_from_string(std::string(kMinimal), kFile, {"numerics.spacing=1e-6"}), 1);
  EXPECT_GT(huge.bytes_per_rank(), 1e11);
  // Fibers by area fraction of a tiny diameter: the DEM dominates.
  const Case fibers =
      load_case_from_string(replaced(replaced(with_fibers(), "  count: 10", "  area_fraction: 0.3"),
                                     "  diameter: 2.5e-4", "  diameter: 1e-8"),
                            kFile);
  const CaseSize many = estimate_case_size(fibers, 1);
  EXPECT_GT(many.dem, 1e11);
  EXPECT_EQ(many.dominant_key, "fibers.area_fraction");
}

// The InputError a constructor throws for `text`, or an empty key.
template <class F>
InputError error_of(F&& build) {
  try {
    build();
  } catch (const InputError& e) {
    return e;
  }
  return InputError(kFile, 0, "", "no error");
}

// A mold far from the lattice's origin (0 without a domain): its node
// indices would pass long's range (main: cast to INT64_MIN, then a signed
// overflow in the last index).
TEST(HostileInput, MoldFarFromTheOriginIsRefused) {
  const std::string far = replaced(
      replaced(std::string(kMinimal), "{min: [0, 0], max: [0.03, 0.03]}",
               "{min: [3.0e15, 0], max: [3.000000000001e15, 0.03]}"),
      "{min: [0, 0], max: [0.03, 0.02]}", "{min: [3.0e15, 0], max: [3.000000000001e15, 0.02]}");
  const Case c = load_case_from_string(far, kFile);
  const InputError e = error_of([&] { LatticeFill<2> fill(c); });
  EXPECT_EQ(e.key(), "mold") << e.what();
  EXPECT_EQ(e.line(), 9);
  EXPECT_NE(std::string(e.what()).find("spacings from the lattice origin"), std::string::npos)
      << e.what();
}

// kMinimal + `extra` loads, and building its run on one rank fails with an
// InputError at `line`, `key`, with `message` in it: the checks made at
// the start of a run, not by the loader.
void expect_run_error(std::string_view extra, int line, const std::string& key,
                      std::string_view message) {
  const Comm self(MPI_COMM_SELF);
  const Case c = load_case_from_string(std::string(kMinimal) + std::string(extra), kFile);
  const InputError e = error_of([&] { Simulation<2> sim(c, self, testing::quiet()); });
  EXPECT_EQ(e.key(), key) << e.what();
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
}

// A domain too large for the decomposition's cells: an InputError at
// `domain` from the decomposition, before the filling (main cast
// floor(2e300 / cut-off) to long: one cell, then the filling's error).
TEST(HostileInput, DomainTooLargeForTheDecompositionIsRefused) {
  expect_run_error("domain: {min: [-1.0e300, -1.0e300], max: [1.0e300, 1.0e300]}  # 14\n", 14,
                   "domain", "decomposition");
}

// Front events over a domain whose trapped-air grid (cells of half the
// spacing) passes 2^31 cells: refused at the start (main built the run and
// would overflow nothing here, but allocate 24 B per cell at the first
// output).
TEST(HostileInput, TrappedAirGridPast2To31CellsIsRefused) {
  expect_run_error(
      "domain: {min: [0, 0], max: [30, 9]}  # 14\n"
      "output:                      # 15\n"
      "  front_events: true         # 16\n",
      16, "output.front_events", "trapped-air grid");
}

// The memory guard's error points at the dominant key's line.
TEST(HostileInput, ErrorAtKeyFindsTheLine) {
  const Case c = load_case_from_string(std::string(kMinimal), kFile);
  const InputError e = input_error_at(c, "numerics.spacing", "too fine");
  EXPECT_EQ(e.line(), 7);
  EXPECT_EQ(e.key(), "numerics.spacing");
  const Case set = load_case_from_string(std::string(kMinimal), kFile, {"numerics.spacing=1e-6"});
  EXPECT_EQ(input_error_at(set, "numerics.spacing", "too fine").file(), "--set");
}

}  // namespace
}  // namespace sphdem
