// design files (TOML) -> DesignSpec (docs/design-format.md).
//
// one small helper layer does the checking: `Table` knows its key path and gives typed,
// range-checked values ("allowed keys" included); `Column` is a numeric series (inline
// array or CSV column) that remembers where every value was written. The section parsers
// below only say what the schema is. Cross references are collected while parsing and
// resolved at the end, each reported at the key that names it.
#include "camopt/io/design_file.hpp"
#include "camopt/io/design_document.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <system_error>
#include <utility>

#include "camopt/core/error.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/kinematics/contact_assembly.hpp"
#include "design_hla.hpp"
#include "design_parser.hpp"
#include "toml_table.hpp"

namespace camopt::io {
namespace {

using namespace toml_detail;

// ---- "file or inline arrays": two columns from a CSV file or from two inline arrays

struct Series {
  Column x, y;
  std::string source_file;  // resolved CSV path, "" when inline
};

// an xy cam profile goes once counter-clockwise around the cam centre with its polar angle
// increasing from point to point (star-shaped): a loop, a fold or a figure eight is no cam,
// and the contact search relies on the monotone angle
void check_star_shaped(const Series& s) {
  const std::vector<double>& x = s.x.values;
  const std::vector<double>& y = s.y.values;
  const std::size_t n = x.size();
  const auto polar_deg = [&](std::size_t i) { return format_value(std::atan2(y[i], x[i]) * 180.0 / std::numbers::pi, 7); };
  double turned = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const double step = std::atan2(x[i] * y[j] - x[j] * y[i], x[i] * x[j] + y[i] * y[j]);
    if (!(step > 0.0))
      s.x.fail(s.x.ref(j), "point " + std::to_string(j + 1) + " (" + format_number(x[j]) + ", " + format_number(y[j]) +
                                " mm) is at polar angle " + polar_deg(j) + " deg, not beyond point " +
                                std::to_string(i + 1) + "'s " + polar_deg(i) +
                                " deg: an xy profile runs counter-clockwise around the cam centre with its polar "
                                "angle increasing from point to point (no loop, fold or self-intersection)");
    turned += step;
  }
  if (std::abs(turned - 2.0 * std::numbers::pi) > 1e-9)
    s.x.fail(s.x.where, "the points go " + format_number(turned / (2.0 * std::numbers::pi)) +
                            " times around the cam centre; an xy profile goes round it once");
}

// x_csv: accepted CSV names of the x column; x_key / y_key: inline keys (y_key is also the
// CSV name of the y column)
Series read_series(const Table& t, const std::vector<std::string>& x_csv, std::string_view x_key,
                   std::string_view y_key) {
  if (!t.has("file")) {
    if (!t.has(x_key) && !t.has(y_key))
      t.fail("missing table: give 'file' or inline '" + std::string(x_key) + "' and '" + std::string(y_key) + "'");
    Series s{t.numbers(x_key), t.numbers(y_key), {}};
    check_same_size(s.x, s.y);
    return s;
  }
  if (t.has(x_key) || t.has(y_key))
    t.fail(t.has(x_key) ? x_key : y_key, "give either 'file' or inline arrays, not both");

  const std::string name = t.string("file");
  const SourceRef via = t.where("file");
  const fs::path path = t.context().resolve(name);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    t.fail("file", "file " + quote(name) + " not found (resolved to " + quote(path.string()) + ")");
  try {
    const CsvTable csv = read_csv(path.string());
    const std::size_t xi = csv.require_one_of(x_csv, x_key);
    const std::size_t yi = csv.require_one_of({std::string(y_key)}, y_key);
    const auto column = [&](std::size_t c) {
      // the cells' locations are kept as line numbers (Column::ref builds one for an error)
      return Column{csv.columns[c], csv.values[c], {}, SourceRef{csv.file, 0, 0, csv.columns[c]}, via, csv.lines};
    };
    return Series{column(xi), column(yi), path.string()};
  } catch (const InputError& e) {
    throw InputError(via, e.what());
  }
}

// ---- the design file

struct Reference {
  enum class To { node, control, profile, material } to;
  std::string name;
  SourceRef where;                 // the key naming it
  std::optional<NodeKind> kind;    // a node of this kind is required ...
  std::string role;                // ... by this role ("a compression spring")
  bool free_node = false;          // the node must not be set by a control
  std::optional<NodeKind> also;    // a second kind that is accepted
};

template <class Spec>
const Spec* find_named(const std::vector<Spec>& specs, const std::string& name) {
  for (const auto& spec : specs)
    if (spec.name == name) return &spec;
  return nullptr;
}

template <class Spec>
std::string names_of(const std::vector<Spec>& specs) {
  if (specs.empty()) return "none defined";
  std::string out = "defined: ";
  for (std::size_t i = 0; i < specs.size(); ++i) out += (i > 0 ? ", " : "") + specs[i].name;
  return out;
}

// names are unique within a section
template <class Spec>
void check_unique(const std::vector<Spec>& specs, const Spec& spec, const Table& t) {
  for (const auto& other : specs)
    if (other.name == spec.name)
      t.fail("name", "duplicate name " + quote(spec.name) + " (already used by " + other.where.key_path +
                         " at line " + std::to_string(other.where.line) + ")");
}

// the value of `key` as messages quote it: value 3, value "linear", boolean true
std::string value_text(const Table& t, std::string_view key) {
  const toml::node& node = t.require(key);
  if (node.is_number()) return "value " + format_number(*node.value<double>());
  if (const auto* s = node.as_string()) return "value " + quote(s->get());
  return describe(node);
}

// keys of a contact force law: on a contact connection and in a valve seat table
const Keys kContactLawKeys = {"law", "stiffness_N_per_mm", "damping_N_s_per_m", "damping_law", "restitution"};

// law = "hertz" (the default) or "linear"
ContactLaw contact_law_of(const Table& t) {
  if (!t.has("law")) return ContactLaw::hertz;
  return t.choice<ContactLaw>("law", {{"hertz", ContactLaw::hertz}, {"linear", ContactLaw::linear}});
}

// law, stiffness_N_per_mm, damping_N_s_per_m, damping_law, restitution (docs/design-format.md,
// "Contact force law"); the table's other keys are its caller's
ContactLawSpec read_contact_law(const Table& t) {
  ContactLawSpec law;
  law.law = contact_law_of(t);
  if (law.law == ContactLaw::linear) {
    if (!t.has("stiffness_N_per_mm"))
      t.fail("law", "value \"linear\" needs 'stiffness_N_per_mm' (the linear law's stiffness k in F = k d + c d')");
    law.stiffness_N_per_mm = t.number("stiffness_N_per_mm", gt(0.0));
    if (t.has("damping_law"))
      t.fail("damping_law", value_text(t, "damping_law") +
                                " is not allowed with law = \"linear\" (damping_law chooses the hertz law's "
                                "damping; the linear law's damping is linear)");
    if (t.has("restitution"))
      t.fail("restitution", value_text(t, "restitution") +
                                " is not allowed with law = \"linear\" (restitution sets the hertz law's "
                                "Hunt-Crossley damping; give damping_N_s_per_m)");
  } else {
    if (t.has("stiffness_N_per_mm"))
      t.fail("stiffness_N_per_mm", value_text(t, "stiffness_N_per_mm") +
                                       " is not allowed with law = \"hertz\" (the hertz stiffness follows from "
                                       "the materials and the geometry; stiffness_N_per_mm is for law = \"linear\")");
    if (t.has("damping_law"))
      law.damping_law = t.choice<ContactDampingLaw>(
          "damping_law", {{"hunt_crossley", ContactDampingLaw::hunt_crossley}, {"linear", ContactDampingLaw::linear}});
    law.restitution = t.optional_number("restitution", gt(0.0) & le(1.0));
    if (law.restitution && law.damping_law != ContactDampingLaw::hunt_crossley)
      t.fail("restitution", value_text(t, "restitution") +
                                " is not allowed with damping_law = \"linear\" (restitution sets the "
                                "Hunt-Crossley damping; give damping_N_s_per_m)");
    if (law.restitution && t.has("damping_N_s_per_m"))
      t.fail("restitution", value_text(t, "restitution") +
                                " is not allowed together with damping_N_s_per_m (both set the damping "
                                "coefficient; give one of them)");
  }
  law.damping_N_s_per_m = t.optional_number("damping_N_s_per_m", ge(0.0));
  return law;
}

const Keys kRootKeys = {"schema", "design", "driver", "control", "node", "profile",
                        "connection", "material", "spring", "gas_force", "oil", "hla"};

class Parser {
 public:
  explicit Parser(const Context& context) : context_(context) {}

