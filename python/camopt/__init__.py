"""camopt: valvetrain cam design from Python (docs/python.md).

Units are in the names: lengths mm, angles deg (cam degrees for the driver), speeds rpm of
the crankshaft, forces N. A job returns what the CLI writes: ``columns`` holds the CSV's
columns (a dict of name -> numpy float64 array, the names exactly the CSV headers) and
``summary`` the summary.json content (a dict).

    import camopt
    design = camopt.Design.load("designs/roller_finger_follower.toml")
    run = camopt.kinematics(design, step_deg=0.5, rpm=6000)
    print(run.summary["positions"][0]["max_lift_mm"])
    lift = run.columns["lift_mm"]

Errors: camopt.InputError (the CLI's exit 3 messages: file, line, key; option, value, rule)
and camopt.NumericalError (exit 4: the angle and the residual), both camopt.Error. A long
solve releases the GIL and stops on Ctrl-C (KeyboardInterrupt) between control positions (a
flexible run: between its output points).
"""

import json as _json
import os as _os
import tempfile as _tempfile

from . import _camopt
from ._camopt import Error, InputError, NumericalError

__all__ = ["Design", "Result", "kinematics", "dynamics", "lift", "synthesize", "optimize", "study", "read_results", "Error",
           "InputError", "NumericalError", "__version__"]

__version__ = _camopt.version


class Design:
    """A design: its TOML text and the file it came from (or the name it is given).

    Build one with ``Design.load(path)`` or ``Design.from_text(text, path=...)``. The text is
    what a job compiles; ``compile()`` parses and compiles it once (and again after the text
    changes). Relative ``file = ...`` references in the text resolve from the file's folder.
    """

    def __init__(self, text, path="<text>"):
        """A design from its TOML text; ``path`` names it in messages and summary.json."""
        self._text = str(text)
        self._path = _os.fspath(path)
        self._overrides = []
        self._compiled = None

    @classmethod
    def load(cls, path):
        """The design file at ``path`` (TOML). InputError when it cannot be read."""
        path = _os.fspath(path)
        return cls(_camopt.read_design_file(path), path)

    @classmethod
    def from_text(cls, text, path="<text>"):
        """A design from TOML text; ``path`` names it in messages (default ``<text>``)."""
        return cls(text, path)

    @property
    def text(self):
        """The design's TOML text, with the values ``set`` changed edited in (the file's
        comments and layout kept): the text a job runs."""
        if not self._overrides:
            return self._text
        return _camopt.design_text(self._text, self._path, self._overrides)

    @property
    def overrides(self):
        """The values ``set`` changed: a dict of key path -> TOML text, in order."""
        return dict(self._overrides)

    def get(self, key):
        """The value at a key path (docs/design-format.md, "Key paths"): ``design.name``,
        ``node.finger.mass_kg`` (an array of tables by its entries' ``name``),
        ``connection.cam_roller.b.radius_mm`` (an inline table), ``node.finger.pivot_mm[0]`` (an
        array element) or ``node.finger.pivot_mm`` (the whole array). Returns a float, int, bool,
        str or list, in the key's unit (its name says it). InputError when the path leads
        nowhere."""
        return _from_toml(_camopt.design_get(self._text, self._path, self._overrides, key))

    def set(self, key, value):
        """Change the value at a key path (see ``get``): a number, bool, str or list of numbers,
        in the key's unit. Raises InputError now when the path leads nowhere or the value's type
        is not the key's ("set node.fingr.mass_kg=0.05: no [[node]] named ..."), and at
        ``compile()`` when the value breaks a rule of the design format, naming the change.
        Contacts with ``touch_at_rest`` are re-assembled when the design compiles, so a new
        roller radius or pivot gives an assembled mechanism. Returns the design."""
        changes = self._overrides + [(str(key), _to_toml(value))]
        _camopt.design_text(self._text, self._path, changes)  # raises for a path that leads nowhere
        self._overrides = changes
        self._compiled = None
        return self

    @property
    def path(self):
        """The file the design came from, as messages and summary.json name it."""
        return self._path

    @property
    def name(self):
        """The design's name (its ``name`` key), from the compiled design."""
        return self.compile().name

    @property
    def notes(self):
        """The drawing check's warnings (a list of str), as the CLI prints them on stderr."""
        return list(self.compile().notes)

    def compile(self):
        """The design parsed, checked and compiled (cached). InputError names the file, the
        line and the key path of a bad value, as ``camopt validate`` does."""
        if self._compiled is None:
            self._compiled = _camopt.compile_design(self._text, self._path, self._overrides)
        return self._compiled

    def validate(self):
        """The findings of ``camopt validate``: a dict with ``description`` (the compiled
        mechanism: nodes, connections, solve order; the flexible model's parameters with their
        units, each marked [default] when not in the design; the oil), and ``warnings`` (the
        drawing check's, a list of str). InputError names a bad key (file, line, key path)."""
        description, warnings = _camopt.validate_design(self.compile())
        return {"description": description, "warnings": list(warnings)}

    def __repr__(self):
        return "camopt.Design(path=%r)" % self._path


