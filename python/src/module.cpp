// camopt._camopt: the jobs layer for Python (docs/python.md). The pure-Python package
// python/camopt wraps these functions with keyword arguments and docstrings; this file maps
// a job's options from Python values, its results to numpy arrays and JSON text, and the
// error channels to Python exceptions. Long solves run without the GIL; Ctrl-C cancels them
// between steps (control positions, engine speeds) and within a flexible run between its
// output points.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "camopt/core/error.hpp"
#include "camopt/io/npz.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/io/design_document.hpp"
#include "camopt/io/design_file.hpp"
#include "camopt/io/input_file.hpp"
#include "camopt/jobs/common.hpp"
#include "camopt/jobs/dynamics.hpp"
#include "camopt/jobs/kinematics.hpp"
#include "camopt/jobs/lift.hpp"
#include "camopt/jobs/modes.hpp"
#include "camopt/jobs/optimize.hpp"
#include "camopt/jobs/synthesize.hpp"
#include "camopt/jobs/validate.hpp"
#include "camopt/io/constraint_file.hpp"

namespace py = pybind11;

namespace camopt::python {

namespace {

// the module's exception types (created once, alive as long as the interpreter)
PyObject* error_type = nullptr;            // camopt.Error
PyObject* input_error_type = nullptr;      // camopt.InputError: the CLI's exit 3
PyObject* numerical_error_type = nullptr;  // camopt.NumericalError: the CLI's exit 4

// a job's observer from Python: it keeps the notes, and between steps asks the interpreter
// for a pending signal on the thread that called the job (the only thread that may run
// Python's signal handlers); Ctrl-C leaves KeyboardInterrupt set and cancels the job
class PythonObserver : public jobs::Observer {
 public:
  void note(const std::string& message) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    notes_.push_back(message);
  }
  bool cancel_requested() override {
    if (std::this_thread::get_id() != caller_) return false;
    const py::gil_scoped_acquire gil;
    return PyErr_CheckSignals() != 0;
  }
  std::vector<std::string> take_notes() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return std::move(notes_);
  }

 private:
  std::thread::id caller_ = std::this_thread::get_id();
  std::mutex mutex_;
  std::vector<std::string> notes_;
};