  DesignSpec run(const toml::table& document) {
    const Table root(context_, document, "");
    root.allow(kRootKeys);
    if (const long long schema = root.integer("schema"); schema != 1)
      root.fail("schema", "value " + std::to_string(schema) + " is not a supported schema version (must be 1)");

    DesignSpec spec;
    spec.file = context_.file;
    spec.directory = context_.directory;
    parse_header(root.table("design"), spec);
    spec.driver = parse_driver(root.table("driver"));
    for (const Table& t : root.array_of_tables("control")) add(spec.controls, parse_control(t), t);
    for (const Table& t : root.array_of_tables("node")) add(spec.nodes, parse_node(t), t);
    for (const Table& t : root.array_of_tables("profile")) add(spec.profiles, parse_profile(t), t);
    for (const Table& t : root.array_of_tables("material")) add(spec.materials, parse_material(t), t);
    for (const Table& t : root.array_of_tables("connection")) add(spec.connections, parse_connection(t), t);
    for (const Table& t : root.array_of_tables("spring")) add(spec.springs, parse_spring(t), t);
    for (const Table& t : root.array_of_tables("gas_force")) spec.gas_forces.push_back(parse_gas_force(t));
    if (const auto t = root.optional_table("oil")) spec.oil = parse_oil(*t);
    parse_hlas(root, spec);
    resolve(spec);
    return spec;
  }