class Result:
    """What a job writes, in memory.

    ``columns``: dict of CSV header (with its unit, e.g. ``lift_mm``, ``vel_mm_per_deg``) ->
    numpy float64 array, in the CSV's column order; ``summary``: the summary.json content;
    ``notes``: the lines the CLI prints on stderr (per control position, warnings).

    synthesize and optimize write several tables: ``tables`` maps each CSV's name
    (``"profile.csv"``, ``"grinding.csv"``, optimize's ``"lift.csv"``) to its columns, and
    ``columns`` is profile.csv's; ``summary`` is report.json; ``files`` maps every file the CLI
    writes but report.json (profile.dxf, design.toml, ...) to its bytes; ``design`` is the
    written design.toml as a ``Design`` (see ``synthesize``).
    """

    def __init__(self, columns, summary, notes, tables=None, design=None, files=None):
        self.columns = columns
        self.summary = summary
        self.notes = notes
        self.tables = tables if tables is not None else {}
        self.design = design
        self.files = files if files is not None else {}

    def __repr__(self):
        return "camopt.Result(columns=[%s])" % ", ".join(self.columns)


def _to_toml(value):
    """A Python value as TOML text: numbers in shortest round-trip form, strings quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise InputError("set: value %r is not a finite number" % value)
        return repr(value)
    if isinstance(value, str):
        return _json.dumps(value)  # a TOML basic string: JSON's escapes are TOML's
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_to_toml(v) for v in value) + "]"
    try:
        return _to_toml(float(value))  # numpy scalars
    except (TypeError, ValueError):
        raise InputError("set: value %r is not a number, bool, string or list" % (value,)) from None


def _from_toml(text):
    """A TOML value's text as a Python value."""
    import tomllib

    return tomllib.loads("v = " + text)["v"]


def _design(design):
    """A Design from a Design, a path or a path-like."""
    if isinstance(design, Design):
        return design
    return Design.load(design)


