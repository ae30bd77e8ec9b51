"""Study throughput: points per second of a synthesis + rigid-dynamics study against the number
of worker processes (1, 2), locally and on a local Dask cluster, and the per-point overhead of
the study and Dask layers over the same jobs called directly through the Python API.

    PYTHONPATH=build/python /usr/bin/python3 bench/study_throughput.py [--points 16] [--repeat 3]

Each figure is the best of --repeat runs. The tables of every run are compared with the serial
run's (they must be identical, point by point).
"""

import argparse
import os
import time

import camopt
from camopt.studies import parse_study

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def study_spec(points):
    return parse_study({
        "study": {"name": "throughput", "design": os.path.join(ROOT, "designs", "roller_finger_follower.toml")},
        "sampling": {"method": "latin_hypercube", "points": points, "seed": 1},
        "parameter": [{"key": "connection.cam_roller.b.radius_mm", "min": 7.5, "max": 9.5},
                      {"key": "node.finger.pivot_mm[0]", "min": -23.0, "max": -21.0}],
        "pipeline": {"synthesize": {"target": os.path.join(ROOT, "designs", "targets", "rff_intake_lift.csv")},
                     "rigid": {"rpm": "3000:7000:3"}},
        "response": [{"name": "max_hertz_MPa", "stage": "rigid", "path": "results[*].connections.*.max_hertz_MPa"},
                     {"name": "separation_rpm", "stage": "rigid", "path": "separation[*].contacts.*.separation_rpm",
                      "reduce": "min"}],
    }, os.path.join(ROOT, "bench", "throughput.toml"))


def direct(spec):
    """The same jobs through the API, without the study layer: seconds, and the rigid job's own
    solve time (summary run_time_s, the in-process C++ time of that stage)."""
    from camopt.studies.sampling import sample

    target = spec.pipeline["synthesize"]["target"]
    solve = 0.0
    t0 = time.perf_counter()
    for values in sample(spec):
        design = camopt.Design.load(spec.design)
        design.set(spec.parameters[0].key, float(values[0])).set(spec.parameters[1].key, float(values[1]))
        made = camopt.synthesize(target, design)
        solve += camopt.dynamics(made.design, rpm="3000:7000:3").summary["run_time_s"]
    return time.perf_counter() - t0, solve


def best(repeat, run):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - t0)
    return min(times), result


def table(result):
    return [(r.index, r.values, r.responses, r.status, r.error) for r in result.points]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--points", type=int, default=16)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    spec = study_spec(args.points)
    n = args.points
    rows = []
    api_s, rigid_solve_s = min((direct(spec) for _ in range(args.repeat)), key=lambda x: x[0])
    rows.append(("API calls, no study layer", api_s, None))
    serial_s, serial = best(args.repeat, lambda: camopt.study(spec, workers=1))
    assert all(r.status == "ok" for r in serial.points), [r.error for r in serial.points if r.status != "ok"]
    rows.append(("study, in process (workers 1)", serial_s, serial))
    local_s, local = best(args.repeat, lambda: camopt.study(spec, workers=2))
    rows.append(("study, 2 local processes", local_s, local))
    import distributed

    for workers in (1, 2):
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                      dashboard_address=None) as cluster, distributed.Client(cluster) as client:
            camopt.study(spec, client=client)  # workers import camopt once
            s, r = best(args.repeat, lambda: camopt.study(spec, client=client))
            rows.append((f"study, Dask {workers} worker{'s' if workers > 1 else ''}", s, r))
    print(f"{n} points, synthesis + rigid dynamics at 3 speeds, best of {args.repeat}")
    print(f"{'run':38} {'s':>8} {'points/s':>9} {'ms/point':>9}  table")
    for name, seconds, result in rows:
        same = "" if result is None else ("= serial" if table(result) == table(serial) else "DIFFERS")
        print(f"{name:38} {seconds:8.3f} {n / seconds:9.2f} {1e3 * seconds / n:9.2f}  {same}")
    print(f"rigid job's own solve time (summary run_time_s): {1e3 * rigid_solve_s / n:.2f} ms/point")
    print(f"study layer over the API calls: {1e3 * (serial_s - api_s) / n:+.2f} ms/point")
    dask1 = next(s for name, s, _ in rows if name == "study, Dask 1 worker")
    print(f"Dask (1 worker) over the in-process study: {1e3 * (dask1 - serial_s) / n:+.2f} ms/point")


if __name__ == "__main__":
    main()
