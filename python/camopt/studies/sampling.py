"""The study's points: full factorial, Latin hypercube or scrambled Sobol (scipy.stats.qmc)."""

from __future__ import annotations

import itertools

import numpy as np
from scipy.stats import qmc

from .spec import Parameter, StudySpec


def _round(parameters: tuple[Parameter, ...], points: np.ndarray) -> np.ndarray:
    for j, p in enumerate(parameters):
        if p.integer:
            points[:, j] = np.round(points[:, j])
    return points


def sample(spec: StudySpec) -> np.ndarray:
    """The points as an (n, d) array, one column per parameter in the study's order.

    Full factorial: every combination of the levels, the last parameter varying fastest.
    Latin hypercube and Sobol: `points` points from scipy's generators seeded with `seed`, scaled
    from the unit cube to [min, max] (the same seed gives the same points on every machine).
    """
    parameters = spec.parameters
    if spec.method == "full_factorial":
        return np.array(list(itertools.product(*(p.levels for p in parameters))), dtype=float)
    d = len(parameters)
    if spec.method == "latin_hypercube":
        unit = qmc.LatinHypercube(d=d, seed=spec.seed).random(spec.points)
    else:
        unit = qmc.Sobol(d=d, scramble=True, seed=spec.seed).random(spec.points)
    low = np.array([p.low for p in parameters])
    high = np.array([p.high for p in parameters])
    return _round(parameters, qmc.scale(unit, low, high))
