"""A long solve releases the GIL (another Python thread runs meanwhile) and stops on Ctrl-C
with KeyboardInterrupt, checked between control positions and between a flexible run's output
points."""

import _thread
import os
import threading
import time

import pytest

import camopt
from conftest import SOURCE_DIR

# the variable valve lift over 300 control positions at 0.25 deg, on one thread: a few
# seconds of solving, one cancellation check per position
LONG = dict(control="0:16:300", step_deg=0.25, outputs="lift", threads=1)


@pytest.fixture(scope="module")
def cvvl():
    os.chdir(SOURCE_DIR)
    return camopt.Design.load("designs/cvvl_swing_cam.toml")


def timed_sweep(design, **options):
    t0 = time.monotonic()
    run = camopt.kinematics(design, **options)
    return run, time.monotonic() - t0


def test_another_python_thread_runs_during_a_long_sweep(cvvl):
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    time.sleep(0.05)
    try:
        t0 = time.monotonic()
        _, seconds = timed_sweep(cvvl, **LONG)
    finally:
        stop.set()
        t.join()
    during = [x for x in ticks if t0 < x < t0 + seconds]
    assert seconds > 0.5
    # the ticker sleeps 1 ms a tick: with the GIL held by the sweep it would make none
    assert len(during) > 50 * seconds, (len(during), seconds)


def seconds_to_interrupt(delay, job):
    """Ctrl-C `delay` seconds into `job()`: the seconds until it raised KeyboardInterrupt."""
    timer = threading.Timer(delay, _thread.interrupt_main)
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        job()
    stopped = time.monotonic() - t0
    timer.join()
    return stopped


def test_ctrl_c_stops_a_long_sweep_between_control_positions(cvvl):
    _, full = timed_sweep(cvvl, **LONG)
    assert full > 1.0
    stopped = seconds_to_interrupt(0.2, lambda: camopt.kinematics(cvvl, **LONG))
    assert stopped < 0.2 + full / 4, (stopped, full)
    # the module is usable after the interrupt
    assert camopt.kinematics(cvvl, step_deg=1.0).summary["positions"][0]["status"] == "ok"


# one flexible run of the variable valve lift from rest at a tight tolerance, over as many
# revolutions as take at least 2 s on this machine (30 take 0.7 s on an idle one, 3 s under
# load): one control position and one speed, so the only checks are the ones between the
# run's output points
FLEXIBLE = dict(model="flexible", rpm=6000, start="rest", rtol=1e-8, atol=1e-9)


def test_ctrl_c_stops_one_long_flexible_run_between_output_points(cvvl):
    revolutions = 30
    while True:
        t0 = time.monotonic()
        full = camopt.dynamics(cvvl, revolutions=revolutions, **FLEXIBLE)
        full_s = time.monotonic() - t0
        assert full.summary["results"][0]["revolutions_integrated"] == revolutions
        if full_s > 2.0 or revolutions >= 960:
            break
        revolutions *= 2
    delay = 0.3
    assert full_s > 4 * delay, (full_s, revolutions)
    stopped = seconds_to_interrupt(delay, lambda: camopt.dynamics(cvvl, revolutions=revolutions, **FLEXIBLE))
    # seen within half a second of the signal, far below the run's own time
    assert stopped < delay + 0.5, (stopped, full_s)
    assert stopped < full_s / 2, (stopped, full_s)
    # the module is usable after the interrupt
    assert camopt.dynamics(cvvl, model="flexible", rpm=3000).summary["model"] == "flexible"