def _range_text(value):
    """A control option (``--control``): a number, a sequence of numbers or the CLI's text."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        return ",".join(repr(float(v)) for v in value)
    return repr(float(value))


def _list_text(value, default):
    """A comma list option: a str, or a sequence of str or numbers."""
    if value is None:
        return default
    if isinstance(value, str):
        return value
    return ",".join(str(v) for v in value)


def read_results(path):
    """A result table camopt wrote: ``kinematics.npz`` / ``dynamics.npz`` (``--format npz``) or a
    CSV (long or wide), or the table in a result folder (its kinematics or dynamics table).

    Returns a dict of column name -> numpy float64 array, the names exactly the file's column
    names (units in them); an empty CSV cell (a quantity that does not exist there) is NaN.
    Raises InputError naming the file and what is wrong for a damaged or foreign file.
    """
    import numpy as _np
    path = _os.fspath(path)
    if _os.path.isdir(path):
        for name in ("kinematics.npz", "kinematics.csv", "dynamics.npz", "dynamics.csv"):
            if _os.path.exists(_os.path.join(path, name)):
                return read_results(_os.path.join(path, name))
        raise InputError(f"{path}: no kinematics or dynamics table in it (kinematics.csv/.npz, dynamics.csv/.npz)")
    if path.endswith(".npz"):
        return _camopt.read_npz(path)
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines:
        raise InputError(f"{path}: empty file (a header line naming the columns is required)")
    names = lines[0].split(",")
    columns = [[] for _ in names]
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != len(names):
            raise InputError(f"{path}:{number}: {len(cells)} cells, the header has {len(names)}")
        for column, cell in zip(columns, cells):
            try:
                column.append(float(cell) if cell else float("nan"))
            except ValueError:
                raise InputError(f"{path}:{number}: '{cell}' is not a number") from None
    return {name: _np.array(column, dtype=_np.float64) for name, column in zip(names, columns)}


def kinematics(design, step_deg=None, control=None, outputs=None, rpm=None, duration_at=None, threads=None):
    """The kinematic sweep of a design, as ``camopt kinematics`` writes it.

    design: a Design or a design file's path.
    step_deg: driver step [cam deg, or mm for a translating driver]; default: the design's
        driver.step_deg (--step).
    control: positions of the design's first control [deg or mm]: a number, a list of numbers,
        or "START:STOP:COUNT" (--control); default: the control's default.
    outputs: "lift", "velocity", "acceleration", "jerk", "nodes", "contacts", "all",
        "node:NAME", "contact:NAME", a comma list or a list of them (--outputs); default lift,
        velocity, acceleration, jerk.
    rpm: engine speed [rpm, crankshaft], up to 1e6: adds SI columns (m/s, m/s^2, m/s^3, rpm).
    duration_at: lift heights for the summary's durations [mm, "0.040in", or deg for a rotating
        output node], a comma list (--duration-at); default 1,0.1.
    threads: worker threads (one per control position at most); default every core.

    Returns a Result: ``columns`` exactly kinematics.csv's (one row per control position and
    driver point), ``summary`` summary.json's content. Raises InputError or NumericalError
    with the CLI's messages; KeyboardInterrupt on Ctrl-C (checked between control positions).
    """
    design = _design(design)
    columns, summary, notes = _camopt.kinematics(
        design.compile(), _range_text(control), _list_text(outputs, "lift,velocity,acceleration,jerk"),
        None if step_deg is None else float(step_deg), None if rpm is None else float(rpm),
        _list_text(duration_at, ""), threads)
    return Result(columns, _json.loads(summary), notes)


def dynamics(design, rpm=None, model="rigid", control=None, step_deg=None, contacts=None, revolutions=None,
             start=None, coil_displacements=None, rtol=None, atol=None, cam_deg=None, release_cam=None, threads=None):
    """Valvetrain dynamics of a design, as ``camopt dynamics --model rigid|flexible|modes`` writes
    them (docs/dynamics.md).

    design: a Design or a design file's path.
    rpm: engine speeds [rpm, crankshaft]: a number, a list of numbers or "START:STOP:COUNT",
        each in (0, 1e6] (--rpm).
    model: "rigid" (kinematically constrained inverse dynamics), "flexible" (the compliant
        train integrated in time, the last revolution reported) or "modes" (natural frequencies
        and mass-normalised mode shapes of the flexible model at its static equilibrium, no
        speed: rpm is not used; ``columns`` is modes.csv).
    control: positions of the design's first control [deg or mm] (--control).
    step_deg: cam angle step [cam deg]; default the design's driver.step_deg (--step).
    contacts: rigid model only: "rigid" (mode a, the default) or "compliant" (stiff separable
        Hertz contacts integrated in time, mode b).
    revolutions: flexible only: cam revolutions integrated at most [1..1000], default 3.
    start: flexible only: "static" (default) or "rest" (every body at rest, every revolution
        reported).
    coil_displacements: flexible only: add every spring coil mass's displacement [mm].
    rtol, atol: flexible only: CVODE relative tolerance (default 1e-6) and absolute tolerance
        on deviations [mm or rad] (default 1e-7).
    cam_deg: modes only: cam angles [cam deg] at which to linearise: a number, a list or
        "START:STOP:COUNT" (--cam-deg); default the driver's start and the angle of peak lift.
    release_cam: modes only: the contacts on the driver carry no stiffness (--release-cam).
    threads: modes only: worker threads of the kinematic sweep; default every core.

    An option of the other model raises InputError, as the CLI does. Returns a Result:
    ``columns`` exactly dynamics.csv's (one row per rpm, control position and cam angle; a
    cell the CSV leaves empty is NaN), ``summary`` summary.json's content. Raises InputError
    or NumericalError with the CLI's messages; KeyboardInterrupt on Ctrl-C (checked between
    runs: control positions, or speeds x positions; within a flexible run between its output
    points, at most every 20 ms).
    """
    design = _design(design)
    if model == "modes":
        return _modes(design, rpm, control, cam_deg, release_cam, threads,
                      dict(contacts=contacts, revolutions=revolutions, start=start,
                           coil_displacements=coil_displacements, rtol=rtol, atol=atol, step_deg=step_deg))
    _reject_unused(model, "--model modes only", cam_deg=cam_deg, release_cam=release_cam)
    if rpm is None:
        raise TypeError("camopt.dynamics: rpm is required with model=%r (the CLI's --rpm)" % model)
    columns, summary, notes = _camopt.dynamics(
        design.compile(), model, _range_text(rpm), _range_text(control), None if step_deg is None else float(step_deg),
        contacts, revolutions, start, coil_displacements, None if rtol is None else float(rtol),
        None if atol is None else float(atol))
    return Result(columns, _json.loads(summary), notes)


# the CLI's names of the keyword options, for its messages
_CLI_NAMES = {"contacts": "--contacts", "revolutions": "--revolutions", "start": "--start",
              "coil_displacements": "--coil-displacements", "rtol": "--rtol", "atol": "--atol",
              "cam_deg": "--cam-deg", "release_cam": "--release-cam", "step_deg": "--step"}


def _reject_unused(model, only, **given):
    """InputError, as the CLI's, for an option given (not None) that the model does not take."""
    for name, value in given.items():
        if value is not None:
            raise InputError("%s: does nothing with --model %s (%s)" % (_CLI_NAMES[name], model, only))


