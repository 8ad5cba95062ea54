// Where checkpoints live, which ones exist, and keeping the newest K.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <ostream>

#include "sphdem/io/checkpoint.hpp"

namespace sphdem {

namespace fs = std::filesystem;

CheckpointColumn take_column(std::vector<CheckpointColumn>& cols, const std::string& name,
                             const std::string& file) {
  const auto it = std::find_if(cols.begin(), cols.end(),
                               [&](const CheckpointColumn& c) { return c.name == name; });
  if (it == cols.end())
    throw InputError(file, 0, "",
                     "the checkpoint has no field '" + name +
                         "': it was written by an incompatible build of sphdem");
  CheckpointColumn c = std::move(*it);
  cols.erase(it);
  return c;
}

std::string restart_from_checkpoint(const std::string& spec, const std::string& output_dir,
                                    const std::string& case_name, const Comm& comm,
                                    std::ostream* log,
                                    const std::function<void(const std::string&)>& load) {
  const bool latest = spec == "latest";
  std::vector<std::string> candidates;
  if (latest) {
    for (const auto& [step, path] : list_checkpoints(output_dir, case_name))
      candidates.insert(candidates.begin(), path);  // newest first
    if (candidates.empty())
      throw InputError(checkpoint_directory(output_dir), 0, "",
                       fmt::format("--restart latest: no checkpoint of case '{}' here", case_name));
  } else {
    candidates.push_back(spec);
  }
  std::string newest_error;
  for (const std::string& path : candidates) {
    try {
      load(path);
      return path;
    } catch (const InputError& e) {
      if (!latest) throw;
      if (newest_error.empty()) newest_error = e.what();
      if (log && comm.root())
        *log << "skipping an unusable checkpoint: " << e.what() << "\n" << std::flush;
    }
  }
  throw InputError(checkpoint_directory(output_dir), 0, "",
                   "--restart latest: no usable checkpoint; the newest: " + newest_error);
}

std::string checkpoint_directory(const std::string& output_dir) {
  return (fs::path(output_dir) / "checkpoints").string();
}

std::string checkpoint_path(const std::string& output_dir, const std::string& case_name,
                            std::int64_t step) {
  return (fs::path(checkpoint_directory(output_dir)) /
          fmt::format("{}_{:08d}.ckpt.h5", case_name, step))
      .string();
}

std::vector<std::pair<std::int64_t, std::string>> list_checkpoints(const std::string& output_dir,
                                                                   const std::string& case_name) {
  std::vector<std::pair<std::int64_t, std::string>> out;
  const fs::path dir = checkpoint_directory(output_dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  // The case name is matched literally, the step is the digits after it.
  const std::string prefix = case_name + "_";
  const std::string suffix = ".ckpt.h5";
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.empty() ||
        !std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
      continue;
    out.emplace_back(std::stoll(digits), e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

namespace {

// Temporary files of writes that never finished (a crash mid-write).
void remove_stale_temporaries(const std::string& output_dir, const std::string& case_name) {
  std::error_code ec;
  const std::string prefix = "." + case_name + "_";
  for (const fs::directory_entry& e :
       fs::directory_iterator(checkpoint_directory(output_dir), ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && name.size() > 4 &&
        name.compare(name.size() - 4, 4, ".tmp") == 0)
      fs::remove(e.path(), ec);
  }
}

}  // namespace

void remove_stale_checkpoint_temporaries(const Comm& comm, const std::string& output_dir,
                                         const std::string& case_name) {
  if (comm.root()) remove_stale_temporaries(output_dir, case_name);
  comm.barrier();
}

void discard_checkpoints_after(const Comm& comm, const std::string& output_dir,
                               const std::string& case_name, std::int64_t step) {
  if (comm.root()) {
    std::error_code ec;
    for (const auto& [s, path] : list_checkpoints(output_dir, case_name))
      if (s > step) fs::remove(path, ec);
    remove_stale_temporaries(output_dir, case_name);
  }
  comm.barrier();
}

void prune_checkpoints(const Comm& comm, const std::string& output_dir,
                       const std::string& case_name, int keep) {
  if (comm.root()) {
    const auto all = list_checkpoints(output_dir, case_name);
    std::error_code ec;
    for (std::size_t k = 0; k + static_cast<std::size_t>(std::max(keep, 1)) < all.size(); ++k)
      fs::remove(all[k].second, ec);
    remove_stale_temporaries(output_dir, case_name);
  }
  comm.barrier();
}

}  // namespace sphdem
