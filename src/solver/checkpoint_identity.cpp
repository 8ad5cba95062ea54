// What a checkpoint belongs to (case_identity) and when to write one
// (CheckpointCadence), see checkpoint.hpp and docs/checkpoint.md.
#include <fmt/format.h>

#include <chrono>
#include <sstream>

#include "sphdem/checkpoint.hpp"

namespace sphdem {

namespace {

// Doubles as the shortest text that reads back to the same bits.
std::string num(double v) {
  return fmt::format("{}", v);
}

std::string vec(const Vec3a& v) {
  return fmt::format("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]));
}

std::string shape(const Shape& s) {
  if (s.type == Shape::Type::Box) return "box " + vec(s.lo) + " " + vec(s.hi);
  std::string out = "polygon";
  for (const auto& p : s.vertices) out += fmt::format(" [{}, {}]", num(p[0]), num(p[1]));
  return out;
}

std::string table(const VelocityTable& t) {
  std::string out;
  for (std::size_t k = 0; k < t.time.size(); ++k)
    out += fmt::format("{}{}: {}", k ? ", " : "", num(t.time[k]), vec(t.velocity[k]));
  return out;
}

}  // namespace

std::vector<std::string> case_identity(const Case& c) {
  std::vector<std::string> id;
  auto add = [&](const std::string& key, const std::string& value) {
    id.push_back(key + " = " + value);
  };
  add("name", c.name);
  add("dimension", std::to_string(c.dimension));
  add("resin.density", num(c.resin.density));
  add("resin.viscosity", num(c.resin.viscosity));
  add("resin.sound_speed", num(c.resin.sound_speed));
  add("resin.gamma", num(c.resin.gamma));
  const Numerics& n = c.numerics;
  add("numerics.spacing", num(n.spacing));
  add("numerics.h_over_spacing", num(n.h_over_spacing));
  add("numerics.cfl", num(n.cfl));
  add("numerics.force_factor", num(n.force_factor));
  add("numerics.viscous_factor", num(n.viscous_factor));
  add("numerics.fixed_dt", n.fixed_dt ? num(*n.fixed_dt) : "none");
  add("numerics.viscosity_model", n.viscosity_model == ViscosityModel::Morris ? "morris" : "none");
  add("numerics.lattice_correction", n.lattice_correction ? "true" : "false");
  add("numerics.artificial_viscosity", num(n.artificial_viscosity));
  add("numerics.delta_sph", num(n.delta_sph));
  add("numerics.anti_clump", n.anti_clump ? "true" : "false");
  add("numerics.anti_clump_epsilon", num(n.anti_clump_epsilon));
  add("numerics.anti_clump_exponent", std::to_string(n.anti_clump_exponent));
  add("numerics.neighbor_skin", num(n.neighbor_skin));
  add("mold.wall_layers", std::to_string(c.mold.wall_layers));
  for (std::size_t k = 0; k < c.mold.shapes.size(); ++k)
    add(fmt::format("mold.shapes[{}]", k), shape(c.mold.shapes[k]));
  for (std::size_t k = 0; k < c.fill.size(); ++k) add(fmt::format("fill[{}]", k), shape(c.fill[k]));
  if (c.fibers) {
    const FiberSettings& f = *c.fibers;
    add("fibers.count", std::to_string(f.count));
    add("fibers.area_fraction", num(f.area_fraction));
    add("fibers.particles_per_fiber", std::to_string(f.particles_per_fiber));
    add("fibers.diameter", num(f.diameter));
    add("fibers.density", num(f.density));
    add("fibers.youngs_modulus", num(f.youngs_modulus));
    add("fibers.tensile_strength", f.tensile_strength ? num(*f.tensile_strength) : "none");
    add("fibers.shear_strength", f.shear_strength ? num(*f.shear_strength) : "none");
    add("fibers.stiffness_ratio", num(f.stiffness_ratio));
    add("fibers.contact_stiffness_fraction", num(f.contact_stiffness_fraction));
    add("fibers.restitution", num(f.restitution));
    add("fibers.friction", num(f.friction));
    add("fibers.region", shape(f.region));
    add("fibers.angle", f.angle ? num(*f.angle) : "random");
    add("fibers.seed", std::to_string(f.seed));
    add("fibers.dt_safety", num(f.dt_safety));
  }
  for (std::size_t k = 0; k < c.moving_walls.size(); ++k) {
    const MovingWall& w = c.moving_walls[k];
    const std::string key = fmt::format("moving_walls[{}]", k);
    add(key + ".name", w.name);
    add(key + ".region", shape(w.region));
    add(key + ".velocity_table", table(w.velocity));
    add(key + ".pressure_limit", w.pressure_limit ? num(*w.pressure_limit) : "none");
    add(key + ".pressure_relax_time", num(w.pressure_relax_time));
    add(key + ".adhesion_pressure", num(w.adhesion_pressure));
  }
  for (std::size_t k = 0; k < c.sliding_walls.size(); ++k) {
    const SlidingWall& w = c.sliding_walls[k];
    const std::string key = fmt::format("sliding_walls[{}]", k);
    add(key + ".name", w.name);
    add(key + ".region", shape(w.region));
    add(key + ".velocity", vec(w.velocity));
  }
  add("body_force", vec(c.body_force));
  add("initial_velocity", vec(c.initial_velocity));
  add("periodic", fmt::format("{} {} {}", c.periodic[0], c.periodic[1], c.periodic[2]));
  add("domain", c.domain_lo ? vec(*c.domain_lo) + " " + vec(*c.domain_hi) : "default");
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
