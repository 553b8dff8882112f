"""Heavy tops: any rigid body on a fixed frictionless pivot."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Union

import numpy as np

from . import _core
from ._errors import ParameterError, ParameterTypeError
from ._state import EulerState
from ._validate import real
from ._validate import vector as _vector

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .pivots import Pivot, PivotDamping

    AnyRigidState = Union[EulerState, "RigidState"]


@dataclass(frozen=True)
class RigidState:
    """Orientation and angular velocity of a rigid body.

    Attributes
    ----------
    quaternion : ndarray, shape (4,)
        Unit quaternion (w, x, y, z), scalar first, rotating body-frame vectors into the
        space frame.
    omega : ndarray, shape (3,)
        Angular velocity in the body frame (rad/s).

    Examples
    --------
    >>> from kreisel import LagrangeTop
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> s = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 150.0])
    >>> s.quaternion.tolist(), s.omega.tolist()
    ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 150.0])
    >>> s
    RigidState(quaternion=[1, 0, 0, 0], omega=[0, 0, 150])
    """

    quaternion: np.ndarray = field(repr=False)
    omega: np.ndarray = field(repr=False)

    def __repr__(self) -> str:
        q = ", ".join(f"{x:.10g}" for x in self.quaternion)
        w = ", ".join(f"{x:.10g}" for x in self.omega)
        return f"RigidState(quaternion=[{q}], omega=[{w}])"

    def __eq__(self, other) -> bool:
        return (
            isinstance(other, RigidState)
            and np.array_equal(self.quaternion, other.quaternion)
            and np.array_equal(self.omega, other.omega)
        )

    def __hash__(self) -> int:
        return hash((tuple(self.quaternion), tuple(self.omega)))


def _binary_scaled(q: list[float]) -> list[float]:
    """``q`` times the power of two that puts its largest component in [0.5, 1): exact, so
    the normalised quaternion is the same bit for bit, and neither its squares overflow
    (``[1e300, 1e300, 0, 0]``) nor underflow (``[1e-300, 0, 0, 0]``)."""
    big = max(abs(x) for x in q)
    if big == 0.0:
        return q
    e = math.frexp(big)[1]
    return [math.ldexp(x, -e) for x in q]


def euler_state(theta, phi, psi, theta_dot, phi_dot, psi_dot) -> EulerState:
    """A validated EulerState."""
    s = EulerState(
        theta=real("theta", theta),
        phi=real("phi", phi),
        psi=real("psi", psi),
        theta_dot=real("theta_dot", theta_dot),
        phi_dot=real("phi_dot", phi_dot),
        psi_dot=real("psi_dot", psi_dot),
    )
    _core.check_euler_state(s.as_tuple())
    return s


def rigid_state(state) -> RigidState:
    """The RigidState of an EulerState or RigidState."""
    if isinstance(state, RigidState):
        return state
    if isinstance(state, EulerState):
        q, w = _core.rigid_from_euler(*state.as_tuple())
        return RigidState(np.array(q), np.array(w))
    raise ParameterTypeError(
        f"state must be an EulerState or RigidState (from top.state(...) or "
        f"top.state_from_quaternion(...)), not {type(state).__name__}"
    )


def drive(heavy_native, pivot, damping):
    """(pivot, damping, native driven top or None) of a top's ``pivot`` and ``damping``
    arguments: a top given a pivot other than Fixed, or any damping, is a driven top."""
    from .pivots import Fixed, PivotDamping, _check_damping, _check_pivot

    p, d = _check_pivot(pivot), _check_damping(damping)
    if isinstance(p, Fixed) and d is None:
        return p, None, None
    dd = d if d is not None else PivotDamping()
    native = _core.DrivenTop(
        heavy_native, *p._native_args(), dd.viscous, dd.drag, dd.dry, dd.pivot_radius
    )
    return p, d, native


def drive_repr(pivot, damping) -> str:
    """The ``, pivot=..., damping=...`` part of a top's repr (empty for a fixed, undamped one)."""
    from .pivots import Fixed

    out = "" if isinstance(pivot, Fixed) else f", pivot={pivot!r}"
    return out + ("" if damping is None else f", damping={damping!r}")


