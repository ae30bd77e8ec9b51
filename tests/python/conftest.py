"""Shared by the Python tests: the camopt executable, the source tree, running the CLI, and
reading its CSV exactly. ctest sets CAMOPT_BINARY and PYTHONPATH (tests/CMakeLists.txt)."""

import csv
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
CAMOPT = os.environ.get("CAMOPT_BINARY", str(SOURCE_DIR / "build" / "camopt"))


def run_cli(*args, cwd=SOURCE_DIR):
    """camopt -q --threads 2 ARGS: (exit code, stderr)."""
    p = subprocess.run([CAMOPT, "-q", "--threads", "2", *map(str, args)], cwd=cwd, capture_output=True, text=True)
    return p.returncode, p.stderr


def cli_error(*args, kind):
    """The CLI's message for a failing run: stderr without 'camopt: <kind>: ' (exit 3 or 4)."""
    code, stderr = run_cli(*args)
    assert code == {"input error": 3, "numerical failure": 4}[kind], stderr
    prefix = "camopt: " + kind + ": "
    assert stderr.startswith(prefix) and stderr.endswith("\n"), stderr
    return stderr[len(prefix):-1]


def read_csv(path):
    """A CSV written by camopt: dict of header -> float64 array (every value read with float(); an
    empty cell, a quantity that does not exist there, is NaN)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) if r[i] else np.nan for r in body], dtype=np.float64)
            for i, name in enumerate(header)}


def read_summary(path):
    """summary.json without its wall times."""
    with open(path) as f:
        return without_times(json.load(f))


def without_times(summary):
    """A summary without run_time_s (a wall time, never the same twice)."""
    return {k: v for k, v in summary.items() if k != "run_time_s"}


def assert_same_columns(python_columns, csv_columns):
    """The same names in the same order, every value the same 64 bits (the CSV writes a
    negative zero as 0, so -0.0 matches 0; a NaN matches a NaN)."""
    assert list(python_columns) == list(csv_columns)
    for name, expected in csv_columns.items():
        got = python_columns[name]
        assert got.dtype == np.float64 and got.shape == expected.shape, name
        bits = (got + 0.0).view(np.uint64)
        differ = np.flatnonzero((bits != expected.view(np.uint64)) & ~(np.isnan(got) & np.isnan(expected)))
        assert differ.size == 0, "%s: row %d: python %r, csv %r" % (name, differ[0], got[differ[0]], expected[differ[0]])


def assert_same_run_of_written_design(run, design, cli_folder, out, table):
    """A job's Result on the Design a synthesis or optimisation returned equals the CLI's run of
    the written cli_folder/design.toml into `out`: every column of `table` and the summary but
    for design_file, which names each its own file."""
    assert_same_columns(run.columns, read_csv(out / table))
    expected = read_summary(out / "summary.json")
    got = without_times(run.summary)
    assert got.pop("design_file") == design.path
    assert expected.pop("design_file") == str(cli_folder / "design.toml")
    assert got == expected


@pytest.fixture
def source_dir():
    return SOURCE_DIR
