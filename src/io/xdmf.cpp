// The XDMF index: one temporal collection per particle set ("fluid", "wall",
// "dem") and per set's line cells ("dem_lines"), each holding one Uniform grid
// of the same name per snapshot, every array a reference into the snapshot's
// HDF5 file (relative name, so the directory can be moved). A set is its own
// top-level collection so that XDMFReader names its block the same at every
// time step (an ExtractBlock of "dem" follows the fibers through an animation)
// and Xdmf3ReaderS keeps it at the same piece index (docs/tools.md,
// "ParaView"). Written by rank 0 only.
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "sphdem/io/io.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;

std::string escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// 17 significant digits round-trip a double, so times match the HDF5 attribute.
std::string time_element(double time) {
  return fmt::format("          <Time Value=\"{:.17g}\"/>\n", time);
}

// `ref` is "<file>:/<set>/<dataset>"; cols is 1 or 3.
std::string data_item(const std::string& ref, std::int64_t n, int cols, bool integer,
                      int indent = 12) {
  const std::string dims = cols == 1 ? std::to_string(n) : fmt::format("{} {}", n, cols);
  return fmt::format(
      "{:{}}<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"8\" "
      "Format=\"HDF\">{}</DataItem>\n",
      "", indent, dims, integer ? "Int" : "Float", escape(ref));
}

std::string attribute(const std::string& prefix, const std::string& name, std::int64_t n, int cols,
                      bool integer, const char* center = "Node") {
  return fmt::format("          <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n",
                     escape(name), cols == 1 ? "Scalar" : "Vector", center) +
         data_item(prefix + name, n, cols, integer) + "          </Attribute>\n";
}

// One vertex cell per particle. Xdmf3 readers build no cells from a Polyvertex
// topology without connectivity, and cell-less points do not render; rows are
// in id order, so id - id_min is each particle's point index (both readers
// evaluate the Function).
std::string topology(const std::string& prefix, std::int64_t n, std::int64_t id_min) {
  const std::string shift =
      id_min >= 0 ? fmt::format("$0 - {}", id_min) : fmt::format("$0 + {}", -id_min);
  return fmt::format(
             "          <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
             "NodesPerElement=\"1\">\n"
             "            <DataItem ItemType=\"Function\" Function=\"{}\" Dimensions=\"{}\">\n",
             n, shift, n) +
         data_item(prefix + "id", n, 1, true, 14) +
         "            </DataItem>\n          </Topology>\n";
}

// The set's points again, with its line cells (two-node polylines, e.g. the
// bonds of fibers) as the topology and the cells' fields as cell data.
// Geometry, ids and per-particle attributes of a set: what its point grid
// and its fiber-polyline grid share.
template <class Set>
std::string point_data(const std::string& prefix, const Set& set) {
  std::string out = "          <Geometry GeometryType=\"XYZ\">\n";
  out += data_item(prefix + "position", set.count, 3, false);
  out += "          </Geometry>\n";
  out += attribute(prefix, "id", set.count, 1, true);
  for (const auto& [name, cols] : set.fields)
    out += attribute(prefix, name, set.count, cols, false);
  return out;
}

template <class Set>
std::string lines_grid(const std::string& file, double time, const Set& set) {
  const std::string prefix = file + ":/" + set.name + "/";
  const std::string lines = prefix + "lines/";
  std::string out =
      fmt::format("        <Grid Name=\"{}_lines\" GridType=\"Uniform\">\n", escape(set.name));
  out += time_element(time);
  out += fmt::format(
      "          <Topology TopologyType=\"Polyline\" NumberOfElements=\"{}\" "
      "NodesPerElement=\"2\">\n",
      set.line_count);
  out += data_item(lines + "nodes", set.line_count, 2, true) + "          </Topology>\n";
  out += point_data(prefix, set);
  for (const auto& [name, cols] : set.line_fields)
    out += attribute(lines, name, set.line_count, cols, false, "Cell");
  return out + "        </Grid>\n";
}

template <class Set>  // SnapshotWriter::SetEntry, a private type
std::string uniform_grid(const std::string& file, double time, const Set& set) {
  const std::string prefix = file + ":/" + set.name + "/";
  std::string out =
      fmt::format("        <Grid Name=\"{}\" GridType=\"Uniform\">\n", escape(set.name));
  out += time_element(time);
  out += topology(prefix, set.count, set.id_min);
  out += point_data(prefix, set);
  return out + "        </Grid>\n";
}

}  // namespace

std::string SnapshotWriter::xdmf_text(const std::string& title, const std::vector<Entry>& entries) {
  // Sets in order of first appearance (fluid, wall, dem as the run lists them).
  std::vector<std::string> names;
  for (const auto& e : entries)
    for (const auto& s : e.sets)
      if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);

  std::string out = fmt::format(
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
      "  <Domain Name=\"{}\">\n",
      escape(title));
  // One collection per set (lines = false) and per set's line cells (lines = true).
  for (const bool lines : {false, true}) {
    for (const auto& name : names) {
      std::string grids;
      for (const auto& e : entries) {
        for (const auto& s : e.sets) {
          // Empty grids upset ParaView's readers; the set is left out of the
          // snapshots where it has no particles (or no line cells).
          if (s.name != name || s.count == 0 || (lines && s.line_count == 0)) continue;
          grids += lines ? lines_grid(e.file, e.time, s) : uniform_grid(e.file, e.time, s);
        }
      }
      if (grids.empty()) continue;
      out += fmt::format(
          "    <Grid Name=\"{}{}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          escape(name), lines ? "_lines" : "");
      out += grids + "    </Grid>\n";
    }
  }
  return out + "  </Domain>\n</Xdmf>\n";
}

void SnapshotWriter::write_xdmf(const std::vector<Entry>& entries) const {
  const std::string tmp = (fs::path(directory_) / ("." + case_name_ + ".xdmf.tmp")).string();
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::trunc);
    out << xdmf_text(case_name_, entries);
    out.close();
    if (!out) {
      // errno is the stream's last failing call's (a full disk: ENOSPC).
      const std::string why = errno != 0 ? std::string(": ") + std::strerror(errno) : "";
      std::error_code ec;
      fs::remove(tmp, ec);  // no partial file stays behind
      throw std::runtime_error("sphdem: cannot write '" + tmp + "'" + why);
    }
  }
  fs::rename(tmp, xdmf_path_);
}

}  // namespace sphdem
