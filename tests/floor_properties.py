"""Properties every run of a top on a floor must have, and random valid runs to check them on.

This module holds no tests; ``test_floor_properties.py`` (a derandomised share, run by
`make test`) and ``fuzz/floor_campaign.py`` (a long campaign in worker processes) use it.

- :func:`random_floor_case` draws one valid run: a :class:`kreisel.PlayTop` of 1 to 4 contact
  parts (spheres, sharp points, spheroids, rounded or sharp rims) or the classic one-sphere
  form, with a body's mass and moments, a friction law, restitution and loss lengths, and a
  start (on the floor, tilted, upside down, lying flat, dropped, thrown, or an explicit
  :class:`kreisel.PlayState`).
- :func:`part_gaps` is the height of each part's lowest point above the floor, computed here
  from the trajectory's ``u`` and the height of G alone (the support function of each part,
  not kreisel's contact code).
- :func:`check_run` lists the violated properties of a finished run; :func:`run_case` runs a
  case; :func:`outcome` sorts a run into ok / refused / violation.

Every reference value here is computed from the geometry and the state columns (orientation,
angular velocity, position and velocity of G), never taken from kreisel's own diagnostics:
the gap from the support function, the energy from the masses and the velocities. kreisel's
``energy`` and ``u`` columns are themselves checked against those.
"""

from __future__ import annotations

import math
import os
import re

import numpy as np

#: a part more than this below the floor (m) has entered it
GAP_TOL = 1e-9
#: a part in contact may be pulled by at most this share of the top's weight (the rounding
#: of a normal force solved where it crosses zero at a located lift-off)
PULL_TOL = 1e-9
#: whether check_run checks (g), the pull (on unless the environment's KREISEL_CHECK_PULL=0)
CHECK_PULL = os.environ.get("KREISEL_CHECK_PULL") != "0"
#: the energy may exceed its start by this fraction of the start's energy scale ...
ENERGY_RTOL = 1e-9
#: ... plus this many times the run's rtol (the integration's own error: DOP853 does not
#: conserve energy exactly; measured on the campaign's marginal cases 2775 and 3795 of seed 1,
#: whose excess scales with rtol: 9.5e-9 at rtol 1e-9, 2.9e-9 at 1e-10, none at 1e-11, while
#: every energy source found so far gave 7e-7 to 6e-4) ...
ENERGY_PER_RTOL = 50.0
#: the rtol of a run that does not set one (kreisel's default)
DEFAULT_RTOL = 1e-10
#: ... plus this (J)
ENERGY_ATOL = 1e-15
#: how a run may end: at t_end, or at a terminal event (rest, or a ring lying flat)
ALLOWED_STATUSES = ("completed", "event")
TERMINAL_EVENTS = ("rest", "flat")
#: the state columns that must be finite in every row
STATE_COLUMNS = ("t", "quaternion", "omega", "com", "com_velocity", "u", "energy", "dissipated")
#: a kreisel error that refuses a run and says what to change: the pace guard and the step
#: cap ("give a shorter t_end"), the stall guard ("give a t_end before the stall")
REFUSAL = re.compile(r"give a (shorter t_end|t_end before the stall)")

TAU = 2.0 * math.pi


# --------------------------------------------------------------------------------------
# geometry: the support function of each part, independent of kreisel
# --------------------------------------------------------------------------------------


def support(part, u, sin_theta=None):
    """``phi(u)``: how far a part's lowest point lies below its centre when the figure axis
    makes ``u = cos(theta)`` with the vertical (the play guide, "Bodies of revolution").

    - sphere of radius r (r = 0: a sharp point): ``r``;
    - spheroid (equatorial a across the axis, axial b along it): the support function of an
      ellipse in the direction -ez, ``sqrt(a^2 (1 - u^2) + b^2 u^2)``;
    - torus (tube centre line of radius R, tube radius r; r = 0 a sharp rim): the rim's
      lowest point is R sin(theta) below the ring's centre and the tube adds r:
      ``R sqrt(1 - u^2) + r``.

    ``u`` is clipped to [-1, 1] (rounding may put it a hair outside). ``sin_theta``, where
    given, is ``sqrt(1 - u^2)`` computed without cancellation (:func:`sin_theta_of_quaternion`):
    near ``u = -1`` or ``1`` a rounding of ``u`` by one ulp moves ``sqrt(1 - u^2)`` by 1.5e-8,
    so a sharp rim of 4 cm lying exactly flat would seem 1e-9 m below the floor.
    """
    u = np.clip(np.asarray(u, dtype=float), -1.0, 1.0)
    s = np.sqrt(1.0 - u * u) if sin_theta is None else np.asarray(sin_theta, dtype=float)
    kind = type(part).__name__
    if kind == "Sphere":
        return np.full_like(u, part.radius)
    if kind == "Spheroid":
        a, b = part.equatorial, part.axial
        return np.sqrt(a * a * s * s + b * b * u * u)
    if kind == "Torus":
        return part.major * s + part.minor
    raise TypeError(f"not a contact part: {part!r}")


