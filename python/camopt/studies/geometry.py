"""Geometry optimisation: an outer NLopt loop over the study's parameters, the pipeline (the cam
re-synthesized or re-optimised, then kinematics and dynamics) run at every evaluation.

NLopt's derivative-free algorithms see the parameters scaled to [0, 1]. A point that fails
(its design does not assemble, a solve fails) is infeasible: its limits read as violated and its
objective as the worst value seen so far, so the search steps back from it instead of stopping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import nlopt
import numpy as np

from .pipeline import OK, PointResult
from .spec import StudySpec

Evaluate = Callable[[int, tuple[float, ...]], PointResult]

_RESULT_NAMES = {
    nlopt.SUCCESS: "success", nlopt.STOPVAL_REACHED: "stopval reached", nlopt.FTOL_REACHED: "ftol reached",
    nlopt.XTOL_REACHED: "xtol reached", nlopt.MAXEVAL_REACHED: "max evaluations reached",
    nlopt.MAXTIME_REACHED: "max time reached",
}


@dataclass
class OptimisationResult:
    """The best feasible evaluation (or None), NLopt's stop reason, every evaluation in order."""

    best: PointResult | None
    reason: str
    evaluations: list[PointResult]


def _feasible(spec: StudySpec, r: PointResult) -> bool:
    if r.status != OK:
        return False
    names = [x.name for x in spec.responses]
    for limit in spec.optimisation.limits:
        value = r.responses[names.index(limit.response)]
        if not limit.low <= value <= limit.high:
            return False
    return True


def optimise_geometry(spec: StudySpec, evaluate: Evaluate) -> OptimisationResult:
    """Run NLopt from the centre of the parameter box; `evaluate(index, values)` runs one point."""
    opt_spec = spec.optimisation
    names = [r.name for r in spec.responses]
    objective_at = names.index(opt_spec.objective)
    low = np.array([p.low for p in spec.parameters])
    span = np.array([p.high - p.low for p in spec.parameters])
    d = len(spec.parameters)
    evaluations: list[PointResult] = []
    cache: dict[tuple[float, ...], PointResult] = {}
    sign = -1.0 if opt_spec.maximize else 1.0  # NLopt minimises sign * objective

    def run(u: np.ndarray) -> PointResult:
        values = tuple(float(v) for v in low + span * np.clip(u, 0.0, 1.0))
        values = tuple(float(round(v)) if p.integer else v for p, v in zip(spec.parameters, values))
        if values not in cache:
            result = evaluate(len(evaluations), values)
            evaluations.append(result)
            cache[values] = result
        return cache[values]

    def worst() -> float:
        seen = [sign * r.responses[objective_at] for r in evaluations
                if r.status == OK and math.isfinite(r.responses[objective_at])]
        return max(seen) + (max(seen) - min(seen) + 1.0) if seen else 1e30

    def objective(u, grad):
        r = run(u)
        value = sign * r.responses[objective_at]
        return value if r.status == OK and math.isfinite(value) else worst()

    opt = nlopt.opt(getattr(nlopt, opt_spec.algorithm), d)
    opt.set_lower_bounds(np.zeros(d))
    opt.set_upper_bounds(np.ones(d))
    opt.set_min_objective(objective)
    for limit in opt_spec.limits:
        at = names.index(limit.response)
        scale = max(1.0, abs(limit.high) if math.isfinite(limit.high) else abs(limit.low))
        if math.isfinite(limit.high):
            opt.add_inequality_constraint(
                lambda u, g, at=at, h=limit.high, s=scale: _limit_value(run(u), at, h, s, 1.0), 1e-9)
        if math.isfinite(limit.low):
            opt.add_inequality_constraint(
                lambda u, g, at=at, lo=limit.low, s=scale: _limit_value(run(u), at, lo, s, -1.0), 1e-9)
    opt.set_maxeval(opt_spec.max_evaluations)
    opt.set_xtol_rel(opt_spec.relative_tolerance)
    opt.set_initial_step(np.full(d, 0.25))
    if opt_spec.algorithm.startswith("GN_"):
        opt.set_population(0)
    try:
        opt.optimize(np.full(d, 0.5))
        reason = _RESULT_NAMES.get(opt.last_optimize_result(), f"nlopt result {opt.last_optimize_result()}")
    except nlopt.RoundoffLimited:
        reason = "roundoff limited (the best point so far is kept)"
    feasible = [r for r in evaluations if _feasible(spec, r)]
    best = min(feasible, key=lambda r: (sign * r.responses[objective_at], r.index)) if feasible else None
    return OptimisationResult(best, reason, evaluations)


def _limit_value(r: PointResult, at: int, bound: float, scale: float, side: float) -> float:
    """NLopt's c(u) <= 0 form of response <= bound (side 1) or >= bound (side -1), scaled."""
    if r.status != OK or not math.isfinite(r.responses[at]):
        return 1.0
    return side * (r.responses[at] - bound) / scale