 private:
  template <class Spec>
  void add(std::vector<Spec>& specs, Spec spec, const Table& t) {
    check_unique(specs, spec, t);
    specs.push_back(std::move(spec));
  }

  void refer(Reference::To to, const Table& t, std::string_view key, std::optional<NodeKind> kind = {},
             std::string role = {}) {
    refer(to, t.string(key), t.where(key), kind, std::move(role));
  }
  void refer(Reference::To to, std::string name, SourceRef where, std::optional<NodeKind> kind = {},
             std::string role = {}) {
    references_.push_back({to, std::move(name), std::move(where), kind, std::move(role), false, std::nullopt});
  }

  void parse_header(const Table& t, DesignSpec& spec) {
    t.allow({"name", "description", "output_node"});
    spec.name = t.string("name");
    spec.description = t.text_or("description", "");
    spec.output_node = t.string("output_node");
    output_node_ = spec.output_node;
    refer(Reference::To::node, t, "output_node");
  }

  DriverSpec parse_driver(const Table& t) {
    t.allow({"node", "start_deg", "stop_deg", "step_deg", "crank_per_cam"});
    DriverSpec d;
    d.node = t.string("node");
    refer(Reference::To::node, t, "node");
    references_.back().free_node = true;
    // the sweep's range and step, bounded so a sweep has at most 1e6 points (docs/cli.md, "Limits")
    d.start_deg = t.number_or("start_deg", 0.0, ge(-1e6) & le(1e6));
    d.stop_deg = t.number_or("stop_deg", d.start_deg + 360.0, gt(d.start_deg, "start_deg") & le(d.start_deg + 1e6, "start_deg + 1e6"));
    d.step_deg = t.number_or("step_deg", 1.0, ge((d.stop_deg - d.start_deg) * 1e-6, "(stop_deg - start_deg) / 1e6") &
                                                  le(d.stop_deg - d.start_deg, "stop_deg - start_deg"));
    d.crank_per_cam = t.number_or("crank_per_cam", 2.0, ge(0.01) & le(100.0));
    d.where = t.where();
    return d;
  }

  ControlSpec parse_control(const Table& t) {
    t.allow({"name", "unit", "min", "max", "default"});
    ControlSpec c;
    c.name = t.string("name");
    c.unit = t.has("unit") ? t.choice<std::string>("unit", {{"deg", "deg"}, {"mm", "mm"}}) : "deg";
    c.min = t.number("min");
    c.max = t.number("max", ge(c.min, "min"));
    c.default_value = t.number_or("default", c.min, ge(c.min, "min") & le(c.max, "max"));
    c.where = t.where();
    return c;
  }

