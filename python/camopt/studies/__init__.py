"""Design studies: DOE over design and constraint-set keys, Pareto sets, main effects and
geometry optimisation, on the local cores or a Dask cluster (docs/studies.md)."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from . import analysis, executors, outputs, sampling
from .geometry import optimise_geometry
from .pipeline import OK, PointResult, evaluate_point, summary_of
from .spec import StudyInputError, StudySpec, load_study, parse_study

__all__ = ["study", "load_study", "parse_study", "StudySpec", "StudyResult", "StudyInputError"]


@dataclass
class StudyResult:
    """A finished study: every point (rows), the Pareto points, the main effects, and for a
    geometry optimisation the best point and NLopt's stop reason."""

    spec: StudySpec
    points: list[PointResult]
    pareto: list[int]  # point indices
    main_effects: list[dict[str, Any]]
    best: PointResult | None = None
    stop_reason: str = ""
    seconds: float = 0.0
    executor: str = "serial"

    @property
    def rows(self) -> list[dict[str, Any]]:
        """Every point as a dict: parameters by key, responses by name, status, error, seconds."""
        return [summary_of(r, self.spec) for r in self.points]

    def column(self, name: str) -> np.ndarray:
        """A parameter or response over the points, as a float array (NaN where a point failed)."""
        keys = [p.key for p in self.spec.parameters]
        if name in keys:
            return np.array([r.values[keys.index(name)] for r in self.points])
        names = [r.name for r in self.spec.responses]
        if name in names:
            return np.array([r.responses[names.index(name)] for r in self.points])
        raise KeyError(f"{name}: neither a parameter ({', '.join(keys)}) nor a response ({', '.join(names)})")


def _run_points(spec: StudySpec, points: list[tuple[float, ...]], workers: int | None, scheduler: str | None,
                client, progress) -> tuple[list[PointResult], str]:
    if client is not None or scheduler is not None:
        where = scheduler or "dask client"
        return executors.run_dask(spec, points, client=client, scheduler=scheduler, progress=progress), where
    count = workers if workers is not None else executors.default_workers()
    if count == 1:
        return executors.run_serial(spec, points, progress=progress), "serial"
    return executors.run_local(spec, points, count, progress=progress), f"{count} local processes"


def _analyse(spec: StudySpec, results: list[PointResult]) -> tuple[list[int], list[dict[str, Any]]]:
    values = np.array([r.values for r in results], dtype=float).reshape(len(results), len(spec.parameters))
    responses = np.array([r.responses for r in results], dtype=float).reshape(len(results), len(spec.responses))
    pareto: list[int] = []
    if spec.pareto:
        names = [r.name for r in spec.responses]
        columns = responses[:, [names.index(n) for n, _ in spec.pareto]]
        mask = analysis.pareto_mask(columns, [m for _, m in spec.pareto])
        pareto = [results[i].index for i in np.flatnonzero(mask)]
    levels = [p.levels if spec.method == "full_factorial" else () for p in spec.parameters]
    ranges = [(p.low, p.high) for p in spec.parameters]
    effects = analysis.main_effects(values, responses, levels, spec.main_effect_bins, ranges) if len(results) else []
    return pareto, effects


def _document(result: StudyResult) -> dict[str, Any]:
    spec = result.spec
    ok = sum(1 for r in result.points if r.status == OK)
    doc: dict[str, Any] = {
        "study": spec.name, "study_file": spec.file, "design_file": spec.design,
        "method": "nlopt " + spec.optimisation.algorithm if spec.optimisation else spec.method,
        "seed": spec.seed, "points": len(result.points), "points_ok": ok, "points_failed": len(result.points) - ok,
        "parameters": [{"key": p.key, "min": p.low, "max": p.high} for p in spec.parameters],
        "responses": [{"name": r.name, "stage": r.stage, "path": r.path, "reduce": r.reduce} for r in spec.responses],
        "pipeline": list(spec.pipeline), "pareto_points": result.pareto,
        "executor": result.executor, "run_time_s": result.seconds,
        "points_per_s": len(result.points) / result.seconds if result.seconds > 0 else None,
    }
    if spec.optimisation:
        best = result.best
        doc["optimisation"] = {
            "objective": spec.optimisation.objective, "sense": "maximize" if spec.optimisation.maximize else "minimize",
            "stop_reason": result.stop_reason, "evaluations": len(result.points),
            "best_point": best.index if best else None,
            "best_parameters": {p.key: v for p, v in zip(spec.parameters, best.values)} if best else None,
            "best_responses": {r.name: outputs.finite_or_none(v) for r, v in zip(spec.responses, best.responses)}
            if best else None,
        }
    return doc


def study(spec: StudySpec | str, out: str | None = None, workers: int | None = None, scheduler: str | None = None,
          client=None, progress=None) -> StudyResult:
    """Run a study (a StudySpec or the path of STUDY.toml).

    out: a folder for results.csv, pareto.csv, main_effects.csv and study.json (written as one set).
    workers: local processes (default: all cores; 1 runs in this process).
    scheduler: a Dask scheduler's address (tcp://HOST:PORT), or client: a distributed.Client of
    yours; the points then run on that cluster's workers.
    progress: called as progress(done, total) after each batch.
    A point that fails is a row with its status and message, not an exception. A geometry
    optimisation ([optimize]) evaluates its points one after the other, in this process.
    """
    if isinstance(spec, (str, os.PathLike)):
        spec = load_study(os.fspath(spec))
    if out is not None:
        outputs.check_out_dir(spec, out)
    start = time.perf_counter()
    best, reason = None, ""
    if spec.optimisation:
        found = optimise_geometry(spec, partial(_evaluate_here, spec))
        results, best, reason, where = found.evaluations, found.best, found.reason, "serial"
    else:
        points = [tuple(p) for p in sampling.sample(spec)]
        results, where = _run_points(spec, points, workers, scheduler, client, progress)
    pareto, effects = _analyse(spec, results)
    result = StudyResult(spec, results, pareto, effects, best, reason, time.perf_counter() - start, where)
    if out is not None:
        by_index = {r.index: r for r in results}
        outputs.write_outputs(out, {
            "results.csv": outputs.results_table(spec, results),
            "pareto.csv": outputs.results_table(spec, [by_index[i] for i in pareto]),
            "main_effects.csv": outputs.main_effects_table(spec, effects),
            "study.json": outputs.study_json(_document(result)),
        })
    return result


def _evaluate_here(spec: StudySpec, index: int, values: tuple[float, ...]) -> PointResult:
    return evaluate_point(spec, index, values, threads=0)
