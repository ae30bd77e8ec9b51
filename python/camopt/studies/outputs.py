"""A study's files: results.csv, pareto.csv, main_effects.csv and study.json, written as one set.

Numbers are Python's shortest round-trip repr (the same digits as the C++ writers' to_chars);
a failed point's responses are empty cells. The set is written to temporary files in the
folder and renamed into place only when every file is complete, so an interrupted or failed
run leaves the folder as it was; no file the study reads is ever overwritten.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import tempfile
from typing import Any

from .pipeline import PointResult
from .spec import StudyInputError, StudySpec

FILES = ("results.csv", "pareto.csv", "main_effects.csv", "study.json")


def number(value: float) -> str:
    """The shortest text that reads back to `value`; empty for NaN (a failed point)."""
    return "" if math.isnan(value) else repr(float(value))


def results_table(spec: StudySpec, results: list[PointResult]) -> str:
    """One row per point: point, the parameters by key, the responses by name, status, error."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["point"] + [p.key for p in spec.parameters] + [r.name for r in spec.responses]
                    + ["status", "error"])
    for r in results:
        writer.writerow([str(r.index)] + [number(v) for v in r.values] + [number(v) for v in r.responses]
                        + [r.status, r.error])
    return out.getvalue()


def main_effects_table(spec: StudySpec, rows: list[dict[str, Any]]) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["parameter", "level", "value", "response", "mean", "count"])
    for row in rows:
        writer.writerow([spec.parameters[row["parameter"]].key, str(row["group"]), number(row["value"]),
                         spec.responses[row["response"]].name, number(row["mean"]), str(row["count"])])
    return out.getvalue()


def check_out_dir(spec: StudySpec, out_dir: str) -> None:
    """The folder may be created; it must not be a file, and no output may be an input."""
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise StudyInputError(f"--out: {out_dir}: exists and is not a folder")
    inputs = {os.path.realpath(p) for p in [spec.file, spec.design, *[v for s in spec.pipeline.values()
                                                                      for k, v in s.items()
                                                                      if k in ("target", "constraints")]]}
    for name in FILES:
        target = os.path.realpath(os.path.join(out_dir, name))
        if target in inputs:
            raise StudyInputError(f"--out: {out_dir}: {name} would overwrite an input of the study")


def write_outputs(out_dir: str, texts: dict[str, str]) -> None:
    """Write every file of `texts` into `out_dir` as one set (temporaries, then renames)."""
    os.makedirs(out_dir, exist_ok=True)
    temporaries: list[tuple[str, str]] = []
    try:
        for name, text in texts.items():
            fd, temp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=out_dir)
            temporaries.append((temp, os.path.join(out_dir, name)))
            with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
        for temp, final in temporaries:
            os.replace(temp, final)
        temporaries.clear()
    finally:
        for temp, _ in temporaries:
            if os.path.exists(temp):
                os.unlink(temp)


def study_json(document: dict[str, Any]) -> str:
    return json.dumps(document, indent=2, allow_nan=False, default=_json_default) + "\n"


def _json_default(value: Any) -> Any:
    raise TypeError(f"not JSON: {type(value).__name__}")


def finite_or_none(value: float) -> float | None:
    return value if math.isfinite(value) else None