  NodeSpec parse_node(const Table& t) {
    NodeSpec n;
    n.name = t.identifier("name");
    n.kind = t.choice<NodeKind>("type", {{"rotational", NodeKind::rotational},
                                         {"translational", NodeKind::translational},
                                         {"floating", NodeKind::floating}});
    const Keys common = {"name", "type", "mass_kg", "inertia_kg_mm2", "cg_mm", "damping_ratio"};
    const Keys rotational = {"pivot_mm", "pivot_motion", "control", "rest_deg", "torsional_stiffness_Nm_per_rad",
                             "damping_Nm_s_per_rad"};
    const Keys translational = {"origin_mm", "direction", "control", "rest_mm", "axial_stiffness_N_per_mm",
                                "damping_N_s_per_m", "seat"};
    const Keys floating = {"torsional_stiffness_Nm_per_rad", "damping_Nm_s_per_rad"};
    const Keys& own = n.kind == NodeKind::rotational      ? rotational
                      : n.kind == NodeKind::translational ? translational
                                                          : floating;
    // a valve seat stops a valve's travel: only a node with a line of travel can have one
    if (n.kind != NodeKind::translational && t.has("seat"))
      t.fail("seat", value_text(t, "seat") + " is not allowed: a valve seat needs a translational node (node " +
                         quote(n.name) + " is " + to_string(n.kind) + ")");
    t.allow(concat(common, own), concat(rotational, translational),
            std::string("type = ") + quote(to_string(n.kind)));

    if (n.kind == NodeKind::rotational) {
      n.pivot_mm = t.vec2("pivot_mm");
      if (const auto m = t.optional_table("pivot_motion")) {
        m->allow({"control", "about_mm", "gain"});
        PivotMotionSpec motion;
        motion.control = m->string("control");
        refer(Reference::To::control, *m, "control");
        motion.about_mm = m->vec2("about_mm");
        motion.gain = m->number_or("gain", 1.0);
        motion.where = m->where();
        n.pivot_motion = motion;
      }
      n.rest = t.number_or("rest_deg", 0.0);
    } else if (n.kind == NodeKind::translational) {
      n.origin_mm = t.vec2("origin_mm");
      n.direction = t.direction_or("direction", {0.0, 1.0});
      n.rest = t.number_or("rest_mm", 0.0);
    }
    if (t.has("control")) {
      n.control = t.string("control");
      refer(Reference::To::control, t, "control");
    }
    n.mass_kg = t.optional_number("mass_kg", gt(0.0) & le(1000.0));
    n.inertia_kg_mm2 = t.optional_number("inertia_kg_mm2", gt(0.0) & le(1e9));
    n.cg_mm = t.optional_vec2("cg_mm");
    n.torsional_stiffness_Nm_per_rad = t.optional_number("torsional_stiffness_Nm_per_rad", gt(0.0));
    n.axial_stiffness_N_per_mm = t.optional_number("axial_stiffness_N_per_mm", gt(0.0));
    n.damping_ratio = t.optional_number("damping_ratio", ge(0.0));
    // a damper across the node's compliance: given directly, or as damping_ratio
    const auto damper = [&](std::string_view key, std::string_view stiffness_key) -> std::optional<double> {
      const std::optional<double> value = t.optional_number(key, ge(0.0));
      if (!value) return value;
      if (n.damping_ratio)
        t.fail(key, value_text(t, key) + " is not allowed together with damping_ratio (both set the damper of " +
                        "the node's compliance; give one of them)");
      if (!t.has(stiffness_key))
        t.fail(key, value_text(t, key) + " needs '" + std::string(stiffness_key) +
                        "' (the damper acts across the node's compliance; a rigid node has none)");
      return value;
    };
    if (n.kind == NodeKind::translational) {
      n.damping_N_s_per_m = damper("damping_N_s_per_m", "axial_stiffness_N_per_mm");
      if (t.has("seat")) n.seat = parse_seat(t, n.name);
    } else {
      n.damping_Nm_s_per_rad = damper("damping_Nm_s_per_rad", "torsional_stiffness_Nm_per_rad");
    }
    n.where = t.where();
    return n;
  }

  // seat = false, or seat = { ... } on a translational node
  SeatSpec parse_seat(const Table& node, const std::string& node_name) {
    SeatSpec seat;
    seat.where = node.where("seat");
    const toml::node& value = node.require("seat");
    if (value.is_boolean()) {
      if (value.as_boolean()->get())
        node.fail("seat", "boolean true: give a seat table (seat = {} for the default seat) or false for none");
      if (node_name != output_node_)
        node.fail("seat", "boolean false is allowed only on the output node (design.output_node = " +
                              quote(output_node_) + "), for a mechanism that is not a valvetrain; other nodes " +
                              "have no seat unless a seat table is given");
      seat.enabled = false;
      return seat;
    }
    if (!value.is_table()) node.fail("seat", "expected false or a seat table, got " + describe(value));

    const Table t = node.table("seat");
    const Keys geometry = {"diameter_mm", "angle_deg", "width_mm"};
    const Keys hertz_only = {"crown_radius_mm", "material"};  // the hertz law's section and E*
    const bool hertz = contact_law_of(t) == ContactLaw::hertz;
    t.allow(concat(concat(geometry, hertz ? hertz_only : Keys{}), kContactLawKeys), hertz_only, "law = \"linear\"");
    seat.law = read_contact_law(t);
    seat.diameter_mm = t.number_or("diameter_mm", seat.diameter_mm, gt(0.0));
    seat.angle_deg = t.number_or("angle_deg", seat.angle_deg, gt(0.0) & lt(90.0));
    seat.width_mm = t.number_or("width_mm", seat.width_mm, gt(0.0));
    seat.crown_radius_mm = t.number_or("crown_radius_mm", seat.crown_radius_mm, gt(0.0));
    if (t.has("material")) {
      seat.material = t.string("material");
      refer(Reference::To::material, t, "material");
    }
    seat.given = true;
    return seat;
  }

