"""What a study's table says: responses read from summaries, the Pareto set, main effects."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


class ResponseMissing(LookupError):
    """A response path that names nothing in a summary."""


def _walk(node: Any, parts: list[str], where: str, out: list[float]) -> None:
    if not parts:
        if isinstance(node, bool) or not isinstance(node, (int, float)):
            raise ResponseMissing(f"{where}: is {type(node).__name__}, not a number")
        out.append(float(node))
        return
    head, rest = parts[0], parts[1:]
    key, star, index = head, False, None
    if head.endswith("[*]"):
        key, star = head[:-3], True
    elif head.endswith("]") and "[" in head:
        key, index_text = head[:-1].split("[", 1)
        if not index_text.isdigit():
            raise ResponseMissing(f"{where}.{head}: an index is a number or *")
        index = int(index_text)
    if key == "*":
        if not isinstance(node, dict):
            raise ResponseMissing(f"{where}: * needs a table of values")
        for name, value in node.items():
            _walk(value, rest, f"{where}.{name}", out)
        return
    if key:
        if not isinstance(node, dict) or key not in node:
            known = ", ".join(node) if isinstance(node, dict) else type(node).__name__
            raise ResponseMissing(f"{where}.{key}: not in the summary (there: {known})")
        node, where = node[key], f"{where}.{key}" if where else key
    if star or index is not None:
        if not isinstance(node, list):
            raise ResponseMissing(f"{where}: not a list")
        if index is not None:
            if index >= len(node):
                raise ResponseMissing(f"{where}[{index}]: the list has {len(node)} items")
            _walk(node[index], rest, f"{where}[{index}]", out)
        else:
            for i, item in enumerate(node):
                _walk(item, rest, f"{where}[{i}]", out)
        return
    _walk(node, rest, where, out)


def response_value(summary: dict, path: str, reduce: str) -> float:
    """The scalar `reduce` (max, min, mean, first, sum) of every value `path` reaches in a summary.

    The path is dotted keys; `list[*]` takes every item, `list[2]` one, and `*` every value of a
    table (contacts.*.separation_rpm: every contact's). NaN and infinity are kept as they are.
    """
    values: list[float] = []
    _walk(summary, path.split("."), "", values)
    if not values:
        raise ResponseMissing(f"{path}: reaches no value")
    if reduce == "max":
        return max(values)
    if reduce == "min":
        return min(values)
    if reduce == "mean":
        return math.fsum(values) / len(values)
    if reduce == "sum":
        return math.fsum(values)
    return values[0]


def pareto_mask(values: np.ndarray, maximize: list[bool]) -> np.ndarray:
    """The non-dominated rows of `values` (n points x k responses; NaN rows are never in it).

    A point is dominated when another is at least as good in every response and better in one.
    """
    n = values.shape[0]
    signed = np.where(np.array(maximize, dtype=bool), -values, values)  # every column minimised
    finite = np.all(np.isfinite(signed), axis=1)
    mask = finite.copy()
    for i in np.flatnonzero(finite):
        others = signed[finite]
        no_worse = np.all(others <= signed[i], axis=1)
        better = np.any(others < signed[i], axis=1)
        mask[i] = not np.any(no_worse & better)
    return mask if n else np.zeros(0, dtype=bool)


def main_effects(points: np.ndarray, responses: np.ndarray, levels: list[tuple[float, ...]], bins: int,
                 ranges: list[tuple[float, float]] | None = None) -> list[dict[str, Any]]:
    """Per parameter and response, the mean response at each level of the parameter.

    A parameter with levels (full factorial) groups the points by level; a sampled one groups
    them into `bins` equal-width intervals of its range (`ranges[j]`, default the points' own
    extent; labelled by their centres). Failed
    points (NaN response) are left out of that response's means. Returns rows with the
    parameter's column, the group, its value, the response's column, the mean and the count.
    """
    rows: list[dict[str, Any]] = []
    for j in range(points.shape[1]):
        x = points[:, j]
        if levels[j]:
            groups = [(v, x == v) for v in levels[j]]
        else:
            low, high = ranges[j] if ranges else (float(np.min(x)), float(np.max(x)))
            edges = np.linspace(low, high, bins + 1)
            which = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, bins - 1)
            groups = [(0.5 * (edges[b] + edges[b + 1]), which == b) for b in range(bins)]
        for k in range(responses.shape[1]):
            y = responses[:, k]
            for g, (value, member) in enumerate(groups):
                ok = member & np.isfinite(y)
                count = int(np.count_nonzero(ok))
                mean = math.fsum(y[ok]) / count if count else math.nan
                rows.append({"parameter": j, "group": g, "value": float(value), "response": k, "mean": mean,
                             "count": count})
    return rows