def part_gaps(shapes, traj):
    """(n_parts, n_rows): the height of each part's lowest point above the floor,
    ``gap = z_G + z u - phi(u)``, from ``traj.u`` and ``traj.com[:, 2]`` only.

    A part centred at ``z`` on the figure axis (measured from G) has its centre at height
    ``z_G + z u``; its lowest point is ``phi(u)`` lower (:func:`support`). ``shapes`` is
    ``top.shape`` (the classic ``PlayTop(m, A, C, s, rho)`` is ``[Sphere(rho, z=-s)]``).
    """
    u = np.asarray(traj.u, dtype=float)
    zg = np.asarray(traj.com, dtype=float)[:, 2]
    q = getattr(traj, "quaternion", None)
    s = None if q is None else sin_theta_of_quaternion(q)
    return np.array([zg + p.z * u - support(p, u, s) for p in shapes]).reshape(len(shapes), -1)


def sin_theta_of_quaternion(q):
    """``sin(theta)``, the horizontal length of the figure axis e3, from quaternions (w, x, y,
    z), rows of ``q``: the (1, 3) and (2, 3) entries of the rotation matrix, so that a top
    lying exactly flat has 0, not the square root of a rounding of ``1 - u^2``."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = (q[..., k] for k in range(4))
    n = np.sum(q * q, axis=-1)
    return np.hypot(2.0 * (x * z + w * y), 2.0 * (y * z - w * x)) / n


def resting_height(shapes, u):
    """The height of G at which the lowest part touches the floor, at ``u``."""
    return max(float(support(p, u)) - p.z * u for p in shapes)


def u_of_quaternion(q):
    """``u = cos(theta)``, the vertical component of the figure axis e3, from quaternions
    (w, x, y, z), rows of ``q``: the (3, 3) entry of the rotation matrix."""
    q = np.asarray(q, dtype=float)
    n = np.sum(q * q, axis=-1)
    return 1.0 - 2.0 * (q[..., 1] ** 2 + q[..., 2] ** 2) / n


def energy_of(m, A, C, g, omega, com, com_velocity):
    """Kinetic + potential energy (J), from the body angular velocity, the height of G and its
    velocity: ``m |v|^2 / 2 + (A (w1^2 + w2^2) + C w3^2) / 2 + m g z_G``. Vectorised over
    rows."""
    w = np.atleast_2d(np.asarray(omega, dtype=float))
    v = np.atleast_2d(np.asarray(com_velocity, dtype=float))
    z = np.atleast_2d(np.asarray(com, dtype=float))[:, 2]
    rot = 0.5 * (A * (w[:, 0] ** 2 + w[:, 1] ** 2) + C * w[:, 2] ** 2)
    return 0.5 * m * np.sum(v * v, axis=1) + rot + m * g * z


# --------------------------------------------------------------------------------------
# random valid runs
# --------------------------------------------------------------------------------------


def _log_uniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _rate(rng, scale, zero=0.4):
    """A rate (rad/s or m/s): 0 with probability ``zero``, else of random sign and a magnitude
    log-uniform over three decades below ``scale``."""
    if rng.random() < zero:
        return 0.0
    return float(rng.choice([-1.0, 1.0])) * _log_uniform(rng, scale * 1e-3, scale)


def _draw_part(rng, size):
    """One part of characteristic size ``size`` (m), centred at 0 (placed later)."""
    kind = rng.choice(["sphere", "sphere", "spheroid", "torus", "torus"])
    if kind == "sphere":
        r = 0.0 if rng.random() < 0.2 else size * rng.uniform(0.05, 1.0)
        return ["sphere", r, 0.0]
    if kind == "spheroid":
        a, b = size * rng.uniform(0.1, 1.0), size * rng.uniform(0.1, 1.0)
        if rng.random() < 0.1:
            b = a  # a round spheroid: the sphere
        return ["spheroid", a, b, 0.0]
    major = size * rng.uniform(0.2, 1.0)
    minor = 0.0 if rng.random() < 0.4 else major * rng.uniform(0.01, 0.5)
    return ["torus", major, minor, 0.0]


def _axial_half(p):
    """Half the extent of a part along the axis (its tube or semi-axis)."""
    return p[1] if p[0] == "sphere" else p[2]


def _lateral(p):
    """The part's largest distance from the axis."""
    return p[1] + p[2] if p[0] == "torus" else p[1]