  ProfileSpec parse_profile(const Table& t) {
    ProfileSpec p;
    p.name = t.string("name");
    p.form = t.choice<ProfileForm>("form", {{"polar", ProfileForm::polar},
                                            {"xy", ProfileForm::xy},
                                            {"base_plus_lift", ProfileForm::base_plus_lift},
                                            {"circle", ProfileForm::circle},
                                            {"eccentric", ProfileForm::eccentric}});
    const Keys common = {"name", "form"};
    const Keys polar = {"file", "angle_deg", "radius_mm"};
    const Keys xy = {"file", "x_mm", "y_mm"};
    const Keys base_plus_lift = {"base_radius_mm", "file", "angle_deg", "lift_mm"};
    const Keys circle = {"disc_radius_mm"};
    const Keys eccentric = {"disc_radius_mm", "eccentricity_mm"};
    const Keys* own = &polar;
    switch (p.form) {
      case ProfileForm::polar: own = &polar; break;
      case ProfileForm::xy: own = &xy; break;
      case ProfileForm::base_plus_lift: own = &base_plus_lift; break;
      case ProfileForm::circle: own = &circle; break;
      case ProfileForm::eccentric: own = &eccentric; break;
    }
    t.allow(concat(common, *own), concat(concat(polar, xy), concat(base_plus_lift, eccentric)),
            std::string("form = ") + quote(to_string(p.form)));

    const std::vector<std::string> angle_names = {"angle_deg", "polar_angle_deg"};
    // tables of one revolution: >= 6 points, angles strictly increasing over < 360 deg
    const auto polar_table = [&](std::string_view value_key, const Rule& value_rule) {
      Series s = read_series(t, angle_names, "angle_deg", value_key);
      s.x.check_min_points(6);
      s.x.check_increasing();
      // a closed table that repeats its first point at +360 deg (common in measured data,
      // e.g. MBSim's contour.asc) is accepted: the repeat is dropped when it matches
      if (s.x.values.size() > 6 && std::abs(s.x.values.back() - s.x.values.front() - 360.0) <= 1e-9 &&
          std::abs(s.y.values.back() - s.y.values.front()) <= 1e-9 * std::max(1.0, std::abs(s.y.values.front()))) {
        for (Column* c : {&s.x, &s.y}) {
          c->values.pop_back();
          if (!c->refs.empty()) c->refs.pop_back();
          if (!c->lines.empty()) c->lines.pop_back();
        }
      }
      s.x.check_span_below_turn();
      s.y.check_each(value_rule);
      p.source_file = s.source_file;
      p.angle_deg = s.x.values;
      return s.y.values;
    };
    switch (p.form) {
      case ProfileForm::polar: p.radius_mm = polar_table("radius_mm", gt(0.0)); break;
      case ProfileForm::base_plus_lift:
        p.base_radius_mm = t.number("base_radius_mm", gt(0.0));
        // radius = base + lift > 0
        p.lift_mm = polar_table("lift_mm", gt(-p.base_radius_mm, "-base_radius_mm"));
        break;
      case ProfileForm::xy: {
        const Series s = read_series(t, {"x_mm"}, "x_mm", "y_mm");
        s.x.check_min_points(6);
        check_star_shaped(s);
        p.x_mm = s.x.values;
        p.y_mm = s.y.values;
        p.source_file = s.source_file;
        break;
      }
      case ProfileForm::circle: p.disc_radius_mm = t.number("disc_radius_mm", gt(0.0)); break;
      case ProfileForm::eccentric:
        p.disc_radius_mm = t.number("disc_radius_mm", gt(0.0));
        p.eccentricity_mm = t.number_or("eccentricity_mm", 0.0, ge(0.0) & lt(p.disc_radius_mm, "disc_radius_mm"));
        break;
    }
    p.where = t.where();
    return p;
  }

  MaterialSpec parse_material(const Table& t) {
    t.allow({"name", "youngs_modulus_GPa", "poisson_ratio", "density_kg_per_m3"});
    MaterialSpec m;
    m.name = t.string("name");
    m.youngs_modulus_GPa = t.number("youngs_modulus_GPa", ge(0.001) & le(2000.0));
    m.poisson_ratio = t.number("poisson_ratio", gt(0.0) & lt(0.5));
    m.density_kg_per_m3 = t.optional_number("density_kg_per_m3", gt(0.0));
    m.where = t.where();
    return m;
  }

  PinSpec parse_pin(const Table& t) {
    t.allow({"node", "point_mm"});
    PinSpec pin;
    pin.node = t.string("node");
    refer(Reference::To::node, t, "node");
    pin.point_mm = t.vec2("point_mm");
    pin.where = t.where();
    return pin;
  }

  SurfaceSpec parse_surface(const Table& t) {
    SurfaceSpec s;
    s.node = t.string("node");
    refer(Reference::To::node, t, "node");
    s.shape = t.choice<SurfaceShape>(
        "shape", {{"profile", SurfaceShape::profile}, {"circle", SurfaceShape::circle}, {"line", SurfaceShape::line}});
    const Keys common = {"node", "shape"};
    const Keys profile = {"profile", "origin_mm", "orientation_deg"};
    const Keys circle = {"center_mm", "radius_mm", "roller", "concave"};
    const Keys line = {"point_mm", "normal", "half_width_mm"};
    const Keys& own = s.shape == SurfaceShape::profile ? profile : s.shape == SurfaceShape::circle ? circle : line;
    t.allow(concat(common, own), concat(concat(profile, circle), line),
            std::string("shape = ") + quote(to_string(s.shape)));
    switch (s.shape) {
      case SurfaceShape::profile:
        s.profile = t.string("profile");
        refer(Reference::To::profile, t, "profile");
        s.origin_mm = t.optional_vec2("origin_mm").value_or(Vec2{0.0, 0.0});
        s.orientation_deg = t.number_or("orientation_deg", 0.0);
        break;
      case SurfaceShape::circle:
        s.origin_mm = t.vec2("center_mm");
        s.radius_mm = t.number("radius_mm", ge(1e-3) & le(1e6));
        s.roller = t.boolean_or("roller", false);
        s.concave = t.boolean_or("concave", false);
        break;
      case SurfaceShape::line:
        s.origin_mm = t.vec2("point_mm");
        s.normal = t.direction("normal");
        s.half_width_mm = t.optional_number("half_width_mm", gt(0.0));
        break;
    }
    s.where = t.where();
    return s;
  }

