// SnapshotWriter at any rank count: rows in global-id order whatever the
// ownership, ranks with no particles taking part, atomic publication and an
// XDMF listing every snapshot. Rank 0 reads the files back with serial
// HDF5 once the collective write has returned.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphdem/io/io.hpp"
#include "sphdem/parallel/comm.hpp"

namespace fs = std::filesystem;
using sphdem::Comm;
using sphdem::ParticleSetView;
using sphdem::SnapshotWriter;

namespace {

constexpr std::int64_t kFluidFirstId = 1000;
constexpr std::int64_t kFluidCount = 25;  // not a multiple of 2 or 3: uneven ownership
constexpr std::int64_t kWallCount = 7;

// The values every particle carries, a function of its id and the step, so
// a reader can tell a misplaced row (check_snapshot.py --test-pattern uses
// the same formulas).
double pos_x(std::int64_t id, std::int64_t) {
  return 0.5 * static_cast<double>(id);
}
double pos_y(std::int64_t id, std::int64_t s) {
  return 0.25 * static_cast<double>(id + s);
}
double vel_x(std::int64_t id, std::int64_t s) {
  return static_cast<double>(id) + 0.5 * s;
}
double vel_y(std::int64_t id, std::int64_t) {
  return -static_cast<double>(id);
}
double density(std::int64_t id, std::int64_t s) {
  return 1000.0 + static_cast<double>(id + s);
}
double pressure(std::int64_t id, std::int64_t s) {
  return 2.0 * static_cast<double>(id) - s;
}

// One rank's particles of a 2D set, stored in descending id order so the
// writer has to sort.
struct OwnedSet {
  std::string name;
  bool with_pressure = false;
  std::vector<std::int64_t> id;
  std::vector<double> position, velocity, rho, p;

  void fill(std::int64_t step) {
    position.clear();
    velocity.clear();
    rho.clear();
    p.clear();
    for (std::int64_t i : id) {
      position.insert(position.end(), {pos_x(i, step), pos_y(i, step)});
      velocity.insert(velocity.end(), {vel_x(i, step), vel_y(i, step)});
      rho.push_back(density(i, step));
      if (with_pressure) p.push_back(pressure(i, step));
    }
  }
  ParticleSetView view() const {
    ParticleSetView v{name, id.size(), id.data(), 2, position.data(), {}};
    v.fields.push_back({"velocity", "m/s", 2, velocity.data()});
    v.fields.push_back({"density", "kg/m^3", 1, rho.data()});
    if (with_pressure) v.fields.push_back({"pressure", "Pa", 1, p.data()});
    return v;
  }
};

// Fluid ids dealt round-robin over the ranks, so every rank's rows
// interleave with the others'.
OwnedSet fluid_of(const Comm& comm) {
  OwnedSet s{"fluid", true, {}, {}, {}, {}, {}};
  for (std::int64_t k = kFluidCount - 1; k >= 0; --k)
    if (k % comm.size() == comm.rank()) s.id.push_back(kFluidFirstId + k);
  return s;
}

// Wall particles all on rank 0: the other ranks write nothing.
OwnedSet wall_of(const Comm& comm) {
  OwnedSet s{"wall", false, {}, {}, {}, {}, {}};
  if (comm.root())
    for (std::int64_t k = kWallCount - 1; k >= 0; --k) s.id.push_back(k);
  return s;
}

// SPHDEM_IO_DIR lets the io_h5py/io_paraview fixture choose the directory.
std::string output_dir(const Comm& comm, const std::string& name) {
  const char* env = std::getenv("SPHDEM_IO_DIR");
  std::string dir = env != nullptr && name == "two_snapshots"
                        ? std::string(env)
                        : "io_out_np" + std::to_string(comm.size()) + "_" + name;
  if (comm.root()) fs::remove_all(dir);
  comm.barrier();
  return dir;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string time_text(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "<Time Value=\"%.17g\"/>", t);
  return buf;
}

// Serial read-back helpers (rank 0 only, after the writer's barrier).
struct Array {
  std::vector<hsize_t> dims;
  std::vector<double> values;
  std::vector<std::int64_t> ints;
};

Array read_array(hid_t file, const std::string& name, bool integer) {
  Array a;
  hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (d < 0) throw std::runtime_error("cannot open " + name);
  hid_t space = H5Dget_space(d);
  a.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, a.dims.data(), nullptr);
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  herr_t rc = 0;
  if (integer) {
    a.ints.resize(n);
    if (n > 0) rc = H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.ints.data());
  } else {
    a.values.resize(n);
    if (n > 0) rc = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data());
  }
  H5Sclose(space);
  H5Dclose(d);
  if (rc < 0) throw std::runtime_error("cannot read " + name);
  return a;
}