def _make_part(p):
    from kreisel.shapes import Sphere, Spheroid, Torus

    if p[0] == "sphere":
        return Sphere(p[1], z=p[2])
    if p[0] == "spheroid":
        return Spheroid(p[1], p[2], z=p[3])
    return Torus(p[1], p[2], z=p[3])


def _hull_margin(parts):
    """min over u of the resting height of G: >= 0 when G lies in the convex hull of the
    parts (every orientation puts G on or above the floor), as a real body's G must."""
    shapes = [_make_part(p) for p in parts]
    us = np.concatenate([np.linspace(-1.0, 1.0, 401), [-1.0, 1.0, 0.0]])
    return min(resting_height(shapes, u) for u in us)


def _inertia(rng, radius, height, m):
    """(A, C, body) of a uniform solid of revolution of the given radius and height (m) and
    mass m, about its centre: a cylinder, a spheroid, a cone, a thin ring, or a thin disk
    (C = 2 A exactly, the flat limit)."""
    body = str(rng.choice(["cylinder", "spheroid", "cone", "ring", "disk"]))
    r, h = radius, height
    if body == "cylinder":
        return m * (3 * r * r + h * h) / 12, m * r * r / 2, body
    if body == "spheroid":
        return m * (r * r + h * h / 4) / 5, 2 * m * r * r / 5, body
    if body == "cone":
        return 3 * m * r * r / 20 + 3 * m * h * h / 80, 3 * m * r * r / 10, body
    if body == "ring":
        return m * r * r / 2 + m * h * h / 12, m * r * r, body
    return m * r * r / 4, m * r * r / 2, body


def _volume(body, r, h):
    if body == "spheroid":
        return 4.0 / 3.0 * math.pi * r * r * max(h, 0.2 * r) / 2
    if body == "cone":
        return math.pi * r * r * max(h, 0.2 * r) / 3
    return math.pi * r * r * max(h, 0.2 * r)


