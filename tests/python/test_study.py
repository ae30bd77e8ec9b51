"""Studies through the Python API: the same table serially, on local processes and on a local
Dask cluster; a failing point kept as a row; a geometry optimisation with a closed-form optimum;
the CLI's `camopt study`."""

import csv
import math
import os
import subprocess

import numpy as np
import pytest

import camopt
from camopt.studies import parse_study

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DESIGNS = os.path.join(SOURCE_DIR, "designs")
CONSTRAINTS = os.path.join(SOURCE_DIR, "constraints")


def rff_study(tmp_path, **changes):
    data = {
        "study": {"name": "rff mass x roller", "design": os.path.join(DESIGNS, "roller_finger_follower.toml")},
        "parameter": [
            # -0.01 kg breaks the design's rule (mass > 0): those points fail, the study goes on
            {"key": "node.finger.mass_kg", "values": [0.03, 0.05, -0.01]},
            {"key": "connection.cam_roller.b.radius_mm", "values": [8.0, 9.0]},
        ],
        "pipeline": {"kinematics": {"step_deg": 2.0, "outputs": "contacts"}, "rigid": {"rpm": [3000, 6000], "step_deg": 2.0}},
        "response": [
            {"name": "max_pressure_angle_deg", "stage": "kinematics", "path": "positions[*].max_pressure_angle_deg"},
            {"name": "max_hertz_MPa", "stage": "rigid", "path": "results[*].connections.*.max_hertz_MPa"},
            {"name": "separation_rpm", "stage": "rigid", "path": "separation[*].contacts.*.separation_rpm",
             "reduce": "min"},
        ],
        "pareto": {"minimize": ["max_hertz_MPa"], "maximize": ["separation_rpm"]},
    }
    data.update(changes)
    return parse_study(data, str(tmp_path / "study.toml"))


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def test_a_point_equals_the_api_run_of_its_design(tmp_path):
    spec = rff_study(tmp_path)
    result = camopt.study(spec, workers=1)
    assert [r.index for r in result.points] == list(range(6))
    ok = [r for r in result.points if r.status == "ok"]
    assert len(ok) == 4
    # point 1: mass 0.03, roller 9 mm, run by hand through the API
    design = camopt.Design.load(os.path.join(DESIGNS, "roller_finger_follower.toml"))
    design.set("node.finger.mass_kg", 0.03).set("connection.cam_roller.b.radius_mm", 9.0)
    kin = camopt.kinematics(design, step_deg=2.0, outputs="contacts").summary
    rigid = camopt.dynamics(design, rpm=[3000, 6000], step_deg=2.0).summary
    point = result.points[1]
    assert point.values == (0.03, 9.0)
    assert point.responses[0] == max(p["max_pressure_angle_deg"] for p in kin["positions"])
    assert point.responses[1] == max(c["max_hertz_MPa"] for r in rigid["results"] for c in r["connections"].values())
    assert point.responses[2] == min(c["separation_rpm"] for s in rigid["separation"] for c in s["contacts"].values())
    # a bigger roller on the same cam: the roller centre moved out, the lift and its stress changed
    assert result.points[0].responses[1] != point.responses[1]


def test_failed_points_are_rows_with_the_design_s_message(tmp_path):
    result = camopt.study(rff_study(tmp_path), workers=1, out=str(tmp_path / "out"))
    rows = read_rows(tmp_path / "out" / "results.csv")
    assert rows[0] == ["point", "node.finger.mass_kg", "connection.cam_roller.b.radius_mm", "max_pressure_angle_deg",
                       "max_hertz_MPa", "separation_rpm", "status", "error"]
    failed = [r for r in rows[1:] if r[-2] != "ok"]
    assert [r[0] for r in failed] == ["4", "5"]
    for r in failed:
        assert r[-2] == "input error"
        assert r[3:6] == ["", "", ""]
        assert "set node.finger.mass_kg=-0.01" in r[-1] and "mass_kg" in r[-1]
    assert result.column("max_hertz_MPa")[4] != result.column("max_hertz_MPa")[4]  # NaN
    pareto = read_rows(tmp_path / "out" / "pareto.csv")
    assert {r[0] for r in pareto[1:]} == {str(i) for i in result.pareto}
    assert 4 not in result.pareto and 5 not in result.pareto