  ConnectionSpec parse_connection(const Table& t) {
    ConnectionSpec c;
    c.name = t.string("name");
    c.kind = t.choice<ConnectionKind>("type", {{"link", ConnectionKind::link},
                                               {"crank_slider", ConnectionKind::crank_slider},
                                               {"gear", ConnectionKind::gear},
                                               {"variable_gear", ConnectionKind::variable_gear},
                                               {"rack_pinion", ConnectionKind::rack_pinion},
                                               {"contact", ConnectionKind::contact}});
    const Keys common = {"name", "type"};
    // flexible model: bilateral stiffness of links and gears, and the damping of its mode
    const Keys linear_compliance = {"stiffness_N_per_mm", "damping_ratio"};
    const Keys angular_compliance = {"stiffness_Nm_per_rad", "damping_ratio"};
    const Keys link = concat({"a", "b", "length_mm"}, linear_compliance);
    const Keys gear = concat({"nodes", "ratio"}, angular_compliance);
    const Keys variable_gear = concat({"nodes", "ratio_table"}, angular_compliance);
    const Keys rack_pinion = concat({"nodes", "pitch_radius_mm"}, linear_compliance);
    const Keys contact =
        concat({"a", "b", "lash_mm", "materials", "width_mm", "friction_coefficient", "two_sided", "touch_at_rest"},
               kContactLawKeys);
    const Keys* own = &link;
    switch (c.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider: own = &link; break;
      case ConnectionKind::gear: own = &gear; break;
      case ConnectionKind::variable_gear: own = &variable_gear; break;
      case ConnectionKind::rack_pinion: own = &rack_pinion; break;
      case ConnectionKind::contact: own = &contact; break;
    }
    t.allow(concat(common, *own), concat(concat(concat(link, gear), concat(variable_gear, rack_pinion)), contact),
            std::string("type = ") + quote(to_string(c.kind)));

    // gear-like connections name their two nodes: input side first
    const auto node_pair = [&] {
      std::array<SourceRef, 2> where;
      const auto nodes = t.string_pair("nodes", where);
      if (nodes[0] == nodes[1])
        throw InputError(where[1], "value " + quote(nodes[1]) + " must differ from nodes[0] (2 distinct nodes)");
      for (std::size_t i = 0; i < 2; ++i) refer(Reference::To::node, nodes[i], where[i]);
      c.node_a = nodes[0];
      c.node_b = nodes[1];
    };
    switch (c.kind) {
      case ConnectionKind::link:
      case ConnectionKind::crank_slider:
        c.pin_a = parse_pin(t.table("a"));
        c.pin_b = parse_pin(t.table("b"));
        c.length_mm = t.optional_number("length_mm", gt(0.0));
        break;
      case ConnectionKind::gear:
        node_pair();
        c.ratio = t.number("ratio", nonzero());
        break;
      case ConnectionKind::variable_gear: {
        node_pair();
        const Table table = t.table("ratio_table");
        table.allow({"input_deg", "ratio"});
        const Column input = table.numbers("input_deg");
        const Column ratio = table.numbers("ratio");
        check_same_size(input, ratio);
        input.check_min_points(3);
        input.check_increasing();
        ratio.check_each(nonzero());
        c.ratio_input_deg = input.values;
        c.ratio_values = ratio.values;
        break;
      }
      case ConnectionKind::rack_pinion:
        node_pair();
        c.pitch_radius_mm = t.number("pitch_radius_mm", nonzero());
        break;
      case ConnectionKind::contact:
        c.surface_a = parse_surface(t.table("a"));
        c.surface_b = parse_surface(t.table("b"));
        c.two_sided = t.boolean_or("two_sided", false);
        if (c.two_sided && t.has("lash_mm") && t.number("lash_mm") > 0.0)
          t.fail("two_sided", "a two-sided contact (a roller in a slot) has no lash: remove lash_mm");
        c.lash_mm = t.number_or("lash_mm", 0.0, ge(0.0));
        if (t.has("materials")) {
          std::array<SourceRef, 2> where;
          const auto materials = t.string_pair("materials", where);
          for (std::size_t i = 0; i < 2; ++i) refer(Reference::To::material, materials[i], where[i]);
          c.material_a = materials[0];
          c.material_b = materials[1];
        }
        c.width_mm = t.optional_number("width_mm", gt(0.0));
        c.friction_coefficient = t.optional_number("friction_coefficient", ge(0.0));
        c.contact_law = read_contact_law(t);
        c.touch_at_rest = t.boolean_or("touch_at_rest", false);
        break;
    }
    if (c.kind != ConnectionKind::contact) {
      c.stiffness_N_per_mm = t.optional_number("stiffness_N_per_mm", gt(0.0));
      c.stiffness_Nm_per_rad = t.optional_number("stiffness_Nm_per_rad", gt(0.0));
      c.damping_ratio = t.optional_number("damping_ratio", ge(0.0));
    }
    c.where = t.where();
    return c;
  }

