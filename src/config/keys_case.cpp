// The top-level keys of a case file (docs/case-file.md), in the order they
// are read: later keys use earlier ones (the dimension, the resin, the
// periodic axes).
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "schema.hpp"

namespace sphdem::config {

namespace {

bool any_periodic(const Case& c) {
  return std::count(c.periodic.begin(), c.periodic.end(), true) > 0;
}

// Output files are named after the case: a name must be a plain file name
// (no '/', which would write outside the output directory, no spaces or
// control characters, not hidden).
bool file_name_safe(const std::string& s) {
  constexpr std::size_t kMaxName = 100;
  if (s.empty() || s.size() > kMaxName || s.front() == '.' || s.front() == '-') return false;
  return std::all_of(s.begin(), s.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.' ||
           ch == '+';
  });
}

// The file's stem, with the characters a name may not hold replaced by '_'.
std::string name_from_file(const std::string& file) {
  std::string stem = std::filesystem::path(file).stem().string();
  for (char& ch : stem)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '.' && ch != '+')
      ch = '_';
  if (stem.size() > 100) stem.resize(100);
  if (stem.empty() || stem.front() == '.' || stem.front() == '-') stem.insert(0, "case");
  return stem;
}

Key<Case> name() {
  Key<Case> k = string("name", &Case::name, "the case's name: output files are `<name>_<step>.h5`");
  k.defaults_to("the file name without its extension, other characters than those allowed as '_'")
      .constraint("letters, digits, '_', '-', '.', '+'; at most 100; not starting with '.' or '-'")
      .when_absent([](const Map& m, Case& c, Context&) {
        c.name = name_from_file(m.self().source().file());
      });
  const auto read = k.read;
  k.read = [read](const Value& v, Case& c, Context& ctx) {
    read(v, c, ctx);
    if (!file_name_safe(c.name))
      v.fail("'" + c.name +
             "' is not a file-name-safe case name (letters, digits, '_', '-', '.', '+'; at most "
             "100; not starting with '.' or '-')");
  };
  return k;
}

Key<Case> dimension() {
  Key<Case> k{"dimension", "integer", "", "", "2 or 3", "the number of space dimensions, D"};
  k.read = [](const Value& v, Case& c, Context&) {
    const int d = v.integer();
    if (d != 2 && d != 3) v.fail("must be 2 or 3, got " + v.text());
    c.dimension = d;
  };
  k.show = [](const Case& c) { return std::to_string(c.dimension); };
  return k;
}

Key<Case> periodic() {
  Key<Case> k{"periodic",
              "list of axis names",
              "",
              "none",
              "each of x, y (and z in 3D), at most once",
              "periodic axes; they need `domain`"};
  k.read = [](const Value& v, Case& c, Context&) {
    std::vector<std::string> axes{"x", "y", "z"};
    axes.resize(static_cast<std::size_t>(c.dimension));
    for (const Value& item : v.list()) {
      const std::string axis = one_of(item, axes);
      const std::size_t d = static_cast<std::size_t>(axis[0] - 'x');
      if (c.periodic[d]) item.fail("axis '" + axis + "' is listed twice");
      c.periodic[d] = true;
    }
  };
  k.show = [](const Case& c) {
    return fmt::format("{} {} {}", c.periodic[0], c.periodic[1], c.periodic[2]);
  };
  return k;
}

Key<Case> domain() {
  Key<Case> k{"domain",
              "box",
              "m",
              "mold bounding box plus wall layers",
              "",
              "{min, max}; required when `periodic` is not empty: the period along a periodic "
              "axis is max - min"};
  k.read = [](const Value& v, Case& c, Context&) {
    const Shape box = read_box(v, c.dimension);
    c.domain_lo = box.lo;
    c.domain_hi = box.hi;
  };
  k.absent = [](const Map& m, Case& c, Context&) {
    if (any_periodic(c))
      m.require("domain", " (periodic axes need a domain: the period is max - min)");
  };
  k.show = [](const Case& c) {
    return c.domain_lo ? show_vector(*c.domain_lo) + " " + show_vector(*c.domain_hi) : "default";
  };
  k.section_doc = box_keys_doc;
  return k;
}