def test_a_study_over_constraint_set_keys_optimises_each_point_as_the_api(tmp_path):
    # the bucket's high-speed set with its acceleration limit at two values and its minimum
    # radius of curvature raised to 3.5 mm at both: an optimize stage (SLSQP) per point
    design, constraints = os.path.join(DESIGNS, "bucket_tappet.toml"), os.path.join(CONSTRAINTS, "high_speed_bucket.toml")
    spec = parse_study({
        "study": {"design": design},
        "parameter": [{"key": "constraints.limits.acc_max_mm_per_deg2", "values": [0.016, 0.02]},
                      {"key": "constraints.limits.min_radius_of_curvature_mm", "values": [3.5]}],
        "pipeline": {"optimize": {"constraints": constraints, "solver": "slsqp", "points": 720}},
        "response": [
            {"name": "acc_max_mm_per_deg2", "stage": "optimize", "path": "constraints.acc_max.worst"},
            {"name": "acc_limit_mm_per_deg2", "stage": "optimize", "path": "constraints.acc_max.limit"},
            {"name": "min_radius_mm", "stage": "optimize", "path": "constraints.radius_of_curvature_min.worst"},
            {"name": "objective", "stage": "optimize", "path": "objective.value"},
        ],
    }, str(tmp_path / "limits.toml"))
    result = camopt.study(spec, workers=1)
    assert [(r.status, r.error) for r in result.points] == [("ok", "")] * 2
    for point in result.points:
        acc_limit, radius_limit = point.values
        # the same solve through the API, bit for bit
        direct = camopt.optimize(design, constraints, solver="slsqp", points=720, constraint_overrides={
            "limits.acc_max_mm_per_deg2": acc_limit, "limits.min_radius_of_curvature_mm": radius_limit})
        c = direct.summary["constraints"]
        assert point.responses == (c["acc_max"]["worst"], c["acc_max"]["limit"], c["radius_of_curvature_min"]["worst"],
                                   direct.summary["objective"]["value"])
        # each limit is the point's and is active: the worst value sits on it (SLSQP's
        # feasibility, 1e-9 relative)
        assert point.responses[1] == acc_limit
        assert abs(point.responses[0] - acc_limit) <= 1e-9 * acc_limit
        assert abs(point.responses[2] - radius_limit) <= 1e-9 * radius_limit
        # and the optimised lift itself: its largest acceleration on the set's 0.5 deg grid
        lift = direct.tables["lift.csv"]
        on_grid = np.abs(lift["cam_deg"] * 2.0 - np.round(lift["cam_deg"] * 2.0)) < 1e-9
        assert abs(lift["acc_mm_per_deg2"][on_grid].max() - acc_limit) <= 1e-9 * acc_limit
    # a looser acceleration limit lets the lift take more area (the objective is its negative)
    assert result.points[1].responses[3] < result.points[0].responses[3]


def test_local_processes_and_a_dask_cluster_give_the_serial_table(tmp_path):
    distributed = pytest.importorskip("distributed")
    spec = rff_study(tmp_path)
    camopt.study(spec, workers=1, out=str(tmp_path / "serial"))
    camopt.study(spec, workers=2, out=str(tmp_path / "local"))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        camopt.study(spec, client=client, out=str(tmp_path / "dask"))
        camopt.study(spec, scheduler=cluster.scheduler_address, out=str(tmp_path / "dask-address"))
    serial = (tmp_path / "serial" / "results.csv").read_text()
    assert len(read_rows(tmp_path / "serial" / "results.csv")) == 7
    for other in ("local", "dask", "dask-address"):
        for name in ("results.csv", "pareto.csv", "main_effects.csv"):
            assert (tmp_path / other / name).read_text() == (tmp_path / "serial" / name).read_text(), (other, name)
    assert serial.count(",ok,") == 4


def test_geometry_optimisation_finds_the_offset_of_least_pressure_angle(tmp_path):
    # eccentric disc (R 20, e 4) and a translating roller follower (r 8) whose line of travel is
    # x = d: the contact normal runs from the disc centre (e cos t, e sin t) to the roller centre
    # (d, y), |normal| = R + r, so sin(pressure angle) = (d - e cos t) / (R + r) and its largest
    # value over a turn is (|d| + e) / (R + r): least at d = 0, asin(4 / 28)
    spec = parse_study({
        "study": {"design": os.path.join(DESIGNS, "eccentric_offset_roller.toml")},
        "parameter": [{"key": "connection.disc_roller.b.center_mm[0]", "min": -5.0, "max": 8.0}],
        "pipeline": {"kinematics": {"step_deg": 0.5, "outputs": "contacts"}},
        "response": [{"name": "max_pressure_angle_deg", "stage": "kinematics",
                      "path": "positions[*].max_pressure_angle_deg"}],
        "optimize": {"objective": "max_pressure_angle_deg", "sense": "minimize", "algorithm": "LN_COBYLA",
                     "max_evaluations": 60, "relative_tolerance": 1e-6},
    }, str(tmp_path / "offset.toml"))
    result = camopt.study(spec, out=str(tmp_path / "out"))
    best = result.best
    assert best is not None and best.status == "ok"
    assert abs(best.values[0]) < 1e-4
    exact = math.degrees(math.asin(4.0 / 28.0))
    assert abs(best.responses[0] - exact) < 1e-5
    # away from the optimum the response follows the closed form too (every evaluation)
    for r in result.points:
        d = r.values[0]
        assert abs(r.responses[0] - math.degrees(math.asin((abs(d) + 4.0) / 28.0))) < 1e-9, d
    assert 10 <= len(result.points) <= 60