def _draw_top(rng):
    """The top's numbers (plain data): parts or the classic sphere, mass, moments, laws."""
    for _ in range(1000):
        classic = rng.random() < 0.25
        if classic:
            rho = _log_uniform(rng, 2e-3, 3e-2)
            s = 0.0 if rng.random() < 0.1 else rho * rng.uniform(0.0, 0.9)
            parts = [["sphere", rho, -s]]
            radius, height = rho * rng.uniform(0.5, 1.0), 2 * rho * rng.uniform(0.3, 1.0)
        else:
            size = _log_uniform(rng, 2e-3, 5e-2)
            n = int(rng.integers(1, 5))
            raw = [_draw_part(rng, size) for _ in range(n)]
            zs = [size * rng.uniform(-1.0, 1.0) for _ in range(n)]
            if n == 1 or rng.random() < 0.2:
                zs[0] = 0.0
            lo = min(z - _axial_half(p) for z, p in zip(zs, raw))
            hi = max(z + _axial_half(p) for z, p in zip(zs, raw))
            z_g = lo + (hi - lo) * rng.uniform(0.1, 0.9)  # G on the axis inside the hull
            parts = [p[:-1] + [z - z_g] for p, z in zip(raw, zs)]
            radius = max(_lateral(p) for p in parts) * rng.uniform(0.6, 1.0)
            height = (hi - lo) * rng.uniform(0.6, 1.0)
            if max(_lateral(p) for p in parts) < 1e-3 or _hull_margin(parts) < 0.0:
                continue  # a needle, or G outside the body: no rigid body
        density = _log_uniform(rng, 300.0, 20000.0)
        a_, c_, body = _inertia(rng, radius, height, 1.0)
        m = density * _volume(body, radius, height)
        if not 1e-3 <= m <= 3.0:
            continue
        friction = str(
            rng.choice(
                [
                    "Frictionless",
                    "Viscous",
                    "Coulomb",
                    "Coulomb",
                    "CoulombContensou",
                    "CoulombContensou",
                ]
            )
        )
        law = {
            "Frictionless": lambda: ["Frictionless"],
            "Viscous": lambda: ["Viscous", _log_uniform(rng, 1e-2, 5.0)],
            "Coulomb": lambda: ["Coulomb", float(rng.uniform(0.0, 1.0))],
            "CoulombContensou": lambda: [
                "CoulombContensou",
                float(rng.uniform(0.05, 1.0)),
                0.0 if rng.random() < 0.1 else _log_uniform(rng, 1e-5, 1e-3),
            ],
        }[friction]()
        top = {
            "m": m,
            "A": a_ * m,
            "C": c_ * m,
            "body": body,
            "friction": law,
            "restitution": float(rng.choice([0.0, 0.0, 0.95, rng.uniform(0.0, 0.95)])),
            "rolling_resistance": 0.0 if rng.random() < 0.6 else _log_uniform(rng, 1e-5, 2e-3),
            "drilling_resistance": 0.0 if rng.random() < 0.7 else _log_uniform(rng, 1e-5, 2e-3),
        }
        if classic:
            top.update(form="classic", s=-parts[0][2], rho=parts[0][1])
        else:
            top.update(form="parts", parts=parts)
        return top
    raise RuntimeError("no valid top in 1000 draws")


def _draw_state(rng, top):
    """The start (plain data): Euler angles and rates with an optional drop height and
    horizontal velocity, or an explicit PlayState (quaternion, omega, com, com_velocity)."""
    theta = float(
        rng.choice(
            [
                0.0,
                math.pi,
                math.pi / 2,
                rng.uniform(0.0, math.pi),
                rng.uniform(0.0, math.pi),
                _log_uniform(rng, 1e-9, 1e-2),
                math.pi - _log_uniform(rng, 1e-9, 1e-2),
            ]
        )
    )
    drop = float(rng.choice([0.0, _log_uniform(rng, 1e-6, 0.05), rng.uniform(0.0, 0.05)]))
    if rng.random() < 0.8:
        st = {
            "form": "euler",
            "theta": theta,
            "phi": 0.0 if rng.random() < 0.5 else float(rng.uniform(0.0, TAU)),
            "psi": 0.0 if rng.random() < 0.5 else float(rng.uniform(0.0, TAU)),
            "theta_dot": _rate(rng, 30.0, zero=0.6),
            "phi_dot": _rate(rng, 100.0, zero=0.5),
            "psi_dot": _rate(rng, 300.0, zero=0.3),
            "vx": _rate(rng, 1.0, zero=0.7),
            "vy": _rate(rng, 1.0, zero=0.8),
            "height": None if rng.random() < 0.5 else drop,
        }
        return st
    # explicit: a unit quaternion tilting e3 by theta about a horizontal axis (then a turn
    # about e3), G where the lowest part is `drop` above the floor
    phi, psi = float(rng.uniform(0.0, TAU)), float(rng.uniform(0.0, TAU))
    if rng.random() < 0.3:
        phi = psi = 0.0
    q = _quat_zxz(phi, theta, psi)
    u = float(u_of_quaternion(q))
    shapes = [_make_part(p) for p in _parts_of(top)]
    z_g = resting_height(shapes, u) + drop
    omega = [_rate(rng, 100.0, 0.5), _rate(rng, 100.0, 0.5), _rate(rng, 300.0, 0.3)]
    vel = [_rate(rng, 1.0, 0.6), _rate(rng, 1.0, 0.7), _rate(rng, 1.0, 0.5)]
    com = [float(rng.uniform(-0.1, 0.1)) if rng.random() < 0.3 else 0.0, 0.0, z_g]
    return {
        "form": "explicit",
        "quaternion": [float(x) for x in q],
        "omega": omega,
        "com": com,
        "com_velocity": vel,
    }


