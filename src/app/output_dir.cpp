#include "output_dir.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "sphdem/core/errors.hpp"

namespace sphdem::app {

namespace {

namespace fs = std::filesystem;

// The files sphdem writes into an output directory.
bool written_by_sphdem(const fs::directory_entry& e) {
  const std::string name = e.path().filename().string();
  const auto ends_with = [&](const std::string& s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  if (name == "checkpoints" || name == "case.yaml" || name == "timings.csv" ||
      name == "timings.json" || ends_with(".xdmf"))
    return true;
  if (name.front() == '.' && ends_with(".tmp")) return true;  // interrupted writes
  // Snapshots: <case>_<digits>.h5
  if (!ends_with(".h5")) return false;
  const std::string stem = name.substr(0, name.size() - 3);
  const std::size_t underscore = stem.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == stem.size()) return false;
  return std::all_of(stem.begin() + static_cast<long>(underscore) + 1, stem.end(),
                     [](char ch) { return ch >= '0' && ch <= '9'; });
}

}  // namespace

void prepare_output_dir(const Comm& comm, const std::string& dir, bool restart, bool overwrite) {
  std::string error;
  if (comm.root() && !restart) {
    std::error_code ec;
    std::vector<fs::path> earlier;
    if (fs::is_directory(dir, ec)) {
      for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
        if (written_by_sphdem(e)) earlier.push_back(e.path());
    }
    if (!earlier.empty() && !overwrite) {
      error =
          "holds the output of an earlier run: pass --restart latest to continue it, or "
          "--overwrite to replace it";
    } else {
      for (const fs::path& p : earlier) fs::remove_all(p, ec);
    }
  }
  if (comm.any(!error.empty()))
    throw InputError(dir, 0, "", error.empty() ? "rejected on rank 0" : error);
}

}  // namespace sphdem::app
