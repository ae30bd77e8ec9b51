#!/usr/bin/env python3
"""Generate the cam / swing-cam / lever profile tables of designs/ and print the
assembly coordinates that the design files quote.

usage: python3 scripts/make_profiles.py [--check]

Plain python 3 (no numpy). Writes designs/profiles/*.csv (header angle_deg,radius_mm,
1 deg rows, 360 of them) and prints, per design, the drawing coordinates pasted into
designs/*.toml. --check only prints (writes nothing).

Conventions (docs/design-format.md): every coordinate is the drawing (all nodes at zero
displacement) in mm, angles counter-clockwise positive; a polar table is r(psi) in the
profile's own frame, placed with origin_mm / orientation_deg.
"""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROFILES = os.path.join(ROOT, "designs", "profiles")
EHL_LIFT = os.path.join(os.path.dirname(ROOT), "shared", "data", "real", "ehl_cam_tappet_asfand",
                        "CamAngle_vs_Lift_smooth.csv")
CHECK_ONLY = "--check" in sys.argv
DEG = math.pi / 180.0


# ---------------------------------------------------------------- small helpers
def write_polar(name, comment_lines, radius):
    """radius: 360 values at 0..359 deg [mm]."""
    assert len(radius) == 360
    path = os.path.join(PROFILES, name)
    if CHECK_ONLY:
        return path
    os.makedirs(PROFILES, exist_ok=True)
    with open(path, "w") as f:
        for line in comment_lines:
            f.write("# " + line + "\n")
        f.write("angle_deg,radius_mm\n")
        for i, r in enumerate(radius):
            f.write("%d,%.6f\n" % (i, r))
    return path