def _modes(design, rpm, control, cam_deg, release_cam, threads, others):
    """dynamics(model="modes"): the flexible and rigid models' options refused as the CLI does."""
    flexible = {k: others.pop(k) for k in ("revolutions", "start", "coil_displacements", "rtol", "atol")}
    _reject_unused("modes", "flexible model only", **flexible)
    _reject_unused("modes", "rigid model only", contacts=others.pop("contacts"))
    notes = []
    if rpm is not None:
        notes.append("dynamics (modes): note: --rpm is not used (the modes are at no speed)")
    columns, summary, more = _camopt.modes(design.compile(), _range_text(control), _range_text(cam_deg),
                                           bool(release_cam), threads)
    return Result(columns, _json.loads(summary), notes + list(more))


def _number(value):
    return None if value is None else float(value)


def _target(target):
    """The target table: (name, header, columns); a path is read by the C++ CSV reader
    (header None), a dict {column: numbers} is a table in memory named "<target>"."""
    if isinstance(target, dict):
        header = [str(k) for k in target]
        return "<target>", header, [[float(v) for v in target[k]] for k in target]
    return _os.fspath(target), None, None


def lift(law, lift_mm=10.0, duration_deg=None, open_deg=None, close_deg=None, dwell_deg=0.0, ramp_height_mm=0.0,
         ramp_length_deg=0.0, close_law=None, close_ramp_height_mm=None, close_ramp_length_deg=None, ramp_blend=0.5,
         peak_deg=180.0, acc_bspline=None, bspline_degree=None, polydyne_rpm=None, polydyne_fn_hz=None,
         step_deg=0.25, basis="cam"):
    """A target valve lift from the lift-law library over one cam revolution, as ``camopt lift``
    writes it: opening ramp, rise, dwell, fall, closing ramp, base circle. Every angle is in
    cam degrees. An option left None is not given (the CLI's default applies).

    law: lift law of the opening flank, and of the closing flank unless close_law (--law,
        --close-law): e.g. "polynomial-345", "modified-sine", "cycloidal", "bspline", "polydyne".
    lift_mm: maximum lift [mm] (--lift).
    duration_deg: whole event at zero lift, ramps and dwell included, split evenly between the
        flanks [cam deg], default 130 (--duration); or open_deg and close_deg: the opening flank
        (start of its ramp to max lift) and the closing flank (end of the dwell to the end of its
        ramp) [cam deg] (--open, --close), not with duration_deg.
    dwell_deg: dwell at maximum lift [cam deg] (--dwell).
    ramp_height_mm, ramp_length_deg: each ramp's height [mm] and length [cam deg]; 0: no ramp
        (--ramp-height, --ramp-length); close_ramp_height_mm, close_ramp_length_deg: the closing
        ramp's, default the same (--close-ramp-height, --close-ramp-length).
    ramp_blend: fraction of each ramp spent reaching its constant velocity, 0 < f <= 1
        (--ramp-blend).
    peak_deg: cam angle of maximum lift, the middle of the dwell [cam deg], 0 <= angle < 360
        (--peak-at).
    acc_bspline: law bspline: the acceleration b-spline's control values, a shape [any unit]
        (a list; --acc-bspline); bspline_degree: its degree, 2..5, default 3 (--bspline-degree).
    polydyne_rpm: law polydyne: design engine speed [rpm, crankshaft] (--polydyne-rpm);
        polydyne_fn_hz: the valvetrain's natural frequency [Hz] (--polydyne-fn).
    step_deg: table step [cam deg]; must divide 360 (--step).
    basis: "cam" (column cam_deg) or "crank" (crank_deg = 2 x cam, derivatives per crank deg)
        (--basis).

    Returns a Result: ``columns`` exactly the CLI's table (cam_deg or crank_deg, lift_mm,
    vel_mm_per_deg, acc_mm_per_deg2, jerk_mm_per_deg3), which ``synthesize`` takes as its
    target; ``summary`` the event's figures the CLI prints (max_lift_mm, max_lift_at_cam_deg,
    duration_0mm_cam_deg, duration_1mm_cam_deg, ..., derivatives per cam deg); ``notes`` those
    lines. Raises InputError with the CLI's message naming the option.
    """
    columns, summary, notes = _camopt.lift(
        str(law), None if close_law is None else str(close_law), float(lift_mm), _number(duration_deg),
        _number(open_deg), _number(close_deg), float(dwell_deg), float(ramp_height_mm), float(ramp_length_deg),
        _number(close_ramp_height_mm), _number(close_ramp_length_deg), float(ramp_blend), float(peak_deg),
        None if acc_bspline is None else [float(v) for v in acc_bspline],
        None if bspline_degree is None else int(bspline_degree), _number(polydyne_rpm), _number(polydyne_fn_hz),
        float(step_deg), str(basis))
    return Result(columns, _json.loads(summary), list(notes))


