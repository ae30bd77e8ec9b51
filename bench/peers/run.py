"""camopt in process against the numpy and scipy peers, side by side in one run, each with its
error against a closed form or a tight reference (bench/README.md, "Peers").

    PYTHONPATH=build/python /usr/bin/python3 bench/peers/run.py [--repeat N] [--csv FILE]

rigid:    designs/eccentric_flat_follower.toml (a direct-acting valve whose lift law is exact),
          721 cam angles (0.5 deg) x 3 engine speeds (3000, 5000, 7000 rpm): camopt's rigid job
          (every dynamics.csv column and the summary) against vectorised numpy on the exact law
          and on a periodic cubic spline of the 1 deg lift table (rigid_numpy.py); errors of the
          contact force and cam torque against the closed form, relative to their peaks, and of
          the separation speed [rpm] (camopt's refined between grid points, the scripts' the
          least over their grid).
CVVL:     designs/cvvl_swing_cam.toml at control 0, the same angles and speeds: camopt's rigid
          job against numpy's pad-valve force from a spline of the 1 deg valve lift table
          (error against camopt's pad force, exact at each point).
flexible: bench/peers/linear_valve.toml (the single-mass valve of the flexible model's exact
          test) at 9400 rpm, one revolution from the static start, output every 0.1 cam deg:
          camopt's flexible job against scipy Radau and LSODA (flexible_scipy.py), plain and
          with the contact switches as events; the lift error [mm] against DOP853 with events at
          rtol 1e-12 (the tight reference), and the number of contact events.
Times: the best of --repeat wall times of the whole call, in this process.
"""

import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import camopt  # noqa: E402  (PYTHONPATH=build/python)
import flexible_scipy  # noqa: E402
import rigid_numpy  # noqa: E402

RPMS = [3000.0, 5000.0, 7000.0]
STEP_DEG = 0.5


def best_of(repeat, f):
    """the best wall time [s] of `repeat` calls, and the last call's result; a camopt Result
    also gets `best_solve_s`, the best of its summaries' run_time_s (the solve alone)"""
    best, solve, out = math.inf, math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
        if isinstance(out, camopt.Result):
            solve = min(solve, out.summary["run_time_s"])
    if isinstance(out, camopt.Result):
        out.best_solve_s = solve
    return best, out


def rel_error(value, exact):
    return float(np.max(np.abs(value - exact)) / np.max(np.abs(exact)))


def rigid_rows(repeat):
    design = camopt.Design.load(os.path.join(ROOT, "designs/eccentric_flat_follower.toml"))
    design.compile()
    theta = np.arange(0, 721) * STEP_DEG
    exact = rigid_numpy.exact_law(theta, RPMS)
    exact_sep = rigid_numpy.separation_rpm()
    # camopt: the rigid job in process (its columns are rpm-major, as the scripts' arrays)
    t_camopt, run = best_of(repeat, lambda: camopt.dynamics(design, rpm=RPMS, step_deg=STEP_DEG))
    shape = (len(RPMS), len(theta))
    force = run.columns["contact_disc_face_force_N"].reshape(shape)
    torque = run.columns["cam_torque_Nm"].reshape(shape)
    sep = run.summary["separation"][0]["contacts"]["disc_face"]["separation_rpm"]
    rows = [dict(case="rigid direct-acting valve", tool="camopt (rigid job, in process)", ms=t_camopt * 1e3,
                 solve_ms=run.best_solve_s * 1e3, force_err_rel=rel_error(force, exact["force_N"]),
                 torque_err_rel=rel_error(torque, exact["cam_torque_Nm"]), separation_err_rpm=abs(sep - exact_sep))]
    # numpy on the exact law, and on a spline of the 1 deg lift table
    table_deg = np.arange(0, 361, 1.0)
    table_mm = rigid_numpy.exact_lift(table_deg)[0]
    for name, f in (("numpy, exact law", lambda: rigid_numpy.exact_law(theta, RPMS)),
                    ("numpy, spline of the 1 deg lift table",
                     lambda: rigid_numpy.spline_law(table_deg, table_mm, theta, RPMS))):
        t, out = best_of(repeat, f)
        lift = rigid_numpy.spline_lift(table_deg, table_mm, theta) if "spline" in name else rigid_numpy.exact_lift(theta)
        sep = rigid_numpy.separation_rpm_grid(lift[0], lift[2])
        rows.append(dict(case="rigid direct-acting valve", tool=name, ms=t * 1e3, solve_ms=math.nan,
                         force_err_rel=rel_error(out["force_N"], exact["force_N"]),
                         torque_err_rel=rel_error(out["cam_torque_Nm"], exact["cam_torque_Nm"]),
                         separation_err_rpm=abs(sep - exact_sep)))
    return rows