// `job()` run without the GIL; a cancelled job raises the Python error its observer left
// (KeyboardInterrupt), or KeyboardInterrupt
template <class Job>
auto without_gil(Job&& job) -> decltype(job()) {
  std::optional<decltype(job())> result;
  {
    const py::gil_scoped_release release;
    try {
      result.emplace(job());
    } catch (const jobs::Cancelled&) {
    }
  }
  if (!result) {
    if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  return std::move(*result);
}

// a compiled design: the spec and the mechanism the jobs take, the file it names, and the
// drawing check's warnings
struct CompiledDesign {
  jobs::LoadedDesign design;
  std::string path;
  std::vector<std::string> notes;
};

// a table's columns as a dict of name -> float64 array, in the table's order
py::dict columns_dict(const io::Columns& table) {
  py::dict out;
  std::set<std::string> seen;
  for (std::size_t c = 0; c < table.header.size(); ++c) {
    if (!seen.insert(table.header[c]).second)
      throw std::logic_error("the table has two columns named '" + table.header[c] + "'");
    const std::vector<double>& values = table.values[c];
    py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
    if (!values.empty()) std::memcpy(array.mutable_data(), values.data(), values.size() * sizeof(double));
    out[py::str(table.header[c])] = std::move(array);
  }
  return out;
}

// a --format npz table, read as camopt report reads it (the same messages)
py::dict read_npz_columns(const std::string& path) { return columns_dict(io::read_npz(path)); }

// the design file's text, read as the CLI reads it (the same messages)
std::string read_design_file(const std::string& path) { return io::read_input_file(path, "design file"); }

// Design.set's changes: (key path, TOML text of the value), in order
using Overrides = std::vector<std::pair<std::string, std::string>>;

// Design.set's changes as the io's overrides, each named as the design's messages name it
std::vector<io::Override> design_overrides(const Overrides& overrides) {
  std::vector<io::Override> out;
  for (const auto& [key, value] : overrides) out.push_back(io::Override{key, value, "set " + key + "=" + value});
  return out;
}

// a design's text as an editable document with the overrides applied; an override that
// leads nowhere or changes a value's type raises InputError naming it ("set key=value: ...")
io::DesignDocument design_document(const std::string& text, const std::string& path, const Overrides& overrides) {
  std::string directory = std::filesystem::path(path).parent_path().string();
  if (directory.empty()) directory = ".";
  io::DesignDocument doc = io::DesignDocument::from_text(text, path, directory);
  for (const io::Override& o : design_overrides(overrides)) doc.set(o);
  return doc;
}

// the value at `key` (TOML text) of the design with its overrides
std::string design_get(const std::string& text, const std::string& path, const Overrides& overrides,
                       const std::string& key) {
  return design_document(text, path, overrides).get(key);
}

// the design's text with its overrides edited in (comments and layout kept)
std::string design_text(const std::string& text, const std::string& path, const Overrides& overrides) {
  return design_document(text, path, overrides).text();
}

// a design's text with its overrides parsed and compiled; `path` names it in messages and
// resolves its relative `file = ...` references; a value an override gave that breaks a rule
// is reported at the override
std::shared_ptr<CompiledDesign> compile_design(const std::string& text, const std::string& path,
                                               const Overrides& overrides) {
  PythonObserver observer;
  auto compiled = std::make_shared<CompiledDesign>();
  compiled->design = jobs::compile_design(design_document(text, path, overrides).spec(), path, observer,
                                         design_overrides(overrides));
  compiled->path = path;
  compiled->notes = observer.take_notes();
  return compiled;
}

// the validate job: (description, drawing warnings)
py::tuple validate_design(const CompiledDesign& compiled) {
  jobs::DesignFindings f = jobs::validate_design(compiled.design.spec, compiled.design.mech);
  return py::make_tuple(std::move(f.description), std::move(f.warnings));
}

// a step or speed the caller gave (not None) is > 0, as the CLI checks its options
double given_positive(const char* option, const std::optional<double>& value) {
  if (!value) return 0.0;
  jobs::check_positive(option, *value);
  return *value;
}

// worker threads: the caller's count, or every hardware thread
int worker_threads(const std::optional<int>& threads) {
  if (threads) {
    CAMOPT_THROW_UNLESS(*threads >= 1, "threads: value " + std::to_string(*threads) + " must be >= 1");
    return *threads;
  }
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

// the kinematics job: (columns, summary as JSON text, notes)
py::tuple kinematics(const CompiledDesign& compiled, const std::string& control, const std::string& outputs,
                     std::optional<double> step_deg, std::optional<double> rpm, const std::string& duration_at,
                     std::optional<int> threads) {
  jobs::KinematicsOptions options;
  options.design_file = compiled.path;
  options.control = control;
  options.outputs = outputs;
  options.step_deg = given_positive("--step", step_deg);
  options.rpm = given_positive("--rpm", rpm);
  options.duration_at = duration_at;
  options.threads = worker_threads(threads);
  jobs::validate(options);
  PythonObserver observer;
  const jobs::KinematicsResult result =
      without_gil([&] { return jobs::run_kinematics(compiled.design, options, observer); });
  return py::make_tuple(columns_dict(result.columns), result.summary.dump(), observer.take_notes());
}

// the options of `camopt dynamics` that only one model takes, given for another: the CLI's
// InputError "OPTION: does nothing with --model M (... only)"
struct ModelOptions {
  std::optional<std::string> contacts;  // the rigid model's
  std::optional<int> revolutions;       // the flexible model's, and below
  std::optional<std::string> start;
  std::optional<bool> coil_displacements;
  std::optional<double> rtol, atol;
};
void reject_unused(const std::string& model, const ModelOptions& m) {
  const auto unused = [&model](bool given, const char* option, const char* only) {
    if (given) throw InputError(std::string(option) + ": does nothing with --model " + model + " (" + only + ")");
  };
  if (model != "flexible") {
    unused(m.revolutions.has_value(), "--revolutions", "flexible model only");
    unused(m.start.has_value(), "--start", "flexible model only");
    unused(m.coil_displacements.has_value(), "--coil-displacements", "flexible model only");
    unused(m.rtol.has_value(), "--rtol", "flexible model only");
    unused(m.atol.has_value(), "--atol", "flexible model only");
  }
  if (model != "rigid") unused(m.contacts.has_value(), "--contacts", "rigid model only");
}

// the dynamics job, rigid or flexible: (columns, summary as JSON text, notes)
py::tuple dynamics(const CompiledDesign& compiled, const std::string& model, const std::string& rpm,
                   const std::string& control, std::optional<double> step_deg, const ModelOptions& m) {
  reject_unused(model, m);
  jobs::DynamicsOptions options;
  options.design_file = compiled.path;
  options.model = model;
  options.contacts = m.contacts.value_or("rigid");
  options.rpm = rpm;
  options.control = control;
  options.step_deg = given_positive("--step", step_deg);
  dynamics::FlexibleOptions& f = options.flexible;
  f.revolutions = m.revolutions.value_or(f.revolutions);
  const std::string start = m.start.value_or("static");
  if (start != "static" && start != "rest")
    throw InputError("--start: value '" + start + "' is not one of static, rest");
  f.start_at_rest = start == "rest";
  f.coil_displacements = m.coil_displacements.value_or(false);
  f.relative_tolerance = m.rtol.value_or(f.relative_tolerance);
  f.absolute_tolerance = m.atol.value_or(f.absolute_tolerance);
  jobs::validate(options);
  PythonObserver observer;
  const jobs::DynamicsResult result =
      without_gil([&] { return jobs::run_dynamics(compiled.design, options, observer); });
  return py::make_tuple(columns_dict(result.columns), result.summary.dump(), observer.take_notes());
}

// the lift job: (columns, summary as JSON text, notes)
py::tuple lift(const jobs::LiftOptions& options) {
  PythonObserver observer;
  const jobs::LiftResult result = jobs::run_lift(options, observer);
  return py::make_tuple(columns_dict(result.table), result.summary.dump(), observer.take_notes());
}

// camopt.NumericalError with its status: code, message and where (the angle, the residual)
// and, for a job that writes a report before it fails (optimize), `report`: its JSON text
void raise_numerical(const NumericalError& e, const std::string& report = "") {
  const Status& s = e.status();
  py::object error = py::reinterpret_borrow<py::object>(numerical_error_type)(e.what());
  error.attr("code") = to_string(s.code);
  error.attr("detail") = s.message;
  error.attr("where") = s.where;
  error.attr("report") = report.empty() ? py::none() : py::module_::import("json").attr("loads")(report);
  PyErr_SetObject(numerical_error_type, error.ptr());
}

// the modes job (dynamics --model modes): (columns, summary as JSON text, notes)
py::tuple modes(const CompiledDesign& compiled, const std::string& control, const std::string& cam_deg,
                bool release_cam, std::optional<int> threads) {
  jobs::ModesOptions options;
  options.design_file = compiled.path;
  options.control = control;
  options.cam_deg = cam_deg;
  options.release_cam = release_cam;
  options.threads = worker_threads(threads);
  PythonObserver observer;
  const jobs::ModesResult result = without_gil([&] { return jobs::run_modes(compiled.design, options, observer); });
  return py::make_tuple(columns_dict(result.columns), result.summary.dump(), observer.take_notes());
}

// a target table given in memory: (column names, columns of numbers) written as the CSV text
// of that table (numbers shortest round-trip, so read back to the same bits) and read by the
// CSV reader, with its checks and messages; `name` stands for the file
io::CsvTable table_in_memory(const std::string& name, const std::vector<std::string>& header,
                             const std::vector<std::vector<double>>& values) {
  std::string text;
  for (std::size_t c = 0; c < header.size(); ++c) text += (c ? "," : "") + header[c];
  text += "\n";
  std::size_t rows = 0;
  for (const auto& column : values) rows = std::max(rows, column.size());
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < values.size(); ++c) {
      if (r >= values[c].size()) continue;  // a short column: the row has fewer cells (the reader says so)
      char buffer[64];
      const auto end = std::to_chars(buffer, buffer + sizeof buffer, values[c][r]).ptr;
      text += (c ? "," : "") + std::string(buffer, end);
    }
    text += "\n";
  }
  return io::parse_csv(text, name);
}

