"""`--format npz` read by numpy alone and by camopt.read_results equals the CSV bit for bit;
a damaged archive raises InputError naming the file and the fault."""

import numpy as np
import pytest

import camopt
from conftest import read_csv, run_cli


def _bits(a):
    return np.asarray(a, dtype=np.float64).view(np.uint64)


@pytest.mark.parametrize("args", [
    ("kinematics", "designs/cvvl_swing_cam.toml", "--control", "0:16:3", "--outputs", "all", "--step", "1"),
    ("dynamics", "designs/cvvl_swing_cam.toml", "--model", "rigid", "--rpm", "2000,6000", "--step", "1"),
])
def test_npz_equals_the_csv_bit_for_bit(args, tmp_path):
    table = args[0] + (".csv")
    for fmt in ("long", "npz"):
        code, stderr = run_cli(*args, "--format", fmt, "--no-report", "--out", tmp_path / fmt)
        assert code == 0, stderr
    csv = read_csv(tmp_path / "long" / table)
    archive = np.load(tmp_path / "npz" / (args[0] + ".npz"))
    assert list(archive.keys()) == list(csv.keys())
    for name in csv:
        assert archive[name].dtype == np.float64
        assert np.array_equal(_bits(archive[name]), _bits(csv[name])), name
    # the package's reader: the same arrays, from the archive, the CSV or the folder
    for source in (tmp_path / "npz" / (args[0] + ".npz"), tmp_path / "long" / table, tmp_path / "npz"):
        read = camopt.read_results(source)
        assert list(read.keys()) == list(csv.keys())
        for name in csv:
            assert np.array_equal(_bits(read[name]), _bits(csv[name])), (source, name)


def test_a_damaged_archive_is_an_input_error(tmp_path):
    code, stderr = run_cli("kinematics", "designs/roller_finger_follower.toml", "--format", "npz", "--no-report",
                           "--out", tmp_path)
    assert code == 0, stderr
    path = tmp_path / "kinematics.npz"
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 30])
    with pytest.raises(camopt.InputError, match=r"kinematics\.npz: not a \.npz archive as camopt writes it: .*truncated"):
        camopt.read_results(path)