def _quat_zxz(phi, theta, psi):
    """The quaternion (w, x, y, z) of Rz(phi) Rx(theta) Rz(psi)."""

    def mul(a, b):
        w1, x1, y1, z1 = a
        w2, x2, y2, z2 = b
        return (
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        )

    rz1 = (math.cos(phi / 2), 0.0, 0.0, math.sin(phi / 2))
    rx = (math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0)
    rz2 = (math.cos(psi / 2), 0.0, 0.0, math.sin(psi / 2))
    return np.array(mul(mul(rz1, rx), rz2))


def _parts_of(top):
    if top["form"] == "classic":
        return [["sphere", top["rho"], -top["s"]]]
    return top["parts"]


def random_floor_case(rng):
    """One valid random run (a dict): ``spec`` (plain JSON data: the top and the start),
    ``top`` (a :class:`kreisel.PlayTop`), ``state`` (a :class:`kreisel.PlayState`) and
    ``construction_refusals`` (messages of valid tops kreisel refused on the way, each
    followed by a redraw; see :func:`build`).

    Valid means physically sensible: parts of mm to cm, G inside the convex hull of the
    parts (a body's centre of mass is inside its hull), the moments of a uniform solid of
    revolution of the parts' extent (so A, C > 0 and C <= 2 A, C = 2 A for a thin disk), a
    density between a foam's and tungsten's, and a start on or above the floor.
    """
    import kreisel

    refusals = []
    for _ in range(100):
        spec = {"top": _draw_top(rng)}
        spec["state"] = _draw_state(rng, spec["top"])
        try:
            case = build(spec)
        except kreisel.KreiselError as e:
            refusals.append(f"{type(e).__name__}: {e}")
            continue
        case["construction_refusals"] = refusals
        return case
    raise RuntimeError(f"no case kreisel accepts in 100 draws: {refusals[-3:]}")


def build(spec):
    """The case of a spec: ``{"spec", "top", "state"}`` (kreisel objects built)."""
    import kreisel

    t = spec["top"]
    law = getattr(kreisel, t["friction"][0])(*t["friction"][1:])
    extra = {
        k: t[k] for k in ("restitution", "rolling_resistance", "drilling_resistance") if t[k] != 0.0
    }
    if t["form"] == "classic":
        top = kreisel.PlayTop(t["m"], t["A"], t["C"], s=t["s"], rho=t["rho"], friction=law, **extra)
    else:
        top = kreisel.PlayTop(
            t["m"], t["A"], t["C"], shape=[_make_part(p) for p in t["parts"]], friction=law, **extra
        )
    s = spec["state"]
    if s["form"] == "euler":
        kw = {k: v for k, v in s.items() if k != "form" and v != 0.0 and v is not None}
        kw["theta"] = s["theta"]
        if s["height"] is not None:
            kw["height"] = s["height"]
        state = top.state(**kw)
    else:
        state = kreisel.PlayState(
            *(np.array(s[k], dtype=float) for k in ("quaternion", "omega", "com", "com_velocity"))
        )
    return {"spec": spec, "top": top, "state": state}