def solve_linear(a, b):
    """gaussian elimination with partial pivoting (small dense systems)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for i in range(n):
        p = max(range(i, n), key=lambda k: abs(m[k][i]))
        m[i], m[p] = m[p], m[i]
        for k in range(n):
            if k != i:
                f = m[k][i] / m[i][i]
                for j in range(i, n + 1):
                    m[k][j] -= f * m[i][j]
    return [m[i][n] / m[i][i] for i in range(n)]


def quintic_hermite(x0, y0, x1, y1):
    """polynomial on [x0, x1] with value, 1st and 2nd derivative y0 = (f, f', f'') at x0
    and y1 at x1; returns f(x) -> (f, f', f'')."""
    h = x1 - x0
    # in t = (x - x0) / h: f = sum c_k t^k, derivatives scaled by h
    rows, rhs = [], []
    for t, (f, f1, f2) in ((0.0, y0), (1.0, y1)):
        rows.append([t ** k for k in range(6)])
        rhs.append(f)
        rows.append([k * t ** (k - 1) if k >= 1 else 0.0 for k in range(6)])
        rhs.append(f1 * h)
        rows.append([k * (k - 1) * t ** (k - 2) if k >= 2 else 0.0 for k in range(6)])
        rhs.append(f2 * h * h)
    c = solve_linear(rows, rhs)

    def f(x):
        t = (x - x0) / h
        v = sum(c[k] * t ** k for k in range(6))
        d1 = sum(k * c[k] * t ** (k - 1) for k in range(1, 6)) / h
        d2 = sum(k * (k - 1) * c[k] * t ** (k - 2) for k in range(2, 6)) / (h * h)
        return v, d1, d2
    return f


class NaturalCubicSpline:
    """C2 interpolant through (x, y); evaluates value, 1st and 2nd derivative."""

    def __init__(self, x, y):
        n = len(x)
        self.x, self.y = x, y
        h = [x[i + 1] - x[i] for i in range(n - 1)]
        # tridiagonal system for the second derivatives m (natural: m0 = mn = 0)
        a = [0.0] * n
        b = [1.0] * n
        c = [0.0] * n
        d = [0.0] * n
        for i in range(1, n - 1):
            a[i] = h[i - 1]
            b[i] = 2 * (h[i - 1] + h[i])
            c[i] = h[i]
            d[i] = 6 * ((y[i + 1] - y[i]) / h[i] - (y[i] - y[i - 1]) / h[i - 1])
        for i in range(1, n):
            w = a[i] / b[i - 1]
            b[i] -= w * c[i - 1]
            d[i] -= w * d[i - 1]
        m = [0.0] * n
        m[-1] = d[-1] / b[-1]
        for i in range(n - 2, -1, -1):
            m[i] = (d[i] - c[i] * m[i + 1]) / b[i]
        self.m, self.h = m, h

    def __call__(self, t):
        x, y, m, h = self.x, self.y, self.m, self.h
        lo, hi = 0, len(x) - 2
        while lo < hi:  # interval search
            mid = (lo + hi + 1) // 2
            if x[mid] <= t:
                lo = mid
            else:
                hi = mid - 1
        i = lo
        hh = h[i]
        u, v = x[i + 1] - t, t - x[i]
        f = (m[i] * u ** 3 + m[i + 1] * v ** 3) / (6 * hh) + (y[i] / hh - m[i] * hh / 6) * u + \
            (y[i + 1] / hh - m[i + 1] * hh / 6) * v
        f1 = (-m[i] * u ** 2 + m[i + 1] * v ** 2) / (2 * hh) - (y[i] / hh - m[i] * hh / 6) + \
            (y[i + 1] / hh - m[i + 1] * hh / 6)
        f2 = (m[i] * u + m[i + 1] * v) / hh
        return f, f1, f2


def polar_table_from_points(points):
    """points: (x, y, dx, dy) of a closed convex-ish curve around the origin, any order
    and density, with the curve tangent (dx, dy); returns r at 0..359 deg by cubic
    hermite interpolation in the polar angle (exact r and dr/dpsi at every sample)."""
    samples = []
    for x, y, dx, dy in points:
        r = math.hypot(x, y)
        psi = math.degrees(math.atan2(y, x)) % 360.0
        cross = x * dy - y * dx  # r^2 dpsi/dt
        dot = x * dx + y * dy    # r dr/dt
        drdpsi = r * dot / cross  # [mm/rad]
        samples.append((psi, r, drdpsi))
    samples.sort()
    ext = [(p - 360.0, r, d) for p, r, d in samples[-3:]] + samples + \
        [(p + 360.0, r, d) for p, r, d in samples[:3]]
    out = []
    j = 0
    for k in range(360):
        while ext[j + 1][0] < k:
            j += 1
        (p0, r0, d0), (p1, r1, d1) = ext[j], ext[j + 1]
        h = (p1 - p0) * DEG
        t = (k - p0) * DEG / h
        h00, h10 = 2 * t ** 3 - 3 * t ** 2 + 1, t ** 3 - 2 * t ** 2 + t
        h01, h11 = -2 * t ** 3 + 3 * t ** 2, t ** 3 - t ** 2
        out.append(h00 * r0 + h10 * h * d0 + h01 * r1 + h11 * h * d1)
    return out


def polar_curvature_radius(r, step_deg=1.0):
    """radius of curvature [mm] of a periodic polar table at each row (finite
    differences; > 0 convex, < 0 concave)."""
    n = len(r)
    h = step_deg * DEG
    out = []
    for i in range(n):
        r0, rm, rp = r[i], r[i - 1], r[(i + 1) % n]
        r1 = (rp - rm) / (2 * h)
        r2 = (rp - 2 * r0 + rm) / (h * h)
        den = r0 * r0 + 2 * r1 * r1 - r0 * r2
        out.append((r0 * r0 + r1 * r1) ** 1.5 / den if den != 0 else float("inf"))
    return out


def bump_coefficients(powers=(2, 10, 14, 18)):
    """symmetric polynomial bump s(x) = 1 + sum c_k x^p_k on |x| <= 1 with s(1) = s'(1) =
    s''(1) = s'''(1) = 0 (a 'polydyne'-type lift law: C3 into the dwell, negative
    acceleration over the whole nose)."""
    rows, rhs = [], []
    for der in range(4):
        row = []
        for p in powers:
            c = 1.0
            for k in range(der):
                c *= (p - k)
            row.append(c)
        rows.append(row)
        rhs.append(-1.0 if der == 0 else 0.0)
    return list(zip(solve_linear(rows, rhs), powers))


def bump(x, coeffs):
    """value of the polynomial bump at x (0 outside |x| < 1)."""
    if abs(x) >= 1.0:
        return 0.0
    return 1.0 + sum(c * x ** p for c, p in coeffs)


def smoothstep7(x):
    """0 -> 1 on [0, 1] with zero 1st..3rd derivatives at both ends."""
    if x <= 0:
        return 0.0
    if x >= 1:
        return 1.0
    return x ** 4 * (35 - 84 * x + 70 * x * x - 20 * x ** 3)


def rot(p, a_deg, about=(0.0, 0.0)):
    c, s = math.cos(a_deg * DEG), math.sin(a_deg * DEG)
    x, y = p[0] - about[0], p[1] - about[1]
    return (about[0] + c * x - s * y, about[1] + s * x + c * y)


def fmt(p):
    return "[%.4f, %.4f]" % (p[0], p[1])


def circle_intersection(c0, r0, c1, r1, pick_near):
    """intersection of two circles nearest to pick_near."""
    dx, dy = c1[0] - c0[0], c1[1] - c0[1]
    d = math.hypot(dx, dy)
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(max(0.0, r0 * r0 - a * a))
    mx, my = c0[0] + a * dx / d, c0[1] + a * dy / d
    p1 = (mx + h * dy / d, my - h * dx / d)
    p2 = (mx - h * dy / d, my + h * dx / d)
    d1 = math.hypot(p1[0] - pick_near[0], p1[1] - pick_near[1])
    d2 = math.hypot(p2[0] - pick_near[0], p2[1] - pick_near[1])
    return p1 if d1 <= d2 else p2


# ---------------------------------------------------------------- radial lobes
def radial_lobe(base_radius, lift, half_width_deg, nose_deg=180.0, powers=(2, 10, 14, 18)):
    """r(phi) = rb + h(phi): a *radial* lift table, not a synthesized profile (the follower
    lift of a roller or a lever differs from h). h is the polynomial bump of
    bump_coefficients, nose at nose_deg, zero outside nose +- half_width."""
    co = bump_coefficients(powers)
    out = []
    for k in range(360):
        d = (k - nose_deg + 180.0) % 360.0 - 180.0
        out.append(base_radius + lift * bump(d / half_width_deg, co))
    return out


def report_table(name, r):
    rho = polar_curvature_radius(r)
    conv = [x for x in rho if x > 0]
    conc = [x for x in rho if x < 0]
    print("  %s: base %.4f mm, max %.4f mm, min convex radius of curvature %.3f mm%s" % (
        name, min(r), max(r), min(conv),
        (", min concave radius %.2f mm" % max(conc)) if conc else ", convex everywhere"))


# ---------------------------------------------------------------- bucket tappet lobe
def bucket_tappet_lobe():
    """exact flat-faced-follower cam for the EHL tappet lift (cam deg, 0.5 deg steps,
    -84..+80, max 7.44 mm; rb = 18.5 mm). Source angle -> cam angle + 180, so the cam is
    on its base circle at cam 0 and the nose meets the tappet at ~180 deg."""
    rows = []
    with open(EHL_LIFT) as f:
        next(f)
        for line in f:
            a, s = line.split(",")
            rows.append((float(a), float(s)))
    x = [a for a, _ in rows]
    y = [s for _, s in rows]
    spl = NaturalCubicSpline(x, y)
    rad = 180.0 / math.pi  # per deg -> per rad factors
    # join points: the raw table starts with a velocity step (0.0074 mm/deg at 0.0004 mm)
    # and ends on a slow tail (0.094 mm at +80); quintic ramps take both to zero lift with
    # zero velocity and acceleration (lift in mm, angles in deg)
    j_open, j_close = -82.0, 78.0
    open_len, close_len = 4.0, 30.0
    ramp_open = quintic_hermite(j_open - open_len, (0.0, 0.0, 0.0), j_open, spl(j_open))
    ramp_close = quintic_hermite(j_close, spl(j_close), j_close + close_len, (0.0, 0.0, 0.0))

    def lift(a):  # source angle [deg] -> (s, ds/da, d2s/da2) [mm, mm/deg, mm/deg^2]
        if a <= j_open - open_len or a >= j_close + close_len:
            return 0.0, 0.0, 0.0
        if a < j_open:
            return ramp_open(a)
        if a > j_close:
            return ramp_close(a)
        return spl(a)

    rb = 18.5
    pts = []
    min_rho, min_rho_at, max_offset = 1e9, 0, 0.0
    n = 7200  # 0.05 deg
    for i in range(n):
        th = 360.0 * i / n  # cam angle [deg]
        s, s1, s2 = lift(th - 180.0)
        s1 *= rad        # [mm/rad]
        s2 *= rad * rad  # [mm/rad^2]
        t = th * DEG
        # envelope of the face y = rb + s (tappet above the cam, cam turning ccw):
        # contact at offset s' along the face; rho = rb + s + s'' (Rothbart, Cam Design
        # Handbook, ch. 5, flat-faced translating follower)
        px = (rb + s) * math.sin(t) + s1 * math.cos(t)
        py = (rb + s) * math.cos(t) - s1 * math.sin(t)
        rho = rb + s + s2
        dx, dy = rho * math.cos(t), -rho * math.sin(t)
        # profile frame: 0 deg axis towards the tappet (drawing: orientation_deg = 90)
        pts.append((py, -px, dy, -dx))
        if rho < min_rho:
            min_rho, min_rho_at = rho, th
        max_offset = max(max_offset, abs(s1))
    assert min_rho > 0, "flat-follower cam is not convex"
    r = polar_table_from_points(pts)
    # check: lift reproduced by the table (support function of the tabulated curve)
    peak = max(lift(a / 10.0)[0] for a in range(-900, 900))
    print("bucket_tappet: source peak lift %.4f mm, min rho (envelope) %.3f mm at cam %.2f deg, "
          "max contact offset on the face %.3f mm" % (peak, min_rho, min_rho_at, max_offset))
    print("  ramps: opening quintic %.1f..%.1f src deg, closing quintic %.1f..%.1f src deg" % (
        j_open - open_len, j_open, j_close, j_close + close_len))
    report_table("bucket_lobe.csv", r)
    write_polar("bucket_lobe.csv", [
        "exact cam profile for a direct-acting flat (bucket) tappet, envelope of the face",
        "(x = (rb+s) sin t + s' cos t, y = (rb+s) cos t - s' sin t; scripts/make_profiles.py)",
        "lift s: ehl_cam_tappet_asfand/CamAngle_vs_Lift_smooth.csv (cam deg, max 7.4436 mm),",
        "cam angle = source angle + 180 deg, quintic ramps to zero lift at %.0f and %.0f cam deg;" % (
            180 + j_open - open_len, 180 + j_close + close_len),
        "rb = 18.5 mm; polar angle [deg] in the profile frame (0 deg axis towards the tappet at",
        "cam angle 0, ccw), radius [mm]; 1 deg rows",
    ], r)
    return r


# ---------------------------------------------------------------- textbook mechanisms
def textbook_coordinates():
    print("eccentric_offset_roller: disc R 20, e 4, roller r 8, offset 3 mm (follower line x = 3)")
    # lowest follower position: disc centre on the line pivot -> roller centre, so the
    # roller centre sits at (R - e) + r = 24 mm from the cam pivot on the line x = 3
    yc = math.sqrt(24.0 ** 2 - 3.0 ** 2)
    print("  roller centre at rest %s, eccentric axis orientation_deg %.4f" % (
        fmt((3.0, yc)), math.degrees(math.atan2(-yc, -3.0))))
    print("eccentric_oscillating_roller: roller centre (0, 24), arm pivot (-40, 24)")
    print("four_bar: ground 60, crank 20, coupler 70, rocker 50 (Grashof: 20 + 70 <= 50 + 60)")
    # drawing at the rocker's limit with crank and coupler stretched in line: B at 90 mm from
    # the crank pivot and 50 mm from the rocker pivot (60, 0)
    b = circle_intersection((0.0, 0.0), 90.0, (60.0, 0.0), 50.0, (70.0, 50.0))
    a = (b[0] * 20.0 / 90.0, b[1] * 20.0 / 90.0)
    print("  crank pin %s, rocker pin %s (stretched limit; folded limit B = (30, 40))" % (fmt(a), fmt(b)))
    print("offset_slider_crank: crank 20, rod 70, slide line x = 10 (offset 10)")
    ys = math.sqrt(50.0 ** 2 - 10.0 ** 2)  # bottom dead centre: crank folded under the rod
    pin = (-20.0 * 10.0 / 50.0, -20.0 * ys / 50.0)
    print("  crank pin at BDC %s, slider pin %s, stroke %.4f mm" % (
        fmt(pin), fmt((10.0, ys)), math.sqrt(90.0 ** 2 - 100) - ys))


# ---------------------------------------------------------------- finger / rocker lobes
def rff_and_rocker():
    rff = radial_lobe(18.0, 4.6, 62.0)
    print("roller_finger_follower: lobe rb 18, radial lift 4.6 mm over +-62 deg (nose at 180)")
    report_table("rff_lobe.csv", rff)
    write_polar("rff_lobe.csv", [
        "radial cam lobe for designs/roller_finger_follower.toml: r = rb + h(phi), NOT a profile",
        "synthesized for the roller (scripts/make_profiles.py radial_lobe). rb = 18 mm, h = 4.6 mm",
        "polydyne-type bump 1 - 1.641 x^2 + 1.969 x^10 - 1.875 x^14 + 0.547 x^18, x = (phi - 180)/62,",
        "zero for |x| >= 1 (C3 into the base circle). polar angle [deg] (0 = base circle, ccw), radius [mm]",
    ], rff)
    rocker = radial_lobe(17.0, 6.0, 64.0)
    print("rocker_arm: lobe rb 17, radial lift 6.0 mm over +-64 deg (nose at 180)")
    report_table("rocker_lobe.csv", rocker)
    write_polar("rocker_lobe.csv", [
        "radial cam lobe for designs/rocker_arm.toml: r = rb + h(phi), NOT a synthesized profile",
        "(scripts/make_profiles.py radial_lobe). rb = 17 mm, h = 6.0 mm polydyne-type bump",
        "1 - 1.641 x^2 + 1.969 x^10 - 1.875 x^14 + 0.547 x^18, x = (phi - 180)/64, zero for |x| >= 1.",
        "polar angle [deg] (0 = base circle, ccw), radius [mm]",
    ], rocker)


# ---------------------------------------------------------------- swing cams
def smooth_box(u, lo, hi, w):
    """1 on [lo + w, hi - w], 0 outside [lo, hi], C3 smoothstep edges of width w."""
    return smoothstep7((u - lo) / w) * smoothstep7((hi - u) / w)


def swing_lobe(dwell_radius, slope, accel, onset, decel_start, peak, ramp_start_deg=0.0, nose_w=4.0):
    """swing-cam (output cam) or lever working-curve lift g(u) added to a dwell curve, u [deg]
    measured from the ramp start towards DECREASING polar angle (the side that a ccw swing
    brings to the follower). The ramp acceleration d2g/du2 is a smooth box of height accel
    [mm/deg^2] from u = 0 (C3 onset over `onset` deg) until the slope reaches `slope`
    [mm/deg]; the slope then stays constant (the working range), and a second smooth box from
    decel_start to peak brings it back to zero at the nose (u = peak); the lobe falls back
    symmetrically (that side never meets the follower). A near-constant acceleration start
    gives the most lift for a given concave radius at the ramp foot (it must stay well above
    the follower-roller radius). Returns (360 radii at 0..359 deg, g)."""
    n = 20  # integration steps per degree
    u1 = slope / accel + onset
    decel = slope / ((peak - decel_start) - nose_w)
    g, v = [0.0], 0.0
    for i in range(int(round(peak * n))):
        u = (i + 0.5) / n
        a = accel * smooth_box(u, 0.0, u1, onset) - decel * smooth_box(u, decel_start, peak, nose_w)
        v_new = v + a / n
        g.append(g[-1] + 0.5 * (v + v_new) / n)
        v = v_new

    def lift(u):
        if u <= 0 or u >= 2 * peak:
            return 0.0
        if u > peak:
            u = 2 * peak - u
        k = u * n
        i = min(int(k), len(g) - 2)
        return g[i] + (g[i + 1] - g[i]) * (k - i)

    if callable(dwell_radius):
        base = dwell_radius
    else:
        base = lambda k: dwell_radius  # noqa: E731
    r = []
    for k in range(360):
        u = (ramp_start_deg - k) % 360.0
        r.append(base(k) + lift(u))
    return r, lift


def add(p, q, s=1.0):
    return (p[0] + s * q[0], p[1] + s * q[1])


def angle_of(v):
    return math.degrees(math.atan2(v[1], v[0]))


def cvvl(write=True, **kw):
    """Delphi-type swing-cam CVVL (SAE 2010-01-1193 fig. 9). Built in a frame centred on
    the finger-roller centre F, then shifted so the camshaft sits at the origin."""
    p = dict(r_f=8.0, dwell=28.0, arm=15.0, arm_dir=177.0, r_i=9.0, rb_c=19.0, tau=-13.0, lift_c=7.0,
             half_c=84.0, eps=1.0, slope=0.27, accel=0.025, onset=3.0, decel_start=32.0, peak=44.0,
             hla=(-25.0, -6.7), tip=(20.0, -8.0), pad_r=10.0)
    p.update(kw)
    F = (0.0, 0.0)
    Ps = (0.0, p["dwell"] + p["r_f"])
    I = add(Ps, (math.cos(p["arm_dir"] * DEG), math.sin(p["arm_dir"] * DEG)), p["arm"])
    t = p["tau"] * DEG
    C = add(I, (math.sin(t), math.cos(t)), p["rb_c"] + p["r_i"])
    H = add(F, p["hla"])
    V = add(F, p["tip"])
    pad = add(V, (0.0, p["pad_r"]))
    shift = (-C[0], -C[1])
    pts = {k: add(v, shift) for k, v in dict(C=C, Ps=Ps, I=I, F=F, H=H, V=V, pad=pad).items()}
    # rest swing angle against the control (pivot on the arc about F): the intermediate
    # roller stays on the input cam's base circle
    rest = []
    for g_deg in range(0, 17, 2):
        Psg = rot(Ps, g_deg, F)
        Ig = circle_intersection(Psg, p["arm"], C, p["rb_c"] + p["r_i"], rot(I, g_deg, F))
        d = angle_of((Ig[0] - Psg[0], Ig[1] - Psg[1])) - angle_of((I[0] - Ps[0], I[1] - Ps[1]))
        d = (d + 180.0) % 360.0 - 180.0
        rest.append((g_deg, d, g_deg - d))
    lobe_c = radial_lobe(p["rb_c"], p["lift_c"], p["half_c"])
    swing, g = swing_lobe(p["dwell"], p["slope"], p["accel"], p["onset"], p["decel_start"], p["peak"])
    orient_c = angle_of((I[0] - C[0], I[1] - C[1]))
    orient_s = -90.0 - p["eps"]
    print("cvvl: drawing coordinates (camshaft at the origin)")
    for k, v in pts.items():
        print("  %-4s %s" % (k, fmt(v)))
    print("  input lobe orientation_deg %.4f, swing profile orientation_deg %.4f" % (orient_c, orient_s))
    print("  |C - Ps| = %.3f mm" % math.hypot(C[0] - Ps[0], C[1] - Ps[1]))
    for g_deg, d, pre in rest:
        print("  control %2d deg: swing rest angle %+7.3f deg, dwell travel before the ramp %.2f deg" % (
            g_deg, d, pre + p["eps"]))
    print("  swing ramp g(u): " + ", ".join("%d:%.3f" % (u, g(u)) for u in (5, 10, 15, 20, 25, 30, 35, 40)))
    report_table("cvvl_input_lobe.csv", lobe_c)
    report_table("cvvl_swing_cam.csv", swing)
    if write:
        write_polar("cvvl_input_lobe.csv", [
            "input (rotational) cam of designs/cvvl_swing_cam.toml: radial lift table r = rb + h(phi)",
            "(scripts/make_profiles.py radial_lobe): rb = %g mm, h = %g mm polydyne-type bump over" % (
                p["rb_c"], p["lift_c"]),
            "+-%g deg around 180 deg. polar angle [deg] (0 = base circle, ccw), radius [mm]" % p["half_c"],
        ], lobe_c)
        write_polar("cvvl_swing_cam.csv", [
            "swing (output) cam of designs/cvvl_swing_cam.toml, polar about the swing-cam pivot",
            "(scripts/make_profiles.py swing_lobe): dwell arc r = %g mm centred on the pivot; lift ramp" % p["dwell"],
            "from 0 deg towards decreasing polar angle: acceleration %g mm/deg^2 (C3 onset over %g deg)" % (
                p["accel"], p["onset"]),
            "up to a slope of %g mm/deg, held to %g deg, nose at -%g deg, mirrored back to the dwell" % (
                p["slope"], p["decel_start"], p["peak"]),
            "(that side never meets the roller).",
            "polar angle [deg] (0 = ramp start, ccw), radius [mm]",
        ], swing)
    return p, pts, orient_c, orient_s


def vvld(write=True, **kw):
    """VVLD-type mechanism (SAE 2010-01-1193 fig. 22): input cam -> swing cam (fixed pivot,
    roller on the input cam) -> pad on the swing cam pushes the roller of an oscillating
    control arm -> the control arm's working curve (idle arc + ramp) drives the roller of an
    end-pivot rocker -> valve. The arm's pivot Q is carried on an arc guide centred on the
    resting rocker-roller centre Rr, turned by the control shaft (gain deg per control deg),
    and the idle arc is concentric with Q: the resting roller stays put at every control
    position and during the idle travel (the arm turns about Q)."""
    p = dict(arm=15.0, arm_dir=177.0, r_i=9.0, rb_c=19.0, tau=-13.0, lift_c=7.0, half_c=84.0,
             sw_pad_r=10.0, sw_pad_arm=12.0, sw_pad_dir=-60.0, r_c=7.0, push_dir=30.0, ca_arm=12.0,
             gain=-0.14, ctrl_max=100.0, r_r=8.0, idle_r=24.0,
             eps=1.0, slope=0.27, accel=0.025, onset=3.0, decel_start=32.0, peak=44.0,
             hla=(25.0, -3.0), tip=(-20.0, -8.0), pad_r=10.0)
    p.update(kw)
    # input cam and swing cam as in cvvl (camshaft at the origin)
    S = (0.0, 0.0)
    I = add(S, (math.cos(p["arm_dir"] * DEG), math.sin(p["arm_dir"] * DEG)), p["arm"])
    t = p["tau"] * DEG
    C = add(I, (math.sin(t), math.cos(t)), p["rb_c"] + p["r_i"])
    Psw = add(S, (math.cos(p["sw_pad_dir"] * DEG), math.sin(p["sw_pad_dir"] * DEG)), p["sw_pad_arm"])
    pd = (math.cos(p["push_dir"] * DEG), math.sin(p["push_dir"] * DEG))
    Rc = add(Psw, pd, p["sw_pad_r"] + p["r_c"])
    Q = add(Rc, (-pd[1], pd[0]), p["ca_arm"])  # control-arm pivot: roller path along push_dir
    Rr = add(Q, (0.0, -1.0), p["idle_r"] + p["r_r"])
    H = add(Rr, p["hla"])
    V = add(Rr, p["tip"])
    pad = add(V, (0.0, p["pad_r"]))
    shift = (-C[0], -C[1])
    pts = {k: add(v, shift) for k, v in dict(C=C, S=S, I=I, Psw=Psw, Rc=Rc, Q=Q, Rr=Rr, H=H, V=V,
                                               pad=pad).items()}
    psi0 = angle_of((Rr[0] - Q[0], Rr[1] - Q[1]))  # rest contact at control 0 [deg, arm frame]
    ramp_start = psi0 - p["eps"]
    table, g_of_u = swing_lobe(p["idle_r"], p["slope"], p["accel"], p["onset"], p["decel_start"], p["peak"],
                               ramp_start_deg=ramp_start % 360.0)
    lobe_c = radial_lobe(p["rb_c"], p["lift_c"], p["half_c"])
    orient_c = angle_of((I[0] - C[0], I[1] - C[1]))
    print("vvld: drawing coordinates (camshaft at the origin)")
    for k, v in pts.items():
        print("  %-4s %s" % (k, fmt(v)))
    print("  input lobe orientation_deg %.4f; control-arm profile orientation 0" % orient_c)
    print("  idle arc r %.4f about Q; pivot guide r %.4f about Rr, gain %g deg per control deg" % (
        p["idle_r"], p["idle_r"] + p["r_r"], p["gain"]))
    # rest pose of the arm against the control (swing cam at rest): Q turns about Rr, the
    # arm roller stays on the swing-cam pad; the rest contact sits on the idle arc at the
    # arm-frame polar angle of Rr - Q
    for k in range(0, int(p["ctrl_max"]) + 1, 10):
        Qg = rot(Q, p["gain"] * k, Rr)
        Rcg = circle_intersection(Qg, p["ca_arm"], Psw, p["sw_pad_r"] + p["r_c"], add(Rc, (Qg[0] - Q[0], Qg[1] - Q[1])))
        b = angle_of((Rcg[0] - Qg[0], Rcg[1] - Qg[1])) - angle_of((Rc[0] - Q[0], Rc[1] - Q[1]))
        b = (b + 180.0) % 360.0 - 180.0
        psi = angle_of((Rr[0] - Qg[0], Rr[1] - Qg[1])) - b
        print("  control %5.1f deg: pivot %s, arm rest angle %+7.3f deg, rest contact at psi %.2f, idle travel "
              "%.2f deg" % (k, fmt(add(Qg, shift)), b, psi, (psi - ramp_start + 180.0) % 360.0 - 180.0))
    report_table("vvld_input_lobe.csv", lobe_c)
    report_table("vvld_control_arm.csv", table)
    if write:
        write_polar("vvld_input_lobe.csv", [
            "input (rotational) cam of designs/vvld.toml: radial lift table r = rb + h(phi)",
            "(scripts/make_profiles.py radial_lobe): rb = %g mm, h = %g mm polydyne-type bump over" % (
                p["rb_c"], p["lift_c"]),
            "+-%g deg around 180 deg. polar angle [deg] (0 = base circle, ccw), radius [mm]" % p["half_c"],
        ], lobe_c)
        write_polar("vvld_control_arm.csv", [
            "working curve of the VVLD control arm (designs/vvld.toml), polar about its drawing pivot Q",
            "(profile frame = drawing frame, orientation 0): idle arc r = %g mm concentric with Q; ramp" % p["idle_r"],
            "from %.3f deg towards decreasing polar angle (accel %g mm/deg^2, slope %g mm/deg, nose %g deg)," % (
                ramp_start % 360.0, p["accel"], p["slope"], p["peak"]),
            "mirrored back. scripts/make_profiles.py vvld. polar angle [deg], radius [mm]",
        ], table)
    return p, pts, orient_c


def valvetronic(write=True, **kw):
    """Valvetronic-type: a floating intermediate lever with a roller on the input cam (T_c),
    a roller on an eccentric control shaft (T_t) and a gate roller (G) on a ground arc
    centred on the camshaft; its working curve drives an end-pivot roller finger follower.
    Rest poses (cam on its base circle): cam roller and gate roller both stay on circles
    about the camshaft, so turning the eccentric only turns the lever about the camshaft
    axis; the working curve's idle arc is a circle about the camshaft axis -> zero lift at
    every control position. During the lift the lever turns about the instant centre
    IC = T_t (the gate normal, line C-G, passes through T_t): the lever point on the
    camshaft axis then moves perpendicular to C -> F (F on the line T_t C produced), so
    the idle arc slides past the finger roller without pushing it."""
    p = dict(rb_c=16.0, lift_c=6.0, half_c=80.0, r_c=8.0, gate_dir=60.0, ic_x=24.0, g_dist=30.0, r_g=5.0,
             r_t=6.0, ecc_r=12.0, ecc=9.0, f_dist=44.0, r_f=8.0, eps=1.0, slope=0.5, accel=0.04,
             onset=3.0, decel_start=30.0, peak=42.0, finger=25.0, tip=20.0, pad_r=10.0, d_dir=-90.0)
    p.update(kw)
    C = (0.0, 0.0)
    u = (math.cos(p["gate_dir"] * DEG), math.sin(p["gate_dir"] * DEG))
    Tc = (p["rb_c"] + p["r_c"], 0.0)
    Tt = (p["ic_x"], p["ic_x"] * u[1] / u[0])  # the instant centre, on the line C-G
    G = (p["g_dist"] * u[0], p["g_dist"] * u[1])
    n_t = (math.cos((p["gate_dir"] - 90) * DEG), math.sin((p["gate_dir"] - 90) * DEG))  # cw tangent at T_t
    # eccentric disc centre D beyond T_t (up-right), eccentric shaft centre E so that a ccw
    # turn of the shaft first moves D along the cw tangent (lever turns cw about C)
    dD = (math.cos((p["gate_dir"] + p["d_dir"]) * DEG), math.sin((p["gate_dir"] + p["d_dir"]) * DEG))
    D = add(Tt, dD, p["ecc_r"] + p["r_t"])
    E = add(D, (n_t[1], -n_t[0]), -p["ecc"])  # D - E = ecc * (-n_t rotated): ccw motion along n_t
    F = (-p["f_dist"] * u[0], -p["f_dist"] * u[1])
    w = (-u[0], -u[1])            # push direction on the finger roller (away from C)
    perp = (u[1], -u[0])
    H = add(F, perp, p["finger"])
    V = add(add(F, perp, -p["tip"]), w, 3.0)
    pad = add(V, u, p["pad_r"])
    rho_w = p["f_dist"] - p["r_f"]
    psi_f = angle_of(F) % 360.0
    ramp_start = psi_f - p["eps"]
    table, g = swing_lobe(rho_w, p["slope"], p["accel"], p["onset"], p["decel_start"], p["peak"],
                          ramp_start_deg=ramp_start)
    lobe = radial_lobe(p["rb_c"], p["lift_c"], p["half_c"])
    orient_e = angle_of((D[0] - E[0], D[1] - E[1]))
    # lever rest rotation about C against the eccentric angle
    rt = math.hypot(*Tt)
    print("valvetronic: drawing coordinates (camshaft at the origin)")
    for k, v in dict(C=C, Tc=Tc, Tt=Tt, G=G, D=D, E=E, F=F, H=H, V=V, pad=pad).items():
        print("  %-3s %s" % (k, fmt(v)))
    print("  gate ground circle r %.4f about C; idle arc r %.4f about C; eccentric orientation_deg %.4f" % (
        p["g_dist"] - p["r_g"], rho_w, orient_e))
    print("  valve direction %s, tip normal %s" % (fmt(w), fmt(u)))
    for gdeg in range(0, 181, 30):
        Dg = rot(D, gdeg, E)
        Tg = circle_intersection(C, rt, Dg, p["ecc_r"] + p["r_t"], Tt)
        lam = angle_of(Tg) - angle_of(Tt)
        nx, ny = Dg[0] - Tg[0], Dg[1] - Tg[1]
        print("  eccentric %3d deg: lever rest rotation about C %+7.3f deg, idle travel %.2f deg, eccentric "
              "normal passes %.2f mm from C" % (gdeg, lam, p["eps"] - lam, abs(Tg[0] * ny - Tg[1] * nx) / math.hypot(nx, ny)))
    report_table("valvetronic_lobe.csv", lobe)
    report_table("valvetronic_lever.csv", table)
    if write:
        write_polar("valvetronic_lobe.csv", [
            "input cam of designs/valvetronic.toml: radial lift table r = rb + h(phi)",
            "(scripts/make_profiles.py radial_lobe): rb = %g mm, h = %g mm polydyne-type bump over" % (
                p["rb_c"], p["lift_c"]),
            "+-%g deg around 180 deg. polar angle [deg] (0 = base circle, ccw), radius [mm]" % p["half_c"],
        ], lobe)
        write_polar("valvetronic_lever.csv", [
            "working curve of the Valvetronic-type intermediate lever (designs/valvetronic.toml), polar",
            "about the camshaft axis in the drawing (orientation 0): idle arc r = %g mm about the camshaft" % rho_w,
            "axis, ramp from %.3f deg towards decreasing polar angle (accel %g mm/deg^2, slope %g mm/deg," % (
                ramp_start, p["accel"], p["slope"]),
            "nose %g deg, mirrored back). scripts/make_profiles.py valvetronic. polar angle [deg], radius [mm]" % p[
                "peak"],
        ], table)
    pts = dict(C=C, Tc=Tc, Tt=Tt, G=G, D=D, E=E, F=F, H=H, V=V, pad=pad)
    return p, pts, orient_e, w, u


def main():
    bucket_tappet_lobe()
    rff_and_rocker()
    textbook_coordinates()
    cvvl()
    vvld()
    valvetronic()
    if not CHECK_ONLY:
        print("wrote %s" % PROFILES)


if __name__ == "__main__":
    main()
