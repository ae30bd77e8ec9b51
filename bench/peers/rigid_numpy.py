"""Rigid (kinematically driven) forces of a direct-acting valve in vectorised numpy: the peer
that camopt's mode (a) is measured against (bench/peers/run.py).

The valve is designs/eccentric_flat_follower.toml: an eccentric disc (R 20, e 4 mm) under a
centred flat-faced translating follower, so the lift law is exact,
    s = e (1 - cos theta),  s' = e sin theta,  s'' = e cos theta   [mm, mm/rad, mm/rad^2],
the contact sits s' along the face at height rb + s (rb = R - e), and at cam speed w [rad/s]
    contact force  F = P + k s + m s'' w^2 1e-3                       [N]
    cam torque     T = F (s' + mu (rb + s))                           [N mm]
    Hertz (line)   p = sqrt(F/L E* / (pi R)),  b = sqrt(4 F/L R / (pi E*))
    sliding        -(rb + s) w,  entrainment  -(rb + s + 2 s'') w / 2   [mm/s]
    separation     the lowest engine speed with F = 0 somewhere: F is least at theta = 180
                   deg, where w^2 = (P + 2 k e) / (m e 1e-3)
(m = follower + a third of the spring's mass; Johnson, Contact Mechanics, 1985, eq. 4.45 for
the line contact; Rothbart, Cam Design Handbook, ch. 5 for the flat follower).

Two ways to get s, s', s'' at the sweep's angles:
  exact_law:  the closed form above;
  spline_law: a periodic cubic spline of the lift table (the design's lift sampled every 1
              cam deg), differentiated twice: what one does with a measured or exported table.
Everything else is the same vectorised code over (speeds x angles).
"""

import math

import numpy as np
from scipy.interpolate import CubicSpline

# designs/eccentric_flat_follower.toml
VALVE = dict(
    disc_radius_mm=20.0,
    eccentricity_mm=4.0,
    mass_kg=0.10 + 0.01 / 3.0,  # follower + a third of the spring's 10 g
    rate_N_per_mm=10.0,
    preload_N=50.0,
    friction=0.08,
    width_mm=10.0,
    youngs_GPa=210.0,
    poisson=0.3,
    crank_per_cam=2.0,
)


def cam_speed(rpm, crank_per_cam):
    """cam speed [rad/s] at engine speeds [rpm]"""
    return np.asarray(rpm, dtype=float) * (2.0 * math.pi / 60.0) / crank_per_cam


def exact_lift(theta_deg, p=VALVE):
    """s, s', s'' [mm, mm/rad, mm/rad^2] of the eccentric disc under a flat face"""
    t = np.radians(theta_deg)
    e = p["eccentricity_mm"]
    c, s = np.cos(t), np.sin(t)
    return e * (1.0 - c), e * s, e * c


def spline_lift(table_deg, table_mm, theta_deg):
    """s, s', s'' from a periodic cubic spline of a lift table (cam deg -> mm), per rad"""
    spl = CubicSpline(table_deg, table_mm, bc_type="periodic")
    r = 180.0 / math.pi
    return spl(theta_deg), spl(theta_deg, 1) * r, spl(theta_deg, 2) * (r * r)


def forces(s, s1, s2, rpm, p=VALVE):
    """every rigid output over (speeds x angles) from the lift law: a dict of arrays"""
    w = cam_speed(rpm, p["crank_per_cam"])[:, None]
    rb = p["disc_radius_mm"] - p["eccentricity_mm"]
    e_star = p["youngs_GPa"] * 1e3 / (2.0 * (1.0 - p["poisson"] ** 2))  # [MPa]
    spring = p["preload_N"] + p["rate_N_per_mm"] * s
    inertia = p["mass_kg"] * 1e-3 * s2 * (w * w)
    force = spring + inertia
    height = rb + s
    per_length = np.maximum(force, 0.0) / p["width_mm"]
    radius = p["disc_radius_mm"]
    return dict(
        force_N=force,
        hertz_MPa=np.sqrt(per_length * e_star / (math.pi * radius)),
        half_width_mm=np.sqrt(4.0 * per_length * radius / (math.pi * e_star)),
        sliding_m_per_s=-height * w * 1e-3,
        entrainment_m_per_s=-(height + 2.0 * s2) * w * 0.5e-3,
        cam_torque_Nm=force * (s1 + p["friction"] * height) * 1e-3,
        spring_load_N=np.broadcast_to(spring, force.shape),
        guide_N=-p["friction"] * force,
        inertia_N=-inertia,
    )


def exact_law(theta_deg, rpm, p=VALVE):
    """the forces from the exact lift law"""
    return forces(*exact_lift(theta_deg, p), rpm, p)


def spline_law(table_deg, table_mm, theta_deg, rpm, p=VALVE):
    """the forces from a spline of the lift table"""
    return forces(*spline_lift(table_deg, table_mm, theta_deg), rpm, p)


def separation_rpm(p=VALVE):
    """the exact separation speed [engine rpm]: F = 0 first at theta = 180 deg"""
    e = p["eccentricity_mm"]
    w2 = (p["preload_N"] + 2.0 * p["rate_N_per_mm"] * e) / (p["mass_kg"] * 1e-3 * e)
    return math.sqrt(w2) * p["crank_per_cam"] * 60.0 / (2.0 * math.pi)


def separation_rpm_grid(s, s2, p=VALVE):
    """the separation speed a vectorised script gets from its grid: the least root of
    F(theta_i, w) = 0 over the grid points"""
    with np.errstate(divide="ignore", invalid="ignore"):
        w2 = (p["preload_N"] + p["rate_N_per_mm"] * s) / (-p["mass_kg"] * 1e-3 * s2)
    w2 = np.where(s2 < 0, w2, np.inf)
    return math.sqrt(np.min(w2)) * p["crank_per_cam"] * 60.0 / (2.0 * math.pi)


# designs/cvvl_swing_cam.toml's valve: the finger's pad pushes it along its axis (the pad's
# friction acts across the axis, on the guide), so the pad force is the valve's own balance
CVVL_VALVE = dict(mass_kg=0.055 + 0.045 / 3.0, rate_N_per_mm=35.0, preload_N=220.0, crank_per_cam=2.0)


def cvvl_pad_force(table_deg, table_mm, theta_deg, rpm, p=CVVL_VALVE):
    """the CVVL's pad-valve contact force [N] over (speeds x angles) from a periodic cubic
    spline of the valve lift table: F = P + k s + m s'' w^2 1e-3 while the valve is off its
    seat, 0 on it (the lash is open, the seat holds the spring)"""
    s, _, s2 = spline_lift(table_deg, table_mm, theta_deg)
    w = cam_speed(rpm, p["crank_per_cam"])[:, None]
    force = p["preload_N"] + p["rate_N_per_mm"] * s + p["mass_kg"] * 1e-3 * s2 * (w * w)
    return np.where(np.interp(theta_deg, table_deg, table_mm) > 0.0, force, 0.0)
