"""The study's sampling, Pareto set, main effects and response paths, each against an
independent formulation written here."""

import itertools
import math

import numpy as np
import pytest

from camopt.studies import analysis, sampling
from camopt.studies.spec import StudyInputError, parse_study

BASE = {
    "study": {"design": "design.toml"},
    "parameter": [{"key": "node.finger.mass_kg", "min": 0.03, "max": 0.05, "levels": 3},
                  {"key": "connection.cam_roller.b.radius_mm", "min": 7.0, "max": 10.0, "levels": 4}],
    "pipeline": {"kinematics": {"step_deg": 1.0}},
    "response": [{"name": "pa_deg", "stage": "kinematics", "path": "positions[*].max_pressure_angle_deg"}],
}


def spec_of(**changes):
    data = {k: (v.copy() if isinstance(v, dict) else list(v)) for k, v in BASE.items()}
    data.update(changes)
    return parse_study(data, "/tmp/s/study.toml")


def test_full_factorial_is_every_combination_last_fastest():
    points = sampling.sample(spec_of())
    expected = [(m, r) for m in (0.03, 0.04, 0.05) for r in (7.0, 8.0, 9.0, 10.0)]
    assert points.shape == (12, 2)
    for got, want in zip(points, expected):
        assert abs(got[0] - want[0]) <= 1e-15 and got[1] == want[1]


def test_latin_hypercube_has_one_point_in_every_stratum_and_repeats_with_its_seed():
    params = [{"key": "a.b", "min": -2.0, "max": 6.0}, {"key": "c.d", "min": 1.0, "max": 2.0},
              {"key": "e.f", "min": 0.0, "max": 10.0}]
    spec = spec_of(parameter=params, sampling={"method": "latin_hypercube", "points": 16, "seed": 7})
    points = sampling.sample(spec)
    assert points.shape == (16, 3)
    for j, p in enumerate(params):
        strata = np.floor((points[:, j] - p["min"]) / (p["max"] - p["min"]) * 16).astype(int)
        assert sorted(strata) == list(range(16))  # one point per 1/16 of every range
    assert np.array_equal(points, sampling.sample(spec))
    other = spec_of(parameter=params, sampling={"method": "latin_hypercube", "points": 16, "seed": 8})
    assert not np.array_equal(points, sampling.sample(other))


def test_sobol_points_are_balanced_in_every_dyadic_interval():
    params = [{"key": "a.b", "min": 0.0, "max": 1.0}, {"key": "c.d", "min": 0.0, "max": 1.0}]
    points = sampling.sample(spec_of(parameter=params, sampling={"method": "sobol", "points": 32, "seed": 3}))
    # a (0, m, 2) net in base 2: every elementary box of area 1/32 holds one point
    for k in range(6):
        cells = {(int(x * 2 ** k), int(y * 2 ** (5 - k))) for x, y in points}
        assert len(cells) == 32


def test_sobol_refuses_a_count_that_breaks_its_balance():
    with pytest.raises(StudyInputError, match=r"sampling.points: 20: must be a power of 2"):
        spec_of(parameter=[{"key": "a.b", "min": 0.0, "max": 1.0}], sampling={"method": "sobol", "points": 20})


def brute_force_pareto(values, maximize):
    keep = []
    for i, a in enumerate(values):
        if not all(math.isfinite(v) for v in a):
            keep.append(False)
            continue
        dominated = False
        for j, b in enumerate(values):
            if i == j or not all(math.isfinite(v) for v in b):
                continue
            at_least = all((bv >= av) if m else (bv <= av) for av, bv, m in zip(a, b, maximize))
            strictly = any((bv > av) if m else (bv < av) for av, bv, m in zip(a, b, maximize))
            dominated = dominated or (at_least and strictly)
        keep.append(not dominated)
    return keep


def test_pareto_set_equals_the_pairwise_definition():
    rng = np.random.default_rng(11)
    values = np.round(rng.uniform(0, 5, size=(60, 3)), 0)  # ties on purpose
    values[[4, 9], 1] = np.nan  # failed points
    for maximize in ([False, False, False], [True, False, True]):
        mask = analysis.pareto_mask(values, maximize)
        assert list(mask) == brute_force_pareto(values.tolist(), maximize)
        assert not mask[4] and not mask[9]


def test_pareto_of_a_circle_front_keeps_exactly_the_front():
    # points on the quarter circle x^2 + y^2 = 1 (both minimised) plus points strictly behind it
    t = np.linspace(0, np.pi / 2, 9)
    front = np.column_stack([np.cos(t), np.sin(t)])
    behind = front * 1.5 + 0.1
    mask = analysis.pareto_mask(np.vstack([front, behind]), [False, False])
    assert list(mask) == [True] * 9 + [False] * 9


def test_main_effects_of_an_additive_response_are_its_parts_plus_the_other_mean():
    a_levels, b_levels = (1.0, 2.0, 4.0), (0.0, 0.5, 1.0, 1.5)
    points = np.array(list(itertools.product(a_levels, b_levels)))
    y = np.sin(points[:, 0]) + points[:, 1] ** 2  # y = f(a) + g(b)
    rows = analysis.main_effects(points, y[:, None], [a_levels, b_levels], 4)
    mean_g = sum(b * b for b in b_levels) / 4
    mean_f = sum(math.sin(a) for a in a_levels) / 3
    got = {(r["parameter"], r["value"]): (r["mean"], r["count"]) for r in rows}
    for a in a_levels:
        mean, count = got[(0, a)]
        assert count == 4 and abs(mean - (math.sin(a) + mean_g)) < 1e-15
    for b in b_levels:
        mean, count = got[(1, b)]
        assert count == 3 and abs(mean - (b * b + mean_f)) < 1e-15


