"""camopt.dynamics equals `camopt dynamics` bit for bit: every column of dynamics.csv and every
key of summary.json, for the rigid model (and its compliant contacts) and the flexible model."""

import os

import pytest

import camopt
from conftest import SOURCE_DIR, assert_same_columns, cli_error, read_csv, read_summary, run_cli, without_times


@pytest.fixture(autouse=True)
def in_source_dir():
    os.chdir(SOURCE_DIR)


def same_as_cli(tmp_path, design, cli_args, **python_args):
    code, stderr = run_cli("dynamics", design, *cli_args, "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    run = camopt.dynamics(design, **python_args)
    assert_same_columns(run.columns, read_csv(tmp_path / "dynamics.csv"))
    assert without_times(run.summary) == read_summary(tmp_path / "summary.json")
    return run


def test_the_rigid_model_over_speeds_equals_the_cli(tmp_path):
    run = same_as_cli(tmp_path, "designs/roller_finger_follower.toml", ["--model", "rigid", "--rpm", "1000:7000:4"],
                      model="rigid", rpm="1000:7000:4")
    assert sorted(set(run.columns["rpm"])) == [1000.0, 3000.0, 5000.0, 7000.0]


def test_the_rigid_model_over_a_control_family_equals_the_cli(tmp_path):
    same_as_cli(tmp_path, "designs/cvvl_swing_cam.toml", ["--rpm", "6000", "--control", "0,8,16", "--step", "0.5"],
                rpm=6000, control=[0, 8, 16], step_deg=0.5)


def test_compliant_contacts_equal_the_cli(tmp_path):
    same_as_cli(tmp_path, "designs/bucket_tappet.toml", ["--model", "rigid", "--contacts", "compliant", "--rpm", "6000"],
                rpm=6000, contacts="compliant")


def test_the_flexible_model_equals_the_cli(tmp_path):
    run = same_as_cli(tmp_path, "designs/rocker_arm.toml", ["--model", "flexible", "--rpm", "6000"],
                      model="flexible", rpm=[6000])
    assert run.summary["model"] == "flexible"


@pytest.mark.parametrize("cli_args, python_args", [
    (["--rpm", "2e6"], {"rpm": 2e6}),
    (["--rpm", "6000", "--revolutions", "2"], {"rpm": 6000, "revolutions": 2}),
    (["--model", "flexible", "--rpm", "6000", "--contacts", "compliant"],
     {"model": "flexible", "rpm": 6000, "contacts": "compliant"}),
    (["--rpm", "6000", "--control", "1"], {"rpm": 6000, "control": 1}),
])
def test_a_bad_option_value_of_dynamics(cli_args, python_args, tmp_path):
    expected = cli_error("dynamics", "designs/bucket_tappet.toml", *cli_args, "--out", tmp_path, kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.dynamics("designs/bucket_tappet.toml", **python_args)
    assert str(e.value) == expected