class _Rigid:
    """What every top on a pivot shares: states and invariants through the native top."""

    __slots__ = ()

    if TYPE_CHECKING:

        def _heavy_native(self) -> _core.HeavyTop: ...

        _driven: _core.DrivenTop | None
        _pivot: Any
        _damping: Any

    @property
    def pivot(self):
        """How the pivot moves (:mod:`kreisel.pivots`; ``Fixed()`` by default)."""
        return self._pivot

    @property
    def damping(self):
        """The torques at the pivot (:class:`kreisel.PivotDamping`), or None."""
        return self._damping

    @property
    def driven(self) -> bool:
        """Whether the pivot moves or is damped (then only simulation applies, no integrals)."""
        return self._driven is not None

    def _fixed_only(self, what: str) -> None:
        """Refuses an exact or integral-based method for a driven or damped top."""
        if self._driven is not None:
            raise ParameterError(
                f"{type(self).__name__}.{what} applies to the top on a fixed, undamped pivot; "
                f"this one has{drive_repr(self._pivot, self._damping)[1:]}: its energy and "
                "momenta are not integrals. Simulate it (kreisel.simulate: the column "
                "'balance' = energy + dissipated - work_by_pivot is its constant)"
            )

    def state(
        self,
        theta: float,
        phi: float = 0.0,
        psi: float = 0.0,
        theta_dot: float = 0.0,
        phi_dot: float = 0.0,
        psi_dot: float = 0.0,
    ) -> EulerState:
        """A state in Euler angles (z-x-z, rad) and their rates (rad/s); theta in [0, pi].

        Examples
        --------
        >>> from kreisel import HeavyTop
        >>> top = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
        >>> top.state(theta=0.3, psi_dot=5.0)
        EulerState(theta=0.3, phi=0.0, psi=0.0, theta_dot=0.0, phi_dot=0.0, psi_dot=5.0)
        """
        return euler_state(theta, phi, psi, theta_dot, phi_dot, psi_dot)

    def state_from_quaternion(self, q: ArrayLike, omega: ArrayLike) -> RigidState:
        """A state from a quaternion (w, x, y, z; normalised here, components of any finite
        size; not zero) and the body angular velocity ``omega`` (rad/s, shape (3,), each
        component of magnitude at most 1e100).

        Examples
        --------
        >>> from kreisel import HeavyTop
        >>> top = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
        >>> top.state_from_quaternion([2.0, 0.0, 0.0, 0.0], [0.0, 0.0, 5.0])
        RigidState(quaternion=[1, 0, 0, 0], omega=[0, 0, 5])
        """
        w = [_core.check_rate(f"omega[{i}]", x) for i, x in enumerate(_vector("omega", omega, 3))]
        qq, ww = self._heavy_native().check_rigid(_binary_scaled(_vector("q", q, 4)), w)
        return RigidState(np.array(qq), np.array(ww))

    def _native_model(self):
        return self._driven if self._driven is not None else self._heavy_native()

    def _native_state(self, state) -> list:
        """The flat numbers (q, omega) the core takes."""
        s = rigid_state(state)
        return [*np.asarray(s.quaternion, dtype=float), *np.asarray(s.omega, dtype=float)]

    def invariants(self, state: AnyRigidState) -> dict[str, float]:
        """``{"energy", "Mz"}`` and, where they are integrals, ``"M3"`` and
        ``"kovalevskaya"``, of a state.

        Examples
        --------
        >>> from kreisel import HeavyTop
        >>> top = HeavyTop(I1=2.0, I2=2.0, I3=1.0, m=1.0, com=[0.0, 0.0, 0.1])
        >>> inv = top.invariants(top.state(theta=0.3, psi_dot=5.0))
        >>> {k: round(v, 6) for k, v in inv.items()}
        {'energy': 13.437185, 'Mz': 4.776682, 'M3': 5.0}
        """
        self._fixed_only("invariants")
        s = rigid_state(state)
        out = dict(self._heavy_native().invariants(list(s.quaternion), list(s.omega)))
        for name, value in out.items():
            if not math.isfinite(value):
                w = ", ".join(f"{x:g}" for x in s.omega)
                raise ParameterError(
                    f"state with omega = [{w}] is not allowed here: its {name} is {value}, "
                    "not a finite number, for this top"
                )
        return out

    def lyapunov(
        self,
        state: AnyRigidState,
        t_end: float,
        *,
        tau: float = 1.0,
        d0: float = 1e-9,
        direction: ArrayLike = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0),
        rtol: float = 1e-10,
        atol: float = 1e-12,
    ) -> LyapunovEstimate:
        """The largest Lyapunov exponent (1/s) of the motion from ``state``, by Benettin's
        renormalisation of a second motion started ``d0`` away along ``direction`` (a
        6-vector: body rotation vector, rad, and omega change, rad/s), every ``tau`` s, both
        integrated with DOP853 at ``rtol``, ``atol``.

        Positive for a chaotic top; for an integrable one (Euler, Lagrange, Kovalevskaya)
        separations grow linearly, so the running estimate decays like ln(t)/t. Returns the
        estimate at ``t_end`` and its history (``t``, ``running``) to judge convergence.

        Examples
        --------
        >>> from kreisel import HeavyTop
        >>> top = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
        >>> est = top.lyapunov(top.state(theta=0.3, psi_dot=5.0), 2.0, tau=0.5)
        >>> round(est.exponent, 6), est.t.tolist()
        (0.24136, [0.5, 1.0, 1.5, 2.0])
        """
        s = rigid_state(state)
        out = self._native_model().lyapunov(
            list(s.quaternion),
            list(s.omega),
            real("t_end", t_end),
            real("tau", tau),
            real("d0", d0),
            _vector("direction", direction, 6),
            real("rtol", rtol),
            real("atol", atol),
        )
        return LyapunovEstimate(out["exponent"], out["t"], out["running"])