def synthesize(target, design, cam="rotational", control=None, points=1440, smooth=False, knot_spacing_deg=None,
               wheel_radius_mm=0.0, min_radius_mm=0.0, closure_tolerance_mm=0.05, max_round_trip_error=0.005,
               target_node="", master_radius_mm=None, grinding_step_deg=0.25):
    """The cam profile that gives a target motion (theory of envelopes), as ``camopt synthesize``
    writes it.

    target: the target lift: a CSV file's path (cam_deg or crank_deg, and lift_mm [mm]; or
        <node>_angle_deg [deg] with target_node), or the same table in memory, a dict of column
        name -> numbers, e.g. {"cam_deg": angles, "lift_mm": lifts} (messages name it
        "<target>").
    design: a Design loaded from a file, or a design file's path; its profile on the cam is
        replaced (--design).
    cam: "rotational" (the driver's) or "swing" (--cam).
    control: control position [deg or mm]; default the position of largest lift (--control).
    points: profile resolution [count per revolution], 36..36000 (--points).
    smooth: least-squares fit of a noisy target (--smooth); knot_spacing_deg: its knot spacing
        [cam deg], default 4 (--knot-spacing, only with smooth).
    wheel_radius_mm: grinding wheel radius [mm] (0: no check); min_radius_mm: smallest allowed
        radius of curvature [mm]; closure_tolerance_mm: largest lift at a partial table's ends
        closed on the base circle [mm]; max_round_trip_error: largest error of the profile's
        forward kinematics against the target [mm; deg for a rotational target_node].
    target_node: the node whose motion the target gives (default the valve).
    master_radius_mm: grinding table master [mm] (0: flat; default the follower's roller);
        grinding_step_deg: its cam angle step [cam deg], 0.01..10.

    Returns a Result: ``tables["profile.csv"]`` (also ``columns``) and ``tables["grinding.csv"]``
    exactly the CLI's, ``summary`` report.json, ``files`` profile.dxf, design.toml, ...;
    ``design`` the written design.toml as a Design that the next job runs directly (its
    profile.csv in a temporary folder the Design owns). Raises InputError or NumericalError
    with the CLI's messages.
    """
    design = _design(design)
    if not smooth and knot_spacing_deg is not None:
        raise InputError("--knot-spacing: does nothing without --smooth")
    name, header, values = _target(target)
    folder = _tempfile.TemporaryDirectory(prefix="camopt-")
    tables, report, notes, files = _camopt.synthesize(
        design.compile(), design._overrides, name, header, values, folder.name, cam, _number(control), int(points), bool(smooth),
        4.0 if knot_spacing_deg is None else float(knot_spacing_deg), float(wheel_radius_mm), float(min_radius_mm),
        float(closure_tolerance_mm), float(max_round_trip_error), target_node, _number(master_radius_mm),
        float(grinding_step_deg))
    return Result(tables["profile.csv"], _json.loads(report), list(notes), tables, _folder_design(files, folder), files)