Key<Case> fill() {
  Key<Case> k = shape_list("fill", &Case::fill, "resin at t = 0; every shape inside the mold");
  k.defaults_to("required unless fibers is given");
  k.section_doc = [] {
    KeysDoc d = shape_keys_doc();
    d.notes =
        "A non-empty list of shapes, filled with resin particles at the start. Every\n"
        "fill shape must lie inside the mold: its corners (for a polygon: its\n"
        "vertices) and 7 more points evenly spaced along each edge must be inside the\n"
        "union of the mold shapes, or on its boundary (within 1e-9 of the mold's\n"
        "size). Sampling the edges catches concave molds (an L or a U) whose bounding\n"
        "box contains the fill but whose shape does not. A fill may span several mold\n"
        "shapes. Error: `key 'fill[0]': fill region lies outside the mold (point\n"
        "(0.01125, 0.018) is outside)`.\n";
    return d;
  };
  return k;
}

Key<Case> fibers() {
  Key<Case> k = optional_mapping("fibers", fiber_keys, &Case::fibers,
                                 "DEM fibers: with `fill`, carried by the resin (coupled); "
                                 "without, a fibers-only run; with `periodic` axes only with "
                                 "`fill` (fibers cross the periodic faces: shear cells)");
  const auto read = k.read;
  k.read = [read](const Value& v, Case& c, Context& ctx) {
    read(v, c, ctx);
    // A fibers-only run decomposes the mold's box on its own, without
    // periodic faces (dem_run.cpp).
    if (any_periodic(c) && c.fill.empty())
      v.fail("fibers with periodic axes need `fill` (a fibers-only run has no periodic faces)");
  };
  k.absent = [](const Map& m, Case&, Context&) {
    if (!m.has("fill")) m.require("fill", " (or fibers: for a case without resin)");
  };
  return k;
}

Key<Case> output() {
  Key<Case> k = mapping("output", output_keys, &Case::output, "snapshots and progress lines");
  k.absent = [](const Map&, Case& c, Context&) { output_defaults(c.output, c); };
  return k;
}

void check_fill_inside_mold(const Case& c, const Source& src) {
  for (const Shape& f : c.fill) {
    if (auto p = point_outside(f, c.mold.shapes, c.dimension)) {
      src.fail(f.line, f.key,
               "fill region lies outside the mold (point " + format_point(*p, c.dimension) +
                   " is outside)");
    }
  }
  if (c.fibers) {
    if (auto p = point_outside(c.fibers->region, c.mold.shapes, c.dimension)) {
      src.fail(c.fibers->region.line, c.fibers->region.key,
               "fiber region lies outside the mold (point " + format_point(*p, c.dimension) +
                   " is outside)");
    }
  }
}