def test_camopt_study_runs_a_study_file_and_names_a_bad_key(tmp_path):
    binary = os.environ["CAMOPT_BINARY"]
    study = tmp_path / "s.toml"
    study.write_text(f'''
[study]
design = "{os.path.join(DESIGNS, "eccentric_offset_roller.toml")}"
[[parameter]]
key = "connection.disc_roller.b.radius_mm"
min = 7.0
max = 9.0
levels = 3
[pipeline]
kinematics = {{ step_deg = 1.0 }}
[[response]]
name = "max_lift_mm"
stage = "kinematics"
path = "positions[*].max_lift_mm"
''')
    run = subprocess.run([binary, "study", str(study), "--out", str(tmp_path / "out"), "--workers", "1"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    rows = read_rows(tmp_path / "out" / "results.csv")
    assert [r[1] for r in rows[1:]] == ["7.0", "8.0", "9.0"] and all(r[-2] == "ok" for r in rows[1:])
    study.write_text(study.read_text().replace("levels = 3", "levels = 1"))
    bad = subprocess.run([binary, "study", str(study), "--out", str(tmp_path / "out2")], capture_output=True, text=True)
    assert bad.returncode == 3
    assert bad.stderr == f"camopt: input error: {study}: parameter[0].levels: 1: must be >= 2\n"
    assert not (tmp_path / "out2").exists()


def test_the_bundled_study_runs_every_point_and_trades_stress_against_separation(tmp_path):
    result = camopt.study(os.path.join(DESIGNS, "studies", "rff_roller_pivot.toml"), workers=1)
    assert len(result.points) == 16 and all(r.status == "ok" for r in result.points)
    # a bigger roller lowers the Hertz stress (the main effect falls bin by bin)
    means = [row["mean"] for row in result.main_effects if row["parameter"] == 0 and row["response"] == 2]
    assert len(means) == 4 and all(a > b for a, b in zip(means, means[1:]))
    # the Pareto set: no other point has both less stress and a higher separation speed
    hertz, separation = result.column("max_hertz_MPa"), result.column("separation_rpm")
    for i in result.pareto:
        assert not any(hertz[j] <= hertz[i] and separation[j] >= separation[i]
                       and (hertz[j] < hertz[i] or separation[j] > separation[i]) for j in range(16))
    assert 1 <= len(result.pareto) < 16


def test_a_synthesis_stage_makes_each_point_s_cam_for_its_follower(tmp_path):
    target = os.path.join(DESIGNS, "targets", "rff_intake_lift.csv")
    spec = parse_study({
        "study": {"design": os.path.join(DESIGNS, "roller_finger_follower.toml")},
        "parameter": [{"key": "connection.cam_roller.b.radius_mm", "values": [8.0, 9.5]}],
        "pipeline": {"synthesize": {"target": target}, "kinematics": {"step_deg": 1.0}},
        "response": [{"name": "round_trip_mm", "stage": "synthesize", "path": "checks.round_trip_max_error_mm"},
                     {"name": "max_lift_mm", "stage": "kinematics", "path": "positions[*].max_lift_mm"}],
    }, str(tmp_path / "synth.toml"))
    result = camopt.study(spec, workers=1)
    assert [r.status for r in result.points] == ["ok", "ok"], [r.error for r in result.points]
    for point in result.points:
        design = camopt.Design.load(os.path.join(DESIGNS, "roller_finger_follower.toml"))
        made = camopt.synthesize(target, design.set("connection.cam_roller.b.radius_mm", point.values[0]))
        assert point.responses[0] == made.summary["checks"]["round_trip_max_error_mm"]
        assert point.responses[1] == camopt.kinematics(made.design, step_deg=1.0).summary["positions"][0]["max_lift_mm"]
    # each roller gets its own cam, and both reproduce the same target lift
    assert result.points[0].responses[0] < 1e-6 and result.points[1].responses[0] < 1e-6
    assert abs(result.points[0].responses[1] - result.points[1].responses[1]) < 1e-5
