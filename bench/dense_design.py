#!/usr/bin/env python3
"""Write the start-up benchmark's design: the bundled CVVL (designs/cvvl_swing_cam.toml) with
both profile tables resampled to 18 000 rows (0.02 deg), by periodic cubic Hermite
interpolation (Catmull-Rom) of the bundled 1 deg tables.

usage: python3 bench/dense_design.py OUT_DIR [--rows N]

Writes OUT_DIR/cvvl_dense.toml and OUT_DIR/profiles/*.csv (plain python 3, no numpy). The
tables are smooth and the mechanism assembles as the bundled one does; only the parse and
spline-fit cost of a minimal run is of interest (bench/README.md, "Start-up").
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DESIGN = os.path.join(ROOT, "designs", "cvvl_swing_cam.toml")
PROFILES = ("cvvl_input_lobe.csv", "cvvl_swing_cam.csv")


def read_table(path):
    """(angle_deg, radius_mm) rows of a bundled polar table."""
    rows = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line or line[0].isalpha():
                continue
            a, r = line.split(",")
            rows.append((float(a), float(r)))
    return rows


def resample(rows, count):
    """r at count evenly spaced angles over 360 deg (the table is evenly spaced, periodic)."""
    n = len(rows)
    step = 360.0 / n
    r = [v for _, v in rows]
    out = []
    for i in range(count):
        a = 360.0 * i / count
        k = int(a // step)
        t = a / step - k
        p0, p1, p2, p3 = r[(k - 1) % n], r[k % n], r[(k + 1) % n], r[(k + 2) % n]
        # catmull-rom: cubic hermite with central-difference slopes
        m1, m2 = 0.5 * (p2 - p0), 0.5 * (p3 - p1)
        t2, t3 = t * t, t * t * t
        out.append((a, (2 * t3 - 3 * t2 + 1) * p1 + (t3 - 2 * t2 + t) * m1 + (-2 * t3 + 3 * t2) * p2
                    + (t3 - t2) * m2))
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out_dir = sys.argv[1]
    count = int(sys.argv[sys.argv.index("--rows") + 1]) if "--rows" in sys.argv else 18000
    os.makedirs(os.path.join(out_dir, "profiles"), exist_ok=True)
    for name in PROFILES:
        rows = resample(read_table(os.path.join(ROOT, "designs", "profiles", name)), count)
        with open(os.path.join(out_dir, "profiles", name), "w") as f:
            f.write("# %s resampled to %d rows (bench/dense_design.py)\nangle_deg,radius_mm\n" % (name, count))
            for a, r in rows:
                f.write("%.12g,%.9f\n" % (a, r))
    with open(DESIGN) as f:
        text = f.read()
    with open(os.path.join(out_dir, "cvvl_dense.toml"), "w") as f:
        f.write(text.replace('name = "cvvl_swing_cam"', 'name = "cvvl_dense"', 1))


if __name__ == "__main__":
    main()
