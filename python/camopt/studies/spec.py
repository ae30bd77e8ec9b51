"""The study file (STUDY.toml) read into a plain, checked StudySpec.

Every error names the file, the key path, the value and the rule, as the design-file reader
does (docs/studies.md lists the keys).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field
from typing import Any

from .. import InputError

SAMPLING_METHODS = ("full_factorial", "latin_hypercube", "sobol")
STAGES = ("synthesize", "optimize", "kinematics", "rigid", "flexible")
REDUCTIONS = ("max", "min", "mean", "first", "sum")
NLOPT_ALGORITHMS = ("LN_COBYLA", "LN_BOBYQA", "LN_NELDERMEAD", "LN_SBPLX", "GN_DIRECT_L", "GN_ISRES")


class StudyInputError(InputError):
    """A study file or argument that breaks a rule: the message names where, the value and the rule
    (a camopt.InputError, as the CLI's exit 3)."""


@dataclass(frozen=True)
class Parameter:
    """A design key (or `constraints.<key>` of the constraint set) varied over [low, high]."""

    key: str
    low: float
    high: float
    levels: tuple[float, ...] = ()  # the full-factorial levels (given or evenly spaced)
    integer: bool = False  # rounded to the nearest integer (a coil count, a surge-mass count)


@dataclass(frozen=True)
class Response:
    """A scalar taken from a stage's summary: `path` into its JSON, `*` over list items or keys."""

    name: str
    stage: str
    path: str
    reduce: str = "max"


@dataclass(frozen=True)
class Limit:
    """A geometry-optimisation constraint on a response: low <= response <= high."""

    response: str
    low: float = -math.inf
    high: float = math.inf


@dataclass(frozen=True)
class GeometryOptimisation:
    """The outer NLopt loop over the parameters: optimise one response under limits on others."""

    objective: str
    maximize: bool
    algorithm: str = "LN_COBYLA"
    max_evaluations: int = 40
    relative_tolerance: float = 1e-4
    limits: tuple[Limit, ...] = ()


@dataclass(frozen=True)
class StudySpec:
    """A study: the design, the parameters and how they are sampled, the pipeline run at every
    point, the responses kept, and either a Pareto set or a geometry optimisation."""

    file: str
    name: str
    design: str  # absolute path
    parameters: tuple[Parameter, ...]
    method: str
    points: int
    seed: int
    pipeline: dict[str, dict[str, Any]]  # stage -> its options (file paths absolute)
    responses: tuple[Response, ...]
    pareto: tuple[tuple[str, bool], ...] = ()  # (response, maximize)
    main_effect_bins: int = 4
    optimisation: GeometryOptimisation | None = None
    constraints: str | None = None  # the constraint set (absolute path) of an optimize stage
    base: dict = field(default_factory=dict)  # the raw table, for study.json


def _fail(where: str, value: Any, rule: str) -> None:
    raise StudyInputError(f"{where}: {value!r}: {rule}")


class _Table:
    """A TOML table that knows its path and rejects keys it does not know."""

    def __init__(self, file: str, path: str, data: Any):
        self.file, self.path = file, path
        if not isinstance(data, dict):
            _fail(self.where(), data, "must be a table")
        self.data = data

    def where(self, key: str | None = None) -> str:
        inner = ".".join(p for p in (self.path, key) if p)
        return f"{self.file}: {inner}" if inner else self.file

    def allow(self, keys: tuple[str, ...]) -> None:
        for key in self.data:
            if key not in keys:
                raise StudyInputError(f"{self.where(key)}: unknown key (allowed: {', '.join(keys)})")

    def has(self, key: str) -> bool:
        return key in self.data

    def get(self, key: str, kind: type | tuple, default: Any = None, required: bool = False) -> Any:
        if key not in self.data:
            if required:
                raise StudyInputError(f"{self.where(key)}: missing (required)")
            return default
        value = self.data[key]
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if not isinstance(value, kind) or (kind in (int, float) and isinstance(value, bool)):
            names = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
            _fail(self.where(key), value, f"must be a {names}")
        if isinstance(value, float) and not math.isfinite(value):
            _fail(self.where(key), value, "must be finite")
        return value

    def table(self, key: str) -> "_Table | None":
        return _Table(self.file, ".".join(p for p in (self.path, key) if p), self.data[key]) if key in self.data else None

    def tables(self, key: str) -> list["_Table"]:
        items = self.data.get(key, [])
        if not isinstance(items, list):
            _fail(self.where(key), items, "must be an array of tables ([[" + key + "]])")
        return [_Table(self.file, f"{key}[{i}]", item) for i, item in enumerate(items)]


def _path(directory: str, value: str) -> str:
    return value if os.path.isabs(value) else os.path.normpath(os.path.join(directory, value))


def _parameter(t: _Table, method: str) -> Parameter:
    t.allow(("key", "min", "max", "levels", "values", "integer"))
    key = t.get("key", str, required=True)
    if not key or key.startswith(".") or key.endswith("."):
        _fail(t.where("key"), key, "must be a key path such as node.finger.mass_kg")
    integer = t.get("integer", bool, False)
    if t.has("values"):
        values = t.get("values", list)
        if t.has("min") or t.has("max") or t.has("levels"):
            raise StudyInputError(f"{t.where('values')}: give either values or min/max (and levels), not both")
        if method != "full_factorial":
            _fail(t.where("values"), values, "a list of values needs sampling.method = \"full_factorial\"")
        if not values:
            _fail(t.where("values"), values, "must hold at least one number")
        levels = []
        for i, v in enumerate(values):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                _fail(t.where(f"values[{i}]"), v, "must be a finite number")
            levels.append(float(v))
        return Parameter(key, min(levels), max(levels), tuple(levels), integer)
    low = t.get("min", float, required=True)
    high = t.get("max", float, required=True)
    if not low < high:
        _fail(t.where("max"), high, f"must be greater than min ({low!r})")
    levels: tuple[float, ...] = ()
    if method == "full_factorial":
        count = t.get("levels", int, required=True)
        if count < 2:
            _fail(t.where("levels"), count, "must be >= 2")
        levels = tuple(low + (high - low) * i / (count - 1) for i in range(count))
        if integer:
            levels = tuple(sorted({float(round(v)) for v in levels}))
    elif t.has("levels"):
        _fail(t.where("levels"), t.data["levels"], "levels are for sampling.method = \"full_factorial\"")
    return Parameter(key, low, high, levels, integer)


def _response(t: _Table, stages: dict) -> Response:
    t.allow(("name", "stage", "path", "reduce"))
    name = t.get("name", str, required=True)
    stage = t.get("stage", str, required=True)
    if stage not in STAGES:
        _fail(t.where("stage"), stage, "must be one of " + ", ".join(STAGES))
    if stage not in stages:
        _fail(t.where("stage"), stage, "the pipeline has no such stage (add [pipeline." + stage + "])")
    path = t.get("path", str, required=True)
    if not path:
        _fail(t.where("path"), path, "must name a summary value, e.g. positions[*].max_pressure_angle_deg")
    reduce = t.get("reduce", str, "max")
    if reduce not in REDUCTIONS:
        _fail(t.where("reduce"), reduce, "must be one of " + ", ".join(REDUCTIONS))
    return Response(name, stage, path, reduce)


def _pipeline(t: _Table | None, file: str, directory: str) -> dict[str, dict[str, Any]]:
    if t is None:
        raise StudyInputError(f"{file}: pipeline: missing (required: at least one of {', '.join(STAGES)})")
    t.allow(STAGES)
    if "synthesize" in t.data and "optimize" in t.data:
        raise StudyInputError(f"{t.where('optimize')}: a pipeline synthesizes or optimises the cam, not both")
    stages: dict[str, dict[str, Any]] = {}
    for stage in STAGES:
        sub = t.table(stage)
        if sub is None:
            continue
        options = dict(sub.data)
        for key in ("target", "constraints"):
            if key in options:
                if not isinstance(options[key], str):
                    _fail(sub.where(key), options[key], "must be a file path (a string)")
                options[key] = _path(directory, options[key])
        stages[stage] = options
    if not stages:
        raise StudyInputError(f"{t.where()}: empty (at least one of {', '.join(STAGES)})")
    if "synthesize" in stages and "target" not in stages["synthesize"]:
        raise StudyInputError(f"{t.where('synthesize.target')}: missing (the target lift CSV)")
    if "optimize" in stages and "constraints" not in stages["optimize"]:
        raise StudyInputError(f"{t.where('optimize.constraints')}: missing (the constraint set TOML)")
    return stages


def _optimisation(t: _Table, responses: dict[str, Response]) -> GeometryOptimisation:
    t.allow(("objective", "sense", "algorithm", "max_evaluations", "relative_tolerance", "limit"))
    objective = t.get("objective", str, required=True)
    if objective not in responses:
        _fail(t.where("objective"), objective, "must name a [[response]] (" + ", ".join(responses) + ")")
    sense = t.get("sense", str, required=True)
    if sense not in ("minimize", "maximize"):
        _fail(t.where("sense"), sense, "must be minimize or maximize")
    algorithm = t.get("algorithm", str, "LN_COBYLA")
    if algorithm not in NLOPT_ALGORITHMS:
        _fail(t.where("algorithm"), algorithm, "must be one of " + ", ".join(NLOPT_ALGORITHMS))
    evaluations = t.get("max_evaluations", int, 40)
    if evaluations < 1:
        _fail(t.where("max_evaluations"), evaluations, "must be >= 1")
    rtol = t.get("relative_tolerance", float, 1e-4)
    if not rtol > 0:
        _fail(t.where("relative_tolerance"), rtol, "must be > 0")
    limits = []
    for lt in t.tables("limit"):
        lt.path = t.path + "." + lt.path
        lt.allow(("response", "min", "max"))
        name = lt.get("response", str, required=True)
        if name not in responses:
            _fail(lt.where("response"), name, "must name a [[response]] (" + ", ".join(responses) + ")")
        low, high = lt.get("min", float, -math.inf), lt.get("max", float, math.inf)
        if not (lt.has("min") or lt.has("max")):
            raise StudyInputError(f"{lt.where()}: give min and/or max")
        if low > high:
            _fail(lt.where("max"), high, f"must be >= min ({low!r})")
        limits.append(Limit(name, low, high))
    if algorithm in ("LN_BOBYQA", "LN_NELDERMEAD", "LN_SBPLX", "GN_DIRECT_L") and limits:
        _fail(t.where("algorithm"), algorithm, "takes no limits: use LN_COBYLA or GN_ISRES with [[optimize.limit]]")
    return GeometryOptimisation(objective, sense == "maximize", algorithm, evaluations, rtol, tuple(limits))


def parse_study(data: dict, file: str) -> StudySpec:
    """Check a study table (as tomllib reads it) from `file`; relative paths are from its folder."""
    directory = os.path.dirname(os.path.abspath(file))
    root = _Table(file, "", data)
    root.allow(("schema", "study", "sampling", "parameter", "pipeline", "response", "pareto", "optimize"))
    schema = root.get("schema", int, 1)
    if schema != 1:
        _fail(root.where("schema"), schema, "must be 1 (the only study-file schema)")
    study = root.table("study") or _Table(file, "study", {})
    study.allow(("name", "design", "main_effect_bins"))
    name = study.get("name", str, os.path.splitext(os.path.basename(file))[0])
    design = _path(directory, study.get("design", str, required=True))
    bins = study.get("main_effect_bins", int, 4)
    if bins < 2:
        _fail(study.where("main_effect_bins"), bins, "must be >= 2")

    optimisation_table = root.table("optimize")
    sampling = root.table("sampling") or _Table(file, "sampling", {})
    sampling.allow(("method", "points", "seed"))
    method = sampling.get("method", str, "full_factorial")
    if method not in SAMPLING_METHODS:
        _fail(sampling.where("method"), method, "must be one of " + ", ".join(SAMPLING_METHODS))
    if optimisation_table is not None:
        if root.has("sampling"):
            raise StudyInputError(f"{file}: optimize: a geometry optimisation chooses its own points (no [sampling])")
        method = "latin_hypercube"  # the parameters need min/max only
    points = sampling.get("points", int, 0)
    seed = sampling.get("seed", int, 0)
    if method == "full_factorial" and sampling.has("points"):
        _fail(sampling.where("points"), points, "full_factorial takes its points from the levels")
    if method != "full_factorial" and optimisation_table is None:
        if points < 1:
            _fail(sampling.where("points"), points, "must be >= 1")
        if method == "sobol" and points & (points - 1):
            _fail(sampling.where("points"), points, "must be a power of 2 (Sobol points keep their balance only then)")

    parameters = tuple(_parameter(t, method) for t in root.tables("parameter"))
    if not parameters:
        raise StudyInputError(f"{file}: parameter: missing (at least one [[parameter]])")
    keys = [p.key for p in parameters]
    for i, key in enumerate(keys):
        if key in keys[:i]:
            _fail(f"{file}: parameter[{i}].key", key, "appears twice")
    if method == "full_factorial":
        points = math.prod(len(p.levels) for p in parameters)

    pipeline = _pipeline(root.table("pipeline"), file, directory)
    constraints = pipeline.get("optimize", {}).get("constraints")
    for i, p in enumerate(parameters):
        if p.key.startswith("constraints.") and constraints is None:
            _fail(f"{file}: parameter[{i}].key", p.key, "a constraint-set key needs a [pipeline.optimize] stage")
    responses = tuple(_response(t, pipeline) for t in root.tables("response"))
    if not responses:
        raise StudyInputError(f"{file}: response: missing (at least one [[response]])")
    by_name = {}
    for i, r in enumerate(responses):
        if r.name in by_name or r.name in keys:
            _fail(f"{file}: response[{i}].name", r.name, "names another response or a parameter")
        by_name[r.name] = r

    pareto: list[tuple[str, bool]] = []
    pareto_table = root.table("pareto")
    if pareto_table is not None:
        pareto_table.allow(("minimize", "maximize"))
        for sense in ("minimize", "maximize"):
            for i, name in enumerate(pareto_table.get(sense, list, [])):
                if name not in by_name:
                    _fail(pareto_table.where(f"{sense}[{i}]"), name, "must name a [[response]]")
                pareto.append((name, sense == "maximize"))
        if not pareto:
            raise StudyInputError(f"{pareto_table.where()}: give minimize and/or maximize")
    optimisation = _optimisation(optimisation_table, by_name) if optimisation_table is not None else None
    return StudySpec(file, name, design, parameters, method, points, seed, pipeline, responses, tuple(pareto), bins,
                     optimisation, constraints, data)


def load_study(path: str) -> StudySpec:
    """Read and check STUDY.toml."""
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except OSError as e:
        raise StudyInputError(f"{path}: cannot read the study file ({e.strerror})") from None
    except tomllib.TOMLDecodeError as e:
        raise StudyInputError(f"{path}: {e}") from None
    return parse_study(data, path)
