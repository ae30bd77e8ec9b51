"""camopt.kinematics equals `camopt kinematics` bit for bit: every column of kinematics.csv
and every key of summary.json, on every bundled design and on a control family."""

import os
import pathlib

import pytest

import camopt
from conftest import SOURCE_DIR, assert_same_columns, read_csv, read_summary, run_cli, without_times

DESIGNS = sorted(p.name for p in (SOURCE_DIR / "designs").glob("*.toml"))


@pytest.mark.parametrize("design", DESIGNS)
def test_every_bundled_design_equals_the_cli_bit_for_bit(design, tmp_path):
    path = "designs/" + design
    code, stderr = run_cli("kinematics", path, "--outputs", "all", "--rpm", "6000", "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    os.chdir(SOURCE_DIR)
    run = camopt.kinematics(path, outputs="all", rpm=6000, threads=2)
    assert_same_columns(run.columns, read_csv(tmp_path / "kinematics.csv"))
    assert without_times(run.summary) == read_summary(tmp_path / "summary.json")


def test_a_control_family_at_a_step_equals_the_cli(tmp_path):
    path = "designs/cvvl_swing_cam.toml"
    code, stderr = run_cli("kinematics", path, "--control", "0:16:5", "--step", "0.5", "--outputs", "lift,contacts",
                           "--duration-at", "0.5,0.05", "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    os.chdir(SOURCE_DIR)
    design = camopt.Design.load(path)
    run = camopt.kinematics(design, control="0:16:5", step_deg=0.5, outputs=["lift", "contacts"],
                            duration_at=[0.5, 0.05])
    assert_same_columns(run.columns, read_csv(tmp_path / "kinematics.csv"))
    assert without_times(run.summary) == read_summary(tmp_path / "summary.json")
    # one note per control position, as the CLI prints them
    assert sum(n.startswith("kinematics: control ") for n in run.notes) == 5


def test_a_design_from_text_names_its_path_and_gives_the_same_columns():
    # its profile table (file = "profiles/...") resolves from the folder of the path it is given
    text = (SOURCE_DIR / "designs/bucket_tappet.toml").read_text()
    named = str(SOURCE_DIR / "designs/tappet_from_text.toml")
    from_text = camopt.kinematics(camopt.Design.from_text(text, path=named), step_deg=1.0)
    from_file = camopt.kinematics(str(SOURCE_DIR / "designs/bucket_tappet.toml"), step_deg=1.0)
    assert from_text.summary["design_file"] == named
    assert_same_columns(from_text.columns, from_file.columns)


@pytest.mark.parametrize("design", ["designs/cvvl_swing_cam.toml", "designs/four_bar.toml"])
def test_validate_gives_what_the_cli_prints(design):
    import subprocess
    from conftest import CAMOPT
    p = subprocess.run([CAMOPT, "validate", design], cwd=SOURCE_DIR, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    os.chdir(SOURCE_DIR)
    findings = camopt.Design.load(design).validate()
    assert p.stdout == design + ": ok\n" + findings["description"] + "\n"
    assert p.stderr == "".join(design + ": warning: " + w + "\n" for w in findings["warnings"])


# the CLI's --set and Design.set: a roller radius and a contact solved at rest
SETS = [("connection.disc_roller.b.radius_mm", "9", 9.0), ("connection.disc_roller.touch_at_rest", "true", True)]


@pytest.mark.parametrize("cli_args, job, table", [
    (["kinematics", "--step", "2", "--outputs", "all"], lambda d: camopt.kinematics(d, step_deg=2, outputs="all"),
     "kinematics.csv"),
    (["dynamics", "--rpm", "2000,4000"], lambda d: camopt.dynamics(d, rpm=[2000, 4000]), "dynamics.csv"),
    (["dynamics", "--model", "modes"], lambda d: camopt.dynamics(d, model="modes"), "modes.csv"),
])
def test_a_run_with_set_has_the_cli_summary_with_its_overrides(cli_args, job, table, tmp_path):
    path = "designs/eccentric_offset_roller.toml"
    sets = [a for key, text, _ in SETS for a in ("--set", key + "=" + text)]
    code, stderr = run_cli(*sets, cli_args[0], path, *cli_args[1:], "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    os.chdir(SOURCE_DIR)
    design = camopt.Design.load(path)
    for key, _, value in SETS:
        design.set(key, value)
    run = job(design)
    expected = read_summary(tmp_path / "summary.json")
    assert expected["overrides"] == {"connection.disc_roller.b.radius_mm": 9, "connection.disc_roller.touch_at_rest": True}
    assert without_times(run.summary) == expected
    assert_same_columns(run.columns, read_csv(tmp_path / table))
    # the same design without changes records none
    assert "overrides" not in job(camopt.Design.load(path)).summary
