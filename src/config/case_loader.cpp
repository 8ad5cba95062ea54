// The case-file schema (docs/case-file.md): YAML tree -> validated Case.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "fibers_reader.hpp"
#include "overrides.hpp"
#include "shapes.hpp"
#include "sphdem/config.hpp"
#include "sphdem/errors.hpp"
#include "sphdem/particles.hpp"
#include "yaml_reader.hpp"

namespace sphdem {

namespace {

using config::Interval;
using config::Map;
using config::Source;
using config::Value;

constexpr Interval kUnitInterval{0, 1, true, false};  // (0, 1]
constexpr double kMaxMach = 0.1;                      // weakly compressible limit

std::string one_of(const Value& v, const std::vector<std::string>& allowed) {
  const std::string s = v.string();
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    v.fail("unknown value '" + s + "'" + config::suggestion(s, allowed));
  }
  return s;
}

std::string format_point(const Vec3a& p, int dim) {
  std::string s = "(";
  for (int d = 0; d < dim; ++d) s += fmt::format("{}{:.6g}", d ? ", " : "", p[d]);
  return s + ")";
}

int read_dimension(const Value& v) {
  const int d = v.integer();
  if (d != 2 && d != 3) v.fail("must be 2 or 3, got " + v.text());
  return d;
}

// c0 is given directly, or as reference_velocity / mach; exactly one way.
double read_sound_speed(const Map& m) {
  const std::optional<Value> c0 = m.get("sound_speed");
  const std::optional<Value> mach = m.get("mach");
  const std::optional<Value> vref = m.get("reference_velocity");
  if (c0 && (mach || vref)) {
    const Value& extra = mach ? *mach : *vref;
    extra.fail("give either sound_speed or mach with reference_velocity, not both");
  }
  if (c0) return config::positive(*c0);
  if (!mach && !vref) {
    m.require("sound_speed", " (give sound_speed, or both mach and reference_velocity)");
  }
  const double ma = config::positive(m.require("mach", " (needed with reference_velocity)"));
  return config::positive(m.require("reference_velocity", " (needed with mach)")) / ma;
}

Resin read_resin(const Value& v) {
  const Map m =
      v.map({"density", "viscosity", "sound_speed", "mach", "reference_velocity", "gamma"});
  Resin r;
  r.density = config::positive(m.require("density"));
  r.viscosity = config::non_negative(m.require("viscosity"));
  r.sound_speed = read_sound_speed(m);
  if (auto g = m.get("gamma")) r.gamma = config::positive(*g);
  return r;
}

// A fixed time step must respect the CFL and viscous limits that the
// adaptive step would (with |v|max = 0, the most lenient case).
void check_fixed_dt(const Map& m, const Numerics& n, const Resin& r) {
  const std::optional<Value> v = m.get("fixed_dt");
  if (!v) return;
  const double h = n.h_over_spacing * n.spacing;
  const double cfl_limit = n.cfl * h / r.sound_speed;
  if (*n.fixed_dt > cfl_limit) {
    v->fail(fmt::format("{} s exceeds the stable limit cfl*h/c0 = {:.4g} s", v->text(), cfl_limit));
  }
  const double visc_limit = n.viscous_factor * h * h * r.density / r.viscosity;
  if (r.viscosity > 0 && *n.fixed_dt > visc_limit) {
    v->fail(
        fmt::format("{} s exceeds the stable limit viscous_factor*h^2*density/viscosity = {:.4g} s",
                    v->text(), visc_limit));
  }
  if (!(n.end_time > *n.fixed_dt)) {
    const Value end_time = m.require("end_time");
    end_time.fail(fmt::format("must be greater than numerics.fixed_dt ({} s)", v->text()));
  }
}

void read_numerics_options(const Map& m, Numerics& n) {
  if (auto x = m.get("h_over_spacing")) {
    n.h_over_spacing = config::in_interval(*x, {1, 3, false, false});
  }
  if (auto x = m.get("cfl")) n.cfl = config::in_interval(*x, kUnitInterval);
  if (auto x = m.get("force_factor")) n.force_factor = config::in_interval(*x, kUnitInterval);
  if (auto x = m.get("viscous_factor")) n.viscous_factor = config::in_interval(*x, kUnitInterval);
  if (auto x = m.get("fixed_dt")) n.fixed_dt = config::positive(*x);
  if (auto x = m.get("viscosity_model")) {
    n.viscosity_model =
        one_of(*x, {"morris", "none"}) == "morris" ? ViscosityModel::Morris : ViscosityModel::None;
  }
  if (auto x = m.get("artificial_viscosity")) n.artificial_viscosity = config::non_negative(*x);
  if (auto x = m.get("delta_sph")) n.delta_sph = config::non_negative(*x);
  if (auto x = m.get("anti_clump")) n.anti_clump = x->boolean();
  if (auto x = m.get("lattice_correction")) n.lattice_correction = x->boolean();
  if (auto x = m.get("anti_clump_epsilon")) n.anti_clump_epsilon = config::non_negative(*x);
  if (auto x = m.get("anti_clump_exponent")) {
    n.anti_clump_exponent = config::integer_at_least(*x, 1);
  }
  if (auto x = m.get("neighbor_skin")) {
    n.neighbor_skin = config::in_interval(*x, {0, 1, false, true});
  }
}

Numerics read_numerics(const Value& v, const Resin& r) {
  const Map m =
      v.map({"spacing", "h_over_spacing", "cfl", "force_factor", "viscous_factor", "fixed_dt",
             "end_time", "viscosity_model", "artificial_viscosity", "delta_sph", "anti_clump",
             "anti_clump_epsilon", "anti_clump_exponent", "neighbor_skin", "lattice_correction"});
  Numerics n;
  n.spacing = config::positive(m.require("spacing"));
  n.end_time = config::positive(m.require("end_time"));
  read_numerics_options(m, n);
  check_fixed_dt(m, n, r);
  return n;
}

Mold read_mold(const Value& v, int dim) {
  const Map m = v.map({"wall_layers", "shapes"});
  Mold mold;
  if (auto x = m.get("wall_layers")) mold.wall_layers = config::integer_at_least(*x, 1);
  mold.shapes = config::read_shape_list(m.require("shapes"), dim);
  return mold;
}

// Rows [t, v_x, v_y(, v_z)] with strictly increasing t.
VelocityTable read_velocity_table(const Value& v, int dim) {
  const std::vector<Value> rows = v.list();
  if (rows.empty()) {
    v.fail("needs at least one row [t, v_x, v_y" + std::string(dim == 3 ? ", v_z]" : "]"));
  }
  VelocityTable table;
  for (const Value& row : rows) {
    const std::vector<Value> cells = row.list();
    if (cells.size() != static_cast<std::size_t>(dim + 1)) {
      row.fail(fmt::format("expected {} numbers [t, velocity] (dimension {}), got {}", dim + 1, dim,
                           cells.size()));
    }
    const double t = cells[0].number();
    if (!table.time.empty() && !(t > table.time.back())) {
      cells[0].fail(
          fmt::format("times must be strictly increasing ({} after {})", t, table.time.back()));
    }
    Vec3a vel{};
    for (int d = 0; d < dim; ++d) vel[d] = cells[d + 1].number();
    table.time.push_back(t);
    table.velocity.push_back(vel);
  }
  return table;
}

// Wall names are unique across both kinds: the output's wall_id and the
// log refer to walls by name.
class WallNames {
 public:
  std::string claim(const Value& name) {
    const auto [it, fresh] = first_use_.emplace(name.string(), name.key());
    if (!fresh) name.fail("duplicate wall name '" + it->first + "' (also " + it->second + ")");
    return it->first;
  }

