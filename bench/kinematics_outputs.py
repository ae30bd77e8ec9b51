#!/usr/bin/env python3
"""Every bundled design's kinematics, every output, written by one camopt build and compared
with another's: the check that a change to the kinematic kernel leaves the results as they
were (bit for bit, or within a stated bound where a reordering of floating-point operations
is unavoidable).

usage: python3 bench/kinematics_outputs.py write CAMOPT OUT_DIR
       python3 bench/kinematics_outputs.py compare BEFORE_DIR AFTER_DIR [--lift-mm 1e-12]

write: `CAMOPT kinematics DESIGN --outputs all --no-report` for every designs/*.toml (the
designs with a control over their whole range: 17 positions for the CVVLs, 11 for the VVLD
and the Valvetronic), into OUT_DIR/<design>/. compare: every kinematics.csv cell of AFTER
against BEFORE; prints per design the largest difference in the position columns (lift [mm]
and angles [deg]) and in every other column relative to that column's peak, and the number
of cells that differ at all, and the summary.json keys that differ (run_time_s aside); exits 1 when a position differs by more than --lift-mm, a
derivative or contact quantity by more than 1e-9 of its peak, or the tables differ in shape.
"""
import csv
import glob
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# control ranges (START:STOP:COUNT) of the designs with a control: the papers' resolutions
CONTROLS = {"cvvl_swing_cam": "0:16:17", "cvvl_swing_cam_hla": "0:16:17", "vvld": "0:100:11",
            "valvetronic": "0:60:11"}


def write(camopt, out_dir):
    for path in sorted(glob.glob(os.path.join(ROOT, "designs", "*.toml"))):
        name = os.path.splitext(os.path.basename(path))[0]
        cmd = [camopt, "-q", "kinematics", path, "--out", os.path.join(out_dir, name), "--outputs", "all",
               "--no-report"]
        if name in CONTROLS:
            cmd += ["--control", CONTROLS[name]]
        subprocess.run(cmd, check=True)
        print("wrote", name)


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def is_position(column):
    # positions of nodes ([mm] or [deg]) and the valve lift: no rate in the unit
    return (column.endswith("_mm") or column.endswith("_deg")) and "_per_" not in column


def summary_differences(before, after):
    """keys of summary.json whose values differ (the run time aside), as key paths"""
    def walk(a, b, path):
        if isinstance(a, dict) and isinstance(b, dict):
            for k in sorted(set(a) | set(b)):
                if k != "run_time_s":
                    yield from walk(a.get(k), b.get(k), path + "." + k)
        elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
            for i, (x, y) in enumerate(zip(a, b)):
                yield from walk(x, y, "%s[%d]" % (path, i))
        elif a != b:
            yield path
    with open(before) as f, open(after) as g:
        return list(walk(json.load(f), json.load(g), ""))


def compare(before_dir, after_dir, lift_bound):
    failed = False
    for before in sorted(glob.glob(os.path.join(before_dir, "*", "kinematics.csv"))):
        name = os.path.basename(os.path.dirname(before))
        after = os.path.join(after_dir, name, "kinematics.csv")
        hb, rb = read(before)
        ha, ra = read(after)
        if hb != ha or len(rb) != len(ra):
            print("%s: the tables differ in shape" % name)
            failed = True
            continue
        worst_pos, worst_rel, differ = 0.0, 0.0, 0
        worst_pos_col = worst_rel_col = ""
        for c, column in enumerate(hb):
            try:
                xb = [float(r[c]) if r[c] else 0.0 for r in rb]
                xa = [float(r[c]) if r[c] else 0.0 for r in ra]
            except ValueError:
                if [r[c] for r in rb] != [r[c] for r in ra]:
                    print("%s: column %s differs" % (name, column))
                    failed = True
                continue
            differ += sum(1 for r1, r2 in zip(rb, ra) if r1[c] != r2[c])
            d = max(abs(a - b) for a, b in zip(xa, xb))
            if is_position(column):
                if d > worst_pos:
                    worst_pos, worst_pos_col = d, column
            else:
                peak = max(abs(b) for b in xb) or 1.0
                if d / peak > worst_rel:
                    worst_rel, worst_rel_col = d / peak, column
        bad = worst_pos > lift_bound or worst_rel > 1e-9
        failed |= bad
        summary = summary_differences(os.path.join(os.path.dirname(before), "summary.json"),
                                      os.path.join(after_dir, name, "summary.json"))
        if summary:
            print("%s: summary.json differs at %s" % (name, ", ".join(summary[:5])))
        print("%-30s cells differing %7d  positions max %.3g (%s)  others max %.3g of peak (%s)%s" %
              (name, differ, worst_pos, worst_pos_col or "-", worst_rel, worst_rel_col or "-",
               "  FAIL" if bad else ""))
    return 1 if failed else 0


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "write":
        write(sys.argv[2], sys.argv[3])
        return 0
    if len(sys.argv) >= 4 and sys.argv[1] == "compare":
        bound = float(sys.argv[sys.argv.index("--lift-mm") + 1]) if "--lift-mm" in sys.argv else 1e-12
        return compare(sys.argv[2], sys.argv[3], bound)
    sys.exit(__doc__)


if __name__ == "__main__":
    sys.exit(main())