def cvvl_rows(repeat):
    """the CVVL (control 0) in mode (a), 721 angles x 3 speeds: camopt's whole rigid job (every
    force of the three contacts, torque, reactions) against numpy's pad-valve force from a
    spline of the 1 deg valve lift table (the one force a lift table gives without the
    linkage); the reference is camopt's own pad force, exact at each point"""
    design = camopt.Design.load(os.path.join(ROOT, "designs/cvvl_swing_cam.toml"))
    design.compile()
    theta = np.arange(0, 721) * STEP_DEG
    t_camopt, run = best_of(repeat, lambda: camopt.dynamics(design, rpm=RPMS, control=0, step_deg=STEP_DEG))
    pad = run.columns["contact_pad_valve_force_N"].reshape(len(RPMS), len(theta))
    table = camopt.kinematics(design, control=0, outputs="lift", step_deg=1.0)
    table_deg, table_mm = table.columns["cam_deg"], table.columns["lift_mm"]
    t, force = best_of(repeat, lambda: rigid_numpy.cvvl_pad_force(table_deg, table_mm, theta, RPMS))
    case = "rigid CVVL control 0"
    return [dict(case=case, tool="camopt (rigid job, in process)", ms=t_camopt * 1e3,
                 solve_ms=run.best_solve_s * 1e3, force_err_rel=0.0),
            dict(case=case, tool="numpy, pad force from a spline of the 1 deg lift table", ms=t * 1e3,
                 solve_ms=math.nan, force_err_rel=rel_error(force, pad))]


def flexible_rows(repeat, rpm=9400.0):
    design = camopt.Design.load(os.path.join(HERE, "linear_valve.toml"))
    design.compile()
    w = flexible_scipy.cam_speed(rpm)
    t_out = np.arange(0, 3601) * math.radians(0.1) / w
    reference = flexible_scipy.with_events(w, t_out, "DOP853", 1e-12, 1e-15)
    ref_lift, ref_events = reference["lift_mm"], len(reference["events"])
    rows = []
    for rtol, atol in ((1e-6, 1e-7), (1e-8, 1e-10)):
        t, run = best_of(repeat, lambda: camopt.dynamics(design, rpm=rpm, model="flexible", revolutions=1,
                                                         step_deg=0.1, rtol=rtol, atol=atol))
        result = run.summary["results"][0]
        events = len(result["events"])
        rows.append(dict(case="flexible single-mass valve", tool="camopt flexible rtol %g atol %g mm" % (rtol, atol),
                         ms=t * 1e3, solve_ms=run.best_solve_s * 1e3,
                         lift_err_mm=float(np.max(np.abs(run.columns["lift_mm"] - ref_lift))),
                         events=events, reference_events=ref_events))
    for method in ("Radau", "LSODA"):
        for how, f in (("plain", flexible_scipy.plain), ("events", flexible_scipy.with_events)):
            rtol, atol = 1e-6, 1e-10  # atol [m]: 1e-7 mm, camopt's default
            t, out = best_of(repeat, lambda: f(w, t_out, method, rtol, atol))
            rows.append(dict(case="flexible single-mass valve",
                             tool="scipy %s, %s, rtol %g atol %g m" % (method, how, rtol, atol), ms=t * 1e3,
                             solve_ms=math.nan, lift_err_mm=float(np.nanmax(np.abs(out["lift_mm"] - ref_lift))),
                             events=len(out["events"]) if out["events"] is not None else math.nan,
                             reference_events=ref_events))
    return rows


COLUMNS = ["case", "tool", "ms", "solve_ms", "ratio_to_camopt", "force_err_rel", "torque_err_rel",
           "separation_err_rpm", "lift_err_mm", "events", "reference_events"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--csv", default="")
    args = ap.parse_args()
    rows = rigid_rows(args.repeat) + cvvl_rows(args.repeat) + flexible_rows(max(1, args.repeat // 4))
    # each case's time against camopt's default run of the case
    for case in {r["case"] for r in rows}:
        base = next(r["ms"] for r in rows if r["case"] == case and r["tool"].startswith("camopt"))
        for r in rows:
            if r["case"] == case:
                r["ratio_to_camopt"] = r["ms"] / base
    fmt = lambda v: "" if v is None or (isinstance(v, float) and math.isnan(v)) else (
        "%.3g" % v if isinstance(v, float) else str(v))
    print("%-28s %-48s %9s %9s %7s %10s %10s %9s %10s %6s %6s" % (
        "case", "tool", "ms", "solve ms", "ratio", "force err", "torque err", "sep rpm", "lift mm", "events", "ref"))
    for r in rows:
        print("%-28s %-48s %9s %9s %7s %10s %10s %9s %10s %6s %6s" % tuple(fmt(r.get(c)) for c in COLUMNS))
    if args.csv:  # written beside, then renamed into place
        tmp = args.csv + ".tmp"
        with open(tmp, "w") as f:
            f.write("case,tool,wall_ms,solve_ms,time_ratio_to_camopt,force_error_rel,torque_error_rel,"
                    "separation_error_rpm,lift_error_mm,events,reference_events\n")
            for r in rows:
                cells = ['"%s"' % r["case"], '"%s"' % r["tool"]]
                for c in COLUMNS[2:]:
                    v = r.get(c)
                    cells.append("" if v is None or (isinstance(v, float) and math.isnan(v)) else repr(v))
                f.write(",".join(cells) + "\n")
        os.replace(tmp, args.csv)

if __name__ == "__main__":
    main()