@dataclass(frozen=True)
class LyapunovEstimate:
    """A largest-Lyapunov-exponent estimate: ``exponent`` (1/s) at the end, and the
    running estimate ``running`` at the renormalisation times ``t``."""

    exponent: float
    t: np.ndarray = field(repr=False)
    running: np.ndarray = field(repr=False)


class HeavyTop(_Rigid):
    """A rigid body on a fixed frictionless pivot under uniform gravity.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments of inertia about the pivot (kg m^2), obeying the triangle
        inequality and the parallel-axis theorem.
    m : float
        Mass (kg), > 0.
    com : sequence of 3 floats
        Centre of mass in the body frame, measured from the pivot (m).
    g : float
        Gravitational acceleration (m/s^2), >= 0.
    pivot : kreisel.pivots.Fixed, Harmonic or Path, optional
        How the pivot moves (default: at rest at the origin).
    damping : kreisel.PivotDamping, optional
        Viscous, air-drag and dry friction torques at the pivot.

    A top with a moving pivot or damping is simulated like any other (:func:`simulate`,
    :func:`simulate_many`, :meth:`lyapunov`, sweeps); its trajectories carry the pivot's
    position, its force on the top and the power it puts in, the power dissipated, and
    ``balance = energy + dissipated - work_by_pivot``, which is constant. Source: theory:
    driven and damped tops.

    ``kind`` tells the integrable cases: ``"euler"`` (no torque), ``"lagrange"`` (I1 == I2,
    centre of mass on the 3-axis), ``"kovalevskaya"`` (I1 == I2 == 2 I3, centre of mass in the
    equatorial plane), else ``"general"`` (generically chaotic).
    Source: theory: heavy top.

    Examples
    --------
    >>> top = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
    >>> top.kind
    'general'
    >>> s = top.state(theta=0.3, psi_dot=5.0)
    >>> {k: round(v, 6) for k, v in top.invariants(s).items()}
    {'energy': 38.437185, 'Mz': 14.330047}
    """

    __slots__ = ("_I", "_m", "_com", "_g", "_native", "_pivot", "_damping", "_driven")

    def __init__(
        self,
        I1: float,
        I2: float,
        I3: float,
        m: float,
        com: ArrayLike,
        g: float = 9.81,
        pivot: Pivot | None = None,
        damping: PivotDamping | None = None,
    ) -> None:
        inertia = [real("I1", I1), real("I2", I2), real("I3", I3)]
        mass, grav = real("m", m), real("g", g)
        c = _vector("com", com, 3)
        self._native = _core.HeavyTop(inertia[0], inertia[1], inertia[2], mass, c, grav)
        self._I, self._m, self._com, self._g = tuple(inertia), mass, tuple(c), grav
        self._pivot, self._damping, self._driven = drive(self._native, pivot, damping)

    def _heavy_native(self):
        return self._native

    I1 = property(lambda self: self._I[0], doc="Moment about body axis 1 (kg m^2).")
    I2 = property(lambda self: self._I[1], doc="Moment about body axis 2 (kg m^2).")
    I3 = property(lambda self: self._I[2], doc="Moment about body axis 3 (kg m^2).")
    m = property(lambda self: self._m, doc="Mass (kg).")
    com = property(lambda self: np.array(self._com), doc="Centre of mass, body frame (m).")
    g = property(lambda self: self._g, doc="Gravitational acceleration (m/s^2).")
    kind = property(lambda self: self._native.kind, doc="The integrable case, or 'general'.")

    def __repr__(self) -> str:
        c = ", ".join(repr(x) for x in self._com)
        return (
            f"HeavyTop(I1={self._I[0]!r}, I2={self._I[1]!r}, I3={self._I[2]!r}, "
            f"m={self._m!r}, com=[{c}], g={self._g!r}"
            f"{drive_repr(self._pivot, self._damping)})"
        )

    def _repr_html_(self) -> str:
        from ._html import table

        c = ", ".join(f"{x:.6g}" for x in self._com)
        rows = [
            ("I1, I2, I3", ", ".join(f"{x:.6g}" for x in self._I), "kg m²",
             "principal moments about the pivot"),
            ("m", self._m, "kg", "mass"),
            ("com", f"[{c}]", "m", "centre of mass, body frame, from the pivot"),
            ("g", self._g, "m/s²", "gravitational acceleration"),
        ]  # fmt: skip
        if self._driven is not None:
            rows.append(("pivot", repr(self._pivot), "", "how the pivot moves"))
            rows.append(("damping", repr(self._damping), "", "torques at the pivot"))
        return table(f"Heavy top (kind: {self.kind})", repr(self), rows)

    def __eq__(self, other) -> bool:
        return isinstance(other, HeavyTop) and repr(self) == repr(other)

    def __hash__(self) -> int:
        return hash(repr(self))
