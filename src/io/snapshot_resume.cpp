// SnapshotWriter::resume (io.hpp): a restarted run continues the XDMF series
// of the run it restarts. The list of earlier snapshots is read back from
// their HDF5 files (rank 0, serially), so the restart needs nothing but the
// directory; snapshots newer than the checkpoint were written by the run
// after its last checkpoint and are written again, so they are deleted.
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <filesystem>

#include "hdf5_helpers.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/io/io.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;
using h5::check;
using h5::Handle;

// The objects of a group in the order they were written (their headers'
// file addresses grow as the writer appends), so the XDMF lists fields in
// the same order as the run that wrote them.
std::vector<std::string> children(hid_t group, const std::string& path) {
  std::vector<std::string> names;
  const auto add = [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->push_back(name);
    return 0;
  };
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, add, &names), "list group", path);
  std::vector<std::pair<haddr_t, std::string>> by_address;
  for (const std::string& name : names) {
    H5O_info_t info;
    check(H5Oget_info_by_name2(group, name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT),
          "inspect object", path);
    by_address.emplace_back(info.addr, name);
  }
  std::sort(by_address.begin(), by_address.end());
  for (std::size_t k = 0; k < names.size(); ++k) names[k] = by_address[k].second;
  return names;
}

bool is_group(hid_t parent, const std::string& name, const std::string& path) {
  H5O_info_t info;
  check(H5Oget_info_by_name2(parent, name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT),
        "inspect object", path);
  return info.type == H5O_TYPE_GROUP;
}

std::int64_t int_attribute(hid_t obj, const char* name, const std::string& path) {
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "open attribute", path);
  std::int64_t v = 0;
  check(H5Aread(attr.get(), H5T_NATIVE_INT64, &v), "read attribute", path);
  return v;
}

// Columns of a dataset in the file: 1 for [N], the second extent for [N][c].
int columns(hid_t group, const std::string& name, const std::string& path) {
  Handle d(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset", path);
  Handle s(H5Dget_space(d.get()), H5Sclose, "get dataset space", path);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(s.get());
  H5Sget_simple_extent_dims(s.get(), dims, nullptr);
  return rank == 2 ? static_cast<int>(dims[1]) : 1;
}

std::int64_t first_id(hid_t group, std::int64_t count, const std::string& path) {
  if (count == 0) return 0;
  Handle d(H5Dopen2(group, "id", H5P_DEFAULT), H5Dclose, "open dataset", path);
  Handle fs(H5Dget_space(d.get()), H5Sclose, "get dataset space", path);
  const hsize_t start = 0, one = 1;
  check(H5Sselect_hyperslab(fs.get(), H5S_SELECT_SET, &start, nullptr, &one, nullptr),
        "select first row", path);
  Handle ms(H5Screate_simple(1, &one, nullptr), H5Sclose, "create memory space", path);
  std::int64_t id = 0;
  check(H5Dread(d.get(), H5T_NATIVE_INT64, ms.get(), fs.get(), H5P_DEFAULT, &id), "read id", path);
  return id;
}

}  // namespace

void SnapshotWriter::resume(std::int64_t step) {
  std::vector<Entry> entries;
  std::string error;
  if (comm_.root()) {
    try {
      std::vector<std::pair<std::int64_t, fs::path>> files;
      const std::string prefix = case_name_ + "_";
      for (const fs::directory_entry& e : fs::directory_iterator(directory_)) {
        const std::string name = e.path().filename().string();
        // A snapshot whose write was interrupted (a crash) left its temporary.
        if (name.rfind("." + prefix, 0) == 0 && name.size() > 7 &&
            name.compare(name.size() - 7, 7, ".h5.tmp") == 0) {
          fs::remove(e.path());
          continue;
        }
        if (name.size() <= prefix.size() + 3 || name.rfind(prefix, 0) != 0 ||
            name.compare(name.size() - 3, 3, ".h5") != 0)
          continue;
        const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - 3);
        if (digits.empty() || !std::all_of(digits.begin(), digits.end(),
                                           [](char ch) { return ch >= '0' && ch <= '9'; }))
          continue;
        files.emplace_back(std::stoll(digits), e.path());
      }
      std::sort(files.begin(), files.end());
      for (const auto& [s, file] : files) {
        if (s > step) {
          fs::remove(file);
          continue;
        }
        const std::string path = file.string();
        Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open file", path);
        Entry entry;
        entry.step = s;
        entry.file = file.filename().string();
        {
          Handle attr(H5Aopen(f.get(), "time", H5P_DEFAULT), H5Aclose, "open attribute", path);
          check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &entry.time), "read attribute", path);
        }
        for (const std::string& set : children(f.get(), path)) {
          Handle g(H5Gopen2(f.get(), set.c_str(), H5P_DEFAULT), H5Gclose, "open group", path);
          SetEntry e;
          e.name = set;
          e.count = int_attribute(g.get(), "count", path);
          e.id_min = first_id(g.get(), e.count, path);
          for (const std::string& name : children(g.get(), path)) {
            if (name == "id" || name == "position") continue;
            if (name == "lines" && is_group(g.get(), name, path)) {
              Handle l(H5Gopen2(g.get(), "lines", H5P_DEFAULT), H5Gclose, "open group", path);
              e.line_count = int_attribute(l.get(), "count", path);
              for (const std::string& lf : children(l.get(), path))
                if (lf != "id" && lf != "nodes")
                  e.line_fields.emplace_back(lf, columns(l.get(), lf, path));
              continue;
            }
            e.fields.emplace_back(name, columns(g.get(), name, path));
          }
          entry.sets.push_back(std::move(e));
        }
        entries.push_back(std::move(entry));
      }
      write_xdmf(entries);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (comm_.any(!error.empty()))  // every rank throws: an agreed failure (errors.hpp)
    throw CollectiveIoError(error.empty()
                                ? "sphdem: rank 0 could not resume the snapshot series in '" +
                                      directory_ + "'"
                                : "sphdem: cannot resume the snapshot series: " + error);
  entries_ = std::move(entries);
}

}  // namespace sphdem