// a profile's files: the tables as columns ({"profile.csv": ..., "grinding.csv": ...}) and
// every file's text by name (profile.dxf, grinding.csv, profile.csv, design.toml)
std::pair<py::dict, py::dict> exports_dicts(const jobs::ProfileExports& exports) {
  py::dict tables, files;
  tables["profile.csv"] = columns_dict(exports.profile);
  if (!exports.grinding.header.empty()) tables["grinding.csv"] = columns_dict(exports.grinding);
  for (const auto& [name, text] : jobs::export_files(exports)) files[py::str(name)] = py::bytes(text);
  return {tables, files};
}

// the synthesize job: (tables, report as JSON text, notes, files); the target is a CSV file
// (target_path) or a table in memory (target_header, target_values)
py::tuple synthesize(const CompiledDesign& compiled, const std::string& target_name,
                     std::optional<std::vector<std::string>> target_header,
                     std::optional<std::vector<std::vector<double>>> target_values, jobs::SynthesizeOptions options) {
  options.design_file = compiled.path;
  options.target_file = target_name;
  jobs::validate(options);
  const io::CsvTable target =
      target_header ? table_in_memory(target_name, *target_header, *target_values) : io::read_csv(target_name);
  PythonObserver observer;
  const jobs::SynthesizeResult result =
      without_gil([&] { return jobs::run_synthesize(compiled.design.spec, target, options, observer); });
  auto [tables, files] = exports_dicts(result.exports);
  return py::make_tuple(tables, result.report.dump(), observer.take_notes(), files);
}

