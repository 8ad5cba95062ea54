// What a checkpoint belongs to (case_identity) and when to write one
// (CheckpointCadence), see checkpoint.hpp and docs/checkpoint.md.
#include <fmt/format.h>

#include <chrono>
#include <sstream>

#include "sphdem/config/config.hpp"
#include "sphdem/io/checkpoint.hpp"

namespace sphdem {

// Generated from the key schema (docs/case-file.md): every key marked
// "identity", its value as `key = value` (doubles as the shortest text that
// reads back to the same bits).
std::vector<std::string> case_identity(const Case& c) {
  std::vector<std::string> id;
  for (const Setting& s : case_settings(c))
    if (s.identity) id.push_back(s.key + " = " + s.value);
  return id;
}

std::string case_identity_text(const Case& c) {
  std::string out;
  for (const std::string& l : case_identity(c)) out += l + "\n";
  return out;
}

void check_case_identity(const Case& c, const std::string& stored, const std::string& file) {
  std::vector<std::string> theirs;
  std::istringstream in(stored);
  for (std::string line; std::getline(in, line);) theirs.push_back(line);
  const std::vector<std::string> ours = case_identity(c);
  auto key_of = [](const std::string& line) { return line.substr(0, line.find(" = ")); };
  if (!theirs.empty() && theirs.front() != ours.front()) {
    throw InputError(file, 0, "",
                     fmt::format("the checkpoint belongs to case '{}', not '{}'",
                                 theirs.front().substr(7), c.name));
  }
  std::vector<std::string> diffs;
  for (const std::string& line : ours) {
    const std::string key = key_of(line);
    const auto it = std::find_if(theirs.begin(), theirs.end(),
                                 [&](const std::string& t) { return key_of(t) == key; });
    if (it == theirs.end())
      diffs.push_back(fmt::format("{} (not in the checkpoint)", key));
    else if (*it != line)
      diffs.push_back(fmt::format("{} is {} there, {} here", key, it->substr(key.size() + 3),
                                  line.substr(key.size() + 3)));
  }
  for (const std::string& t : theirs) {
    const std::string key = key_of(t);
    if (std::none_of(ours.begin(), ours.end(),
                     [&](const std::string& l) { return key_of(l) == key; }))
      diffs.push_back(fmt::format("{} (only in the checkpoint)", key));
  }
  if (diffs.empty()) return;
  std::string list;
  for (std::size_t k = 0; k < diffs.size() && k < 5; ++k) list += (k ? "; " : "") + diffs[k];
  if (diffs.size() > 5) list += fmt::format("; and {} more", diffs.size() - 5);
  throw InputError(file, 0, "",
                   fmt::format("the checkpoint was written for a different version of case '{}' "
                               "(only output, end_time, parallel and checkpoint keys may change "
                               "on restart): {}",
                               c.name, list));
}

namespace {
double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

CheckpointCadence::CheckpointCadence(const CheckpointSettings& s,
                                     std::optional<std::int64_t> every_steps,
                                     std::function<bool()> stop_requested)
    : every_steps_(every_steps ? *every_steps : s.every_steps.value_or(0)),
      every_seconds_(60.0 * s.every_minutes.value_or(0.0)),
      keep_(s.keep),
      stop_(std::move(stop_requested)),
      last_(now_seconds()) {}

CheckpointCadence::Decision CheckpointCadence::after_step(const Comm& comm,
                                                          std::int64_t step) const {
  Decision d;
  d.write = every_steps_ > 0 && step % every_steps_ == 0;
  if (!stop_ && every_seconds_ <= 0) return d;  // nothing to agree on: no collective
  // 2: stop (and write), 1: the wall clock says write. Rank 0's clock rules.
  std::int64_t flag = stop_ && stop_() ? 2 : 0;
  if (comm.root() && every_seconds_ > 0 && now_seconds() - last_ >= every_seconds_)
    flag = std::max<std::int64_t>(flag, 1);
  flag = comm.max(flag);
  d.write = d.write || flag >= 1;
  d.stop = flag >= 2;
  return d;
}

void CheckpointCadence::written() {
  last_ = now_seconds();
}

}  // namespace sphdem
