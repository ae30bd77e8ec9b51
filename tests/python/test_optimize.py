"""camopt.optimize equals `camopt optimize` bit for bit (lift.csv, profile.csv, grinding.csv,
report.json but its times), its design runs as the CLI's written design.toml, bad options raise
the CLI's messages, and Ctrl-C stops a solve between iterations."""

import _thread
import json
import os
import threading
import time

import pytest

import camopt
from conftest import SOURCE_DIR, assert_same_columns, assert_same_run_of_written_design, cli_error, read_csv, run_cli

DESIGN = "designs/bucket_tappet.toml"
CONSTRAINTS = "constraints/high_speed_bucket.toml"


@pytest.fixture(autouse=True)
def in_source_dir():
    os.chdir(SOURCE_DIR)


def without_solver_times(report):
    """report.json without its wall times (the solve's and every convergence report's)."""
    report = {k: v for k, v in report.items() if k != "time_s"}
    if "convergence" in report:
        report["convergence"] = [{k: v for k, v in c.items() if k != "elapsed_s"} for c in report["convergence"]]
    return report


@pytest.fixture(scope="module")
def cli_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("optimize")
    code, stderr = run_cli("optimize", DESIGN, "--constraints", CONSTRAINTS, "--points", "720", "--no-report", "--out",
                           out, cwd=SOURCE_DIR)
    assert code == 0, stderr
    return out


@pytest.fixture(scope="module")
def run():
    os.chdir(SOURCE_DIR)
    return camopt.optimize(DESIGN, CONSTRAINTS, points=720)


def test_the_lift_profile_and_report_equal_the_cli(run, cli_folder):
    assert sorted(run.tables) == ["grinding.csv", "lift.csv", "profile.csv"]
    for name, table in run.tables.items():
        assert_same_columns(table, read_csv(cli_folder / name))
    assert run.columns is run.tables["lift.csv"]
    with open(cli_folder / "report.json") as f:
        assert without_solver_times(run.summary) == without_solver_times(json.load(f))
    assert run.summary["status"] == "converged"
    assert run.files["profile.dxf"] == (cli_folder / "profile.dxf").read_bytes()


def test_the_returned_design_runs_as_the_cli_written_design(run, cli_folder, tmp_path):
    code, stderr = run_cli("dynamics", cli_folder / "design.toml", "--rpm", "6000", "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    again = camopt.dynamics(run.design, rpm=6000)
    assert_same_run_of_written_design(again, run.design, cli_folder, tmp_path, "dynamics.csv")


@pytest.mark.parametrize("cli_args, python_args", [
    (["--solver", "newton"], {"solver": "newton"}),
    (["--starts", "3"], {"starts": 3}),
    (["--cam", "swing"], {"cam": "swing"}),
])
def test_a_bad_option_of_optimize(cli_args, python_args, tmp_path):
    expected = cli_error("optimize", DESIGN, "--constraints", CONSTRAINTS, *cli_args, "--out", tmp_path,
                         kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.optimize(DESIGN, CONSTRAINTS, **python_args)
    assert str(e.value) == expected


def test_a_constraint_override_of_no_key_names_it_as_the_cli(tmp_path):
    expected = cli_error("optimize", DESIGN, "--constraints", CONSTRAINTS, "--set-constraint", "limits.no_such_key=1",
                         "--out", tmp_path, kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.optimize(DESIGN, CONSTRAINTS, constraint_overrides={"limits.no_such_key": 1})
    assert str(e.value) == expected


def test_a_missing_constraint_set(tmp_path):
    expected = cli_error("optimize", DESIGN, "--constraints", "constraints/none.toml", "--out", tmp_path,
                         kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.optimize(DESIGN, "constraints/none.toml")
    assert str(e.value) == expected


# the swing cam of the CVVL over its control family: seconds of solving, ~80 ipopt iterations
LONG = dict(design="designs/cvvl_swing_cam.toml", constraints="constraints/cvvl_swing_cam.toml", cam="swing",
            points=720)


def test_ctrl_c_stops_an_optimisation_between_iterations():
    t0 = time.monotonic()
    full = camopt.optimize(**LONG)
    full_s = time.monotonic() - t0
    assert full.summary["iterations"] > 20 and full_s > 2.0
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        camopt.optimize(**LONG)
    stopped = time.monotonic() - t0
    timer.join()
    assert stopped < 0.5 + full_s / 4, (stopped, full_s)
    # the module is usable after the interrupt
    assert camopt.optimize(DESIGN, CONSTRAINTS, points=720).summary["status"] == "converged"


def test_an_infeasible_set_raises_the_cli_failure_with_its_report(tmp_path):
    # an acceleration limit far below what 7 mm of lift needs over the event (--set-constraint)
    out = tmp_path / "out"
    expected = cli_error("optimize", DESIGN, "--constraints", CONSTRAINTS, "--set-constraint",
                         "limits.acc_max_mm_per_deg2=0.002", "--points", "720", "--no-report", "--out", out,
                         kind="numerical failure")
    with pytest.raises(camopt.NumericalError) as e:
        camopt.optimize(DESIGN, CONSTRAINTS, points=720, constraint_overrides={"limits.acc_max_mm_per_deg2": 0.002})
    assert str(e.value) == expected
    assert e.value.code == "infeasible"
    with open(out / "report.json") as f:
        cli_report = json.load(f)
    # the feasibility phase's nlopt reports come at most every 0.05 s of wall time: its
    # convergence list and time differ from run to run, every other key is the CLI's
    for report in (e.value.report, cli_report):
        del report["convergence"], report["feasibility_phase"]["time_s"]
    assert without_solver_times(e.value.report) == without_solver_times(cli_report)
    assert "limits.acc_max_mm_per_deg2" in [c["key"] for c in e.value.report["conflicting_constraints"]]