// the optimize job: (tables, report as JSON text, notes, files, verified, the failed checks);
// a solver failure raises NumericalError (the CLI's exit 4, once it wrote report.json)
// constraint_overrides: (key path, TOML value text) changes of the set, as --set-constraint's
py::tuple optimize(const CompiledDesign& compiled, const std::string& constraints, const Overrides& constraint_overrides,
                   jobs::OptimizeOptions options) {
  options.design_file = compiled.path;
  options.constraints_file = constraints;
  jobs::validate(options);
  std::vector<io::Override> changes;
  for (const auto& [key, value] : constraint_overrides)
    changes.push_back(io::parse_override(key + "=" + value, "--set-constraint"));
  opt::OptimizationSpec set = io::load_constraints(constraints, changes);
  PythonObserver observer;
  const jobs::OptimizeResult result =
      without_gil([&] { return jobs::run_optimize(compiled.design.spec, std::move(set), options, observer); });
  if (!result.status.ok()) {
    raise_numerical(NumericalError(result.status), result.report.dump());
    throw py::error_already_set();
  }
  py::dict tables, files;
  if (result.exports) std::tie(tables, files) = exports_dicts(*result.exports);
  for (const auto& [name, table] : result.tables) tables[py::str(name)] = columns_dict(table);
  return py::make_tuple(tables, result.report.dump(), observer.take_notes(), files, result.verified,
                        result.verification_failures);
}


// every C++ exception a job throws, as its Python exception: nothing escapes unmapped
void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const InputError& e) {
    PyErr_SetString(input_error_type, e.what());
  } catch (const NumericalError& e) {
    raise_numerical(e);
  } catch (const jobs::Cancelled&) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
  } catch (const std::bad_alloc&) {
    PyErr_NoMemory();
  } catch (const py::builtin_exception&) {
    throw;  // pybind11's own (a wrong argument type): its translator
  } catch (const std::exception& e) {
    PyErr_SetString(error_type, (std::string("internal error: ") + e.what()).c_str());
  }
}