def test_main_effects_of_sampled_points_use_equal_bins_and_skip_failures():
    # bins are [low, edge) ... [edge, high]: 0.5 falls in the upper one
    x = np.array([[0.0], [0.1], [0.3], [0.5], [0.55], [0.6], [0.99], [1.0]])
    y = np.array([1.0, 3.0, 5.0, 6.0, 7.0, np.nan, 11.0, 13.0])
    rows = analysis.main_effects(x, y[:, None], [()], 2)
    assert [(r["value"], r["mean"], r["count"]) for r in rows] == [(0.25, 3.0, 3), (0.75, 9.25, 4)]
    # bins over the parameter's range, not the points' extent: [-1, 0), [0, 1), [1, 2]
    rows = analysis.main_effects(x, y[:, None], [()], 3, [(-1.0, 2.0)])
    assert [(r["value"], r["count"]) for r in rows] == [(-0.5, 0), (0.5, 6), (1.5, 1)]
    assert math.isnan(rows[0]["mean"]) and rows[1]["mean"] == 33.0 / 6 and rows[2]["mean"] == 13.0


SUMMARY = {
    "positions": [{"max_pressure_angle_deg": 17.5, "status": "ok"}, {"max_pressure_angle_deg": 21.25}],
    "separation": [{"contacts": {"cam_roller": {"separation_rpm": 9961.0}, "pad_valve": {"separation_rpm": 10975.0}}},
                   {"contacts": {"cam_roller": {"separation_rpm": 8800.5}}}],
    "run_time_s": 0.001,
}


def test_response_paths_reach_lists_tables_and_reduce():
    value = analysis.response_value
    assert value(SUMMARY, "positions[*].max_pressure_angle_deg", "max") == 21.25
    assert value(SUMMARY, "positions[*].max_pressure_angle_deg", "mean") == (17.5 + 21.25) / 2
    assert value(SUMMARY, "positions[1].max_pressure_angle_deg", "max") == 21.25
    assert value(SUMMARY, "separation[*].contacts.*.separation_rpm", "min") == 8800.5
    assert value(SUMMARY, "separation[*].contacts.*.separation_rpm", "sum") == 9961.0 + 10975.0 + 8800.5
    assert value(SUMMARY, "separation[0].contacts.pad_valve.separation_rpm", "first") == 10975.0


@pytest.mark.parametrize("path, message", [
    ("positions[*].max_lift_mm", r"positions\[0\].max_lift_mm: not in the summary \(there: max_pressure_angle_deg, status\)"),
    ("positions[*].status", r"positions\[0\].status: is str, not a number"),
    ("positions[5].max_pressure_angle_deg", r"positions\[5\]: the list has 2 items"),
    ("run_time_s[*]", r"run_time_s: not a list"),
])
def test_response_paths_that_reach_nothing_say_where(path, message):
    with pytest.raises(analysis.ResponseMissing, match=message):
        analysis.response_value(SUMMARY, path, "max")


@pytest.mark.parametrize("change, message", [
    ({"sampling": {"method": "grid"}}, r"sampling.method: 'grid': must be one of full_factorial"),
    ({"parameter": [{"key": "a.b", "min": 2.0, "max": 1.0, "levels": 3}]}, r"parameter\[0\].max: 1.0: must be greater than min \(2.0\)"),
    ({"parameter": [{"key": "a.b", "min": 0.0, "max": 1.0}]}, r"parameter\[0\].levels: missing \(required\)"),
    ({"parameter": [{"key": "a.b", "min": 0.0, "max": 1.0, "levels": 2, "step": 1}]}, r"parameter\[0\].step: unknown key"),
    ({"response": [{"name": "x", "stage": "rigid", "path": "a"}]}, r"response\[0\].stage: 'rigid': the pipeline has no such stage"),
    ({"response": [{"name": "x", "stage": "kinematics", "path": "a", "reduce": "median"}]}, r"response\[0\].reduce: 'median'"),
    ({"pareto": {"minimize": ["hertz"]}}, r"pareto.minimize\[0\]: 'hertz': must name a \[\[response\]\]"),
    ({"pipeline": {"synthesize": {"target": "t.csv"}, "optimize": {"constraints": "c.toml"}}}, r"pipeline.optimize: a pipeline synthesizes or optimises the cam, not both"),
    ({"parameter": [{"key": "constraints.max_hertz_MPa", "min": 1.0, "max": 2.0, "levels": 2}]}, r"parameter\[0\].key: 'constraints.max_hertz_MPa': a constraint-set key needs a \[pipeline.optimize\] stage"),
    ({"schema": 2}, r"schema: 2: must be 1"),
])
def test_study_file_errors_name_the_key_the_value_and_the_rule(change, message):
    with pytest.raises(StudyInputError, match=r"^/tmp/s/study.toml: " + message):
        spec_of(**change)


def test_relative_paths_are_from_the_study_file():
    spec = spec_of(pipeline={"synthesize": {"target": "../t/lift.csv"}, "kinematics": {}})
    assert spec.design == "/tmp/s/design.toml"
    assert spec.pipeline["synthesize"]["target"] == "/tmp/t/lift.csv"