  SpringSpec parse_spring(const Table& t) {
    SpringSpec s;
    s.name = t.string("name");
    s.kind = t.choice<SpringKind>("type", {{"compression", SpringKind::compression}, {"torsion", SpringKind::torsion}});
    const Keys common = {"name", "type", "node", "mass_kg", "surge_masses", "installed_length_mm",
                         "solid_length_mm", "wire_diameter_mm", "mean_coil_diameter_mm", "active_coils",
                         "shear_modulus_GPa"};
    const Keys compression = {"rate_N_per_mm", "preload_N", "table", "damping_N_s_per_m", "coil_damping_ratio",
                              "coil_damping_N_s_per_m", "point_mm", "direction"};
    const Keys torsion = {"rate_Nmm_per_deg", "preload_Nmm"};
    const bool is_compression = s.kind == SpringKind::compression;
    t.allow(concat(common, is_compression ? compression : torsion), concat(compression, torsion),
            std::string("type = ") + quote(is_compression ? "compression" : "torsion"));

    s.node = t.string("node");
    refer(Reference::To::node, t, "node", is_compression ? NodeKind::translational : NodeKind::rotational,
          is_compression ? "a compression spring" : "a torsion spring");
    // a compression spring on a floating body: the point it pushes and the line it acts along
    if (is_compression) {
      references_.back().also = NodeKind::floating;
      s.point_mm = t.optional_vec2("point_mm");
      if (t.has("direction")) s.direction = t.direction_or("direction", {0.0, 1.0});
    }
    if (!is_compression) {
      s.rate_Nmm_per_deg = t.number("rate_Nmm_per_deg", gt(0.0));
      s.preload_Nmm = t.number_or("preload_Nmm", 0.0);
    } else if (t.has("table")) {
      // progressive law: exactly one of table / linear rate
      for (const std::string_view key : {"rate_N_per_mm", "preload_N"})
        if (t.has(key)) t.fail(key, "give either 'table' or 'rate_N_per_mm' and 'preload_N', not both");
      const Table table = t.table("table");
      table.allow({"displacement_mm", "force_N"});
      const Column displacement = table.numbers("displacement_mm");
      const Column force = table.numbers("force_N");
      check_same_size(displacement, force);
      displacement.check_min_points(3);
      displacement.check_increasing();
      force.check_increasing();
      s.table_displacement_mm = displacement.values;
      s.table_force_N = force.values;
    } else {
      if (!t.has("rate_N_per_mm")) t.fail("missing required key 'rate_N_per_mm' (or a 'table')");
      s.rate_N_per_mm = t.number("rate_N_per_mm", gt(0.0) & le(1e7));
      s.preload_N = t.number_or("preload_N", 0.0, ge(0.0) & le(1e7));
    }

    s.mass_kg = t.optional_number("mass_kg", gt(0.0) & le(100.0));
    const long long surge_masses = t.integer_or("surge_masses", 0, ge(0.0));
    if (surge_masses > kMaxSurgeMasses)
      t.fail("surge_masses", "value " + std::to_string(surge_masses) + " must be <= " +
                                 std::to_string(kMaxSurgeMasses) + " (every surge mass adds a coordinate to the " +
                                 "flexible model: its cost grows with the count, and 500 masses resolve surge " +
                                 "modes far above any engine order)");
    s.surge_masses = static_cast<int>(surge_masses);
    if (s.surge_masses > 0 && !s.mass_kg)
      t.fail("surge_masses", "value " + std::to_string(s.surge_masses) + " needs 'mass_kg' (the spring mass to distribute)");
    if (is_compression) {
      s.damping_N_s_per_m = t.optional_number("damping_N_s_per_m", ge(0.0));
      // coil-to-coil damping of the multi-mass chain: as the first surge mode's ratio or directly
      s.coil_damping_ratio = t.optional_number("coil_damping_ratio", ge(0.0));
      s.coil_damping_N_s_per_m = t.optional_number("coil_damping_N_s_per_m", ge(0.0));
      if (s.coil_damping_ratio && s.coil_damping_N_s_per_m)
        t.fail("coil_damping_N_s_per_m", value_text(t, "coil_damping_N_s_per_m") +
                                             " is not allowed together with coil_damping_ratio (both set the "
                                             "damper between the coil masses; give one of them)");
      for (const std::string_view key : {"coil_damping_ratio", "coil_damping_N_s_per_m"})
        if (t.has(key) && s.surge_masses == 0)
          t.fail(key, value_text(t, key) + " needs 'surge_masses' > 0 (coil damping acts between the " +
                          "spring's coil masses; a massless spring has none)");
    }
    s.installed_length_mm = t.optional_number("installed_length_mm", gt(0.0));
    s.solid_length_mm = t.optional_number(
        "solid_length_mm", s.installed_length_mm ? gt(0.0) & lt(*s.installed_length_mm, "installed_length_mm") : gt(0.0));
    s.wire_diameter_mm = t.optional_number("wire_diameter_mm", gt(0.0));
    s.mean_coil_diameter_mm = t.optional_number("mean_coil_diameter_mm", gt(0.0));
    s.active_coils = t.optional_number("active_coils", gt(0.0));
    s.shear_modulus_GPa = t.optional_number("shear_modulus_GPa", gt(0.0));
    s.where = t.where();
    return s;
  }

