// The `mold:`, `moving_walls:` and `sliding_walls:` keys (docs/case-file.md).
#include "schema.hpp"

namespace sphdem::config {

namespace {

// --- wall conditions (docs/physics.md "Wall conditions") ---------------------

constexpr const char* kSlipNames[] = {"no_slip", "free_slip", "navier_slip"};

// A setting (and identity line) only when the case gives the key, so that
// the identity of a case without wall conditions keeps its earlier lines.
template <class W>
auto only_when_given(bool (*given)(const W&), std::function<std::string(const W&)> show) {
  return [given, show](const W& w, const std::string& key, std::vector<Setting>& out) {
    if (given(w)) out.push_back({key, show(w), true, false});
  };
}

template <class W>
Key<W> wall_condition(std::string default_text) {
  Key<W> k{"wall_condition",
           "enum",
           "",
           std::move(default_text),
           "no_slip, free_slip or navier_slip",
           "what the resin sees at this wall: no_slip (it sticks), free_slip (it slides "
           "freely), navier_slip (it slides with a slip_length)"};
  k.read = [](const Value& v, W& w, Context&) {
    const std::string name = one_of(v, {kSlipNames[0], kSlipNames[1], kSlipNames[2]});
    for (int i = 0; i < 3; ++i)
      if (name == kSlipNames[i]) w.wall_condition = static_cast<WallSlip>(i);
  };
  k.show = [](const W& w) {
    return w.wall_condition ? std::string(kSlipNames[static_cast<int>(*w.wall_condition)])
                            : std::string("none");
  };
  k.section_settings =
      only_when_given<W>([](const W& w) { return w.wall_condition.has_value(); }, k.show);
  return k;
}

template <class W>
Key<W> slip_length() {
  Key<W> k = optional_number<W>("slip_length", "m", non_negative_number(), &W::slip_length,
                                "Navier slip length b (wall slip velocity = b * wall shear "
                                "rate); with navier_slip only; 0 = no-slip");
  k.defaults_to("required with navier_slip");
  k.section_settings =
      only_when_given<W>([](const W& w) { return w.slip_length.has_value(); }, k.show);
  return k;
}

template <class W>
Key<W> contact_angle(std::string default_text) {
  Key<W> k =
      optional_number<W>("contact_angle", "deg", in_range(0, 180, true, true), &W::contact_angle,
                         "with resin.surface_tension: the resin's static contact angle at this "
                         "wall, measured through the resin (docs/physics.md \"Surface tension\")");
  k.defaults_to(std::move(default_text));
  k.section_settings =
      only_when_given<W>([](const W& w) { return w.contact_angle.has_value(); }, k.show);
  return k;
}

// The thermal condition (resin.thermal): a temperature [K] the wall holds,
// and optionally a heat-transfer coefficient to it.
template <class W>
Key<W> wall_temperature(std::string default_text) {
  Key<W> k = optional_number<W>("temperature", "K", positive_number(), &W::temperature,
                                "with resin.thermal: the wall's temperature (the mold "
                                "temperature); a value below 250 K gives a Celsius warning");
  k.read = [](const Value& v, W& w, Context& ctx) {
    const double t = positive(v);
    warn_if_celsius(v, t, ctx);
    w.temperature = t;
  };
  k.defaults_to(std::move(default_text));
  k.section_settings =
      only_when_given<W>([](const W& w) { return w.temperature.has_value(); }, k.show);
  return k;
}

template <class W>
Key<W> heat_transfer_coefficient() {
  Key<W> k = optional_number<W>("heat_transfer_coefficient", "W/(m^2 K)", positive_number(),
                                &W::heat_transfer_coefficient,
                                "with temperature: the surface loses htc (T_surface - "
                                "temperature) per unit area; none: the surface is held at "
                                "temperature");
  k.defaults_to("none (held at temperature)");
  k.section_settings = only_when_given<W>(
      [](const W& w) { return w.heat_transfer_coefficient.has_value(); }, k.show);
  return k;
}

// slip_length belongs to navier_slip, and navier_slip needs it.
template <class W>
void check_wall_condition(const Map& m, W& w, Context&) {
  const bool navier = w.wall_condition == WallSlip::NavierSlip;
  if (navier && !w.slip_length) m.require("slip_length", " (wall_condition navier_slip)");
  if (!navier && w.slip_length) {
    m.require("slip_length").fail("only with wall_condition: navier_slip");
  }
  if (w.heat_transfer_coefficient && !w.temperature)
    m.require("heat_transfer_coefficient").fail("only with temperature");
}

Section<Mold> make_mold() {
  Section<Mold> s;
  s.keys = {
      integer("wall_layers", "", 1, &Mold::wall_layers,
              "layers of dummy wall particles (those beyond the support 2h are not made)")
          .identity(),
      shape_list("shapes", &Mold::shapes, "the cavity is their union; polygons in 2D only")
          .required()
          .identity(),
      wall_condition<Mold>("no_slip").identity(),
      slip_length<Mold>().identity(),
      contact_angle<Mold>("90").identity(),
      wall_temperature<Mold>("none (adiabatic)").identity(),
      heat_transfer_coefficient<Mold>().identity(),
      shape_list("vents", &Mold::vents,
                 "with output.front_events: the wall particles inside these shapes vent the "
                 "cavity; air closed in by resin and walls that vent nowhere is trapped air")
          .defaults_to("none: every wall vents"),
  };
  s.finish = check_wall_condition<Mold>;
  s.notes =
      "The cavity is the union of the shapes; walls are built around it.\n"
      "`wall_condition` applies to every wall particle that no moving or sliding\n"
      "wall claims; those take their own `wall_condition`, or this one. A wall\n"
      "region of its own condition is a sliding wall with velocity zero.\n";
  return s;
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

template <class W>
Key<W> wall_name() {
  Key<W> k{"name",
           "string",
           "",
           "",
           "unique among all walls (moving and sliding)",
           "the wall's name in the log and the output's wall_id"};
  k.read = [](const Value& v, W& w, Context& ctx) { w.name = ctx.walls.claim(v); };
  k.show = [](const W& w) { return w.name; };
  return k;
}

template <class W>
void remember_line(const Map& m, W& w, Context& ctx) {
  w.line = m.self().line();
  check_wall_condition(m, w, ctx);
}

Key<MovingWall> velocity_table() {
  Key<MovingWall> k{"velocity_table",
                    "table",
                    "s, m/s",
                    "",
                    "1 + D numbers per row; at least one row; times increasing",
                    "rows [t, v_x, v_y(, v_z)], linear in between, constant outside"};
  k.read = [](const Value& v, MovingWall& w, Context& ctx) {
    w.velocity = read_velocity_table(v, ctx.c.dimension);
  };
  k.show = [](const MovingWall& w) { return show_table(w.velocity); };
  return k;
}

Section<MovingWall> make_moving_wall() {
  using W = MovingWall;
  Section<W> s;
  s.keys = {
      wall_name<W>().required().identity(),
      shape("region", &W::region, "the wall particles inside it belong to this wall")
          .required()
          .identity(),
      velocity_table().required().identity(),
      optional_number("pressure_limit", "Pa", positive_number(), &W::pressure_limit,
                      "V/P switchover: the wall slows down to keep the resin pressure at its face "
                      "below this")
          .identity(),
      number("pressure_relax_time", "s", positive_number(), &W::pressure_relax_time,
             "how fast the pressure controller reacts")
          .identity(),
      number("adhesion_pressure", "Pa", non_negative_number(), &W::adhesion_pressure,
             "the tension the resin can take at this wall before it separates (the wall's "
             "extrapolated pressure is floored at minus this). 0: resin leaves a decelerating "
             "piston freely; 101325: a sealed piston with air at 1 atm behind the resin front "
             "(WCSPH resin in tension may then cavitate)")
          .identity(),
      wall_condition<W>("mold.wall_condition").identity(),
      slip_length<W>().identity(),
      contact_angle<W>("mold.contact_angle").identity(),
      wall_temperature<W>("mold.temperature").identity(),
      heat_transfer_coefficient<W>().identity(),
  };
  s.finish = remember_line<W>;
  s.intro = "Each item is a wall that moves with a prescribed velocity (the piston).\n";
  s.notes =
      "The velocity is interpolated linearly between rows and held constant before\n"
      "the first and after the last row. With `pressure_limit`, the wall slows down\n"
      "whenever the resin pressure at its face would exceed the limit (the\n"
      "velocity-to-pressure switchover of a molding machine); `pressure_relax_time`\n"
      "sets how fast that controller reacts. `check` and `run` warn when the\n"
      "table carries a box region's face more than a spacing out of the mold by\n"
      "`numerics.end_time` (the piston would crush the last resin into the walls).\n";
  return s;
}

Section<SlidingWall> make_sliding_wall() {
  using W = SlidingWall;
  Section<W> s;
  s.keys = {
      wall_name<W>().required().identity(),
      shape("region", &W::region, "the wall particles inside it belong to this wall")
          .required()
          .identity(),
      vector("velocity", "m/s", &W::velocity, "tangential surface velocity").required().identity(),
      wall_condition<W>("mold.wall_condition").identity(),
      slip_length<W>().identity(),
      contact_angle<W>("mold.contact_angle").identity(),
      wall_temperature<W>("mold.temperature").identity(),
      heat_transfer_coefficient<W>().identity(),
  };
  s.finish = remember_line<W>;
  s.intro =
      "Each item is a wall whose particles stay put but whose surface moves\n"
      "tangentially (a lid-driven cavity, Couette flow).\n";
  return s;
}

}  // namespace

const Section<Mold>& mold_keys() {
  static const Section<Mold> s = make_mold();
  return s;
}

const Section<MovingWall>& moving_wall_keys() {
  static const Section<MovingWall> s = make_moving_wall();
  return s;
}

const Section<SlidingWall>& sliding_wall_keys() {
  static const Section<SlidingWall> s = make_sliding_wall();
  return s;
}

}  // namespace sphdem::config
