"""A property-based fuzz campaign over kreisel's public surface.

Every public constructor and method (found by introspection, see :func:`public_surface`),
``kreisel.special``, the main entry points of ``kreisel.quantum``, ``simulate``,
``simulate_many``, ``sweep`` and the command line are called with valid, boundary and invalid
values drawn by hypothesis. Each call ends in one
outcome:

- ``clean``: a result whose floats are all finite (or non-finite only where documented,
  see :data:`DOCUMENTED_NONFINITE`);
- ``clear``: a ``KreiselError`` whose message names an argument of the call;
- ``unclear``: any other exception, or a ``KreiselError`` that names no argument;
- ``nan``: a result with an undocumented NaN or inf;
- ``panic``: a Rust panic (``pyo3_runtime.PanicException``, a ``BaseException``);
- ``crash``: the interpreter died (a segfault, an abort);
- ``hang``: no answer within the time limit.

The calls are drawn first (hypothesis only generates data here; nothing of kreisel runs in
that process) and then executed by a worker process, which the runner restarts after a
crash or a hang, so that both are counted, not fatal.

    python tests/fuzz/campaign.py --calls 100000      # `make fuzz`

prints the counts by outcome and by function and the first reproducers of every bad
outcome.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import dataclasses
import inspect
import json
import math
import os
import pickle
import re
import select
import subprocess
import sys
import tempfile
import time

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

OUTCOMES = ("clean", "clear", "unclear", "nan", "panic", "crash", "hang")
BAD = ("unclear", "nan", "panic", "crash", "hang")

# --------------------------------------------------------------------------------------
# values
# --------------------------------------------------------------------------------------

PI = math.pi
SPECIAL = [
    math.nan, math.inf, -math.inf, 0.0, -0.0, 5e-324, -5e-324, 1e-320, 1e-300, 1e-100, 1e-8,
    0.5, 1.0, -1.0, 2.0, PI, -PI, PI / 2, 2 * PI, 1e8, 1e17, -1e17, 1e100, 1e300, -1e300,
    2.0**53, 1e-263,
]  # fmt: skip
WRONG_TYPES = ["1.0", "nan", None, [1.0, 2.0], True, {"a": 1}, 1j, (), [[1.0]]]

hostile_float = st.one_of(
    st.sampled_from(SPECIAL),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-10.0, 10.0),
)
any_value = st.one_of(hostile_float, hostile_float, st.sampled_from(WRONG_TYPES))


def mostly(good, *bad, k=4):
    """``good`` k times out of k + 1, else one of ``bad``."""
    return st.one_of(*([good] * k), *bad)


def nice(lo, hi, *extra):
    """Mostly ordinary values in [lo, hi], some given boundary values."""
    base = st.floats(lo, hi)
    return st.one_of(base, base, base, st.sampled_from(extra)) if extra else base


@st.composite
def mutated(draw, params: dict, rate=4):
    """``params`` with (1 time in ``rate``) one entry replaced by a hostile value."""
    p = dict(params)
    if draw(st.integers(0, rate - 1)) == 0 and p:
        k = draw(st.sampled_from(sorted(p)))
        p[k] = draw(any_value)
    return p


@st.composite
def drive_params(draw):
    """A moving or damped pivot (1 time in 4), as plain data: ``{"pivot": (kind, ...),
    "damping": (viscous, drag, dry, pivot_radius)}``, some of it hostile."""
    out = {}
    if draw(st.integers(0, 3)) == 0:
        kind = draw(st.sampled_from(["harmonic", "harmonic", "path", "hostile"]))
        if kind == "harmonic":
            amp = [draw(nice(-0.05, 0.05, 0.0)) for _ in range(3)]
            phase = draw(st.one_of(nice(-7.0, 7.0), st.lists(nice(-7.0, 7.0), min_size=3,
                                                             max_size=3)))  # fmt: skip
            out["pivot"] = ("harmonic", amp, draw(nice(0.0, 200.0, 0.0, 1e3, 1e7)), phase)
        elif kind == "path":
            n = draw(st.integers(1, 8))
            t = sorted(draw(st.lists(nice(0.0, 2.0), min_size=n, max_size=n)))
            pos = [[draw(nice(-0.05, 0.05)) for _ in range(3)] for _ in range(n)]
            out["pivot"] = ("path", t, pos)
        else:
            out["pivot"] = draw(any_value)
    if draw(st.integers(0, 3)) == 0:
        d = tuple(draw(nice(0.0, 0.1, 0.0)) for _ in range(4))
        out["damping"] = d if draw(st.integers(0, 4)) else draw(any_value)
    return out


def _drive(p):
    """The pivot and damping keywords of drawn data (hostile values passed as they are)."""
    import kreisel
    from kreisel import pivots

    p = dict(p)
    pv = p.get("pivot")
    if isinstance(pv, tuple) and pv and pv[0] == "harmonic":
        p["pivot"] = pivots.Harmonic(pv[1], pv[2], pv[3])
    elif isinstance(pv, tuple) and pv and pv[0] == "path":
        p["pivot"] = pivots.Path(pv[1], pv[2])
    d = p.get("damping")
    if isinstance(d, tuple) and len(d) == 4:
        p["damping"] = kreisel.PivotDamping(*d)
    return p


@st.composite
def lagrange_params(draw, rate=4):
    i1 = draw(nice(0.01, 10.0, 1.0))
    i3 = i1 * draw(nice(0.01, 2.0, 2.0, 1.0))  # I3 = 2 I1: the flat limit
    m = draw(nice(0.01, 10.0, 1.0))
    frac = draw(nice(-1.0, 1.0, 0.0, 1.0, -1.0, 1e-100))
    return {**draw(
        mutated({"I1": i1, "I3": i3, "m": m, "l": frac * math.sqrt(i1 / m) * (1 - 1e-9),
                 "g": draw(st.sampled_from([9.81, 0.0, 1.0, 1e-3]))}, rate)
    ), **draw(drive_params())}  # fmt: skip


@st.composite
def heavy_params(draw, rate=4):
    i1, i2 = draw(nice(0.5, 5.0, 1.0)), draw(nice(0.5, 5.0, 1.0))
    kind = draw(st.sampled_from(["general", "lagrange", "kovalevskaya", "euler"]))
    if kind == "kovalevskaya":
        i2 = i1
        i3 = i1 / 2
        com = [draw(nice(0.0, 0.3, 1e-200)), 0.0, 0.0]
    else:
        i3 = draw(nice(abs(i1 - i2) + 0.01, i1 + i2))
        if kind == "lagrange":
            i2 = i1
            com = [0.0, 0.0, draw(nice(-0.3, 0.3))]
        elif kind == "euler":
            com = [0.0, 0.0, 0.0]
        else:
            com = [draw(nice(-0.2, 0.2)) for _ in range(3)]
    p = {"I1": i1, "I2": i2, "I3": i3, "m": draw(nice(0.1, 5.0, 1.0)), "com": com,
         "g": draw(st.sampled_from([9.81, 0.0, 1.0]))}  # fmt: skip
    return {**draw(mutated(p, rate)), **draw(drive_params())}


FRICTIONS = st.one_of(
    st.builds(lambda mu: ("Coulomb", mu), nice(0.0, 1.5, 0.0, 0.3)),
    st.builds(lambda mu: ("Viscous", mu), nice(0.0, 5.0, 0.0, 1.0)),
    st.just(("Frictionless", None)),
    st.builds(lambda mu: ("Coulomb", mu), any_value),
)


@st.composite
def play_params(draw, rate=4):
    c = draw(nice(1e-6, 1e-4, 7e-6))
    p = {
        "m": draw(nice(0.005, 0.1, 0.02)),
        "A": c * draw(nice(0.5, 1.5, 1.0, 0.5)),  # C = 2 A at 0.5
        "C": c,
        "s": draw(nice(0.0, 0.01, 0.0, 0.001)),
        "rho": draw(nice(0.001, 0.02, 0.004)),
        "g": draw(st.sampled_from([9.81, 0.0, 1.0])),
        "friction": draw(FRICTIONS),
        "restitution": draw(nice(0.0, 1.0, 0.0, 1.0, 0.5)),
    }
    return draw(mutated(p, rate))


@st.composite
def euler_state(draw, rate=4, rate_scale=30.0):
    theta = draw(nice(0.0, PI, 0.0, PI, PI / 2, 1e-300))
    r = rate_scale
    p = {
        "theta": theta,
        "phi": draw(nice(-2 * PI, 2 * PI, 0.0)),
        "psi": draw(nice(-2 * PI, 2 * PI, 0.0)),
        "theta_dot": draw(nice(-r, r, 0.0, 1e-263)),
        "phi_dot": draw(nice(-r, r, 0.0, 1e-263)),
        "psi_dot": draw(nice(-10 * r, 10 * r, 0.0, 1e-263)),
    }
    return draw(mutated(p, rate))


@st.composite
def through_vertical_state(draw, i1, i3):
    """A state with Mz = +-M3 (the axis passes through the vertical)."""
    theta = draw(st.floats(0.05, PI - 0.05))
    psi_dot = draw(st.floats(-50.0, 50.0))
    s, c = math.sin(theta), math.cos(theta)
    sign = draw(st.sampled_from([1.0, -1.0]))
    # Mz = sign M3: I1 phidot s^2 + M3 c = sign M3, M3 = I3 (psidot + phidot c)
    k = sign - c
    phi_dot = i3 * psi_dot * k / (i1 * s * s - i3 * c * k)
    return {"theta": theta, "theta_dot": draw(st.floats(-5.0, 5.0)), "phi_dot": phi_dot,
            "psi_dot": psi_dot}  # fmt: skip


def quaternion():
    unit = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4)
    return st.one_of(
        unit, unit, unit,
        st.lists(st.sampled_from(SPECIAL), min_size=4, max_size=4),
        st.sampled_from([[0.0] * 4, [1e300, 1e300, 0.0, 0.0], [1e-300, 0.0, 0.0, 0.0],
                         [5e-324, 0, 0, 0], [1.0, 0.0, 0.0], [[1.0, 0.0, 0.0, 0.0]]]),
        any_value,
    )  # fmt: skip


def vector3(lo=-20.0, hi=20.0):
    v = st.lists(st.floats(lo, hi), min_size=3, max_size=3)
    return st.one_of(v, v, v, st.lists(hostile_float, min_size=3, max_size=3), any_value,
                     st.lists(st.floats(lo, hi), min_size=0, max_size=5))  # fmt: skip


def times(t_max=2.0):
    sorted_t = st.lists(st.floats(0.0, t_max), min_size=1, max_size=40).map(sorted)
    return st.one_of(
        sorted_t, sorted_t,
        st.lists(st.floats(-t_max, t_max), min_size=0, max_size=30),  # unsorted, empty
        st.just([]),
        st.lists(hostile_float, min_size=1, max_size=5),
        st.just([[0.0, 1.0], [2.0, 3.0]]),
        any_value,
    )  # fmt: skip


# --------------------------------------------------------------------------------------
# calls: each target draws its arguments (plain data) and knows how to make the call
# --------------------------------------------------------------------------------------


def _make_lagrange(p):
    import kreisel

    return kreisel.LagrangeTop(**_drive(p))


def _make_heavy(p):
    import kreisel

    return kreisel.HeavyTop(**_drive(p))


def _make_play(p):
    import kreisel

    p = dict(p)
    f = p.pop("friction", None)
    if isinstance(f, tuple) and len(f) == 2 and f[0] in ("Coulomb", "Viscous", "Frictionless"):
        kind, mu = f
        law = getattr(kreisel, kind)
        p["friction"] = law() if mu is None else law(mu)
    elif f is not None:
        p["friction"] = f  # a hostile value in place of a friction law
    return kreisel.PlayTop(**p)


MAKERS = {"LagrangeTop": _make_lagrange, "HeavyTop": _make_heavy, "PlayTop": _make_play}
PARAMS = {"LagrangeTop": lagrange_params, "HeavyTop": heavy_params, "PlayTop": play_params}


def _state(top, kind, sp):
    """A state of ``top`` from drawn data: Euler angles, or a quaternion."""
    if "quaternion" in sp:
        extra = {k: sp[k] for k in ("vx", "vy", "height") if k in sp}
        return top.state_from_quaternion(sp["quaternion"], sp["omega"], **extra)
    return top.state(**sp["euler"])


@st.composite
def state_data(draw, kind, params):
    if kind == "LagrangeTop" and draw(st.integers(0, 5)) == 0:
        try:
            i1, i3 = float(params["I1"]), float(params["I3"])
            ev = draw(through_vertical_state(i1, i3))
        except (TypeError, ValueError, ZeroDivisionError, KeyError):
            ev = draw(euler_state())
        return {"euler": ev}
    if kind != "LagrangeTop" and draw(st.integers(0, 3)) == 0:
        d = {"quaternion": draw(quaternion()), "omega": draw(vector3())}
    else:
        scale = 30.0 if kind != "PlayTop" else 300.0
        d = {"euler": draw(euler_state(rate_scale=scale))}
    if kind == "PlayTop":
        extra = draw(st.sampled_from([{}, {"height": 0.0}, {"height": 0.005}, {"vx": 0.1},
                                      {"height": -1.0}, {"vy": math.inf}]))  # fmt: skip
        if "euler" in d:
            d["euler"] = {**d["euler"], **extra}
        else:
            d.update(extra)
    return d


@dataclasses.dataclass
class Target:
    """A public function or method: how to draw its arguments and how to call it."""

    name: str
    draw: st.SearchStrategy
    call: object  # (args) -> result
    weight: float = 1.0
    stack: bool = False  # in the simulation stack (another developer's)


def _method_target(kind, method, extra, weight=1.0, stack=False):
    @st.composite
    def draw(d):
        p = d(PARAMS[kind]())
        return {"params": p, "state": d(state_data(kind, p)), "args": d(extra)}

    def call(a):
        top = MAKERS[kind](a["params"])
        args = dict(a["args"])
        if args.pop("_state", True):
            args = {"state": _state(top, kind, a["state"]), **args}
        return getattr(top, method)(**args)

    return Target(f"{kind}.{method}", draw(), call, weight, stack)


def _kw(**strategies):
    return st.fixed_dictionaries(strategies)


def _no_state(**strategies):
    return st.fixed_dictionaries({"_state": st.just(False), **strategies})


def _special_targets():
    from kreisel import special

    arr = st.one_of(hostile_float, st.lists(hostile_float, max_size=6), any_value)
    m = st.one_of(nice(-5.0, 1.0, 0.0, 1.0, 0.999999999), hostile_float, any_value)
    n = st.one_of(nice(-50.0, 50.0, 0.0, 1.0, 1.5), hostile_float)
    phi = st.one_of(nice(-10.0, 10.0, PI / 2, 1e17), arr)
    c = st.one_of(nice(-10.0, 10.0, 0.0), hostile_float, hostile_float)
    return [
        Target("special.ellipj", _kw(u=arr, m=m), lambda a: special.ellipj(a["u"], a["m"])),
        Target("special.ellipk", _kw(m=m), lambda a: special.ellipk(a["m"])),
        Target("special.ellipf", _kw(phi=phi, m=m), lambda a: special.ellipf(a["phi"], a["m"])),
        Target("special.ellippi", _kw(n=n, m=m), lambda a: special.ellippi(a["n"], a["m"])),
        Target("special.ellippi(phi)", _kw(n=n, phi=phi, m=m),
               lambda a: special.ellippi(a["n"], a["phi"], a["m"])),
        Target("special.cubic_roots", _kw(c0=c, c1=c, c2=c, c3=c),
               lambda a: special.cubic_roots(a["c0"], a["c1"], a["c2"], a["c3"])),
    ]  # fmt: skip


def _quantum_targets():
    from kreisel import quantum

    # Mostly valid values, so that the levels, not only the checks, are driven.
    moment = mostly(nice(0.3, 3.0, 1.0, 2.0), hostile_float, any_value, k=12)
    hbar = mostly(st.sampled_from([1.0, 0.5, quantum.HBAR]), hostile_float, any_value, k=12)
    qn = mostly(st.integers(-4, 4), st.sampled_from([10**9, -(2**70)]), any_value, k=12)
    j_max = mostly(st.integers(4, 120), st.integers(-2, 3),
                   st.sampled_from([20_000, 20_001, 10**12]), any_value, k=12)  # fmt: skip
    strength = mostly(st.one_of(nice(-500.0, 500.0, 0.0), st.lists(nice(-500.0, 500.0),
                                                                     max_size=6)),
                      hostile_float, any_value, k=12)  # fmt: skip

    def top(a):
        return quantum.SymmetricTop(a["I1"], a["I3"], a["hbar"])

    base = {"I1": moment, "I3": moment, "hbar": hbar}
    constant = mostly(nice(1.0, 2e5, 25536.15), hostile_float, any_value, k=8)
    unit = mostly(st.sampled_from(["MHz", "cm-1", "GHz"]), any_value, k=8)
    return [
        Target("quantum.SymmetricTop()", _kw(**base), lambda a: repr(top(a)), 0.3),
        Target("quantum.SymmetricTop.levels",
               _kw(**base, K=qn, M=qn, J_max=j_max, strength=strength),
               lambda a: top(a).levels(a["K"], a["M"], a["J_max"], a["strength"])),
        Target("quantum.SymmetricTop.ebk_levels",
               _kw(**base, K=qn, M=qn, n=mostly(st.integers(0, 40), st.integers(-2, -1),
                                                any_value, k=8),
                   strength=strength),
               lambda a: top(a).ebk_levels(a["K"], a["M"], a["n"], a["strength"])),
        Target("quantum.SymmetricTop.nutation_action",
               _kw(**base, K=qn, M=qn, energy=mostly(nice(-100.0, 1e4, 0.0), any_value, k=8),
                   strength=mostly(nice(-500.0, 500.0, 0.0), any_value, k=8)),
               lambda a: top(a).nutation_action(a["K"], a["M"], a["energy"], a["strength"])),
        Target("quantum.SymmetricTop.spectrum",
               _kw(**base, J_max=j_max,
                   temperature=mostly(nice(0.01, 1e4, 1.0, 300.0), any_value, k=8)),
               lambda a: top(a).spectrum(a["J_max"], a["temperature"]).intensity, 0.5),
        Target("quantum.SymmetricTop.from_constants",
               _kw(A=constant, B=constant, unit=unit),
               lambda a: quantum.SymmetricTop.from_constants(a["A"], a["B"], a["unit"]).constants(),
               0.5),
    ]  # fmt: skip


def _construct_target(kind):
    def call(a):
        top = MAKERS[kind](a)
        props = {
            n: getattr(top, n)
            for n, v in inspect.getmembers(type(top))
            if isinstance(v, property) and not n.startswith("_")
        }
        return {"repr": repr(top), **props}

    return Target(f"{kind}()", PARAMS[kind](rate=2), call, 1.0)


def _friction_targets():
    import kreisel

    def law(k):
        return lambda a: repr(getattr(kreisel, k)(a["mu"]))

    mu = _kw(mu=st.one_of(nice(0.0, 2.0, 0.0), any_value))
    return [Target(f"{k}()", mu, law(k), 0.3) for k in ("Coulomb", "Viscous")] + [
        Target("Frictionless()", st.just({}), lambda a: repr(kreisel.Frictionless()), 0.05)
    ]


ANGLE = st.one_of(nice(0.0, PI, 0.0, PI, PI / 2), any_value)
RATE = st.one_of(nice(-50.0, 50.0, 0.0), any_value)
T_SMALL = st.one_of(nice(1e-3, 0.05, 0.01), any_value)


def _object_targets():
    th = st.one_of(nice(-1.0, 4.0, 0.0, PI), st.lists(nice(0.0, PI, 0.0, PI), max_size=8),
                   any_value)  # fmt: skip
    u = st.one_of(nice(-1.0, 1.0, -1.0, 1.0, 0.0), st.lists(nice(-1.2, 1.2), max_size=6),
                  any_value)  # fmt: skip
    lag = [
        ("state", _no_state(**{k: v for k, v in (("theta", ANGLE), ("theta_dot", RATE),
                                                   ("phi_dot", RATE), ("psi_dot", RATE))}),
         1.0),
        ("state_from_quaternion", _no_state(q=quaternion(), omega=vector3()), 1.0),
        ("invariants", _kw(), 1.0),
        ("effective_potential", _no_state(theta=th, Mz=st.one_of(nice(-5.0, 5.0), any_value),
                                          M3=st.one_of(nice(-5.0, 5.0), any_value)), 1.0),
        ("analyse", _kw(), 2.0),
        ("turning_points", _kw(), 0.5),
        ("nutation_period", _kw(), 0.5),
        ("mean_precession_rate", _kw(), 1.0),
        ("motion_kind", _kw(), 0.3),
        ("exact", _kw(t=times(5.0), direct=st.booleans()), 2.0),
        ("steady_precession", _no_state(theta0=ANGLE, omega3=RATE), 1.0),
        ("nutation_frequency", _no_state(theta0=ANGLE, omega3=RATE, rate=RATE), 0.5),
        ("sleeping_threshold", _no_state(), 0.2),
        ("lyapunov", _kw(t_end=T_SMALL, tau=st.one_of(nice(1e-3, 0.05, 0.01), any_value)),
         0.3),
    ]  # fmt: skip
    heavy = [
        ("state", _no_state(theta=ANGLE, phi_dot=RATE, psi_dot=RATE), 0.5),
        ("state_from_quaternion", _no_state(q=quaternion(), omega=vector3()), 1.0),
        ("invariants", _kw(), 1.5),
        ("lyapunov", _kw(t_end=T_SMALL, tau=st.one_of(nice(1e-3, 0.05, 0.01), any_value)), 0.3),
    ]
    play = [
        ("state", _no_state(theta=ANGLE, psi_dot=st.one_of(nice(-300.0, 300.0), any_value),
                            height=st.one_of(st.none(), nice(0.0, 0.01), any_value)), 0.5),
        ("state_from_quaternion", _no_state(q=quaternion(), omega=vector3()), 0.5),
        ("jellett", _kw(), 1.0),
        ("energy", _kw(), 1.0),
        ("J_R", _no_state(u=u), 1.0),
        ("regular_precession", _no_state(u=u), 1.0),
        ("stationary_motions", _no_state(J=st.one_of(nice(-1e-5, 1e-5, 0.0), any_value)), 1.0),
        ("classify", _no_state(), 0.5),
        ("predict", _kw(), 1.0),
        ("frictionless_turning_points", _kw(), 0.5),
        ("frictionless_nutation_period", _kw(), 0.5),
    ]  # fmt: skip
    out = []
    for kind, table, stack in (("LagrangeTop", lag, False), ("HeavyTop", heavy, False),
                               ("PlayTop", play, True)):  # fmt: skip
        for method, extra, w in table:
            # PlayTop's own methods live in _play.py, part of the simulation stack; the
            # theory behind them (J_R, stationary motions, ...) is in _atlas and the core.
            in_stack = (stack and method in ("state", "state_from_quaternion", "jellett",
                                             "energy")) or method == "lyapunov"  # fmt: skip
            out.append(_method_target(kind, method, extra, w, in_stack))
    return out


def _simulate_targets(calm=False):
    """simulate and simulate_many; ``calm`` leaves out the inputs of the known hangs."""
    import kreisel

    methods = ["dop853", "rk4", "splitting", "splitting4", "splitting6", "verlet",
               "midpoint", "gauss4"]  # fmt: skip
    events = st.sampled_from([None, [], ["inversion"], ["rest"], ["turning_points"],
                              ["theta_crossing"], "bad"])  # fmt: skip

    def make_events(names):
        if names is None or names == "bad":
            return names
        ev = kreisel.events
        return [ev.theta_crossing(1.0) if n == "theta_crossing" else getattr(ev, n)()
                for n in names]  # fmt: skip

    @st.composite
    def draw(d):
        kind = d(st.sampled_from(["LagrangeTop", "HeavyTop", "PlayTop"]))
        p = d(PARAMS[kind](rate=6))
        method = d(mostly(st.just("dop853"), st.sampled_from(methods), st.just("nope")))
        fixed = method != "dop853"
        dt = d(mostly(nice(1e-4, 1e-2, 1e-3), st.sampled_from(
            [1e-300, 5e-324, 0.0, -1e-3, math.nan, 1.0, 1e-9, None]))) if fixed else d(
            mostly(st.none(), st.just(1e-3)))  # fmt: skip
        if calm and dt is not None and not dt >= 1e-6:
            dt = 1e-3  # tiny fixed steps ran for ever (refused now, tested apart)
        if calm and kind == "PlayTop" and p.get("restitution") == 0.0:
            p = {**p, "restitution": 0.5}  # restitution 0 could hang (tested apart)
        return {
            "kind": kind, "params": p, "state": d(state_data(kind, p)),
            "t_end": d(mostly(nice(1e-3, 0.02, 0.01), any_value)), "method": method, "dt": dt,
            "rtol": d(mostly(st.just(1e-8), st.sampled_from([1e-15, 1e-3, 0.0, 2.0]),
                             hostile_float)),
            "atol": d(mostly(st.just(1e-10), hostile_float)),
            "t_eval": d(st.one_of(st.none(), st.none(), st.none(), times(0.02))),
            "events": d(mostly(st.none(), events)),
            "reduced": d(mostly(st.just(False), st.just(True), k=3)),
        }  # fmt: skip

    def call(a):
        top = MAKERS[a["kind"]](a["params"])
        state = _state(top, a["kind"], a["state"])
        kw = {k: a[k] for k in ("method", "rtol", "atol", "dt", "t_eval")}
        if a["reduced"]:
            kw["reduced"] = True
        traj = kreisel.simulate(top, state, a["t_end"], events=make_events(a["events"]),
                                **kw)  # fmt: skip
        return {k: traj[k] for k in traj.columns}

    @st.composite
    def draw_many(d):
        kind = d(st.sampled_from(["HeavyTop", "PlayTop", "LagrangeTop"]))
        n = d(st.integers(0, 3))
        ps = [d(PARAMS[kind](rate=8)) for _ in range(max(n, 1))]
        return {
            "kind": kind, "params": ps, "states": [d(state_data(kind, ps[0])) for _ in range(n)],
            "t_end": d(st.one_of(nice(1e-3, 0.02, 0.01), any_value)),
            "method": d(st.sampled_from(["dop853", "rk4", "splitting", "nope"])),
            "dt": d(st.one_of(st.none(), nice(1e-4, 1e-2, 1e-3),
                              st.sampled_from([1e-3] if calm else [1e-300, 0.0]))),
            "one_model": d(st.booleans()),
        }  # fmt: skip

    def call_many(a):
        tops = [MAKERS[a["kind"]](p) for p in a["params"]]
        states = [_state(tops[0], a["kind"], s) for s in a["states"]]
        models = tops[0] if a["one_model"] else tops[: len(states)] or tops
        out = kreisel.simulate_many(models, states, a["t_end"], method=a["method"], dt=a["dt"],
                                    threads=1)  # fmt: skip
        return dataclasses.asdict(out) if dataclasses.is_dataclass(out) else out

    return [
        Target("simulate", draw(), call, 6.0, stack=True),
        Target("simulate_many", draw_many(), call_many, 1.0, stack=True),
    ]


def _sweep_target():
    import kreisel

    @st.composite
    def draw(d):
        kind = d(st.sampled_from(["lagrange", "play", "heavy"]))
        p = d({"lagrange": lagrange_params, "play": play_params,
               "heavy": heavy_params}[kind](rate=6))  # fmt: skip
        p = {k: v for k, v in p.items() if k != "friction"}
        var = d(st.sampled_from(["theta", "psi_dot", "m", "bogus"]))
        grid = d(st.one_of(
            st.lists(st.one_of(nice(0.1, 3.0), hostile_float), min_size=0, max_size=3),
            st.fixed_dictionaries({"start": nice(0.1, 1.0), "stop": nice(1.0, 3.0),
                                   "num": st.one_of(st.integers(1, 3), any_value)}),
            any_value,
        ))  # fmt: skip
        return {
            "top": {"kind": kind, **p},
            "state": {"theta": d(st.one_of(nice(0.1, 3.0), any_value))},
            "simulation": {"t_end": d(st.one_of(nice(1e-3, 0.01), any_value))},
            "grid": {var: grid},
        }

    def call(a):
        with tempfile.TemporaryDirectory() as tmp:
            ds = kreisel.sweep(kreisel.SweepSpec.from_tables(a), f"{tmp}/s.zarr", progress=False,
                               threads=1)  # fmt: skip
            return {k: ds[k].values for k in ds.data_vars if ds[k].dtype.kind == "f"}

    return Target("sweep", draw(), call, 0.05, stack=False)


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + "}"
    if value is None:
        return '"none"'
    return json.dumps(str(value))


def _cli_targets():
    @st.composite
    def draw(d):
        kind = d(st.sampled_from(["lagrange", "heavy", "play"]))
        p = d({"lagrange": lagrange_params, "play": play_params,
               "heavy": heavy_params}[kind](rate=5))  # fmt: skip
        p.pop("friction", None)
        text = f'[top]\nkind = "{kind}"\n' + "".join(f"{k} = {_toml(v)}\n" for k, v in p.items())
        st_ = d(euler_state(rate=5))
        text += "[state]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in st_.items())
        sim = {"t_end": d(st.one_of(nice(1e-3, 0.01), any_value)), "samples": 20}
        if kind != "lagrange":
            sim["rtol"] = 1e-6
        text += "[simulation]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in sim.items())
        damage = d(st.sampled_from(["none", "none", "top-int", "array-of-tables", "nested",
                                    "nested-table", "unknown-table", "garbage", "truncate",
                                    "unknown-field", "dup"]))  # fmt: skip
        if damage == "top-int":
            text = "top = 3\n" + text.split("\n", 2)[2]
        elif damage == "array-of-tables":
            text = text.replace("[top]", "[[top]]", 1)
        elif damage == "nested":
            text += "[grid]\nx = " + "[" * 3000 + "]" * 3000 + "\n"
        elif damage == "nested-table":
            text = text.replace("[state]\n", "[state]\nphi = " + "{a = " * 2000 + "1" + "}" * 2000
                                + "\n", 1)  # fmt: skip
        elif damage == "unknown-table":
            text += "[wat]\nx = 1\n"
        elif damage == "garbage":
            text = text.replace("=", "==", 1)
        elif damage == "truncate":
            text = text[: d(st.integers(0, len(text)))]
        elif damage == "unknown-field":
            text = text.replace("[state]\n", "[state]\nbogus = 1\n", 1)
        elif damage == "dup":
            text = text.replace("[state]\n", "[state]\n[state]\n", 1)
        command = d(st.sampled_from(["run", "run", "sweep"]))
        return {"text": text, "command": command}

    def call(a):
        import contextlib
        import io

        from kreisel._cli import main

        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "f.toml")
            with open(path, "w") as fh:
                fh.write(a["text"])
            if a["command"] == "run":
                argv = ["run", path, "--out", os.path.join(tmp, "o"), "--no-figures"]
            else:
                argv = ["sweep", path, "--store", os.path.join(tmp, "s.zarr"), "--no-figure",
                        "--quiet"]  # fmt: skip
            err, out = io.StringIO(), io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
                code = main(argv)
        lines = [x for x in err.getvalue().splitlines() if x.strip()]
        if code == 0:
            return {"exit": 0}
        if code in (1, 2) and len(lines) == 1 and ": error: " in lines[0]:
            raise _CliError(lines[0])
        raise RuntimeError(f"exit {code} with stderr {err.getvalue()[-500:]!r}")

    return [Target("cli", draw(), call, 0.3)]


class _CliError(Exception):
    """A command line that ended with one line naming what was wrong (a clear error)."""


def all_targets(calm=False) -> list[Target]:
    """Every target; ``calm`` leaves out the inputs of the known hangs of the simulation
    stack (a Coulomb drop with restitution 0, tiny fixed steps: tested apart), for the share
    that runs in `make test`."""
    return (
        _special_targets()
        + _quantum_targets()
        + [_construct_target(k) for k in MAKERS]
        + _friction_targets()
        + _object_targets()
        + _simulate_targets(calm)
        + [_sweep_target()]
        + _cli_targets()
    )


def public_surface() -> set[str]:
    """Every public callable of kreisel this campaign must drive: the methods of the public
    classes (by introspection) and the functions of ``kreisel.special``."""
    import kreisel
    from kreisel import special

    out = set()
    for name in ("LagrangeTop", "HeavyTop", "PlayTop"):
        cls = getattr(kreisel, name)
        out.add(f"{name}()")
        for m, v in inspect.getmembers(cls):
            if not m.startswith("_") and callable(v) and not isinstance(v, property):
                out.add(f"{name}.{m}")
    for m, v in inspect.getmembers(special, inspect.isfunction):
        if not m.startswith("_") and v.__module__ == special.__name__:
            out.add(f"special.{m}")
    out |= {"simulate", "simulate_many", "sweep", "cli", "Coulomb()", "Viscous()",
            "Frictionless()"}  # fmt: skip
    return out


# --------------------------------------------------------------------------------------
# outcomes
# --------------------------------------------------------------------------------------

# Documented non-finite values: (target, path) prefixes where NaN or inf is the answer.
DOCUMENTED_NONFINITE = {
    # K(1) and Pi(n | 1) are infinite (the integrals diverge; documented)
    ("special.ellipk", ""): "inf at m = 1",
    ("special.ellippi", ""): "+-inf at m = 1",
    ("special.ellippi(phi)", ""): "+-inf at m = 1 without phi (the complete integral)",
    # Veff is +inf at the verticals unless Mz = +-M3, and overflows to +inf next to them
    ("LagrangeTop.effective_potential", ""): "+inf where sin(theta) = 0 (or it overflows)",
    # the period of a separatrix motion, and of small nutations about an unstable steady one
    ("LagrangeTop.nutation_period", ""): "inf on the separatrix",
    ("LagrangeTop.analyse", "nutation_period"): "inf on the separatrix",
    # no regular precession where D(u) <= 0
    ("PlayTop.J_R", ""): "nan where D(u) <= 0",
    ("sweep", ""): "nan for a failed run or a summary that does not apply",
    ("PlayTop.frictionless_nutation_period", ""): "inf on the separatrix",
}


# The summaries of simulate_many that are NaN by design, by name: every other NaN or inf of
# a batch is a defect, except in the row of a run that failed with its message in ``errors``
# (BatchSummary: "a failed run has NaN ... and its message in errors").
BATCH_NAN_BY_DESIGN = {
    "first_touchdown_time": "a part that never touched (or a column beyond the top's parts)",
    "flat_time": "no ring came down flat",
    "rest_time": "the top did not come to rest",
    "inversion_time": "the top did not turn over",
    "M3_drift": "M3 is not an integral (an asymmetric top, or a damped one)",
    "Mz_drift": "Mz is not an integral (a pivot moving sideways, or damped)",
    "kovalevskaya_drift": "not a Kovalevskaya top",
}


def _batch_nonfinite(result: dict) -> list[str]:
    """The undocumented non-finite summaries of a simulate_many result (as a dict): NAME[i]
    for run i."""
    import numpy as np

    errors = result.get("errors") or ()
    out = []
    for name, value in result.items():
        if name in BATCH_NAN_BY_DESIGN or name == "errors" or value is None:
            continue
        arr = np.asarray(value)
        if arr.dtype.kind not in "fc" or arr.ndim == 0:
            continue
        rows = np.flatnonzero(~np.isfinite(arr).reshape(len(arr), -1).all(axis=1))
        out += [f"{name}[{i}]" for i in rows if i >= len(errors) or errors[i] is None]
    return out


def _nonfinite_paths(x, path=""):
    """Paths of the non-finite floats in a result."""
    import numpy as np

    if isinstance(x, bool) or x is None or isinstance(x, (str, int)):
        return []
    if isinstance(x, float):
        return [] if math.isfinite(x) else [path]
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc":
            return [] if np.all(np.isfinite(x)) else [path]
        if x.dtype.kind == "O":
            return [p for i, v in enumerate(x.ravel()) for p in _nonfinite_paths(v, path)]
        return []
    if isinstance(x, np.generic):
        return _nonfinite_paths(x.item(), path)
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return [p for f in dataclasses.fields(x)
                for p in _nonfinite_paths(getattr(x, f.name), f.name if not path
                                          else f"{path}.{f.name}")]  # fmt: skip
    if isinstance(x, dict):
        return [p for k, v in x.items()
                for p in _nonfinite_paths(v, str(k) if not path else f"{path}.{k}")]  # fmt: skip
    if isinstance(x, (list, tuple)):
        return [p for v in x for p in _nonfinite_paths(v, path)]
    return []


def _documented(target: str, path: str) -> bool:
    return any(t == target and path.startswith(prefix) for t, prefix in DOCUMENTED_NONFINITE)


def _names(args) -> set[str]:
    """The argument names of a call, for judging whether a message names one."""
    out = set()

    def walk(x):
        if isinstance(x, dict):
            for k, v in x.items():
                if isinstance(k, str) and not k.startswith("_"):
                    out.add(k)
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)

    walk(args)
    out |= {"state", "q", "omega", "t", "u", "quaternion", "mu", "friction", "spec", "J",
            "height", "vx", "vy", "states", "models", "t_eval", "dt", "events", "rtol", "atol",
            "t_end", "method", "theta0", "omega3", "rate", "tau", "c0", "c1", "c2", "c3",
            "com", "store", "phi", "n", "m", "theta", "threads",
            # a pivot's and its damping's fields (drawn as plain data)
            "pivot", "damping", "amplitude", "phase", "position", "viscous", "drag", "dry",
            "pivot_radius"}  # fmt: skip
    return out


def classify(target: str, args, fn) -> tuple[str, str]:
    """Runs ``fn(args)``: (outcome, detail)."""
    import kreisel

    try:
        result = fn(args)
    except _CliError as e:
        return "clear", str(e)[:300]
    except kreisel.KreiselError as e:
        msg = str(e)
        names = _names(args)
        named = any(re.search(rf"(^|[^A-Za-z_0-9]){re.escape(n)}($|[^A-Za-z_0-9])", msg)
                    for n in names)  # fmt: skip
        return ("clear" if named else "unclear"), f"{type(e).__name__}: {msg[:300]}"
    except BaseException as e:  # noqa: BLE001 - PanicException derives from BaseException
        if type(e).__name__ == "PanicException":
            return "panic", str(e)[:300]
        if isinstance(e, KeyboardInterrupt):
            raise
        return "unclear", f"{type(e).__name__}: {str(e)[:300]}"
    if target == "simulate_many" and isinstance(result, dict):
        bad = _batch_nonfinite(result)
    else:
        bad = [p for p in _nonfinite_paths(result) if not _documented(target, p)]
    if bad:
        return "nan", f"non-finite at {bad[:5]}"
    return "clean", ""


# --------------------------------------------------------------------------------------
# drawing, the worker and the runner
# --------------------------------------------------------------------------------------


def draw_calls(targets, n_calls: int, *, derandomize: bool, seed: int = 0) -> list:
    """(target index, arguments) for about ``n_calls`` calls, shared by weight."""
    total = sum(t.weight for t in targets)
    calls = []
    for i, t in enumerate(targets):
        n = max(1, round(n_calls * t.weight / total))
        found = _collect(t.draw, n, derandomize, None if derandomize else seed + i)
        calls.extend((i, a) for a in found[:n])
    return calls


@contextlib.contextmanager
def _without_local_constants():
    """Hypothesis draws a share of its numbers from the constants of the local source code
    loaded at that moment (every imported module outside the installed packages). Which
    modules are loaded differs between `pytest tests/fuzz` and `make test`, and every edit of
    the code changes them, so the derandomised share would differ from run to run: here that
    pool is empty (Hypothesis's own pool of boundary values stays). Private to Hypothesis:
    where it is missing nothing is changed, and test_fuzz.py checks the share is repeatable."""
    try:
        from hypothesis.internal.conjecture import providers
    except ImportError:  # pragma: no cover
        yield
        return
    get = getattr(providers, "_get_local_constants", None)
    cache = getattr(getattr(providers, "CONSTANTS_CACHE", None), "cache", None)
    if get is None or not hasattr(providers, "Constants") or cache is None:  # pragma: no cover
        yield
        return
    providers._get_local_constants = providers.Constants
    cache.clear()
    try:
        yield
    finally:
        providers._get_local_constants = get
        cache.clear()


def _collect(strategy, n: int, derandomize: bool, seed) -> list:
    """Up to ``n`` examples of ``strategy``, drawn by hypothesis (derandomised: the same
    examples in every run)."""
    found = []

    @settings(max_examples=n, derandomize=derandomize, deadline=None, database=None,
              suppress_health_check=list(HealthCheck))  # fmt: skip
    @given(strategy)
    def collect(args):
        found.append(args)

    if seed is not None:
        collect = _seeded(collect, seed)
    if derandomize:
        with _without_local_constants():
            collect()
    else:
        collect()
    return found


def _seeded(fn, seed):
    from hypothesis import seed as hseed

    return hseed(seed)(fn)


def worker(calls_path: str, start: int, calm: bool):
    """Executes the calls from ``start``, one line per call start and end on stdout."""
    import warnings

    warnings.simplefilter("error")
    os.environ.setdefault("MPLBACKEND", "Agg")
    with open(calls_path, "rb") as fh:
        calls = pickle.load(fh)
    targets = all_targets(calm)
    out = os.fdopen(1, "w", buffering=1)
    for i in range(start, len(calls)):
        ti, args = calls[i]
        out.write(f"S {i}\n")
        outcome, detail = classify(targets[ti].name, args, targets[ti].call)
        out.write(f"E {i} {outcome} {json.dumps(detail)}\n")


def run_calls(calls, *, timeout: float, calm: bool = False, log=None) -> list:
    """Executes ``calls`` in worker processes: [(outcome, detail)] per call."""
    results = [None] * len(calls)
    fd, path = tempfile.mkstemp(suffix=".pkl")
    with os.fdopen(fd, "wb") as fh:
        pickle.dump(calls, fh)
    env = {**os.environ, "RUST_BACKTRACE": "0", "MPLBACKEND": "Agg"}
    start = 0
    try:
        while start < len(calls):
            proc = subprocess.Popen(
                [sys.executable, os.path.abspath(__file__), "--worker", path, str(start),
                 "calm" if calm else "all"],
                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env,
            )  # fmt: skip
            try:
                start = _follow(proc, results, start, timeout, log)
            finally:
                proc.stdout.close()
                if proc.poll() is None:
                    proc.kill()
                proc.wait()
    finally:
        os.unlink(path)
    return results


def _follow(proc, results, start, timeout, log) -> int:
    """Reads a worker's lines until it ends; returns where the next worker starts."""
    buf = b""
    current, since = None, time.monotonic()
    fd = proc.stdout.fileno()
    while True:
        wait = max(0.0, timeout - (time.monotonic() - since)) if current is not None else timeout
        ready, _, _ = select.select([fd], [], [], wait if current is not None else None)
        if not ready:
            proc.kill()
            proc.wait()
            results[current] = ("hang", f"no answer within {timeout} s")
            return current + 1
        chunk = os.read(fd, 65536)
        if not chunk:
            rc = proc.wait()
            if current is not None and results[current] is None:
                results[current] = ("crash", f"worker exited with {rc}")
                return current + 1
            return len(results)
        buf += chunk
        *lines, buf = buf.split(b"\n")
        for line in lines:
            kind, _, rest = line.decode().partition(" ")
            if kind == "S":
                current, since = int(rest), time.monotonic()
            elif kind == "E":
                i, outcome, detail = rest.split(" ", 2)
                results[int(i)] = (outcome, json.loads(detail))
                if log is not None and int(i) % 1000 == 0:
                    log(f"  {int(i)} calls")


def campaign(n_calls: int, *, derandomize: bool, seed: int = 0, timeout: float = 10.0,
             calm: bool = False, only=None, log=None):  # fmt: skip
    """Draws and runs about ``n_calls`` calls: (targets, calls, results)."""
    targets = all_targets(calm)
    if only is not None:
        keep = [t for t in targets if only(t)]
        targets = keep
    t0 = time.monotonic()
    calls = draw_calls(targets, n_calls, derandomize=derandomize, seed=seed)
    if log:
        log(f"drew {len(calls)} calls in {time.monotonic() - t0:.0f} s")
    # the worker rebuilds all targets: map indices to the full list
    everything = all_targets(calm)
    full = {t.name: i for i, t in enumerate(everything)}
    calls = [(full[targets[ti].name], a) for ti, a in calls]
    results = run_calls(calls, timeout=timeout, calm=calm, log=log)
    return everything, calls, results


def report(targets, calls, results, *, out=sys.stdout, examples=3):
    by_outcome = collections.Counter(r[0] for r in results)
    by_target = collections.defaultdict(collections.Counter)
    bad = collections.defaultdict(list)
    for (ti, args), (outcome, detail) in zip(calls, results):
        name = targets[ti].name
        by_target[name][outcome] += 1
        if outcome in BAD and len(bad[(name, outcome)]) < examples:
            bad[(name, outcome)].append((args, detail))
    print(f"{len(results)} calls", file=out)
    print("by outcome: " + ", ".join(f"{o} {by_outcome.get(o, 0)}" for o in OUTCOMES), file=out)
    width = max(len(n) for n in by_target)
    print(f"{'function':<{width}}  " + " ".join(f"{o:>7}" for o in OUTCOMES), file=out)
    for name in sorted(by_target):
        c = by_target[name]
        print(f"{name:<{width}}  " + " ".join(f"{c.get(o, 0):>7}" for o in OUTCOMES), file=out)
    if bad:
        print("\nbad outcomes (first reproducers):", file=out)
        for (name, outcome), items in sorted(bad.items()):
            stack = (
                " [simulation stack]"
                if targets[[t.name for t in targets].index(name)].stack
                else ""
            )
            for args, detail in items:
                print(f"- {name} {outcome}{stack}: {detail}\n    {args!r}"[:2500], file=out)
    return by_outcome, by_target, bad


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    ap.add_argument("--calls", type=int, default=100_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds per call")
    ap.add_argument("--derandomize", action="store_true")
    ap.add_argument("--calm", action="store_true", help="leave out the known hangs")
    ap.add_argument("--json", help="write the counts here")
    args = ap.parse_args(argv)
    if args.worker:
        worker(args.worker[0], int(args.worker[1]), args.worker[2] == "calm")
        return 0
    t0 = time.monotonic()
    targets, calls, results = campaign(
        args.calls, derandomize=args.derandomize, seed=args.seed, timeout=args.timeout,
        calm=args.calm, log=lambda m: print(m, file=sys.stderr, flush=True),
    )  # fmt: skip
    by_outcome, by_target, _ = report(targets, calls, results)
    print(f"\n{time.monotonic() - t0:.0f} s", file=sys.stderr)
    if args.json:
        with open(args.json, "w") as fh:
            counts = {k: dict(v) for k, v in by_target.items()}
            json.dump({"outcomes": dict(by_outcome), "targets": counts}, fh, indent=1)
    stack = {t.name for t in targets if t.stack}
    outside = sum(c[o] for n, c in by_target.items() if n not in stack for o in BAD)
    return 1 if outside else 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    sys.exit(main())
