"""One study point: the design with the point's parameter values, the pipeline's stages run on
it through the camopt API, and the responses read from the stages' summaries.

A point never raises: an input error, a numerical failure or any other exception is kept as
the point's status and message, so one bad corner of a design space does not stop a study.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from .analysis import ResponseMissing, response_value
from .spec import StudySpec

# the columns "status" takes
OK, INPUT_ERROR, NUMERICAL_FAILURE, RESPONSE_MISSING, INTERNAL_ERROR = (
    "ok", "input error", "numerical failure", "response missing", "internal error")


@dataclass
class PointResult:
    """What one point gave: its responses (NaN where it failed), status, message, seconds."""

    index: int
    values: tuple[float, ...]
    responses: tuple[float, ...]
    status: str = OK
    error: str = ""
    seconds: float = 0.0


def point_design(spec: StudySpec, values: tuple[float, ...]):
    """The study's design with the point's design keys set, and the constraint-set overrides
    (key path in the set -> the number, as ``camopt.optimize``'s constraint_overrides takes it)."""
    import camopt

    design = camopt.Design.load(spec.design)
    constraint_overrides: dict[str, float | int] = {}
    for p, v in zip(spec.parameters, values):
        value = int(v) if p.integer else float(v)
        if p.key.startswith("constraints."):
            constraint_overrides[p.key[len("constraints."):]] = value
        else:
            design.set(p.key, value)
    return design, constraint_overrides


def run_stages(spec: StudySpec, design, constraint_overrides: dict[str, float | int], threads: int = 0) -> dict[str, dict]:
    """Every stage of the pipeline in order; the summary of each, by stage name. `threads` is
    the kinematic sweep's thread count (0: every core) unless the stage gives its own."""
    import camopt

    summaries: dict[str, dict] = {}
    stages = spec.pipeline
    if "synthesize" in stages:
        options = {k: v for k, v in stages["synthesize"].items() if k != "target"}
        made = camopt.synthesize(stages["synthesize"]["target"], design, **options)
        summaries["synthesize"], design = made.summary, made.design
    if "optimize" in stages:
        options = {k: v for k, v in stages["optimize"].items() if k != "constraints"}
        made = camopt.optimize(design, stages["optimize"]["constraints"], constraint_overrides=constraint_overrides,
                               **options)
        summaries["optimize"], design = made.summary, made.design
    if "kinematics" in stages:
        options = dict(stages["kinematics"])
        if threads > 0:
            options.setdefault("threads", threads)
        summaries["kinematics"] = camopt.kinematics(design, **options).summary
    for model in ("rigid", "flexible"):
        if model in stages:
            summaries[model] = camopt.dynamics(design, model=model, **stages[model]).summary
    return summaries


def evaluate_point(spec: StudySpec, index: int, values: tuple[float, ...], threads: int = 1) -> PointResult:
    """Run one point; `threads` is the sweeps' thread count inside the point (1 when the points
    themselves run in parallel)."""
    import camopt

    start = time.perf_counter()
    nan = tuple(math.nan for _ in spec.responses)
    result = PointResult(index, tuple(values), nan)
    try:
        design, constraint_overrides = point_design(spec, values)
        summaries = run_stages(spec, design, constraint_overrides, threads)
        result.responses = tuple(response_value(summaries[r.stage], r.path, r.reduce) for r in spec.responses)
    except camopt.InputError as e:
        result.status, result.error = INPUT_ERROR, str(e)
    except camopt.NumericalError as e:
        result.status, result.error = NUMERICAL_FAILURE, str(e)
    except ResponseMissing as e:
        result.status, result.error = RESPONSE_MISSING, str(e)
    except Exception as e:  # noqa: BLE001 - a point's failure is its row, never the study's
        result.status, result.error = INTERNAL_ERROR, f"{type(e).__name__}: {e}"
    result.seconds = time.perf_counter() - start
    return result


def evaluate_batch(spec: StudySpec, batch: list[tuple[int, tuple[float, ...]]], threads: int = 1
                   ) -> list[PointResult]:
    """Several points in one task (fewer round trips to a Dask worker or a process)."""
    return [evaluate_point(spec, i, v, threads) for i, v in batch]


def summary_of(result: PointResult, spec: StudySpec) -> dict[str, Any]:
    """A result as a dict: parameters and responses by name, status, error, seconds."""
    row: dict[str, Any] = {"point": result.index}
    row.update({p.key: v for p, v in zip(spec.parameters, result.values)})
    row.update({r.name: v for r, v in zip(spec.responses, result.responses)})
    row.update({"status": result.status, "error": result.error, "seconds": result.seconds})
    return row