def reproducer(spec, t_end, rtol=None):
    """A Python one-liner that builds the case's top and state and runs it."""
    t, s = spec["top"], spec["state"]
    law = f"kreisel.{t['friction'][0]}({', '.join(repr(x) for x in t['friction'][1:])})"
    extra = "".join(
        f", {k}={t[k]!r}"
        for k in ("restitution", "rolling_resistance", "drilling_resistance")
        if t[k] != 0.0
    )
    if t["form"] == "classic":
        top = (
            f"top = kreisel.PlayTop({t['m']!r}, {t['A']!r}, {t['C']!r}, s={t['s']!r}, "
            f"rho={t['rho']!r}, friction={law}{extra})"
        )
    else:
        names = {"sphere": "Sphere", "spheroid": "Spheroid", "torus": "Torus"}
        parts = ", ".join(
            f"{names[p[0]]}({', '.join(repr(x) for x in p[1:-1])}, z={p[-1]!r})" for p in t["parts"]
        )
        top = (
            f"top = kreisel.PlayTop({t['m']!r}, {t['A']!r}, {t['C']!r}, shape=[{parts}], "
            f"friction={law}{extra})"
        )
    if s["form"] == "euler":
        kw = [f"theta={s['theta']!r}"] + [
            f"{k}={s[k]!r}"
            for k in ("phi", "psi", "theta_dot", "phi_dot", "psi_dot", "vx", "vy")
            if s[k] != 0.0
        ]
        if s["height"] is not None:
            kw.append(f"height={s['height']!r}")
        state = f"st = top.state({', '.join(kw)})"
    else:
        state = (
            "st = kreisel.PlayState("
            + ", ".join(
                f"{k}=np.array({s[k]!r})" for k in ("quaternion", "omega", "com", "com_velocity")
            )
            + ")"
        )
    tol = "" if rtol is None else f", rtol={rtol!r}"
    return (
        "import numpy as np, kreisel; from kreisel.shapes import Sphere, Spheroid, Torus; "
        f"{top}; {state}; "
        f"tr = kreisel.simulate(top, st, {t_end!r}, events=[kreisel.events.rest()]{tol})"
    )


# --------------------------------------------------------------------------------------
# running and checking
# --------------------------------------------------------------------------------------


def run_case(case, t_end, rtol=None):
    """Runs a case to ``t_end`` (s), ending early at rest: the Trajectory, or the exception
    it raised (returned, not raised; a Rust panic, a BaseException, too)."""
    import kreisel

    kw = {} if rtol is None else {"rtol": rtol}
    case["t_end"] = t_end
    case["rtol"] = rtol
    try:
        return kreisel.simulate(
            case["top"], case["state"], t_end, events=[kreisel.events.rest()], **kw
        )
    except KeyboardInterrupt:
        raise
    except BaseException as e:  # noqa: BLE001 - PanicException derives from BaseException
        return e


def _where(t, i):
    return f"row {i} (t = {t[i]:.9g} s)"