  GasForceSpec parse_gas_force(const Table& t) {
    t.allow({"node", "file", "crank_angle_deg", "force_N"});
    GasForceSpec g;
    g.node = t.string("node");
    refer(Reference::To::node, t, "node", NodeKind::translational, "a gas force");
    const Series s = read_series(t, {"crank_deg", "crank_angle_deg"}, "crank_angle_deg", "force_N");
    s.x.check_min_points(2);
    s.x.check_increasing();
    g.crank_angle_deg = s.x.values;
    g.force_N = s.y.values;
    g.source_file = s.source_file;
    g.where = t.where();
    return g;
  }

  // the engine oil at operating temperature (EHL film thickness)
  OilSpec parse_oil(const Table& t) {
    t.allow({"viscosity_mPa_s", "pressure_viscosity_per_GPa", "composite_roughness_um"});
    OilSpec o;
    o.viscosity_mPa_s = t.number("viscosity_mPa_s", gt(0.0));
    o.pressure_viscosity_per_GPa = t.number("pressure_viscosity_per_GPa", gt(0.0));
    o.composite_roughness_um = t.optional_number("composite_roughness_um", gt(0.0));
    o.where = t.where().str();
    return o;
  }

  // every name used exists (and has the kind its user needs)
  void resolve(const DesignSpec& spec) const {
    for (const Reference& r : references_) {
      switch (r.to) {
        case Reference::To::node: {
          // "ground" is the implicit fixed frame: any connection may attach to it
          if (r.name == "ground" && !r.kind && !r.free_node) break;
          const NodeSpec* node = find_named(spec.nodes, r.name);
          if (!node) unknown(r, "node", names_of(spec.nodes) + "; or 'ground' for the fixed frame");
          if (r.kind && node->kind != *r.kind && !(r.also && node->kind == *r.also))
            throw InputError(r.where, "node " + quote(r.name) + " is " + to_string(node->kind) + "; " + r.role +
                                          " needs a " + to_string(*r.kind) +
                                          (r.also ? std::string(" or ") + to_string(*r.also) : std::string()) + " node");
          if (r.free_node && node->control)
            throw InputError(r.where, "node " + quote(r.name) + " is set by control " + quote(*node->control) +
                                          " and cannot also be the driver");
          break;
        }
        case Reference::To::control:
          if (!find_named(spec.controls, r.name)) unknown(r, "control", names_of(spec.controls));
          break;
        case Reference::To::profile:
          if (!find_named(spec.profiles, r.name)) unknown(r, "profile", names_of(spec.profiles));
          break;
        case Reference::To::material:
          if (!find_named(spec.materials, r.name)) unknown(r, "material", names_of(spec.materials));
          break;
      }
    }
  }

  [[noreturn]] static void unknown(const Reference& r, const char* what, const std::string& names) {
    throw InputError(r.where, "unknown " + std::string(what) + " " + quote(r.name) + " (" + names + ")");
  }

  const Context& context_;
  std::string output_node_;  // design.output_node (read before the nodes)
  std::vector<Reference> references_;
};

}  // namespace

DesignSpec parse_design_document(const toml::table& document, const Context& context) {
  DesignSpec spec = Parser(context).run(document);
  kin::assemble_contacts(spec);
  return spec;
}

DesignSpec parse_design(std::string_view text, const std::string& file_name, const std::string& directory) {
  const Context context{file_name, directory, {}};
  return parse_design_document(parse_document(text, context), context);
}

DesignSpec load_design(const std::string& path) {
  std::string directory;
  const std::string text = read_text_file(path, "design file", directory);
  return parse_design(text, path, directory);
}

}  // namespace camopt::io
