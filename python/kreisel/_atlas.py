"""Where a play top ends: its stationary motions, their stability, and the (alpha, gamma) atlas.

Conventions of theory: play top: ``u = cos(theta)`` (u = 1 upright, G above
the sphere's centre), ``alpha = s/rho``, ``gamma = A/C``, ``J_beta = rho sqrt(C m g s)``,
``J_R(u) = J_beta N(u)/sqrt(D(u))`` with ``N(u) = (alpha + u)^2 + gamma (1 - u^2)`` and
``D(u) = alpha + (1 - gamma) u``. At a fixed Jellett integral J the stationary motions are
the stationary points of ``V(u) = J^2 / (2 rho^2 C N(u)) + m g (rho + s u)``, the least
energy a state with that J and u can have; the stable ones are its minima. Source:
Rauch-Wojciechowski, Skoldstam and Glad, Regul. Chaotic Dyn. 10 (2005) 333 (regular precession,
stability of stationary motions, the atlas).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _core
from ._validate import floats, real


@dataclass(frozen=True)
class RegularPrecession:
    """A regular precession: rolling without slip, G at rest, theta constant.

    Attributes
    ----------
    Omega : float
        Precession rate about the vertical (rad/s), > 0.
    omega3 : float
        Axial spin ``omega . e3 = Omega (u + alpha)`` (rad/s).
    psi_dot : float
        Spin rate ``alpha Omega`` (rad/s).
    J : float
        Jellett's integral, ``J_R(u)`` (kg m^2/s).
    u : float
        Inclination ``cos(theta)``.

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> rp = pt.regular_precession(0.5)
    >>> type(rp).__name__, round(rp.u, 6), f"{rp.J:.6e}"
    ('RegularPrecession', 0.5, '1.402435e-06')
    """

    Omega: float
    omega3: float
    psi_dot: float
    J: float
    u: float


@dataclass(frozen=True)
class StationaryMotion:
    """A stationary motion at a given Jellett integral.

    Attributes
    ----------
    kind : str
        ``"upright"`` (u = 1), ``"hanging"`` (u = -1) or ``"precession"`` (-1 < u < 1).
    u : float
        Inclination ``cos(theta)``.
    stable : bool
        Whether the energy V(u) at fixed J has a minimum there.
    Omega : float
        Rate about the vertical in ``omega = Omega (ez + alpha e3)`` (rad/s), signed as J;
        for a regular precession its precession rate, for a vertical spin the split that
        continues the precessions (the total spin is ``omega3``).
    omega3 : float
        Axial spin ``Omega (u + alpha)`` (rad/s).
    energy : float
        Its energy V(u) (J).

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> m = pt.stationary_motions(1.344380e-05)[-1]
    >>> m.kind, m.u, m.stable, round(m.omega3, 6)
    ('upright', 1.0, True, 149.375556)
    """

    kind: str
    u: float
    stable: bool
    Omega: float
    omega3: float
    energy: float


@dataclass(frozen=True)
class Classification:
    """Where a top lies in the (alpha, gamma) plane (theory: play top).

    Attributes
    ----------
    type : str
        ``"Ia"``, ``"Ib"``, ``"IIa"`` or ``"IIb"`` (theory: the atlas of play tops).
    zone : int
        1..8: 1 = Ia, 2 = Ib; in IIa 3 (u_m > 1), 4 and 5 (u_m in [-1, 1] with
        J_R(-1) > J_R(1) and < J_R(1)), 6 (u_m < -1); in IIb 7 (u_m <= 1), 8 (u_m > 1).
    fig3 : str
        Area of the vertical-axis diagram (theory: the atlas of play tops): ``"a"``
        (gamma >= 1 + alpha), ``"b"`` (gamma <= 1 - alpha) or ``"c"`` (in between: tippe
        tops).

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> c = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015).classify()
    >>> c.type, c.zone, c.fig3
    ('IIb', 7, 'b')
    """

    type: str
    zone: int
    fig3: str


@dataclass(frozen=True)
class Prediction:
    """Where a play top can end under sliding friction.

    Attributes
    ----------
    J : float
        The state's Jellett integral (kg m^2/s), kept by any force at the contact.
    stable : list of StationaryMotion
        Every stable stationary motion at this J, by ascending u.
    ending : StationaryMotion or None
        The stable motion the top must end in, where exactly one is within reach: energy
        never increases and every state has ``E >= V(u)``, so u stays in the connected part
        of ``{u : V(u) <= E}`` that holds the state's u. None where two are within reach.

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> p = pt.predict(pt.state(theta=0.1, psi_dot=150.0))
    >>> f"{p.J:.6e}", len(p.stable), p.ending.kind
    ('1.344380e-05', 2, 'upright')
    """

    J: float
    stable: list
    ending: StationaryMotion | None


def _theory(pt):
    """The native stationary-motion theory of a play top."""
    return _core.PlayStability(pt._native)


def _motion(t) -> StationaryMotion:
    kind, u, stable, omega, omega3, energy = t
    return StationaryMotion(kind, u, bool(stable), omega, omega3, energy)


def J_R(pt, u):
    """``J_R(u) = J_beta N(u)/sqrt(D(u))`` (kg m^2/s), the ``|J|`` of the regular precession at
    inclination u in [-1, 1]; nan where none exists (D(u) <= 0). Same shape as ``u``."""
    arr = floats("u", u)
    out = _theory(pt).j_r(np.ascontiguousarray(arr.ravel())).reshape(arr.shape)
    return float(out) if out.ndim == 0 else out


def stationary_energy(pt, u, J):
    """``V(u) = J^2 / (2 rho^2 C N(u)) + m g (rho + s u)`` (J): the least energy of a state
    with Jellett integral J at inclination u. Same shape as ``u``."""
    arr = np.asarray(u, dtype=float)
    out = (
        _theory(pt)
        .stationary_energy(real("J", J), np.ascontiguousarray(arr.ravel()))
        .reshape(arr.shape)
    )
    return float(out) if out.ndim == 0 else out


def regular_precession(pt, u) -> RegularPrecession:
    """The regular precession at inclination ``u`` (with J > 0). Raises ParameterError where
    none exists: |u| > 1, or ``D(u) <= 0`` (where the precession rate would be infinite)."""
    u = real("u", u)
    om, w3, pd, j = _theory(pt).regular_precession(u)
    return RegularPrecession(Omega=om, omega3=w3, psi_dot=pd, J=j, u=u)


def stationary_motions(pt, J) -> list:
    """Every stationary motion at Jellett integral ``J`` (kg m^2/s), by ascending u: the
    hanging spin, the regular precessions with ``J_R(u) = abs(J)`` (0, 1 or 2), the upright spin;
    each with its stability."""
    return [_motion(t) for t in _theory(pt).stationary_motions(real("J", J))]


def u_m(pt):
    """u_m, the minimum of J_R on the real line; None for type I tops
    (``gamma >= 1 - alpha^2``), where J_R is increasing wherever it is real."""
    return _core.play_u_m(pt.alpha, pt.gamma)


def classify_alpha_gamma(alpha, gamma) -> Classification:
    """The classification of a top with ``alpha = s/rho > 0`` and ``gamma = A/C > 0``."""
    t, z, f = _core.play_classify(real("alpha", alpha), real("gamma", gamma))
    return Classification(type=t, zone=int(z), fig3=f)


def classify(pt) -> Classification:
    """The classification of a play top: type, zone 1..8 and the area of Fig. 3."""
    return classify_alpha_gamma(pt.alpha, pt.gamma)


def zones(alpha, gamma):
    """Zones (1..8; 0 where alpha or gamma is not > 0) of arrays of (alpha, gamma), broadcast."""
    a, g = np.broadcast_arrays(np.asarray(alpha, dtype=float), np.asarray(gamma, dtype=float))
    z = _core.play_zones(np.ascontiguousarray(a.ravel()), np.ascontiguousarray(g.ravel()))
    return z.reshape(a.shape)


def zone_boundaries(alpha):
    """The zone boundaries as gamma(alpha), nan where a curve does not exist.

    Returns a dict of arrays shaped like ``alpha``: ``"u_m=1 lower"``, ``"u_m=1 upper"``
    (the closed curve u_m = 1, alpha < 7 - 4 sqrt(3)), ``"u_m=-1"``, ``"J_R(1)=J_R(-1)"``
    (both inside type IIa), and the lines ``"1+alpha"``, ``"1-alpha"``, ``"1-alpha^2"``.
    """
    a = np.asarray(alpha, dtype=float)
    lo, hi, um, eq = _core.play_zone_boundaries(np.ascontiguousarray(a.ravel()))
    out: dict[str, np.ndarray] = {
        "u_m=1 lower": lo,
        "u_m=1 upper": hi,
        "u_m=-1": um,
        "J_R(1)=J_R(-1)": eq,
    }
    out = {k: v.reshape(a.shape) for k, v in out.items()}
    out["1+alpha"] = 1.0 + a
    out["1-alpha"] = 1.0 - a
    out["1-alpha^2"] = 1.0 - a * a
    return out


def predict(pt, state) -> Prediction:
    """The stable stationary motions at a state's Jellett integral and the one it must end
    in, where that is unique (sliding friction keeps J and only lowers the energy)."""
    j, e = pt.jellett(state), pt.energy(state)
    u0 = float(np.clip(_u_of(state), -1.0, 1.0))
    stable, _reach, ending = _theory(pt).predict(j, e, u0)
    return Prediction(
        J=j,
        stable=[_motion(t) for t in stable],
        ending=None if ending is None else _motion(ending),
    )


def _u_of(state) -> float:
    w, x, y, z = np.asarray(state.quaternion, dtype=float) / np.linalg.norm(state.quaternion)
    # z-component of the body 3-axis in space.
    return float(1.0 - 2.0 * (x * x + y * y))


def frictionless_nutation(pt, state):
    """(u_min, u_max, period, lagrange_period) of the frictionless motion from a contact
    state; see :meth:`PlayTop.frictionless_turning_points`."""
    packed = pt._check(state)
    return _theory(pt).frictionless_nutation(packed)


def frictionless_turning_points(pt, state):
    """(theta_min, theta_max) (rad) of the frictionless play top from a contact state."""
    u_lo, u_hi, _, _ = frictionless_nutation(pt, state)
    return float(np.arccos(np.clip(u_hi, -1, 1))), float(np.arccos(np.clip(u_lo, -1, 1)))


def frictionless_nutation_period(pt, state) -> float:
    """Nutation period (s) of the frictionless play top from a contact state."""
    return float(frictionless_nutation(pt, state)[2])
