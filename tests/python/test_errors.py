"""Every exception camopt raises from Python carries the CLI's message for the same bad input:
InputError (exit 3) for a design key, an option value, a file; NumericalError (exit 4) with
the angle where the solve fails. Both are camopt.Error."""

import os

import pytest

import camopt
from conftest import SOURCE_DIR, cli_error

TAPPET = "designs/bucket_tappet.toml"
CVVL = "designs/cvvl_swing_cam.toml"


@pytest.fixture(autouse=True)
def in_source_dir():
    os.chdir(SOURCE_DIR)


def test_the_exception_types_form_one_family():
    assert issubclass(camopt.InputError, camopt.Error) and issubclass(camopt.NumericalError, camopt.Error)
    assert issubclass(camopt.Error, Exception) and not issubclass(camopt.InputError, camopt.NumericalError)


def test_a_bad_design_key_names_the_file_line_and_key(tmp_path):
    text = (SOURCE_DIR / TAPPET).read_text().replace("[driver]\n", "[driver]\nspeed_rpm = 6000\n", 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    expected = cli_error("kinematics", bad, "--out", tmp_path / "out", kind="input error")
    assert "bad.toml:" in expected and "speed_rpm" in expected
    with pytest.raises(camopt.InputError) as e:
        camopt.Design.load(bad).compile()
    assert str(e.value) == expected
    # the same from text named by the same path, and through a job
    with pytest.raises(camopt.InputError) as e:
        camopt.kinematics(camopt.Design.from_text(text, path=str(bad)))
    assert str(e.value) == expected


def test_a_missing_design_file():
    expected = cli_error("kinematics", "designs/no_such_design.toml", "--out", "/tmp/camopt-never", kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.Design.load("designs/no_such_design.toml")
    assert str(e.value) == expected


@pytest.mark.parametrize("cli_args, python_args", [
    (["--outputs", "lift,speed"], {"outputs": "lift,speed"}),
    (["--step", "-1"], {"step_deg": -1}),
    (["--rpm", "0"], {"rpm": 0}),
    (["--step", "400"], {"step_deg": 400}),
    (["--duration-at", "1,1"], {"duration_at": "1,1"}),
    (["--control", "3"], {"control": 3}),
    (["--step", "0.0001"], {"step_deg": 0.0001}),
])
def test_a_bad_option_value_of_kinematics(cli_args, python_args, tmp_path):
    expected = cli_error("kinematics", TAPPET, *cli_args, "--out", tmp_path, kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.kinematics(TAPPET, **python_args)
    assert str(e.value) == expected


def test_a_control_outside_its_range(tmp_path):
    expected = cli_error("kinematics", CVVL, "--control", "0:99:3", "--out", tmp_path, kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.kinematics(CVVL, control="0:99:3")
    assert str(e.value) == expected


def test_a_linkage_that_cannot_close_is_a_numerical_failure_at_its_angle(tmp_path):
    # the four-bar's ground stretched to 110 mm: crank 20 + coupler 70 no longer reach the
    # rocker's circle over the whole turn
    text = (SOURCE_DIR / "designs/four_bar.toml").read_text().replace("pivot_mm = [60, 0]", "pivot_mm = [110, 0]")
    bad = tmp_path / "far.toml"
    bad.write_text(text)
    expected = cli_error("kinematics", bad, "--out", tmp_path / "out", kind="numerical failure")
    assert "cannot assemble" in expected and "(at driver" in expected
    with pytest.raises(camopt.NumericalError) as e:
        camopt.kinematics(camopt.Design.load(bad))
    assert str(e.value) == expected
    assert e.value.code == "cannot assemble" and e.value.where in expected


def test_a_wrong_argument_type_is_a_python_type_error():
    with pytest.raises(TypeError):
        camopt.kinematics(TAPPET, threads="two")
