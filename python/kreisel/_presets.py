"""Built-in tops for the command line (``--preset NAME``, ``kreisel presets``).

Each preset is what a ``kreisel run`` TOML file holds: a ``[top]`` table (with its kind), a
``[state]`` and a ``[simulation]`` table, in SI units and radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import bodies

# The toy top of the demo and the README: 100 g, centre of mass 4 cm above the tip, a disc of
# radius 2 cm (I3 = m R^2 / 2); sleeping threshold 262 rad/s.
_TOY = {"I1": 1.75e-4, "I3": 2.0e-5, "m": 0.1, "l": 0.04, "g": 9.81}
# slow steady precession of the toy top at theta = 0.6 rad, omega3 = 300 rad/s (rad/s)
_TOY_SLOW = 8.131813622444362
# A gyroscope: a 200 g rotor disc of radius 3.2 cm (I3 = m R^2/2) 4 cm from the pivot along
# its axle (I1 = m R^2/4 + m l^2); steady precession at theta = pi/2 with omega3 = 600 rad/s.
_GYRO = {"I1": 3.712e-4, "I3": 1.024e-4, "m": 0.2, "l": 0.04, "g": 9.81}
_GYRO_RATE = 1.27734375
# The tippe top with its peg: Leine and Glocker's (Eur. J. Mech. A/Solids 22 (2003) 193),
# theory: bodies of revolution: a ball of 15 mm with a peg of 5 mm radius whose centre is 16 mm
# from the
# centre of mass, Coulomb-Contensou friction mu = 0.3 over a patch of 0.5 mm.
# The ball alone ("tippe-ball"), of the demo and BENCHMARKS case T1: a 20 g ball of radius
# 2 cm, centre of mass 6 mm off the centre (alpha = 0.3), C = 0.4 m rho^2, A = 0.8 C
# (gamma = 0.8).
_TIPPE_C = 0.4 * 0.02 * 0.02**2
# A toy top on a spherical tip: 100 g, centre of mass 3 cm above the tip's centre, C = 2e-5,
# A = 1.6e-5 kg m^2 about the centre of mass, Coulomb friction mu = 0.05 (a smooth floor).
_TIPPED = {"m": 0.1, "A": 1.6e-5, "C": 2.0e-5, "s": 0.03, "g": 9.81, "friction": "coulomb",
           "mu": 0.05}  # fmt: skip


# A 100 g rod 20 cm long, 1 cm thick, on a pivot at one end: I1 = m L^2/3, I3 = m r^2/2 (the
# Kapitza top: inverted, it is stable on a vertically shaken pivot when (a omega)^2 >
# 2 g I1 / (m l) = 2.6 m^2/s^2; theory: driven and damped tops).
_ROD = {"I1": 0.1 * 0.2**2 / 3, "I3": 0.1 * 0.005**2 / 2, "m": 0.1, "l": 0.1, "g": 9.81}


@dataclass(frozen=True)
class Preset:
    """A built-in top: its name, one line of what it is, and its three tables."""

    name: str
    summary: str
    top: dict
    state: dict
    simulation: dict = field(default_factory=dict)
    pivot: dict = field(default_factory=dict)
    damping: dict = field(default_factory=dict)

    @property
    def kind(self) -> str:
        return self.top["kind"]


def _body_table(top) -> dict:
    """The [top] table of a play top built by kreisel.bodies: its numbers, its parts, its
    friction law."""
    import dataclasses

    from ._play import CoulombContensou

    law = top.friction
    table = {"kind": "play", "m": top.m, "A": top.A, "C": top.C,
             "shape": [{"kind": p.kind, **dataclasses.asdict(p)} for p in top.shape]}  # fmt: skip
    if isinstance(law, CoulombContensou):
        table.update(friction="coulomb_contensou", mu=law.mu, patch_radius=law.radius)
    else:
        table.update(friction="coulomb", mu=law.mu)
    if top.rolling_resistance:
        table["rolling_resistance"] = top.rolling_resistance
    return table


def _disk_preset(name, summary, radius, thickness, mass, rolling) -> Preset:
    """A disk started on its rolling with the centre at rest at 0.3 rad
    (kreisel.bodies.disk_rolling_rates)."""
    top = bodies.disk(radius, thickness, mass, rolling_resistance=rolling)
    omega, psi_dot = bodies.disk_rolling_rates(top, 0.3)
    return Preset(name, summary, _body_table(top),
                  {"theta": 0.3, "phi_dot": omega, "psi_dot": psi_dot},
                  {"t_end": 3.0, "rtol": 1e-8, "samples": 3001})  # fmt: skip


PRESETS = {
    p.name: p
    for p in (
        Preset(
            "toy",
            "toy top: 100 g, c.o.m. 4 cm above the tip, spun at 400 rad/s, released at 0.5 rad: "
            "nutation in cusps",
            {"kind": "lagrange", **_TOY},
            {"theta": 0.5, "psi_dot": 400.0},
            {"t_end": 2.0},
        ),
        Preset(
            "gyroscope",
            "gyroscope: 200 g rotor 4 cm out on a horizontal axle, 600 rad/s, steady precession",
            {"kind": "lagrange", **_GYRO},
            {"theta": 1.5707963267948966, "phi_dot": _GYRO_RATE, "psi_dot": 600.0},
            {"t_end": 5.0},
        ),
        Preset(
            "sleeping",
            "sleeping top: the toy top at 400 rad/s (> 262 rad/s) released 3 deg off vertical",
            {"kind": "lagrange", **_TOY},
            {"theta": 0.05, "psi_dot": 400.0},
            {"t_end": 2.0},
        ),
        Preset(
            "waves",
            "nutation in waves: the toy top at 0.6 rad, 300 rad/s, pushed along its precession",
            {"kind": "lagrange", **_TOY},
            {"theta": 0.6, "phi_dot": round(0.3 * _TOY_SLOW, 4), "psi_dot": 300.0},
            {"t_end": 1.0},
        ),
        Preset(
            "cusps",
            "nutation in cusps: the toy top released at rest at 0.6 rad, spun at 300 rad/s",
            {"kind": "lagrange", **_TOY},
            {"theta": 0.6, "psi_dot": 300.0},
            {"t_end": 1.0},
        ),
        Preset(
            "loops",
            "nutation in loops: the toy top at 0.6 rad, 300 rad/s, pushed against its precession",
            {"kind": "lagrange", **_TOY},
            {"theta": 0.6, "phi_dot": round(-0.5 * _TOY_SLOW, 4), "psi_dot": 300.0},
            {"t_end": 1.0},
        ),
        Preset(
            "kovalevskaya",
            "Kovalevskaya top: I1 = I2 = 2 I3, pivot 2 cm from the c.o.m. in its equator plane",
            {
                "kind": "heavy",
                "I1": 2e-3,
                "I2": 2e-3,
                "I3": 1e-3,
                "m": 0.5,
                "com": [0.02, 0.0, 0.0],
                "g": 9.81,
            },  # fmt: skip
            {"quaternion": [1.0, 0.2, 0.0, 0.0], "omega": [1.0, -2.0, 3.0]},
            {"t_end": 20.0, "method": "dop853"},
        ),
        Preset(
            "tippe",
            "tippe top with its peg (Leine & Glocker 2003): turns over onto the peg at 1.37 s, "
            "falls back onto its ball at 4.55 s",
            {
                "kind": "play",
                "m": 6e-3,
                "A": 8e-7,
                "C": 7e-7,
                "shape": [
                    {"radius": 0.015, "z": -0.003, "name": "ball"},
                    {"radius": 0.005, "z": -0.016, "name": "peg"},
                ],
                "g": 9.81,
                "friction": "coulomb_contensou",
                "mu": 0.3,
                "patch_radius": 5e-4,
            },  # fmt: skip
            {"theta": 3.0415926535897933, "psi_dot": 180.0},
            {"t_end": 8.0, "rtol": 1e-9},
        ),
        Preset(
            "tippe-ball",
            "tippe top, its ball alone: 20 g, r = 2 cm, alpha 0.3, gamma 0.8, 150 rad/s: turns "
            "over at 2.65 s",
            {
                "kind": "play",
                "m": 0.02,
                "A": 0.8 * _TIPPE_C,
                "C": _TIPPE_C,
                "s": 0.006,
                "rho": 0.02,
                "g": 9.81,
                "friction": "viscous",
                "mu": 1.0,
            },  # fmt: skip
            {"theta": 3.0415926535897933, "psi_dot": 150.0},
            {"t_end": 8.0, "rtol": 1e-9},
        ),
        Preset(
            "egg",
            "hard-boiled egg (kreisel.bodies.egg): spun on its side at 80 rad/s, it rises to "
            "u = 0.88 in 3 s",
            _body_table(bodies.egg()),
            {"theta": math.pi / 2 - 0.1, "phi_dot": 80.0},
            {"t_end": 3.0, "rtol": 1e-8},
        ),
        _disk_preset(
            "euler-disk",
            "Euler's disk (kreisel.bodies.disk, steel): rolls, precesses faster, lies flat at "
            "0.96 s",
            0.0375,
            0.0125,
            0.434,
            2e-3,
        ),  # fmt: skip
        _disk_preset(
            "coin",
            "a spinning coin (kreisel.bodies.disk, a 5.67 g quarter) settling flat at 1.70 s",
            0.01213,
            0.00175,
            0.00567,
            2e-4,
        ),  # fmt: skip
        Preset(
            "toy-top",
            "toy top (kreisel.bodies.toy_top) below its sleeping threshold: precesses, falls "
            "on its shoulder at 2.25 s, rolls to rest at 4.02 s",
            _body_table(bodies.toy_top(rolling_resistance=1e-4)),
            {"theta": 0.3, "psi_dot": 120.0},
            {"t_end": 6.0, "rtol": 1e-8, "samples": 3001},
        ),
        Preset(
            "rate-gyro",
            "rate gyro: 150 g rotor balanced to 1 mm, 2000 rad/s: its axis drifts at 7 mrad/s",
            {
                "kind": "heavy",
                "I1": 6e-5,
                "I2": 6e-5,
                "I3": 1e-4,
                "m": 0.15,
                "com": [0.0, 0.0, 0.001],
                "g": 9.81,
            },  # fmt: skip
            {"theta": 1.5707963267948966, "psi_dot": 2000.0},
            # 0.2 s: a hundred nutations (1.9 ms each), sampled 20 times each
            {"t_end": 0.2, "method": "splitting4", "dt": 1e-5, "samples": 4001},
        ),
        Preset(
            "damped-gyroscope",
            "toy gyroscope with friction: the 600 rad/s rotor slows (I3/c = 5 s) and the "
            "gyroscope falls",
            {"kind": "lagrange", **_GYRO},
            {"theta": 1.5707963267948966, "phi_dot": _GYRO_RATE, "psi_dot": 600.0},
            {"t_end": 12.0, "method": "dop853", "rtol": 1e-9, "samples": 4001},
            damping={"viscous": _GYRO["I3"] / 5.0, "drag": 2e-9},
        ),
        Preset(
            "kapitza",
            "Kapitza's top: a 20 cm rod without spin stands inverted on a pivot shaken 1 cm "
            "up and down at 200 rad/s",
            {"kind": "lagrange", **_ROD},
            {"theta": 0.1},
            {"t_end": 3.0, "method": "dop853", "rtol": 1e-9, "samples": 3001},
            pivot={"kind": "harmonic", "amplitude": [0.0, 0.0, 0.01], "omega": 200.0},
        ),
        Preset(
            "blunt",
            "blunt tip: a toy top on a 1 cm ball tip (alpha 3), Coulomb mu 0.05: it hops, then "
            "rises upright",
            {"kind": "play", **_TIPPED, "rho": 0.01},
            {"theta": 0.3, "phi_dot": 6.5, "psi_dot": 300.0},
            {"t_end": 5.0},
        ),
        Preset(
            "pointed",
            "pointed tip: the same top on a 0.5 mm tip (alpha 60), precessing like a Lagrange top",
            {"kind": "play", **_TIPPED, "rho": 0.0005},
            {"theta": 0.3, "phi_dot": 6.5, "psi_dot": 300.0},
            {"t_end": 5.0},
        ),
    )
}