def check_run(case, traj):
    """The violated properties of a finished run: a list of strings ``"kind: detail"``.

    (a) ``below_floor``: no part's lowest point (:func:`part_gaps`) is ever more than
        ``GAP_TOL`` below the floor. The floor is impenetrable; a part found below it fell
        through (a missed or mishandled contact).
    (b) ``missed_touchdown``: a part that crosses from above the floor to more than
        ``GAP_TOL`` below it between two rows has a ``touchdown`` event of that part in that
        interval; without one the contact was never switched on (the event locator missed
        the crossing). (a) already flags the rows; (b) tells the two defects apart.
    (c) energy: there are no sources of energy (gravity is conservative, the floor only
        takes energy by friction, resistance and inelastic impacts), so with ``E`` the
        energy computed here from the state columns (:func:`energy_of`):
        ``energy_rise``: ``E + dissipated`` never exceeds the start's energy (of the given
        state, computed here) by more than ``ENERGY_RTOL + ENERGY_PER_RTOL * rtol`` of the
        energy scale plus ``ENERGY_ATOL`` (rounding and the integration's error);
        ``energy_step_rise``: ``E`` never rises from one row to the next by more than that;
        ``dissipated_decrease``: ``dissipated`` never falls (a negative dissipation is a
        hidden source); ``start_energy_unaccounted``: the first row's
        ``E + dissipated`` is the given state's energy (a start put on the floor loses its
        velocity into the floor only as recorded dissipation).
    (d) ``nonfinite``: every state column is finite in every row; ``column_mismatch``:
        kreisel's ``u`` and ``energy`` columns agree with those computed here from the
        quaternion and the velocities (the checks above use the independent ones);
        ``time``: the times never decrease and start at 0.
    (e) ``status``: the run ends ``completed`` at ``t_end`` or ``event`` at a terminal
        event (``rest``, ``flat``); ``interrupted`` (nothing here cancels a run) is not
        allowed.
    (f) ``contact_gap``: a part the trajectory has in contact (``part_in_contact``) lies on
        the floor, ``|gap| <= GAP_TOL``: the contact flag and the geometry agree (a part
        held in contact above the floor would be pulled down by a floor that can only push).
    (g) ``pull``: a part in contact is pushed, never pulled: its normal force
        (``part_normal_force``) is never below ``-PULL_TOL * m g``. The floor is a
        unilateral contact (Signorini: ``N >= 0``); a part whose force would pull leaves the
        floor (lift-off) in the same instant, and a pulling floor can feed energy in through
        the friction it lends. Checked unless ``CHECK_PULL`` is off (the environment's
        ``KREISEL_CHECK_PULL=0``; the campaign's ``--no-pull``). Seed 1, cases 0-9999: no
        run flags it (42 did before the lift-offs at a jump and the phases starting with a
        pull were resolved afresh).
    """
    top, state = case["top"], case["state"]
    out = []
    cols = {}
    for name in STATE_COLUMNS:
        try:
            cols[name] = np.asarray(traj[name], dtype=float)
        except Exception as e:  # noqa: BLE001 - a missing or unreadable column is a violation
            out.append(f"nonfinite: column {name!r} unreadable: {type(e).__name__}: {e}")
    if out:
        return out
    t = cols["t"]
    n = len(t)
    if n == 0:
        return ["nonfinite: no rows"]
    for name, a in cols.items():
        bad = ~np.isfinite(a.reshape(n, -1)).all(axis=1)
        if bad.any():
            out.append(
                f"nonfinite: {name} at {_where(t, int(np.argmax(bad)))}, {int(bad.sum())} rows"
            )
    if out:
        return out
    if t[0] != 0.0 or np.any(np.diff(t) < 0.0):
        out.append(f"time: t starts at {t[0]!r} or decreases")

    # (e) status
    status = getattr(traj, "status", None)
    events = list(getattr(traj, "events", []))
    t_end = case.get("t_end")
    if status not in ALLOWED_STATUSES:
        out.append(f"status: {status!r} at t = {t[-1]:.9g}")
    elif status == "event" and (not events or events[-1].name not in TERMINAL_EVENTS):
        out.append(f"status: 'event' but the last event is {events[-1:]!r}")
    elif status == "completed" and t_end is not None and not t[-1] >= t_end * (1 - 1e-12):
        out.append(f"status: 'completed' at t = {t[-1]!r} < t_end = {t_end!r}")

    # (d) kreisel's columns against the independent ones
    u_q = u_of_quaternion(cols["quaternion"])
    du = np.abs(cols["u"] - u_q)
    if du.max() > 1e-9:
        i = int(np.argmax(du))
        out.append(
            f"column_mismatch: u differs from the quaternion's by {du[i]:.3g} at {_where(t, i)}"
        )
    e = energy_of(top.m, top.A, top.C, top.g, cols["omega"], cols["com"], cols["com_velocity"])
    e0 = float(energy_of(top.m, top.A, top.C, top.g, state.omega, state.com, state.com_velocity)[0])
    scale = max(abs(e0), float(np.abs(e).max()), 0.0)
    rtol = case.get("rtol") or DEFAULT_RTOL
    tol = (ENERGY_RTOL + ENERGY_PER_RTOL * rtol) * scale + ENERGY_ATOL
    de = np.abs(cols["energy"] - e)
    if de.max() > tol:
        i = int(np.argmax(de))
        out.append(
            f"column_mismatch: energy differs from m v^2/2 + rotation + m g z_G by "
            f"{de[i]:.3g} J at {_where(t, i)}"
        )

    # (c) energy
    d = cols["dissipated"]
    total = e + d
    rise = total - e0
    if rise.max() > tol:
        i = int(np.argmax(rise))
        out.append(
            f"energy_rise: E + dissipated exceeds the start's {e0:.6g} J by "
            f"{rise[i]:.3g} J ({rise[i] / scale:.2g} relative) at {_where(t, i)}"
        )
    if n > 1:
        step = np.diff(e)
        if step.max() > tol:
            i = int(np.argmax(step))
            out.append(
                f"energy_step_rise: E rises by {step[i]:.3g} J "
                f"({step[i] / scale:.2g} relative) from {_where(t, i)} to the next"
            )
        dd = np.diff(d)
        if dd.min() < -tol:
            i = int(np.argmin(dd))
            out.append(
                f"dissipated_decrease: dissipated falls by {-dd[i]:.3g} J after {_where(t, i)}"
            )
    lost = e0 - total[0]
    if lost > tol:
        out.append(
            f"start_energy_unaccounted: the first row has {lost:.3g} J less than the "
            f"given state ({lost / scale:.2g} relative) and dissipated = {d[0]!r}"
        )

    # (a), (b) the floor
    gaps = part_gaps(top.shape, traj)

    def per_part(name, dtype):
        # A per-part column as (parts, rows), or None (the fault recorded).
        try:
            a = np.asarray(traj[name], dtype=dtype).reshape(n, -1).T
        except Exception as e:  # noqa: BLE001
            out.append(f"nonfinite: column {name!r} unreadable: {type(e).__name__}: {e}")
            return None
        if a.shape != gaps.shape:
            out.append(f"column_mismatch: {name} has shape {a.shape[::-1]}")
            return None
        return a

    contact = per_part("part_in_contact", bool)
    normal = per_part("part_normal_force", float)
    names = top.part_names
    touchdowns = {}
    for ev in events:
        if ev.name == "touchdown":
            touchdowns.setdefault(ev.part, []).append(ev.t)
    for k, g in enumerate(gaps):
        below = g < -GAP_TOL
        if below.any():
            i = int(np.argmin(g))
            out.append(
                f"below_floor: part {names[k]!r} {-g[i]:.3g} m below the floor at "
                f"{_where(t, i)} ({int(below.sum())} of {n} rows, first at "
                f"t = {t[int(np.argmax(below))]:.9g} s)"
            )
        flagged = contact[k] & (np.abs(g) > GAP_TOL) if contact is not None else None
        if flagged is not None and flagged.any():
            i = int(np.argmax(np.where(flagged, np.abs(g), -1.0)))
            out.append(
                f"contact_gap: part {names[k]!r} is in contact {g[i]:.3g} m from the "
                f"floor at {_where(t, i)} ({int(flagged.sum())} rows)"
            )
        if CHECK_PULL and contact is not None and normal is not None:
            pulled = contact[k] & (normal[k] < -PULL_TOL * top.m * top.g)
            if pulled.any():
                i = int(np.argmin(np.where(pulled, normal[k], 0.0)))
                out.append(
                    f"pull: part {names[k]!r} in contact is pulled by the floor with "
                    f"{-normal[k][i]:.3g} N at {_where(t, i)} ({int(pulled.sum())} rows)"
                )
        crossing = np.nonzero((g[:-1] > 0.0) & below[1:])[0]
        tds = np.array(touchdowns.get(names[k], []))
        missed = [i for i in crossing if not np.any((tds >= t[i]) & (tds <= t[i + 1]))]
        if missed:
            i = missed[0]
            out.append(
                f"missed_touchdown: part {names[k]!r} went from {g[i]:.3g} m to "
                f"{g[i + 1]:.3g} m between t = {t[i]:.9g} and {t[i + 1]:.9g} s with no "
                f"touchdown event ({len(missed)} such crossings)"
            )
    return out