template <class T>
T read_attribute(hid_t obj, const char* object, const char* name, hid_t mem_type) {
  T value{};
  hid_t a = H5Aopen_by_name(obj, object, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + name);
  herr_t rc = H5Aread(a, mem_type, &value);
  H5Aclose(a);
  if (rc < 0) throw std::runtime_error(std::string("cannot read attribute ") + name);
  return value;
}

std::string read_string_attribute(hid_t obj, const char* object, const char* name) {
  hid_t a = H5Aopen_by_name(obj, object, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(std::string("no attribute ") + name);
  hid_t type = H5Aget_type(a);
  std::string value(H5Tget_size(type), '\0');
  herr_t rc = H5Aread(a, type, value.data());
  H5Tclose(type);
  H5Aclose(a);
  if (rc < 0) throw std::runtime_error(std::string("cannot read attribute ") + name);
  return value.substr(0, value.find('\0'));
}

void expect_set(hid_t file, const std::string& set, std::int64_t first_id, std::int64_t n,
                std::int64_t step) {
  const std::string g = "/" + set;
  EXPECT_EQ(read_attribute<std::int64_t>(file, g.c_str(), "count", H5T_NATIVE_INT64), n);
  const Array id = read_array(file, g + "/id", true);
  const Array pos = read_array(file, g + "/position", false);
  const Array vel = read_array(file, g + "/velocity", false);
  const Array rho = read_array(file, g + "/density", false);
  ASSERT_EQ(id.dims, (std::vector<hsize_t>{static_cast<hsize_t>(n)}));
  ASSERT_EQ(pos.dims, (std::vector<hsize_t>{static_cast<hsize_t>(n), 3}));
  ASSERT_EQ(vel.dims, (std::vector<hsize_t>{static_cast<hsize_t>(n), 3}));
  ASSERT_EQ(rho.dims, (std::vector<hsize_t>{static_cast<hsize_t>(n)}));
  for (std::int64_t r = 0; r < n; ++r) {
    const std::int64_t i = first_id + r;
    const auto k = static_cast<std::size_t>(r);
    ASSERT_EQ(id.ints[k], i) << set << " row " << r;
    EXPECT_EQ(pos.values[3 * k], pos_x(i, step)) << set << " row " << r;
    EXPECT_EQ(pos.values[3 * k + 1], pos_y(i, step)) << set << " row " << r;
    EXPECT_EQ(pos.values[3 * k + 2], 0.0) << set << " row " << r;
    EXPECT_EQ(vel.values[3 * k], vel_x(i, step)) << set << " row " << r;
    EXPECT_EQ(vel.values[3 * k + 1], vel_y(i, step)) << set << " row " << r;
    EXPECT_EQ(vel.values[3 * k + 2], 0.0) << set << " row " << r;
    EXPECT_EQ(rho.values[k], density(i, step)) << set << " row " << r;
  }
  EXPECT_EQ(read_string_attribute(file, (g + "/velocity").c_str(), "units"), "m/s");
  EXPECT_EQ(read_string_attribute(file, (g + "/position").c_str(), "units"), "m");
}

void expect_snapshot(const std::string& path, std::int64_t step, double time) {
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  EXPECT_EQ(read_attribute<double>(file, "/", "time", H5T_NATIVE_DOUBLE), time);
  EXPECT_EQ(read_attribute<std::int64_t>(file, "/", "step", H5T_NATIVE_INT64), step);
  EXPECT_EQ(read_attribute<int>(file, "/", "dimension", H5T_NATIVE_INT), 2);
  EXPECT_EQ(read_string_attribute(file, "/", "case"), "iotest");
  EXPECT_EQ(read_string_attribute(file, "/", "sphdem_version"), SPHDEM_VERSION);
  expect_set(file, "fluid", kFluidFirstId, kFluidCount, step);
  expect_set(file, "wall", 0, kWallCount, step);
  const Array p = read_array(file, "/fluid/pressure", false);
  for (std::int64_t r = 0; r < kFluidCount; ++r)
    EXPECT_EQ(p.values[static_cast<std::size_t>(r)], pressure(kFluidFirstId + r, step));
  H5Fclose(file);
}

std::vector<std::string> directory_listing(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST(SnapshotWriter, TwoSetsTwoSnapshotsInIdOrder) {
  const Comm comm;
  const std::string dir = output_dir(comm, "two_snapshots");
  SnapshotWriter writer(comm, dir, "iotest");
  OwnedSet fluid = fluid_of(comm);
  OwnedSet wall = wall_of(comm);
  const std::vector<std::pair<std::int64_t, double>> steps = {{10, 0.1}, {20, 0.2}};
  std::vector<std::string> paths;
  for (const auto& [step, time] : steps) {
    fluid.fill(step);
    wall.fill(step);
    paths.push_back(writer.write(step, time, {fluid.view(), wall.view()}));
  }
  EXPECT_EQ(paths[0], (fs::path(dir) / "iotest_00000010.h5").string());
  if (!comm.root()) return;
  for (std::size_t k = 0; k < steps.size(); ++k)
    expect_snapshot(paths[k], steps[k].first, steps[k].second);
  // Only the published files: no temporary left behind.
  EXPECT_EQ(directory_listing(dir),
            (std::vector<std::string>{"iotest.xdmf", "iotest_00000010.h5", "iotest_00000020.h5"}));
  const std::string xdmf = read_text(writer.xdmf_path());
  EXPECT_NE(xdmf.find("<Xdmf Version=\"3.0\""), std::string::npos);
  EXPECT_NE(xdmf.find(time_text(0.1)), std::string::npos);
  EXPECT_NE(xdmf.find(time_text(0.2)), std::string::npos);
  EXPECT_NE(xdmf.find("iotest_00000020.h5:/wall/position"), std::string::npos);
  // One temporal collection per set, fluid before wall, each with a grid of
  // its own name per snapshot: the names ParaView gives the blocks
  // (docs/tools.md, "ParaView"; tests/check_paraview_sets.py).
  const std::string fluid_collection =
      "<Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Temporal\">";
  const std::string wall_collection =
      "<Grid Name=\"wall\" GridType=\"Collection\" CollectionType=\"Temporal\">";
  ASSERT_NE(xdmf.find(fluid_collection), std::string::npos);
  ASSERT_NE(xdmf.find(wall_collection), std::string::npos);
  EXPECT_LT(xdmf.find(fluid_collection), xdmf.find(wall_collection));
  const auto count = [&](const std::string& s) {
    std::size_t n = 0;
    for (auto at = xdmf.find(s); at != std::string::npos; at = xdmf.find(s, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<Grid Name=\"fluid\" GridType=\"Uniform\">"), 2u);
  EXPECT_EQ(count("<Grid Name=\"wall\" GridType=\"Uniform\">"), 2u);
  EXPECT_EQ(count("CollectionType=\"Spatial\""), 0u);
}

TEST(SnapshotWriter, RewritingAStepReplacesItsEntry) {
  const Comm comm;
  const std::string dir = output_dir(comm, "rewrite");
  SnapshotWriter writer(comm, dir, "iotest");
  OwnedSet fluid = fluid_of(comm);
  fluid.fill(5);
  writer.write(5, 0.5, {fluid.view()});
  writer.write(5, 0.75, {fluid.view()});
  if (!comm.root()) return;
  const std::string xdmf = read_text(writer.xdmf_path());
  EXPECT_EQ(xdmf.find(time_text(0.5)), std::string::npos);
  EXPECT_NE(xdmf.find(time_text(0.75)), std::string::npos);
}

TEST(SnapshotWriter, SetEmptyOnEveryRankIsWrittenButNotIndexed) {
  const Comm comm;
  const std::string dir = output_dir(comm, "empty_set");
  SnapshotWriter writer(comm, dir, "iotest");
  OwnedSet fluid = fluid_of(comm);
  OwnedSet probe{"probe", false, {}, {}, {}, {}, {}};
  fluid.fill(1);
  probe.fill(1);
  const std::string path = writer.write(1, 1e-3, {fluid.view(), probe.view()});
  if (!comm.root()) return;
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_attribute<std::int64_t>(file, "/probe", "count", H5T_NATIVE_INT64), 0);
  EXPECT_EQ(read_array(file, "/probe/position", false).dims, (std::vector<hsize_t>{0, 3}));
  EXPECT_EQ(read_array(file, "/probe/id", true).dims, (std::vector<hsize_t>{0}));
  H5Fclose(file);
  const std::string xdmf = read_text(writer.xdmf_path());
  EXPECT_NE(xdmf.find("Name=\"fluid\""), std::string::npos);
  EXPECT_EQ(xdmf.find("probe"), std::string::npos);
}

TEST(SnapshotWriter, IdGapThrowsOnEveryRankNamingTheSet) {
  const Comm comm;
  const std::string dir = output_dir(comm, "id_gap");
  SnapshotWriter writer(comm, dir, "iotest");
  OwnedSet fluid = fluid_of(comm);
  if (comm.root()) fluid.id.front() += 100;  // leaves a hole in the range
  fluid.fill(0);
  try {
    writer.write(0, 0.0, {fluid.view()});
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'fluid'"), std::string::npos) << e.what();
  }
  // Rejected before any file was created.
  if (comm.root()) {
    EXPECT_TRUE(fs::is_empty(dir));
  }
}

TEST(SnapshotWriter, UncreatableDirectoryThrowsWithThePath) {
  const Comm comm;
  const std::string dir = output_dir(comm, "not_a_dir");
  if (comm.root()) {
    fs::create_directories(dir);
    std::ofstream(dir + "/file") << "x";
  }
  comm.barrier();
  const std::string bad = dir + "/file/sub";
  try {
    SnapshotWriter writer(comm, bad, "iotest");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}
