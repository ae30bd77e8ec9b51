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
solve releases the GIL and stops on Ctrl-C (KeyboardInterrupt) between control positions.
"""

import json as _json
import os as _os

from . import _camopt
from ._camopt import Error, InputError, NumericalError

__all__ = ["Design", "Result", "kinematics", "dynamics", "Error", "InputError", "NumericalError", "__version__"]

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
    """

    def __init__(self, columns, summary, notes):
        self.columns = columns
        self.summary = summary
        self.notes = notes

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


def kinematics(design, step_deg=None, control=None, outputs=None, rpm=None, duration_at=None, threads=None):
    """The kinematic sweep of a design, as ``camopt kinematics`` writes it.

    design: a Design or a design file's path.
    step_deg: driver step [cam deg, or mm for a translating driver]; default: the design's
        driver.step_deg (--step).
    control: positions of the design's first control [deg or mm]: a number, a list of numbers,
        or "START:STOP:COUNT" (--control); default: the control's default.
    outputs: "lift", "velocity", "acceleration", "jerk", "nodes", "contacts", "all", a comma
        list or a list of them (--outputs); default lift, velocity, acceleration, jerk.
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


def dynamics(design, rpm, model="rigid", control=None, step_deg=None, contacts=None, revolutions=None, start=None,
             coil_displacements=None, rtol=None, atol=None):
    """Valvetrain dynamics of a design, as ``camopt dynamics --model rigid|flexible`` writes them
    (docs/dynamics.md).

    design: a Design or a design file's path.
    rpm: engine speeds [rpm, crankshaft]: a number, a list of numbers or "START:STOP:COUNT",
        each in (0, 1e6] (--rpm).
    model: "rigid" (kinematically constrained inverse dynamics) or "flexible" (the compliant
        train integrated in time, the last revolution reported).
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

    An option of the other model raises InputError, as the CLI does. Returns a Result:
    ``columns`` exactly dynamics.csv's (one row per rpm, control position and cam angle; a
    cell the CSV leaves empty is NaN), ``summary`` summary.json's content. Raises InputError
    or NumericalError with the CLI's messages; KeyboardInterrupt on Ctrl-C (checked between
    runs: control positions, or speeds x positions).
    """
    design = _design(design)
    columns, summary, notes = _camopt.dynamics(
        design.compile(), model, _range_text(rpm), _range_text(control), None if step_deg is None else float(step_deg),
        contacts, revolutions, start, coil_displacements, None if rtol is None else float(rtol),
        None if atol is None else float(atol))
    return Result(columns, _json.loads(summary), notes)
