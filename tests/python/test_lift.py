"""camopt.lift equals `camopt lift` bit for bit (the table, the lines it prints), raises the
CLI's messages, and its summary and table agree with the 3-4-5 polynomial's closed form."""

import os

import numpy as np
import pytest

import camopt
from conftest import SOURCE_DIR, assert_same_columns, cli_error, read_csv, run_cli

CASES = [
    # asymmetric flanks, two laws, ramps of their own, a dwell, half-degree steps
    (["--law", "polynomial-345", "--close-law", "modified-sine", "--lift", "9.5", "--open", "72", "--close", "64",
      "--dwell", "6", "--ramp-height", "0.25", "--ramp-length", "22", "--close-ramp-height", "0.18",
      "--close-ramp-length", "18", "--peak-at", "110", "--step", "0.5"],
     dict(law="polynomial-345", close_law="modified-sine", lift_mm=9.5, open_deg=72, close_deg=64, dwell_deg=6,
          ramp_height_mm=0.25, ramp_length_deg=22, close_ramp_height_mm=0.18, close_ramp_length_deg=18, peak_deg=110,
          step_deg=0.5)),
    # an acceleration b-spline on the crank basis
    (["--law", "bspline", "--acc-bspline", "0,1,2,1,-0.5,-1,-1,-0.5,0", "--bspline-degree", "4", "--duration", "140",
      "--basis", "crank"],
     dict(law="bspline", acc_bspline=[0, 1, 2, 1, -0.5, -1, -1, -0.5, 0], bspline_degree=4, duration_deg=140,
          basis="crank")),
    # polydyne for a speed and a natural frequency, ramps, the default duration
    (["--law", "polydyne", "--polydyne-rpm", "6000", "--polydyne-fn", "800", "--ramp-height", "0.2", "--ramp-length",
      "20", "--ramp-blend", "0.4"],
     dict(law="polydyne", polydyne_rpm=6000, polydyne_fn_hz=800, ramp_height_mm=0.2, ramp_length_deg=20,
          ramp_blend=0.4)),
]


@pytest.mark.parametrize("cli_args, python_args", CASES)
def test_the_table_and_the_printed_lines_equal_the_cli(cli_args, python_args, tmp_path):
    out = tmp_path / "lift.csv"
    code, stderr = run_cli("lift", *cli_args, "--no-report", "--out", out)
    assert code == 0, stderr
    run = camopt.lift(**python_args)
    assert_same_columns(run.columns, read_csv(out))
    # run_cli's -q prints nothing: the lines come from a run without it
    os.chdir(SOURCE_DIR)
    import subprocess
    from conftest import CAMOPT
    p = subprocess.run([CAMOPT, "lift", *cli_args, "--no-report", "--out", str(out)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    lines = p.stderr.splitlines()
    assert lines[-1].startswith("lift: wrote ")
    assert run.notes == lines[:-1]


def test_the_summary_and_table_follow_the_345_polynomial():
    # no ramp, no dwell: the rise over 65 cam deg to 8 mm at 180 is h (10 u^3 - 15 u^4 + 6 u^5),
    # u = (theta - 115) / 65, its peak acceleration 10 sqrt(3) / 3 h / beta^2 at u = (3 - sqrt 3) / 6
    run = camopt.lift("polynomial-345", lift_mm=8.0, duration_deg=130.0, step_deg=0.25)
    cam, lift = run.columns["cam_deg"], run.columns["lift_mm"]
    assert cam.size == 1440 and cam[-1] == 359.75
    rise = (cam >= 115.0) & (cam <= 180.0)
    u = (cam[rise] - 115.0) / 65.0
    np.testing.assert_allclose(lift[rise], 8.0 * (10 * u**3 - 15 * u**4 + 6 * u**5), rtol=0, atol=1e-12)
    assert np.all(lift[(cam < 115.0) | (cam > 245.0)] == 0.0)
    s = run.summary
    assert s["max_lift_mm"] == pytest.approx(8.0, abs=1e-12)
    assert s["max_lift_at_cam_deg"] == pytest.approx(180.0, abs=0.01)
    assert s["duration_0mm_cam_deg"] == pytest.approx(130.0, abs=0.02)
    assert s["max_acc_mm_per_deg2"] == pytest.approx(10 * np.sqrt(3) / 3 * 8.0 / 65.0**2, rel=1e-6)
    assert s["max_acc_at_cam_deg"] == pytest.approx(115.0 + 65.0 * (3 - np.sqrt(3)) / 6, abs=0.01)


@pytest.mark.parametrize("cli_args, python_args", [
    (["--law", "cycloidal", "--duration", "120", "--open", "60", "--close", "60"],
     dict(law="cycloidal", duration_deg=120, open_deg=60, close_deg=60)),
    (["--law", "cycloidal", "--open", "60"], dict(law="cycloidal", open_deg=60)),
    (["--law", "cycloidal", "--step", "0.7"], dict(law="cycloidal", step_deg=0.7)),
    (["--law", "cycloid"], dict(law="cycloid")),
    (["--law", "cycloidal", "--bspline-degree", "4"], dict(law="cycloidal", bspline_degree=4)),
    (["--law", "cycloidal", "--ramp-height", "0.3", "--ramp-length", "40", "--duration", "60"],
     dict(law="cycloidal", ramp_height_mm=0.3, ramp_length_deg=40, duration_deg=60)),
    (["--law", "cycloidal", "--basis", "valve"], dict(law="cycloidal", basis="valve")),
])
def test_a_bad_option_raises_the_cli_message(cli_args, python_args, tmp_path):
    expected = cli_error("lift", *cli_args, "--out", tmp_path / "lift.csv", kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.lift(**python_args)
    assert str(e.value) == expected
