#pragma once
// the plain description of one run's report: what to draw, not how. collect() fills it from a
// result folder (report.hpp), build_scene() adds the mechanism animation (scene.hpp), and
// three writers consume it: the interactive page (write_html), the static figures
// (write_figures) and the tests. Every plot is defined once, here; the page and the figures
// draw the same definitions. Lengths mm, angles deg, as in the CSV headers the data came from.
#include <optional>
#include <string>
#include <vector>

namespace camopt::report {

// an axis: its quantity and unit, drawn as "label [unit]"
struct Axis {
  std::string label;  // "valve lift", "cam angle"
  std::string unit;   // "mm", "deg", "mm/deg^2", "N", "MPa", "rpm", "-" (dimensionless)
};

// one curve. Display data: decimated for the page (never for the CSVs), at most
// kMaxDisplayPoints points, peaks kept (min-max decimation per bucket)
struct Series {
  std::string name;            // legend entry: "lift", "control 4 deg", "cam_roller"
  std::vector<double> x;       // empty: the plot's shared x_values
  std::vector<double> y;
  std::vector<double> color;   // optional per-point value on the plot's color axis (profile radius)
  int family_member = -1;      // index into ReportData::family (a control position), -1: none
  bool dashed = false;         // a reference curve (kinematic lift under a dynamic one, a target)
};

// a shaded interval of x: active constraint angles, undercut or concave windows, open contacts
struct Band {
  double from = 0.0, to = 0.0;
  std::string label;
};

// a horizontal line at a limit: acceleration limit, Hertz limit, the set's rpm
struct LimitLine {
  double y = 0.0;
  std::string label;
};

enum class PlotKind {
  line,     // y against x, shared x cursor with every line plot of the same link_group
  profile,  // x-y drawn to scale (equal aspect): cam profiles, base circle; colored by `color`
  heatmap   // z over x_values (columns) x y_values (rows): separation speed over rpm x control
};

struct Plot {
  std::string id;       // stable name the page and the tests find it by: "svaj-acceleration"
  std::string title;    // "Valve acceleration"
  std::string section;  // the Section::id it is drawn under
  PlotKind kind = PlotKind::line;
  Axis x, y;
  Axis color;                     // profile: the color scale's quantity; heatmap: z
  std::string link_group;         // line plots sharing this group share the cursor and zoom
  std::vector<double> x_values;   // shared x of the series that give none; heatmap: columns
  std::vector<double> y_values;   // heatmap: rows
  std::vector<double> z;          // heatmap: row-major, y_values.size() x x_values.size(); NaN = none
  std::vector<Series> series;
  std::vector<Band> bands;
  std::vector<LimitLine> limits;
  bool main = false;              // one of the run's main plots, written by --figures
};

// a summary table: key figures, constraint margins, verification verdicts, natural frequencies
struct Table {
  std::string id;       // "constraints", "verification", "summary"
  std::string title;
  std::string section;
  std::vector<std::string> columns;              // with units: "margin [MPa]"
  std::vector<std::vector<std::string>> rows;    // already formatted (shortest round-trip)
  std::vector<int> failed_rows;                  // rows drawn as failed (a verdict that did not pass)
};

struct Section {
  std::string id;     // "svaj", "contacts", "profile", "forces", "speed-map", "mechanism"
  std::string title;  // "Valve lift, velocity, acceleration and jerk"
};

// ---- the mechanism animation -------------------------------------------------------------
// Bodies are drawn in their drawing (design) coordinates and moved per frame by their pose:
// current = R(angle) * drawing + (tx, ty). Ground has index 0 and never moves.
struct SceneShape {
  enum class Kind {
    polyline,  // open polyline: a lever's skeleton, a flat face, a valve stem
    polygon,   // closed outline: a cam or swing-cam profile, a valve head
    circle,    // centre xy[0..1] and radius: a roller, a pivot pin, a base circle
    spring     // a coil spring between xy[0..1] (on `body`) and xy[2..3] (on `body_b`), zig-zag
  };
  Kind kind = Kind::polyline;
  int body = 0;                // index into Scene::bodies (0: ground)
  int body_b = 0;              // spring: the body of its second end
  std::vector<double> xy;      // x0, y0, x1, y1, ... in drawing coordinates [mm]
  double radius = 0.0;         // circle [mm]
  std::string role;            // "profile", "roller", "pivot", "lever", "valve", "spring", "seat"
};

// one control position's frames, at the run's cam angles
struct ScenePosition {
  double control = 0.0;                   // control value [deg or mm]
  std::vector<double> cam_deg;            // frame angles
  std::vector<std::vector<double>> pose;  // per body: tx, ty [mm], angle [rad] per frame (3 n)
  std::vector<std::vector<double>> contact;  // per contact: x, y, nx, ny per frame (4 n)
  std::vector<double> lift_mm;            // the output node's lift per frame, as in the CSV
};

struct Scene {
  std::vector<std::string> bodies;    // names; bodies[0] = "ground"
  std::vector<std::string> contacts;  // contact connection names
  std::vector<SceneShape> shapes;
  std::string control_name;           // "" when the design has no control
  std::string control_unit;           // "deg" or "mm"
  std::string output_body;            // the body whose displacement is the lift ("valve")
  double bbox[4] = {0, 0, 0, 0};      // xmin, ymin, xmax, ymax over every frame [mm]
  std::vector<ScenePosition> positions;
};

// ---- the whole report --------------------------------------------------------------------
struct Fact {
  std::string key;    // "design", "engine speed [rpm]", "solver"
  std::string value;
};

struct ReportData {
  std::string command;     // "kinematics", "synthesize", "optimize", "dynamics rigid", ...
  std::string title;       // "camopt kinematics: cvvl_swing_cam"
  std::string source_dir;  // the result folder, as given
  std::vector<Fact> facts;
  std::vector<std::string> notes;   // what the run did not compute, files left out, warnings
  std::vector<std::string> family;  // family member labels ("control 0 deg", ...), in order
  std::vector<Section> sections;
  std::vector<Plot> plots;
  std::vector<Table> tables;
  std::optional<Scene> scene;
  std::optional<bool> passed;       // a verdict the run gave (optimize --verify), if any
};

inline constexpr int kMaxDisplayPoints = 4000;

}  // namespace camopt::report