 private:
  std::map<std::string, std::string> first_use_;  // name -> key where first used
};

MovingWall read_moving_wall(const Value& v, int dim, WallNames& names) {
  const Map m = v.map({"name", "region", "velocity_table", "pressure_limit", "pressure_relax_time",
                       "adhesion_pressure"});
  MovingWall w;
  w.name = names.claim(m.require("name"));
  w.region = config::read_shape(m.require("region"), dim);
  w.velocity = read_velocity_table(m.require("velocity_table"), dim);
  if (auto x = m.get("pressure_limit")) w.pressure_limit = config::positive(*x);
  if (auto x = m.get("pressure_relax_time")) w.pressure_relax_time = config::positive(*x);
  if (auto x = m.get("adhesion_pressure")) w.adhesion_pressure = config::non_negative(*x);
  w.line = v.line();
  return w;
}

SlidingWall read_sliding_wall(const Value& v, int dim, WallNames& names) {
  const Map m = v.map({"name", "region", "velocity"});
  SlidingWall w;
  w.name = names.claim(m.require("name"));
  w.region = config::read_shape(m.require("region"), dim);
  w.velocity = m.require("velocity").vector(dim);
  w.line = v.line();
  return w;
}

void read_walls(const Map& top, Case& c) {
  WallNames names;
  if (auto list = top.get("moving_walls")) {
    for (const Value& w : list->list())
      c.moving_walls.push_back(read_moving_wall(w, c.dimension, names));
  }
  if (auto list = top.get("sliding_walls")) {
    for (const Value& w : list->list())
      c.sliding_walls.push_back(read_sliding_wall(w, c.dimension, names));
  }
}

void read_periodic(const Map& top, Case& c) {
  std::vector<std::string> axes{"x", "y", "z"};
  axes.resize(static_cast<std::size_t>(c.dimension));
  const std::optional<Value> periodic = top.get("periodic");
  if (periodic) {
    for (const Value& item : periodic->list()) {
      const std::string axis = one_of(item, axes);
      const std::size_t d = static_cast<std::size_t>(axis[0] - 'x');
      if (c.periodic[d]) item.fail("axis '" + axis + "' is listed twice");
      c.periodic[d] = true;
    }
  }
  if (auto domain = top.get("domain")) {
    const Shape box = config::read_box(*domain, c.dimension);
    c.domain_lo = box.lo;
    c.domain_hi = box.hi;
  } else if (std::count(c.periodic.begin(), c.periodic.end(), true) > 0) {
    top.require("domain", " (periodic axes need a domain: the period is max - min)");
  }
}

Output read_output(const std::optional<Value>& v, const Case& c) {
  Output o;
  o.directory = "out/" + c.name;
  if (v) {
    const Map m = v->map({"directory", "every_time", "every_steps", "fields", "progress_every"});
    if (auto x = m.get("directory")) o.directory = x->string();
    if (auto x = m.get("every_time")) o.every_time = config::positive(*x);
    if (auto x = m.get("every_steps")) o.every_steps = config::integer_at_least(*x, 1);
    if (auto x = m.get("progress_every")) o.progress_every = config::integer_at_least(*x, 1);
    if (auto x = m.get("fields")) {
      o.fields.clear();
      for (const Value& f : x->list()) {
        const std::string name = one_of(f, sph_output_fields());  // the registry's
        if (std::find(o.fields.begin(), o.fields.end(), name) != o.fields.end())
          f.fail("field '" + name + "' is listed twice");
        o.fields.push_back(name);
      }
    }
  }
  if (!o.every_time && !o.every_steps) o.every_time = c.numerics.end_time / 100;
  return o;
}

ParallelSettings read_parallel(const std::optional<Value>& v) {
  ParallelSettings p;
  if (!v) return p;
  const Map m = v->map({"balance_every", "imbalance_threshold"});
  if (auto x = m.get("balance_every")) p.balance_every = config::integer_at_least(*x, 0);
  if (auto x = m.get("imbalance_threshold")) p.imbalance_threshold = config::non_negative(*x);
  return p;
}

CheckpointSettings read_checkpoint(const std::optional<Value>& v) {
  CheckpointSettings k;
  if (!v) return k;
  const Map m = v->map({"every_steps", "every_minutes", "keep"});
  if (auto x = m.get("every_steps")) k.every_steps = config::integer_at_least(*x, 1);
  if (auto x = m.get("every_minutes")) k.every_minutes = config::positive(*x);
  if (auto x = m.get("keep")) k.keep = config::integer_at_least(*x, 1);
  return k;
}

void check_fill_inside_mold(const Case& c, const Source& src) {
  for (const Shape& f : c.fill) {
    if (auto p = config::point_outside(f, c.mold.shapes, c.dimension)) {
      src.fail(f.line, f.key,
               "fill region lies outside the mold (point " + format_point(*p, c.dimension) +
                   " is outside)");
    }
  }
}

// The Mach number is a modelling choice, not an error: warn past 0.1, where
// density errors (about Ma^2) exceed 1 %.
void warn_mach(Case& c) {
  double vmax = 0;
  auto norm = [](const Vec3a& v) { return std::hypot(v[0], v[1], v[2]); };
  for (const MovingWall& w : c.moving_walls) {
    for (const Vec3a& v : w.velocity.velocity) vmax = std::max(vmax, norm(v));
  }
  for (const SlidingWall& w : c.sliding_walls) vmax = std::max(vmax, norm(w.velocity));
  const double mach = vmax / c.resin.sound_speed;
  if (mach > kMaxMach) {
    c.warnings.push_back(fmt::format(
        "Mach number {:.3g} (wall speed {:.3g} m/s, sound speed {:.3g} m/s) exceeds {}: expect "
        "density errors of about {:.2g} %",
        mach, vmax, c.resin.sound_speed, kMaxMach, 100 * mach * mach));
  }
}

// What the mold holds at the start: resin (fill), fibers, or both (coupled).
void read_contents(const Map& top, Case& c) {
  const std::optional<Value> fill = top.get("fill");
  const std::optional<Value> fibers = top.get("fibers");
  if (!fill && !fibers) top.require("fill", " (or fibers: for a case without resin)");
  if (fill) c.fill = config::read_shape_list(*fill, c.dimension);
  if (fibers) {
    c.fibers = config::read_fibers(*fibers, c.dimension);
    // A pair and its periodic image would both be listed (dem.hpp).
    if (std::count(c.periodic.begin(), c.periodic.end(), true) > 0)
      fibers->fail("fibers with periodic axes are not supported");
  }
}

Case read_case(const Value& root, const Source& src) {
  const Map top = root.map({"name", "dimension", "resin", "numerics", "mold", "fill",
                            "moving_walls", "sliding_walls", "body_force", "initial_velocity",
                            "periodic", "domain", "output", "parallel", "fibers", "checkpoint"});
  Case c;
  c.dimension = read_dimension(top.require("dimension"));
  const std::optional<Value> name = top.get("name");
  c.name = name ? name->string() : std::filesystem::path(src.file()).stem().string();
  c.resin = read_resin(top.require("resin"));
  c.numerics = read_numerics(top.require("numerics"), c.resin);
  c.mold = read_mold(top.require("mold"), c.dimension);
  read_periodic(top, c);
  read_contents(top, c);
  read_walls(top, c);
  if (auto x = top.get("body_force")) c.body_force = x->vector(c.dimension);
  if (auto x = top.get("initial_velocity")) c.initial_velocity = x->vector(c.dimension);
  c.output = read_output(top.get("output"), c);
  c.parallel = read_parallel(top.get("parallel"));
  c.checkpoint = read_checkpoint(top.get("checkpoint"));
  check_fill_inside_mold(c, src);
  if (c.fibers) {
    if (auto p = config::point_outside(c.fibers->region, c.mold.shapes, c.dimension)) {
      src.fail(c.fibers->region.line, c.fibers->region.key,
               "fiber region lies outside the mold (point " + format_point(*p, c.dimension) +
                   " is outside)");
    }
  }
  warn_mach(c);
  return c;
}

YAML::Node parse_yaml(const std::string& text, const std::string& file) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, "",
                     "YAML syntax error: " + e.msg);
  }
}

}  // namespace

Case load_case_from_string(const std::string& text, const std::string& name_for_errors,
                           const std::vector<std::string>& overrides) {
  YAML::Node root = parse_yaml(text, name_for_errors);
  if (root.IsNull() && overrides.empty())
    throw InputError(name_for_errors, 0, "", "the case file is empty");
  const Source src(name_for_errors, config::apply_overrides(root, overrides));
  const int root_line = root.Mark().line >= 0 ? root.Mark().line + 1 : 1;
  Case c;
  try {
    c = read_case(Value(src, root, "", root_line), src);
  } catch (const YAML::Exception& e) {
    // The reader checks node types before use, so this is a safety net that
    // keeps "bad input -> InputError" true even for a case it did not foresee.
    throw InputError(name_for_errors, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", e.what());
  }
  c.source_file = name_for_errors;
  c.source_text = text;
  return c;
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open case file");
  std::ostringstream text;
  text << in.rdbuf();
  return load_case_from_string(text.str(), path, overrides);
}

}  // namespace sphdem