def kind_of(violation: str) -> str:
    """The kind of a violation string (the word before the first colon)."""
    return violation.split(":", 1)[0]


def outcome(case, result):
    """``(verdict, details)`` of a run's result (a Trajectory or an exception):

    - ``("ok", [])``: a trajectory with no violation;
    - ``("refused", [message])``: a kreisel error that refuses the run and says what to
      change (:data:`REFUSAL`: the pace, step and stall guards) -- acceptable, counted apart;
    - ``("violation", [...])``: :func:`check_run`'s list, or ``"error: ..."`` for any other
      exception (a kreisel error that names no remedy, a numpy error, a Rust panic:
      ``"panic: ..."``).
    """
    import kreisel

    if isinstance(result, BaseException):
        msg = f"{type(result).__name__}: {result}"[:600]
        if isinstance(result, kreisel.KreiselError) and REFUSAL.search(str(result)):
            return "refused", [msg]
        if type(result).__name__ == "PanicException":
            return "violation", [f"panic: {msg}"]
        return "violation", [f"error: {msg}"]
    found = check_run(case, result)
    return ("violation", found) if found else ("ok", [])


def refusal_key(message: str) -> str:
    """A refusal's message with its numbers replaced by '#': refusals counted by kind."""
    return re.sub(r"-?\d+(\.\d+)?(e[-+]?\d+)?", "#", message)
