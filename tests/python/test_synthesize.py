"""camopt.synthesize equals `camopt synthesize` bit for bit (profile.csv, grinding.csv, report.json,
profile.dxf), and the design it returns runs as the CLI's written design.toml does."""

import csv
import json
import os

import numpy as np
import pytest

import camopt
from conftest import (SOURCE_DIR, assert_same_columns, assert_same_run_of_written_design, cli_error, read_csv,
                      read_summary, run_cli)

DESIGN = "designs/roller_finger_follower.toml"
TARGET = "designs/targets/rff_intake_lift.csv"


@pytest.fixture(autouse=True)
def in_source_dir():
    os.chdir(SOURCE_DIR)


@pytest.fixture(scope="module")
def cli_folder(tmp_path_factory):
    """The README's main job on the CLI: the RFF target synthesized into a folder."""
    out = tmp_path_factory.mktemp("synthesize")
    code, stderr = run_cli("synthesize", TARGET, "--design", DESIGN, "--no-report", "--out", out, cwd=SOURCE_DIR)
    assert code == 0, stderr
    return out


@pytest.fixture(scope="module")
def run():
    os.chdir(SOURCE_DIR)
    return camopt.synthesize(TARGET, DESIGN)


def report_of(folder):
    with open(folder / "report.json") as f:
        return json.load(f)


def test_the_profile_grinding_table_and_report_equal_the_cli(run, cli_folder):
    assert list(run.tables) == ["profile.csv", "grinding.csv"]
    assert_same_columns(run.tables["profile.csv"], read_csv(cli_folder / "profile.csv"))
    assert_same_columns(run.tables["grinding.csv"], read_csv(cli_folder / "grinding.csv"))
    assert run.columns is run.tables["profile.csv"]
    assert run.summary == report_of(cli_folder)
    # the files' texts are the CLI's bytes (design.toml: but for the folder it was written for)
    for name in ("profile.csv", "grinding.csv", "profile.dxf"):
        assert run.files[name] == (cli_folder / name).read_bytes(), name


def test_the_returned_design_runs_as_the_cli_written_design(run, cli_folder, tmp_path):
    code, stderr = run_cli("kinematics", cli_folder / "design.toml", "--outputs", "all", "--rpm", "6000", "--no-report",
                           "--out", tmp_path)
    assert code == 0, stderr
    again = camopt.kinematics(run.design, outputs="all", rpm=6000)
    assert_same_run_of_written_design(again, run.design, cli_folder, tmp_path, "kinematics.csv")
    # the valve lift of the synthesized cam follows the target (the round trip report.json states)
    assert run.summary["checks"]["round_trip_max_error_mm"] < 1e-3


def test_the_design_text_is_the_cli_design_toml_but_for_its_folder(run, cli_folder):
    written = (cli_folder / "design.toml").read_text().splitlines()
    text = run.design.text.splitlines()
    assert len(text) == len(written)
    differ = [(a, b) for a, b in zip(text, written) if a != b]
    assert len(differ) == 0, differ  # the RFF design has no other relative file than its profile
    assert os.path.isfile(os.path.join(os.path.dirname(run.design.path), "profile.csv"))


def test_a_changed_design_is_synthesized_and_written_as_the_cli_with_set(tmp_path):
    code, stderr = run_cli("--set", "node.finger.mass_kg=0.05", "synthesize", TARGET, "--design", DESIGN, "--no-report",
                           "--out", tmp_path)
    assert code == 0, stderr
    design = camopt.Design.load(DESIGN)
    design.set("node.finger.mass_kg", 0.05)
    changed = camopt.synthesize(TARGET, design)
    assert_same_columns(changed.columns, read_csv(tmp_path / "profile.csv"))
    assert changed.design.get("node.finger.mass_kg") == 0.05
    # design.toml: the CLI's text with the change edited in; its header names the change as the
    # Design's messages do ("set KEY=VALUE", the CLI "--set KEY=VALUE")
    written = (tmp_path / "design.toml").read_text()
    assert written.count("#   --set node.finger.mass_kg=0.05\n") == 1
    assert changed.design.text == written.replace("#   --set node.", "#   set node.")
    report = report_of(tmp_path)
    assert report["overrides"] == {"node.finger.mass_kg": 0.05}
    assert changed.summary == report


def test_a_target_table_in_memory_equals_its_file(run):
    with open(TARGET, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, body = rows[0], rows[1:]
    table = {name: [float(r[i]) for r in body] for i, name in enumerate(header)}
    again = camopt.synthesize(table, DESIGN)
    assert_same_columns(again.columns, run.columns)
    assert again.summary["target_file"] == "<target>"
    assert {k: v for k, v in again.summary.items() if k != "target_file"} == \
        {k: v for k, v in run.summary.items() if k != "target_file"}


def test_a_bad_target_value_in_memory_names_its_row():
    with pytest.raises(camopt.InputError) as e:
        camopt.synthesize({"cam_deg": [0, 1, 2], "lift_mm": [0, float("nan"), 0]}, DESIGN)
    assert str(e.value) == "<target>:3: column 'lift_mm' value 'nan' is not finite"


@pytest.mark.parametrize("cli_args, python_args", [
    (["--control", "3"], {"control": 3}),
    (["--target-node", "nowhere"], {"target_node": "nowhere"}),
    (["--knot-spacing", "2"], {"knot_spacing_deg": 2}),
    (["--max-round-trip-error", "1e-12"], {"max_round_trip_error": 1e-12}),
])
def test_a_bad_option_of_synthesize(cli_args, python_args, tmp_path):
    code, _ = run_cli("synthesize", TARGET, "--design", DESIGN, *cli_args, "--out", tmp_path)
    kind = {3: "input error", 4: "numerical failure"}[code]
    expected = cli_error("synthesize", TARGET, "--design", DESIGN, *cli_args, "--out", tmp_path, kind=kind)
    error = camopt.InputError if code == 3 else camopt.NumericalError
    with pytest.raises(error) as e:
        camopt.synthesize(TARGET, DESIGN, **python_args)
    assert str(e.value) == expected


def test_modes_equal_the_cli(tmp_path):
    code, stderr = run_cli("dynamics", "designs/cvvl_swing_cam.toml", "--model", "modes", "--control", "0,16",
                           "--no-report", "--out", tmp_path)
    assert code == 0, stderr
    run = camopt.dynamics("designs/cvvl_swing_cam.toml", model="modes", control=[0, 16])
    assert_same_columns(run.columns, read_csv(tmp_path / "modes.csv"))
    assert run.summary == read_summary(tmp_path / "summary.json")
    # mass-normalised shapes: at least one coordinate, frequencies ascending per linearisation
    f = run.columns["frequency_Hz"]
    first = np.flatnonzero(run.columns["mode"] == 1)
    assert len(first) == len(run.summary["results"]) == 4
    for a, b in zip(first, list(first[1:]) + [len(f)]):
        assert np.all(np.diff(f[a:b]) > 0)


@pytest.mark.parametrize("cli_args, python_args", [
    (["--cam-deg", "a"], {"cam_deg": "a"}),
    (["--revolutions", "2"], {"revolutions": 2}),
    (["--contacts", "compliant"], {"contacts": "compliant"}),
])
def test_a_bad_option_of_modes(cli_args, python_args, tmp_path):
    expected = cli_error("dynamics", "designs/bucket_tappet.toml", "--model", "modes", *cli_args, "--out", tmp_path,
                         kind="input error")
    with pytest.raises(camopt.InputError) as e:
        camopt.dynamics("designs/bucket_tappet.toml", model="modes", **python_args)
    assert str(e.value) == expected