def _folder_design(files, folder):
    """design.toml as a Design, its profile.csv written into `folder` (a TemporaryDirectory the
    Design keeps, removed with it): the folder the job wrote design.toml for."""
    with open(_os.path.join(folder.name, "profile.csv"), "wb") as f:
        f.write(files["profile.csv"])
    written = Design(files["design.toml"].decode(), _os.path.join(folder.name, "design.toml"))
    written._folder = folder
    return written


def optimize(design, constraints, cam="rotational", solver="ipopt", points=1440, max_iterations=3000, starts=None,
             verify=False, constraint_overrides=None):
    """A cam's lift optimised under a constraint set, and its profile, as ``camopt optimize``
    writes them (docs/optimisation.md).

    design: a Design loaded from a file, or a design file's path.
    constraints: the constraint set's TOML file (--constraints; see constraints/).
    cam: "rotational" (the driver's, [event] lift model) or "swing" (--cam).
    solver: "ipopt", "slsqp", "mma", "cobyla" or "global" (--solver).
    points: profile resolution [count per revolution], 36..100000 (--points).
    max_iterations: ipopt iterations or nlopt evaluations, 1..1e6 (--max-iterations).
    starts: global only: number of starts, 1..1000 (--starts; default 6).
    verify: run the made design through kinematics, rigid and flexible dynamics (--verify):
        ``summary["verified"]`` and ``summary["verification"]`` say how it did (the CLI exits
        5 when it fails; here the result is returned).
    constraint_overrides: changes of the set before it is read, {key path: value}, e.g.
        {"limits.max_pressure_angle_deg": 28} (--set-constraint KEY=VALUE; a value is a number,
        a bool, a str or a list, as Design.set takes).

    Returns a Result: ``tables`` lift.csv (a swing cam: also swing_pitch.csv), profile.csv and
    grinding.csv; ``columns`` lift.csv's; ``summary`` report.json; ``files`` and ``design`` as
    synthesize's. Raises InputError, or NumericalError when the solver fails (an infeasible
    set: its message names the conflicting limits; its ``report`` is the report.json the CLI
    writes before it exits 4); KeyboardInterrupt on Ctrl-C (checked at every solver iteration).
    """
    design = _design(design)
    if solver != "global" and starts is not None:
        raise InputError("--starts: does nothing with --solver %s (global only)" % solver)
    folder = _tempfile.TemporaryDirectory(prefix="camopt-")
    tables, report, notes, files, verified, failures = _camopt.optimize(
        design.compile(), design._overrides, _os.fspath(constraints),
        [(str(k), _to_toml(v)) for k, v in (constraint_overrides or {}).items()], folder.name, solver, cam, bool(verify), int(points),
        int(max_iterations), 6 if starts is None else int(starts))
    return Result(tables["lift.csv"], _json.loads(report), list(notes), tables, _folder_design(files, folder), files)


def study(spec, out=None, workers=None, scheduler=None, client=None, progress=None):
    """Run a design study (docs/studies.md): ``spec`` is the path of a STUDY.toml or a
    ``camopt.studies.StudySpec``. Every point runs the study's pipeline on the design with the
    point's values ``set``; the result holds every point (its parameters, its responses in their
    units, its status and error), the Pareto set and the main effects, and for a geometry
    optimisation the best point. ``out``: a folder for results.csv, pareto.csv,
    main_effects.csv and study.json. ``workers``: local processes (default every core; 1 runs
    in this process). ``scheduler`` (tcp://HOST:PORT) or ``client`` (a distributed.Client):
    run the points on a Dask cluster. A study-file error raises
    ``camopt.studies.StudyInputError`` naming the file, key, value and rule."""
    from . import studies

    return studies.study(spec, out=out, workers=workers, scheduler=scheduler, client=client, progress=progress)
