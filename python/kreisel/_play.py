"""The play top: a symmetric top with a spherical tip on a plane, with friction."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from . import _atlas, _core
from ._errors import ParameterError, ParameterTypeError
from ._validate import real
from ._validate import vector as _vector
from .shapes import Part, Sphere, _named

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    from ._atlas import Classification, Prediction, RegularPrecession, StationaryMotion


def _native_law(law, make) -> None:
    """Converts mu and lets the core check it and build the law (kept as ``_native``)."""
    mu = real("mu", law.mu)
    object.__setattr__(law, "mu", mu)
    object.__setattr__(law, "_native", make(mu))


@dataclass(frozen=True)
class Coulomb:
    """Coulomb friction: ``|F_t| = mu N`` against the slip while slipping; rolling without slip
    while the needed force stays within ``|F_t| <= mu N`` (true stick-slip).

    Examples
    --------
    >>> from kreisel import Coulomb, PlayTop
    >>> Coulomb(mu=0.2)
    Coulomb(mu=0.2)
    >>> PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015, friction=Coulomb(0.2)).friction
    Coulomb(mu=0.2)
    """

    mu: float = 0.3
    _native: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _native_law(self, _core.Friction.coulomb)

    def __reduce__(self):  # the native law is made again, not pickled
        return (type(self), (self.mu,))


@dataclass(frozen=True)
class Viscous:
    """Viscous friction: tangential force -mu N v_T at the contact (mu in s/m).

    Examples
    --------
    >>> from kreisel import PlayTop, Viscous
    >>> Viscous(mu=0.5)
    Viscous(mu=0.5)
    >>> PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015, friction=Viscous(0.5)).friction
    Viscous(mu=0.5)
    """

    mu: float = 1.0
    _native: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _native_law(self, _core.Friction.viscous)

    def __reduce__(self):
        return (type(self), (self.mu,))


@dataclass(frozen=True)
class Frictionless:
    """No tangential force at the contact.

    Examples
    --------
    >>> from kreisel import Frictionless, PlayTop
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015, friction=Frictionless())
    >>> pt.friction
    Frictionless()
    """

    _native: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_native", _core.Friction.none())

    def __reduce__(self):
        return (type(self), ())


@dataclass(frozen=True)
class CoulombContensou:
    """Coulomb-Contensou friction: Coulomb friction over a circular contact patch of radius
    ``radius`` (m), sliding and drilling sharing one budget through the elliptic force
    reservoir ``|F|^2 + (M/Rbar)^2 <= (mu N)^2``, ``Rbar = 3 pi radius / 16`` (Leine & Glocker,
    Eur. J. Mech. A/Solids 22 (2003) 193-216; theory: several parts). While the contact slides or
    drills, ``F = -mu N v / D`` and ``M = -mu N Rbar^2 w_n / D`` with
    ``D = sqrt(|v|^2 + Rbar^2 w_n^2)``: a spinning contact meets an almost viscous resistance to
    a small slip. It sticks when neither sliding nor drilling, while force and torque stay in
    the ellipse. ``radius = 0`` is :class:`Coulomb` (the same results, bit for bit). Applied at
    every contact part; at impacts the friction impulse is Coulomb's (the patch's drilling
    impulse, at most ``mu Rbar`` times the normal impulse, is left out).

    Examples
    --------
    >>> from kreisel import CoulombContensou, PlayTop
    >>> CoulombContensou(mu=0.3, radius=5e-4)
    CoulombContensou(mu=0.3, radius=0.0005)
    >>> PlayTop(m=6e-3, A=8e-7, C=7e-7, s=0.003, rho=0.015,
    ...         friction=CoulombContensou(0.3, 5e-4)).friction.radius
    0.0005
    """

    mu: float = 0.3
    radius: float = 5e-4
    _native: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        mu, radius = real("mu", self.mu), real("radius", self.radius)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "_native", _core.Friction.coulomb_contensou(mu, radius))

    @property
    def rbar(self) -> float:
        """The effective patch radius ``3 pi radius / 16`` (m)."""
        return 3.0 * np.pi * self.radius / 16.0

    def __reduce__(self):
        return (type(self), (self.mu, self.radius))


_LAWS = (Coulomb, Viscous, Frictionless, CoulombContensou)


@dataclass(frozen=True)
class PlayState:
    """State of a play top.

    Attributes
    ----------
    quaternion : ndarray (4,)
        Orientation (w, x, y, z), body 3-axis = e3 (from the sphere centre to the centre of
        mass).
    omega : ndarray (3,)
        Angular velocity, body frame (rad/s).
    com : ndarray (3,)
        Position of the centre of mass (m).
    com_velocity : ndarray (3,)
        Its velocity (m/s).

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> s = pt.state(theta=0.0, psi_dot=150.0)
    >>> s.quaternion.tolist(), s.omega.tolist()
    ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 150.0])
    >>> [round(float(x), 6) for x in s.com], s.com_velocity.tolist()
    ([0.0, 0.0, 0.018], [0.0, 0.0, 0.0])
    """

    quaternion: np.ndarray = field(repr=False)
    omega: np.ndarray = field(repr=False)
    com: np.ndarray = field(repr=False)
    com_velocity: np.ndarray = field(repr=False)

    def _packed(self):
        return (
            list(self.quaternion),
            list(self.omega),
            list(self.com),
            list(self.com_velocity),
        )

    def __repr__(self) -> str:
        def f(a):
            return "[" + ", ".join(f"{x:.10g}" for x in a) + "]"

        return (
            f"PlayState(quaternion={f(self.quaternion)}, omega={f(self.omega)}, "
            f"com={f(self.com)}, com_velocity={f(self.com_velocity)})"
        )


def _state(packed) -> PlayState:
    return PlayState(*(np.array(x, dtype=float) for x in packed))


class PlayTop:
    """A symmetric top on a horizontal plane: a spherical tip, or any union of contact parts.

    Parameters
    ----------
    m : float
        Mass (kg).
    A, C : float
        Equatorial and axial moments of inertia about the centre of mass (kg m^2),
        0 < C <= 2 A.
    s : float
        Distance from the centre of the tip sphere to the centre of mass along the figure
        axis (m), >= 0.
    rho : float
        Radius of the tip sphere (m), > 0.
    g : float
        Gravitational acceleration (m/s^2).
    friction : Coulomb, Viscous, Frictionless or CoulombContensou
        Tangential force law at every contact.
    shape : list of kreisel.shapes.Sphere, Spheroid or Torus, optional
        The contact parts (between 1 and 4), instead of ``s`` and ``rho``: give exactly one
        of the two. ``PlayTop(m, A, C, s, rho)`` means ``shape=[Sphere(rho, z=-s,
        name="tip")]``. The atlas and the stationary motions use the first part, and need it
        to be a sphere of positive radius at or below G (``z <= 0``).
    restitution : float
        Coefficient of restitution of impacts after a flight, in [0, 1].
    rolling_resistance, drilling_resistance : float
        Lengths (m) of small loss torques, ``-delta N`` against the rolling and the drilling
        rotation.
    air_drag : float
        A torque ``-air_drag omega`` (N m s).
    stick_threshold : float
        The contact model's stick threshold, a share of the top's speed scale
        ``l |omega| + |v| + sqrt(g l)`` (``l`` its reach), in (0, 1e-3]: a sliding part sticks
        where its slip (and, under Coulomb-Contensou friction, its drilling ``rbar |w_n|``)
        falls to it. 1e-9 by default. A setting of the model, not of the integration: a run
        at a tighter ``rtol`` keeps it; a run too loose to resolve it (``rtol`` above a tenth
        of it) sticks at the slip it resolves, ``10 rtol`` of the speed scale (theory: play
        top, contact thresholds).

    Conventions: theory: play top (u = 1 upright, alpha = s/rho, gamma = A/C,
    Jellett's J = L.(s e3 + rho ez)). Source: Rauch-Wojciechowski,
    Skoldstam and Glad, Regul. Chaotic Dyn. 10 (2005) 333.

    Examples
    --------
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> s = pt.state(theta=0.1, psi_dot=150.0)
    >>> print(f"{pt.jellett(s):.6e} kg m^2/s")
    1.344380e-05 kg m^2/s
    >>> pt.classify()
    Classification(type='IIb', zone=7, fig3='b')
    """

    __slots__ = ("_p", "_friction", "_native", "_shape", "_given_shape")

    def __init__(
        self,
        m: float,
        A: float,
        C: float,
        s: float | None = None,
        rho: float | None = None,
        g: float = 9.81,
        friction: Coulomb | Viscous | Frictionless | CoulombContensou | None = None,
        restitution: float = 0.0,
        rolling_resistance: float = 0.0,
        drilling_resistance: float = 0.0,
        air_drag: float = 0.0,
        shape: list[Part] | tuple[Part, ...] | None = None,
        stick_threshold: float = 1e-9,
    ) -> None:
        friction = Coulomb(0.3) if friction is None else friction
        if not isinstance(friction, _LAWS):
            raise ParameterError(
                f"friction = {friction!r} is not allowed: use kreisel.Coulomb(mu), "
                "kreisel.Viscous(mu), kreisel.Frictionless() or kreisel.CoulombContensou(mu, "
                "radius)"
            )
        if (shape is None) == (s is None and rho is None) or (
            shape is None and (s is None or rho is None)
        ):
            raise ParameterError(
                f"s = {s!r}, rho = {rho!r}, shape = {shape!r} is not allowed: give either s and "
                "rho (a tip sphere) or shape (a list of parts), exactly one of the two"
            )
        parts = None if shape is None else _named(shape)
        if parts is not None:
            first = parts[0]
            tip = isinstance(first, Sphere) and first.radius > 0 and first.z <= 0
            s, rho = (-first.z, first.radius) if isinstance(first, Sphere) and tip else (0.0, 0.0)
        p = dict(
            m=real("m", m),
            A=real("A", A),
            C=real("C", C),
            s=real("s", s),
            rho=real("rho", rho),
            g=real("g", g),
            restitution=real("restitution", restitution),
            rolling_resistance=real("rolling_resistance", rolling_resistance),
            drilling_resistance=real("drilling_resistance", drilling_resistance),
            air_drag=real("air_drag", air_drag),
            stick_threshold=real("stick_threshold", stick_threshold),
        )
        rest = (p["restitution"], p["rolling_resistance"], p["drilling_resistance"], p["air_drag"])
        if parts is None:
            self._native = _core.PlayTop(
                p["m"], p["A"], p["C"], p["s"], p["rho"], p["g"], friction._native, *rest,  # type: ignore[arg-type]
            )  # fmt: skip
            self._shape: tuple[Part, ...] = (Sphere(p["rho"], -p["s"], "tip"),)
        else:
            try:
                self._native = _core.PlayTop.with_parts(
                    p["m"], p["A"], p["C"], [q._native() for q in parts], p["g"],
                    friction._native, *rest,  # type: ignore[arg-type]
                )  # fmt: skip
            except ParameterError as e:
                msg = str(e)
                for i, q in enumerate(parts):
                    msg = msg.replace(f"shape[{i}].", f"{type(q).__name__} {q.name!r}: ")
                raise ParameterError(msg) from None
            self._shape = parts
        if p["stick_threshold"] != 1e-9:
            self._native = self._native.with_stick_threshold(p["stick_threshold"])
        self._given_shape = parts is not None
        self._p, self._friction = p, friction

    def __getattr__(self, name):
        p = object.__getattribute__(self, "_p")
        if name in p:
            return p[name]
        raise AttributeError(f"PlayTop has no attribute {name!r}")

    friction = property(lambda self: self._friction, doc="The friction law.")
    shape = property(
        lambda self: self._shape,
        doc="The contact parts, each named (a tuple of kreisel.shapes parts).",
    )
    part_names = property(
        lambda self: tuple(q.name for q in self._shape), doc="The parts' names, in order."
    )
    alpha = property(lambda self: self._atlas_top()._native.alpha, doc="s / rho.")
    gamma = property(lambda self: self._native.gamma, doc="A / C.")
    J_beta = property(
        lambda self: self._atlas_top()._native.j_beta, doc="rho sqrt(C m g s) (kg m^2/s)."
    )

    def _atlas_top(self) -> PlayTop:
        """This top, where the one-sphere theory (atlas, stationary motions) applies to it: its
        first part a sphere of positive radius at or below G; else a ParameterError."""
        if self._p["rho"] > 0.0:
            return self
        first = self._shape[0]
        raise ParameterError(
            f"shape[0] = {first!r} is not allowed here: the atlas and the stationary motions "
            "are the theory of a tip sphere, and need the first part to be a sphere of positive "
            "radius at or below the centre of mass (z <= 0)"
        )

    u_m = property(
        lambda self: _atlas.u_m(self._atlas_top()),
        doc="Where J_R(u) has its minimum on the real line; None for type I tops.",
    )

    def __repr__(self) -> str:
        p = self._p
        extra = "".join(
            f", {k}={p[k]!r}"
            for k in ("restitution", "rolling_resistance", "drilling_resistance", "air_drag")
            if p[k] != 0.0
        )
        if p["stick_threshold"] != 1e-9:
            extra += f", stick_threshold={p['stick_threshold']!r}"

        if self._given_shape:
            return (
                f"PlayTop(m={p['m']!r}, A={p['A']!r}, C={p['C']!r}, shape={list(self._shape)!r}, "
                f"g={p['g']!r}, friction={self._friction!r}{extra})"
            )
        return (
            f"PlayTop(m={p['m']!r}, A={p['A']!r}, C={p['C']!r}, s={p['s']!r}, "
            f"rho={p['rho']!r}, g={p['g']!r}, friction={self._friction!r}{extra})"
        )

    def _repr_html_(self) -> str:
        from ._html import table

        p = self._p
        rows = [
            ("m", p["m"], "kg", "mass"),
            ("A", p["A"], "kg m²", "equatorial moment about the centre of mass"),
            ("C", p["C"], "kg m²", "axial moment"),
            ("s", p["s"], "m", "tip-sphere centre to centre of mass"),
            ("rho", p["rho"], "m", "radius of the tip sphere"),
            ("g", p["g"], "m/s²", "gravitational acceleration"),
            ("friction", repr(self._friction), "", "contact law (Coulomb mu 1, Viscous s/m)"),
            ("restitution", p["restitution"], "1", "of impacts after a flight"),
            ("rolling_resistance", p["rolling_resistance"], "m", "rolling loss length"),
            ("drilling_resistance", p["drilling_resistance"], "m", "drilling loss length"),
            ("air_drag", p["air_drag"], "N m s", "air torque per rad/s"),
            ("stick_threshold", p["stick_threshold"], "1", "share of the speed scale"),
        ]
        tippe = 1 - self.alpha < self.gamma < 1 + self.alpha
        notes = [
            f"alpha = s/rho = {self.alpha:.6g}, gamma = A/C = {self.gamma:.6g}"
            + (" (a tippe top: 1 - alpha < gamma < 1 + alpha)" if tippe else "")
        ]
        return table("Play top (spherical tip on a plane)", repr(self), rows, notes)

    def state(
        self,
        theta: float,
        phi: float = 0.0,
        psi: float = 0.0,
        theta_dot: float = 0.0,
        phi_dot: float = 0.0,
        psi_dot: float = 0.0,
        vx: float = 0.0,
        vy: float = 0.0,
        height: float | None = None,
    ) -> PlayState:
        """A state from Euler angles of e3 (z-x-z, rad) and their rates (rad/s), and the
        horizontal velocity of the centre of mass (m/s). In contact unless ``height`` (m, the
        gap between the tip and the floor, >= 0) is given: a dropped top.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> s = pt.state(theta=0.1, psi_dot=150.0)
        >>> [round(float(x), 6) for x in s.com]
        [0.0, 0.0, 0.017985]
        >>> round(float(pt.state(theta=0.1, height=0.01).com[2]), 6)
        0.027985
        """
        e = [
            real(k, v)
            for k, v in (("theta", theta), ("phi", phi), ("psi", psi), ("theta_dot", theta_dot),
                         ("phi_dot", phi_dot), ("psi_dot", psi_dot))
        ]  # fmt: skip
        h = None if height is None else real("height", height)
        return _state(self._native.state_from_euler(e, real("vx", vx), real("vy", vy), h))

    def state_from_quaternion(
        self,
        q: ArrayLike,
        omega: ArrayLike,
        vx: float = 0.0,
        vy: float = 0.0,
        height: float | None = None,
    ) -> PlayState:
        """A state from a quaternion (w, x, y, z; normalised here) and the body angular
        velocity (rad/s); contact and ``height`` as in :meth:`state`.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> s = pt.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 150.0])
        >>> s.omega.tolist(), [round(float(x), 6) for x in s.com]
        ([0.0, 0.0, 150.0], [0.0, 0.0, 0.018])
        """
        qq = _vector("q", q, 4)
        if not any(qq):
            raise ParameterError("q = [0, 0, 0, 0] is not allowed: a quaternion must be non-zero")
        h = None if height is None else real("height", height)
        w = _vector("omega", omega, 3)
        return _state(self._native.state(qq, w, real("vx", vx), real("vy", vy), h))

    def _check(self, state):
        if not isinstance(state, PlayState):
            raise ParameterTypeError(
                f"state must be a PlayState (from pt.state(...)), not {type(state).__name__}"
            )
        return state._packed()

    def _native_model(self):
        return self._native

    def _native_state(self, state) -> list:
        """The flat numbers (q, omega, com, com_velocity) the core takes."""
        return [x for part in self._check(state) for x in part]

    def jellett(self, state: PlayState) -> float:
        """Jellett's integral J = L.(s e3 + rho ez) (kg m^2/s).

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> f"{pt.jellett(pt.state(theta=0.1, psi_dot=150.0)):.6e}"
        '1.344380e-05'
        """
        return self._invariants(state)[0]

    def energy(self, state: PlayState) -> float:
        """Total energy (J): translation + rotation + m g z_G.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> round(pt.energy(pt.state(theta=0.1, psi_dot=150.0)), 6)
        0.058896
        """
        return self._invariants(state)[1]

    def _invariants(self, state):
        return self._native.invariants(self._check(state))

    # Stationary motions, stability and the atlas: thin wrappers of kreisel._atlas.

    def J_R(self, u: ArrayLike) -> float | NDArray[np.float64]:
        """``J_R(u) = J_beta N(u)/sqrt(D(u))`` (kg m^2/s): the ``|J|`` of the regular precession at
        inclination ``u = cos(theta)``; nan where none exists. Vectorised over ``u``.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> f"{pt.J_R(0.5):.6e}"
        '1.402435e-06'
        >>> [f"{x:.6e}" for x in pt.J_R([-0.5, 0.0, 0.5])]
        ['1.537681e-06', '1.323675e-06', '1.402435e-06']
        """
        return _atlas.J_R(self._atlas_top(), u)

    def regular_precession(self, u: float) -> RegularPrecession:
        """The regular precession at ``u`` (a :class:`RegularPrecession`; ParameterError where
        none exists).

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> rp = pt.regular_precession(0.5)
        >>> round(rp.Omega, 6), round(rp.omega3, 6), round(rp.psi_dot, 6)
        (17.155174, 12.008622, 3.431035)
        """
        return _atlas.regular_precession(self._atlas_top(), u)

    def stationary_motions(self, J: float) -> list[StationaryMotion]:
        """Every stationary motion at Jellett integral ``J`` (kg m^2/s), by ascending u, each a
        :class:`StationaryMotion` with its stability.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> [(m.kind, round(m.u, 6), m.stable) for m in pt.stationary_motions(1.344380e-05)]
        [('hanging', -1.0, True), ('precession', -0.994372, False), ('upright', 1.0, True)]
        """
        return _atlas.stationary_motions(self._atlas_top(), J)

    def classify(self) -> Classification:
        """Type (Ia, Ib, IIa, IIb), zone (1..8) and Fig. 3 area of this top
        (a :class:`Classification`).

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> pt.classify()
        Classification(type='IIb', zone=7, fig3='b')
        >>> PlayTop(m=0.02, A=7e-6, C=6e-6, s=0.004, rho=0.015).classify()
        Classification(type='Ia', zone=1, fig3='c')
        """
        return _atlas.classify(self._atlas_top())

    def predict(self, state: PlayState) -> Prediction:
        """The stable stationary motions at this state's Jellett integral and the one it must
        end in where that is unique (a :class:`Prediction`).

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> p = pt.predict(pt.state(theta=0.1, psi_dot=150.0))
        >>> [m.kind for m in p.stable], p.ending.kind, round(p.ending.u, 6)
        (['hanging', 'upright'], 'upright', 1.0)
        """
        return _atlas.predict(self._atlas_top(), state)

    def frictionless_turning_points(self, state: PlayState) -> tuple[float, float]:
        """(theta_min, theta_max) (rad) of the frictionless motion from a contact state: the
        roots of the gyro function, that of the Lagrange top with I1 = A, I3 = C, l = s.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> lo, hi = pt.frictionless_turning_points(pt.state(theta=0.5, psi_dot=150.0))
        >>> round(lo, 6), round(hi, 6)
        (0.5, 0.503035)
        """
        return _atlas.frictionless_turning_points(self._atlas_top(), state)

    def frictionless_nutation_period(self, state: PlayState) -> float:
        """Nutation period (s) of the frictionless motion from a contact state:
        ``udot^2 = F(u) / (1 + (m s^2/A)(1 - u^2))``, so longer than the Lagrange top's.

        Examples
        --------
        >>> from kreisel import PlayTop
        >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
        >>> round(pt.frictionless_nutation_period(pt.state(theta=0.5, psi_dot=150.0)), 6)
        0.033827
        """
        return _atlas.frictionless_nutation_period(self._atlas_top(), state)