// The Mach number is a modelling choice, not an error: warn past 0.1, where
// density errors (about Ma^2) exceed 1 %.
void warn_mach(Case& c) {
  constexpr double kMaxMach = 0.1;  // weakly compressible limit
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

// How far a moving wall's velocity table carries it by t_end: the table is
// linear between rows and held constant before the first and after the last.
Vec3a stroke(const VelocityTable& t, double t_end) {
  Vec3a d{};
  const std::size_t n = t.time.size();
  if (n == 0 || t_end <= 0) return d;
  auto add = [&](const Vec3a& v0, const Vec3a& v1, double dt) {
    for (int k = 0; k < 3; ++k) d[k] += 0.5 * (v0[k] + v1[k]) * dt;
  };
  auto at = [&](double s) {  // the table at time s, inside [time[0], time[n-1]]
    std::size_t i = 1;
    while (i < n - 1 && t.time[i] < s) ++i;
    const double w = (s - t.time[i - 1]) / (t.time[i] - t.time[i - 1]);
    Vec3a v{};
    for (int k = 0; k < 3; ++k) v[k] = (1 - w) * t.velocity[i - 1][k] + w * t.velocity[i][k];
    return v;
  };
  add(t.velocity[0], t.velocity[0], std::clamp(t.time[0], 0.0, t_end));
  for (std::size_t i = 1; i < n && t.time[i - 1] < t_end; ++i) {
    const double a = std::max(t.time[i - 1], 0.0), b = std::min(t.time[i], t_end);
    if (b > a) add(at(a), at(b), b - a);
  }
  if (t_end > t.time[n - 1])
    add(t.velocity[n - 1], t.velocity[n - 1], t_end - std::max(t.time[n - 1], 0.0));
  return d;
}

// A piston whose table carries its face into the mold and then out of it
// again by the end time (through the bottom of its bath) would crush the
// last resin into the walls: a blow-up, not a result. Warn, since a
// pressure limit may stop it earlier. Box regions only; each point of the
// leading face is followed along its path, and points that never enter the
// mold (a piston wider than its bath) are ignored. A spacing of slack: the
// paper's plates end their 30 mm bath with a 30.1 mm stroke, stopped by
// their pressure limit.
void warn_piston_stroke(Case& c) {
  constexpr int kFacePoints = 9, kPathPoints = 32;
  const int dim = c.dimension;
  for (const MovingWall& w : c.moving_walls) {
    if (w.region.type != Shape::Type::Box) continue;
    const Vec3a d = stroke(w.velocity, c.numerics.end_time);
    const double length = std::hypot(d[0], d[1], d[2]);
    if (!(length > c.numerics.spacing)) continue;
    // The face the motion leads with: the box's side along the stroke's
    // largest component.
    int k = 0;
    for (int j = 1; j < dim; ++j)
      if (std::abs(d[j]) > std::abs(d[k])) k = j;
    const double back = (length - c.numerics.spacing) / length;
    const int lateral = dim == 3 ? kFacePoints * kFacePoints : kFacePoints;
    for (int f = 0; f < lateral; ++f) {
      Vec3a q{};
      int digit = f;
      for (int j = 0; j < dim; ++j) {
        if (j == k) {
          q[j] = d[k] < 0 ? w.region.lo[j] : w.region.hi[j];
          continue;
        }
        const double s = static_cast<double>(digit % kFacePoints) / (kFacePoints - 1);
        digit /= kFacePoints;
        q[j] = w.region.lo[j] + s * (w.region.hi[j] - w.region.lo[j]);
      }
      auto along = [&](double s) {
        Vec3a p = q;
        for (int j = 0; j < 3; ++j) p[j] += s * d[j];
        return p;
      };
      bool entered = false;
      for (int i = 1; i < kPathPoints && !entered; ++i)
        entered = inside_mold(along(back * i / kPathPoints), c.mold.shapes, dim);
      const Vec3a end = along(back);
      if (!entered || inside_mold(end, c.mold.shapes, dim)) continue;
      c.warnings.push_back(fmt::format(
          "moving wall '{}' (line {}): its velocity_table carries it {:.3g} m by "
          "numerics.end_time {:.3g} s, through the mold to {}, more than a spacing outside it: "
          "it would crush the last resin into the mold's walls unless its pressure limit stops "
          "it first (shorten the stroke or the end time, or deepen the resin ahead of it)",
          w.name, w.line, length, c.numerics.end_time, format_point(along(1.0), dim)));
      break;
    }
  }
}

Section<Case> make_case() {
  Section<Case> s;
  s.keys = {
      name().identity(),
      dimension().required().identity(),
      mapping("resin", resin_keys, &Case::resin, "the resin's properties").required(),
      mapping("numerics", numerics_keys, &Case::numerics, "resolution, time step, SPH terms")
          .required(),
      mapping("mold", mold_keys, &Case::mold, "the cavity").required(),
      periodic().identity(),
      domain().identity(),
      fill().identity(),
      fibers(),
      mapping_list("moving_walls", moving_wall_keys, &Case::moving_walls,
                   "walls that move with a prescribed velocity (the piston)"),
      mapping_list("sliding_walls", sliding_wall_keys, &Case::sliding_walls,
                   "walls whose surface moves tangentially"),
      vector("body_force", "m/s^2", &Case::body_force,
             "e.g. gravity [0, -9.81]; when it has a component along a non-periodic axis the "
             "resin starts with hydrostatic densities (p = rho0 |g| depth below the highest resin "
             "particle)")
          .defaults_to("zero")
          .identity(),
      vector("initial_velocity", "m/s", &Case::initial_velocity,
             "velocity of all resin at t = 0 (e.g. the piston's, so an incompressible bath "
             "starts moving with it instead of ringing)")
          .defaults_to("zero")
          .identity(),
      mapping_list("initial_fields", initial_field_keys, &Case::initial_fields,
                   "the resin's velocity, density or pressure at t = 0 as expressions of x, y, z, "
                   "per fill region")
          .identity(),
      output(),
      mapping("parallel", parallel_keys, &Case::parallel, "load balancing across MPI ranks"),
      mapping("checkpoint", checkpoint_keys, &Case::checkpoint, "checkpoints for restart")
          .defaults_to("none (no checkpoints)"),
  };
  s.finish = [](const Map& m, Case& c, Context&) {
    check_fill_inside_mold(c, m.self().source());
    warn_mach(c);
    warn_viscous_pressure(c);
    warn_piston_stroke(c);
  };
  return s;
}

}  // namespace

const Section<Case>& top_keys() {
  static const Section<Case> s = make_case();
  return s;
}

}  // namespace sphdem::config
