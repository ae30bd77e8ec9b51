"""The single-mass valve of bench/peers/linear_valve.toml integrated with scipy: the peer that
camopt's flexible model is measured against (bench/peers/run.py).

SI inside (m, s, kg, N); x the valve lift, 0 on the seat, + opening (the equations of
tests/oracles/valve_oracle.hpp):
    cam    x_c = e (1 - cos w t),  penetration d_c = x_c - lash - x
    seat   penetration d_s = -x
    a contact carries F = k d + c d' while g = min(d, k d + c d') > 0, else nothing
    valve  m x'' = F_c + F_s - F0 - k_v x - c_v x'
Two ways to integrate it:
  plain:  solve_ivp over the revolution with the switching right-hand side as it is;
  events: the contact modes held fixed between switches, each switch (a root of g) a
          terminal event after which the integration restarts in the new mode: what the
          exact solution does, and the tight reference (DOP853 at rtol 1e-13).
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

# bench/peers/linear_valve.toml in SI
LINEAR_VALVE = dict(
    mass=0.05, eccentricity=4e-3, lash=0.15e-3, preload=250.0, spring_rate=40e3, spring_damping=20.0,
    cam_stiffness=2e8, cam_damping=500.0, seat_stiffness=5e8, seat_damping=1000.0,
)


def cam_speed(engine_rpm, crank_per_cam=2.0):
    return engine_rpm * 2.0 * math.pi / 60.0 / crank_per_cam


def static_start(p=LINEAR_VALVE):
    """on the seat at rest: k_s (-x) = F0 + k_v x"""
    return np.array([-p["preload"] / (p["seat_stiffness"] + p["spring_rate"]), 0.0])


def max_step(w):
    """0.5 cam deg [s]: from the static start the right-hand side is zero until the cam takes
    up the lash, and an unbounded first step jumps over the whole lift"""
    return math.radians(0.5) / w


class Valve:
    def __init__(self, w, p=LINEAR_VALVE):
        self.w, self.p = w, p

    def penetrations(self, t, y):
        p, w = self.p, self.w
        xc = p["eccentricity"] * (1.0 - math.cos(w * t))
        vc = p["eccentricity"] * w * math.sin(w * t)
        return (xc - p["lash"] - y[0], vc - y[1]), (-y[0], -y[1])

    def indicators(self, t, y):
        (dc, rc), (ds, rs) = self.penetrations(t, y)
        p = self.p
        return (min(dc, p["cam_stiffness"] * dc + p["cam_damping"] * rc),
                min(ds, p["seat_stiffness"] * ds + p["seat_damping"] * rs))

    def rhs(self, t, y, mode=None):
        """x', x''; mode (cam, seat) engaged, or None: decided by the indicators"""
        (dc, rc), (ds, rs) = self.penetrations(t, y)
        p = self.p
        if mode is None:
            gc, gs = self.indicators(t, y)
            mode = (gc > 0.0, gs > 0.0)
        f = -p["preload"] - p["spring_rate"] * y[0] - p["spring_damping"] * y[1]
        if mode[0]:
            f += p["cam_stiffness"] * dc + p["cam_damping"] * rc
        if mode[1]:
            f += p["seat_stiffness"] * ds + p["seat_damping"] * rs
        return [y[1], f / p["mass"]]


def plain(w, t_out, method, rtol, atol):
    """the switching right-hand side integrated as it is; lift [mm] at t_out and counters"""
    v = Valve(w)
    sol = solve_ivp(v.rhs, (0.0, t_out[-1]), static_start(), method=method, t_eval=t_out, rtol=rtol,
                    atol=[atol, atol * w], max_step=max_step(w))
    if not sol.success:
        raise RuntimeError(sol.message)
    return dict(lift_mm=sol.y[0] * 1e3, rhs=sol.nfev, events=None)


def past_switch(v, dense, t_event, k, engaged):
    """the root of g is found to a tolerance in t, so g there may still have the old mode's
    sign: step along the old mode's solution (by 1e-15 of the period, doubling) until it has
    the new sign"""
    step = 1e-15 * 2.0 * math.pi / v.w
    for _ in range(60):
        t = t_event + step
        y = dense(t)
        g = v.indicators(t, y)[k]
        if (g < 0.0) if engaged else (g > 0.0):
            return t, y
        step *= 2.0
    raise RuntimeError("no sign change of the contact indicator after the event")


def with_events(w, t_out, method, rtol, atol, t_end=None):
    """contact modes fixed between switches, a terminal event at each switch"""
    v = Valve(w)
    t_end = t_out[-1] if t_end is None else t_end
    t0, y0 = 0.0, static_start()
    g = v.indicators(t0, y0)
    mode = [g[0] > 0.0, g[1] > 0.0]
    lift = np.full(len(t_out), np.nan)
    switches, nfev = [], 0

    def make_event(k):
        def ev(t, y):
            return v.indicators(t, y)[k]
        ev.terminal = True
        ev.direction = -1.0 if mode[k] else 1.0  # engaged: wait for g to fall through 0
        return ev

    while t0 < t_end:
        events = [make_event(0), make_event(1)]
        m = tuple(mode)
        sol = solve_ivp(lambda t, y: v.rhs(t, y, m), (t0, t_end), y0, method=method, rtol=rtol,
                        atol=[atol, atol * w], events=events, dense_output=True, max_step=max_step(w))
        if not sol.success:
            raise RuntimeError(sol.message)
        nfev += sol.nfev
        t1 = sol.t[-1]
        inside = (t_out >= t0) & (t_out <= t1)
        lift[inside] = sol.sol(t_out[inside])[0] * 1e3
        hit = [k for k in (0, 1) if len(sol.t_events[k])]
        if not hit:
            break
        k = min(hit, key=lambda j: sol.t_events[j][0])
        t0, y0 = past_switch(v, sol.sol, sol.t_events[k][0], k, mode[k])
        mode[k] = not mode[k]
        switches.append((t0, k, mode[k], y0[1]))
    return dict(lift_mm=lift, rhs=nfev, events=switches)