// the exception types: Error, and InputError and NumericalError under it
void add_exceptions(py::module_& m) {
  error_type = PyErr_NewExceptionWithDoc("camopt.Error", "Every error camopt raises.", PyExc_Exception, nullptr);
  input_error_type = PyErr_NewExceptionWithDoc(
      "camopt.InputError",
      "Bad input: a design key, an option value, a table. The message is the CLI's (exit 3): the file, "
      "line and key path, or the option, the value and the rule.",
      error_type, nullptr);
  numerical_error_type = PyErr_NewExceptionWithDoc(
      "camopt.NumericalError",
      "A numerical failure (the CLI's exit 4): no convergence, cannot assemble, undercut, integrator "
      "failure. The message names where (the angle, the residual); attributes code, detail, where, and "
      "report (optimize: report.json's content, as the CLI writes it before exit 4; else None).",
      error_type, nullptr);
  m.attr("Error") = py::handle(error_type);
  m.attr("InputError") = py::handle(input_error_type);
  m.attr("NumericalError") = py::handle(numerical_error_type);
  py::register_exception_translator(&translate);
}

}  // namespace

}  // namespace camopt::python

PYBIND11_MODULE(_camopt, m) {
  using namespace camopt::python;
  m.doc() = "camopt's jobs for Python (use the package camopt, which wraps them)";
  m.attr("version") = CAMOPT_VERSION;
  add_exceptions(m);
  py::class_<CompiledDesign, std::shared_ptr<CompiledDesign>>(m, "CompiledDesign",
                                                              "A design parsed and compiled (camopt.Design.compile).")
      .def_property_readonly("name", [](const CompiledDesign& c) { return c.design.mech.name; },
                             "the design's name")
      .def_property_readonly("notes", [](const CompiledDesign& c) { return c.notes; },
                             "the drawing check's warnings, as the CLI prints them");
  m.def("read_design_file", &read_design_file, py::arg("path"), "A design file's text (the CLI's checks).");
  m.def(
      "read_npz", &read_npz_columns, py::arg("path"),
      "A result table camopt wrote with --format npz: a dict of column name -> float64 array (InputError for a "
      "damaged or foreign file).");
  m.def("compile_design", &compile_design, py::arg("text"), py::arg("path"), py::arg("overrides"),
        "A design's TOML text with its overrides [(key path, TOML value)] parsed and compiled; path names it "
        "in messages.");
  m.def("design_get", &design_get, py::arg("text"), py::arg("path"), py::arg("overrides"), py::arg("key"),
        "The value at a key path of a design with its overrides, as TOML text.");
  m.def("design_text", &design_text, py::arg("text"), py::arg("path"), py::arg("overrides"),
        "A design's TOML text with its overrides edited in.");
  m.def("validate_design", &validate_design, py::arg("design"),
        "The validate job: (description, drawing warnings).");
  m.def("kinematics", &kinematics, py::arg("design"), py::arg("control"), py::arg("outputs"), py::arg("step_deg"),
        py::arg("rpm"), py::arg("duration_at"), py::arg("threads"),
        "The kinematics job: (columns, summary JSON text, notes).");
  m.def(
      "dynamics",
      [](const CompiledDesign& design, const std::string& model, const std::string& rpm, const std::string& control,
         std::optional<double> step_deg, std::optional<std::string> contacts, std::optional<int> revolutions,
         std::optional<std::string> start, std::optional<bool> coil_displacements, std::optional<double> rtol,
         std::optional<double> atol) {
        return dynamics(design, model, rpm, control, step_deg,
                        {std::move(contacts), revolutions, std::move(start), coil_displacements, rtol, atol});
      },
      py::arg("design"), py::arg("model"), py::arg("rpm"), py::arg("control"), py::arg("step_deg"), py::arg("contacts"),
      py::arg("revolutions"), py::arg("start"), py::arg("coil_displacements"), py::arg("rtol"), py::arg("atol"),
      "The dynamics job (rigid or flexible): (columns, summary JSON text, notes).");
  m.def(
      "lift",
      [](const std::string& law, std::optional<std::string> close_law, double lift_mm, std::optional<double> duration_deg,
         std::optional<double> open_deg, std::optional<double> close_deg, double dwell_deg, double ramp_height_mm,
         double ramp_length_deg, std::optional<double> close_ramp_height_mm,
         std::optional<double> close_ramp_length_deg, double ramp_blend, double peak_deg,
         std::optional<std::vector<double>> acc_controls, std::optional<int> bspline_degree,
         std::optional<double> polydyne_rpm, std::optional<double> polydyne_hz, double step_deg,
         const std::string& basis) {
        return lift({law, std::move(close_law), lift_mm, duration_deg, open_deg, close_deg, dwell_deg, ramp_height_mm,
                     ramp_length_deg, close_ramp_height_mm, close_ramp_length_deg, ramp_blend, peak_deg,
                     std::move(acc_controls), bspline_degree, polydyne_rpm, polydyne_hz, step_deg, basis});
      },
      py::arg("law"), py::arg("close_law"), py::arg("lift_mm"), py::arg("duration_deg"), py::arg("open_deg"),
      py::arg("close_deg"), py::arg("dwell_deg"), py::arg("ramp_height_mm"), py::arg("ramp_length_deg"),
      py::arg("close_ramp_height_mm"), py::arg("close_ramp_length_deg"), py::arg("ramp_blend"), py::arg("peak_deg"),
      py::arg("acc_controls"), py::arg("bspline_degree"), py::arg("polydyne_rpm"), py::arg("polydyne_hz"),
      py::arg("step_deg"), py::arg("basis"), "The lift job: (columns, summary JSON text, notes).");
  m.def("modes", &modes, py::arg("design"), py::arg("control"), py::arg("cam_deg"), py::arg("release_cam"),
        py::arg("threads"), "The modes job (dynamics --model modes): (columns, summary JSON text, notes).");
  m.def(
      "synthesize",
      [](const CompiledDesign& design, const Overrides& overrides, const std::string& target_name,
         std::optional<std::vector<std::string>> header,
         std::optional<std::vector<std::vector<double>>> values, const std::string& out_dir, const std::string& cam,
         std::optional<double> control, int points, bool smooth, double knot_spacing_deg, double wheel_radius_mm,
         double min_radius_mm, double closure_tolerance_mm, double max_round_trip_error, const std::string& target_node,
         std::optional<double> master_radius_mm, double grinding_step_deg) {
        camopt::jobs::SynthesizeOptions o;
        o.overrides = design_overrides(overrides);
        o.out_dir = out_dir;
        o.cam = cam;
        o.control = control;
        o.points = points;
        o.smooth = smooth;
        o.knot_spacing_deg = knot_spacing_deg;
        o.wheel_radius_mm = wheel_radius_mm;
        o.min_radius_mm = min_radius_mm;
        o.closure_tolerance_mm = closure_tolerance_mm;
        o.max_round_trip_error = max_round_trip_error;
        o.target_node = target_node;
        o.master_radius_mm = master_radius_mm;
        o.grinding_step_deg = grinding_step_deg;
        return synthesize(design, target_name, std::move(header), std::move(values), std::move(o));
      },
      py::arg("design"), py::arg("overrides"), py::arg("target_name"), py::arg("target_header"), py::arg("target_values"), py::arg("out_dir"),
      py::arg("cam"), py::arg("control"), py::arg("points"), py::arg("smooth"), py::arg("knot_spacing_deg"),
      py::arg("wheel_radius_mm"), py::arg("min_radius_mm"), py::arg("closure_tolerance_mm"),
      py::arg("max_round_trip_error"), py::arg("target_node"), py::arg("master_radius_mm"),
      py::arg("grinding_step_deg"), "The synthesize job: (tables, report JSON text, notes, files).");
  m.def(
      "optimize",
      [](const CompiledDesign& design, const Overrides& overrides, const std::string& constraints,
         const Overrides& constraint_overrides, const std::string& out_dir,
         const std::string& solver, const std::string& cam, bool verify, int points, int max_iterations, int starts) {
        camopt::jobs::OptimizeOptions o;
        o.overrides = design_overrides(overrides);
        o.out_dir = out_dir;
        o.solver = solver;
        o.cam = cam;
        o.verify = verify;
        o.points = points;
        o.max_iterations = max_iterations;
        o.starts = starts;
        return optimize(design, constraints, constraint_overrides, std::move(o));
      },
      py::arg("design"), py::arg("overrides"), py::arg("constraints"), py::arg("constraint_overrides"),
      py::arg("out_dir"), py::arg("solver"), py::arg("cam"),
      py::arg("verify"), py::arg("points"), py::arg("max_iterations"), py::arg("starts"),
      "The optimize job: (tables, report JSON text, notes, files, verified, failed checks).");
}
