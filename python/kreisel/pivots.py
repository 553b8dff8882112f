"""How the pivot of a heavy top moves, and the friction at it.

A heavy top (:class:`kreisel.HeavyTop`, :class:`kreisel.LagrangeTop`) takes ``pivot=`` one of

- :class:`Fixed` (the default): the pivot rests at the origin;
- :class:`Harmonic`: ``r_O(t) = amplitude * cos(omega t + phase)``, with ``amplitude`` a
  3-vector and ``phase`` one number or one per component, so vertical, horizontal, oblique
  and elliptic shaking are one class;
- :class:`Path`: a sampled path, interpolated by a septic spline that starts and ends at
  rest;

and ``damping=`` a :class:`PivotDamping`. In the frame that moves with the pivot (it does
not turn) the top feels gravity and the inertial force ``-m a_O(t)`` at its centre of mass;
the pivot's force on the top does work at the rate ``R . v_O``, and
``energy + dissipated - work_by_pivot`` is constant along every run.
Source: theory: driven and damped tops.

Examples
--------
>>> import numpy as np
>>> from kreisel import LagrangeTop, PivotDamping, pivots, simulate
>>> shaker = pivots.Harmonic([0.0, 0.0, 0.05], omega=20.0)
>>> round(shaker.period, 6)
0.314159
>>> top = LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0, pivot=shaker,
...                   damping=PivotDamping(viscous=0.01))
>>> traj = simulate(top, top.state(theta=0.5, psi_dot=2.0), 2.0)
>>> bool(np.ptp(traj.balance) < 1e-9 * np.abs(traj.energy).max())  # E + D - W, constant
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ._errors import ParameterError
from ._validate import real
from ._validate import vector as _vector

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["Fixed", "Harmonic", "Path", "Pivot", "PivotDamping", "pivot_from_dict"]


# The largest pivot excursion taken (m): a pivot shaken by more than this is no top's.
LENGTH_MAX = 1e6
# The fastest shaking taken (rad/s, 160 kHz): every period takes an integrator several steps.
OMEGA_MAX = 1e6


def _vector3(name: str, value, unit: str = "m") -> tuple[float, float, float]:
    """Three finite numbers (the heavy top's vector check) of magnitude at most LENGTH_MAX
    (in ``unit``)."""
    out = _vector(name, value, 3)
    for i, x in enumerate(out):
        if abs(x) > LENGTH_MAX:
            raise ParameterError(
                f"{name}[{i}] = {x!r} is not allowed: it must be at most {LENGTH_MAX:g} {unit} "
                "in magnitude"
            )
    return tuple(out)  # type: ignore[return-value]


def _times(t) -> tuple[np.ndarray, bool]:
    arr = np.asarray(t, dtype=np.float64)
    return np.atleast_1d(arr), arr.ndim == 0


class _Pivot:
    """What every pivot has: its motion at given times."""

    __slots__ = ()

    def _kin(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _one(self, t, k: int) -> np.ndarray:
        ts, scalar = _times(t)
        out = self._kin(ts)[k]
        return out[0] if scalar else out

    def position(self, t: ArrayLike) -> np.ndarray:
        """Pivot position (m, space frame, z up) at time(s) ``t`` (s): (3,) or (n, 3)."""
        return self._one(t, 0)

    def velocity(self, t: ArrayLike) -> np.ndarray:
        """Pivot velocity (m/s) at time(s) ``t``: (3,) or (n, 3)."""
        return self._one(t, 1)

    def acceleration(self, t: ArrayLike) -> np.ndarray:
        """Pivot acceleration (m/s^2) at time(s) ``t``: (3,) or (n, 3)."""
        return self._one(t, 2)

    @property
    def period(self) -> float | None:
        """The pivot's period (s), or None for a motion that is not periodic."""
        return None

    @property
    def moves(self) -> bool:
        """Whether the pivot moves at all."""
        return True

    def _native_args(self) -> tuple:
        raise NotImplementedError

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this pivot (``[pivot]``)."""
        raise NotImplementedError


@dataclass(frozen=True, eq=True)
class Fixed(_Pivot):
    """A pivot at rest at the origin (the default).

    Examples
    --------
    >>> from kreisel import pivots
    >>> pivots.Fixed().position(1.0).tolist()
    [0.0, 0.0, 0.0]
    """

    def _kin(self, t):
        z = np.zeros((t.size, 3))
        return z, z.copy(), z.copy()

    @property
    def moves(self) -> bool:
        """False: a fixed pivot does not move."""
        return False

    def _native_args(self) -> tuple:
        return ("fixed", [0.0, 0.0, 0.0], 0.0, [0.0, 0.0, 0.0], [], [])

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this pivot (``[pivot]``).

        Examples
        --------
        >>> from kreisel import pivots
        >>> pivots.Fixed().to_dict()
        {'kind': 'fixed'}
        """
        return {"kind": "fixed"}


@dataclass(frozen=True, eq=True, init=False)
class Harmonic(_Pivot):
    """A pivot shaken harmonically: ``r_O(t) = amplitude * cos(omega t + phase)``.

    Parameters
    ----------
    amplitude : sequence of 3 floats
        Amplitude vector (m, space frame, z up): ``[0, 0, a]`` shakes vertically,
        ``[a, 0, 0]`` horizontally.
    omega : float
        Angular frequency (rad/s), in [0, 1e6].
    phase : float or sequence of 3 floats
        Phase at t = 0 (rad): one number moves every component in step (a straight
        stroke); one per component gives an ellipse, e.g. ``amplitude=[a, a, 0]``,
        ``phase=[0, -pi/2, 0]`` circles the pivot counter-clockwise seen from above.

    Examples
    --------
    >>> from kreisel import pivots
    >>> p = pivots.Harmonic([0.0, 0.0, 0.01], omega=100.0)
    >>> p.position(0.0).tolist(), round(float(p.acceleration(0.0)[2]), 6)
    ([0.0, 0.0, 0.01], -100.0)
    """

    amplitude: tuple[float, float, float]
    omega: float
    phase: float | tuple[float, float, float]

    def __init__(self, amplitude: ArrayLike, omega: float, phase: ArrayLike = 0.0) -> None:
        amp = _vector3("amplitude", amplitude)
        w = real("omega", omega)
        if not 0.0 <= w <= 1e9:
            raise ParameterError(
                f"omega = {w!r} is not allowed: it must be an angular frequency in [0, 1e9] rad/s"
            )
        object.__setattr__(self, "amplitude", amp)
        object.__setattr__(self, "omega", w)
        if np.ndim(phase) == 0:
            ph: float | tuple[float, float, float] = real("phase", phase)
        else:
            ph = _vector3("phase", phase, "rad")
        object.__setattr__(self, "phase", ph)

    @property
    def _phases(self) -> list[float]:
        return list(self.phase) if isinstance(self.phase, tuple) else [self.phase] * 3

    def __repr__(self) -> str:
        a = ", ".join(repr(x) for x in self.amplitude)
        ph = (
            "[" + ", ".join(repr(x) for x in self.phase) + "]"
            if isinstance(self.phase, tuple)
            else repr(self.phase)
        )
        return f"Harmonic(amplitude=[{a}], omega={self.omega!r}, phase={ph})"

    def _kin(self, t):
        arg = self.omega * t[:, None] + np.asarray(self._phases)
        a = np.asarray(self.amplitude)
        c, s = np.cos(arg), np.sin(arg)
        return a * c, -a * self.omega * s, -a * self.omega**2 * c

    @property
    def period(self) -> float | None:
        """2 pi / omega (s); None for omega = 0."""
        return 2.0 * math.pi / self.omega if self.omega > 0 else None

    @property
    def moves(self) -> bool:
        """Whether the pivot moves (omega > 0 and an amplitude)."""
        return self.omega > 0 and any(x != 0.0 for x in self.amplitude)

    def _native_args(self) -> tuple:
        return ("harmonic", list(self.amplitude), self.omega, self._phases, [], [])

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this pivot (``[pivot]``).

        Examples
        --------
        >>> from kreisel import pivots
        >>> pivots.Harmonic([0, 0, 0.01], 50.0).to_dict()
        {'kind': 'harmonic', 'amplitude': [0.0, 0.0, 0.01], 'omega': 50.0, 'phase': 0.0}
        """
        return {
            "kind": "harmonic",
            "amplitude": list(self.amplitude),
            "omega": self.omega,
            "phase": list(self.phase) if isinstance(self.phase, tuple) else self.phase,
        }


class Path(_Pivot):
    """A sampled pivot path, interpolated three times continuously differentiably.

    The interpolant is the septic spline through the samples with zero velocity,
    acceleration and jerk at the first and the last sample (scipy's ``make_interp_spline``
    with ``k=7``). The top's equations need the pivot's acceleration, which must be
    continuous for an integrator to keep its order and for the energy balance to hold; the
    splittings also integrate its rate (the jerk, through the time's conjugate momentum),
    which must be continuous too; and the path is constant outside its samples, so these
    derivatives must vanish at both ends to join it. A cubic spline would be C2 inside but
    its acceleration would jump at the ends; a quintic one clamped in velocity and
    acceleration leaves a jump of the jerk there, which a fixed-step splitting crossing the
    path's end measured as a first-order error of the balance (5e-4 of the energy at
    dt = 2e-4 s). Inside, the septic spline is C6. Start and end the recording with the pivot
    at rest for the interpolant to follow it there.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times (s), strictly increasing, n >= 2.
    position : array_like, shape (n, 3)
        Pivot positions (m, space frame, z up).

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel import pivots
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> p = pivots.Path(t, np.c_[0 * t, 0 * t, 0.01 * np.sin(np.pi * t) ** 3])
    >>> round(float(p.position(0.5)[2]), 6), p.velocity(2.0).tolist()
    (0.01, [0.0, 0.0, 0.0])
    """

    __slots__ = ("_t", "_x", "_ppoly", "_d1", "_d2")

    def __init__(self, t: ArrayLike, position: ArrayLike) -> None:
        try:
            ts = np.asarray(t, dtype=np.float64)
            xs = np.asarray(position, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(
                "t and position are not allowed: they must be numbers (t of shape (n,), "
                "position of shape (n, 3))"
            ) from None
        if ts.ndim != 1 or ts.size < 2:
            raise ParameterError(
                f"t has shape {ts.shape}, which is not allowed: it must be (n,) with n >= 2"
            )
        if xs.shape != (ts.size, 3):
            raise ParameterError(
                f"position has shape {xs.shape}, which is not allowed: it must be "
                f"({ts.size}, 3), one (x, y, z) per sample time"
            )
        bad = np.flatnonzero(~np.isfinite(ts))
        if bad.size:
            raise ParameterError(f"t[{bad[0]}] = {ts[bad[0]]!r} is not allowed: it must be finite")
        bad = np.argwhere(~(np.abs(xs) <= LENGTH_MAX))
        if bad.size:
            i, j = bad[0]
            raise ParameterError(
                f"position[{i}, {j}] = {xs[i, j]!r} is not allowed: it must be finite and at "
                f"most {LENGTH_MAX:g} m in magnitude"
            )
        steps = np.diff(ts)
        bad = np.flatnonzero(steps <= 0)
        if bad.size:
            i = bad[0] + 1
            raise ParameterError(
                f"t[{i}] = {ts[i]!r} is not allowed: sample times must increase strictly "
                f"(t[{i - 1}] = {ts[i - 1]!r})"
            )
        from scipy.interpolate import PPoly, make_interp_spline

        ends = [(1, 0.0), (2, 0.0), (3, 0.0)]
        cs = []
        try:
            for d in range(3):  # PPoly.from_spline takes one coordinate at a time
                spline = make_interp_spline(ts, xs[:, d], k=7, bc_type=(ends, ends))
                pp = PPoly.from_spline(spline)
                # keep the intervals between samples (from_spline pads with repeated knots)
                keep = (pp.x[:-1] >= ts[0]) & (pp.x[:-1] < ts[-1]) & (np.diff(pp.x) > 0)
                cs.append(pp.c[:, keep])
                x = np.r_[pp.x[:-1][keep], ts[-1]]
            c = np.stack(cs, axis=-1)
        except (ValueError, np.linalg.LinAlgError):  # a singular or overflowing system
            c = np.array([np.nan])
        if not np.isfinite(c).all():
            gap = float(np.diff(ts).min())
            raise ParameterError(
                f"t is not allowed: its samples are too close (the smallest step is {gap!r} s) "
                "for the spline through them to be computed in floating point"
            )
        self._t, self._x = ts, xs
        self._ppoly = PPoly(c, x, extrapolate=False)
        self._d1 = self._ppoly.derivative(1)
        self._d2 = self._ppoly.derivative(2)

    def __repr__(self) -> str:
        return f"Path(t=<{self._t.size} samples in [{self._t[0]:g}, {self._t[-1]:g}] s>)"

    def __eq__(self, other) -> bool:
        return (
            isinstance(other, Path)
            and np.array_equal(self._t, other._t)
            and np.array_equal(self._x, other._x)
        )

    def __hash__(self) -> int:
        return hash((self._t.tobytes(), self._x.tobytes()))

    @property
    def t(self) -> np.ndarray:
        """The sample times (s)."""
        return self._t.copy()

    @property
    def samples(self) -> np.ndarray:
        """The sampled positions (m), (n, 3)."""
        return self._x.copy()

    def _kin(self, t):
        lo, hi = self._t[0], self._t[-1]
        inside = (t >= lo) & (t < hi)
        p = np.empty((t.size, 3))
        p[t < lo] = self._x[0]
        p[t >= hi] = self._x[-1]
        v = np.zeros((t.size, 3))
        a = np.zeros((t.size, 3))
        if inside.any():
            ti = t[inside]
            p[inside] = self._ppoly(ti)
            v[inside] = self._d1(ti)
            a[inside] = self._d2(ti)
        return p, v, a

    @property
    def moves(self) -> bool:
        """Whether the samples move at all."""
        return bool(np.ptp(self._x, axis=0).any())

    def _native_args(self) -> tuple:
        c = np.ascontiguousarray(self._ppoly.c)
        return ("path", [0.0, 0.0, 0.0], 0.0, [0.0, 0.0, 0.0], list(self._ppoly.x), list(c.ravel()))

    def to_dict(self) -> dict[str, Any]:
        """The TOML table of this pivot (``[pivot]``): its samples.

        Examples
        --------
        >>> from kreisel import pivots
        >>> pivots.Path([0.0, 1.0], [[0, 0, 0], [0, 0, 0.01]]).to_dict()["t"]
        [0.0, 1.0]
        """
        return {"kind": "path", "t": self._t.tolist(), "position": self._x.tolist()}


@dataclass(frozen=True, eq=True, init=False)
class PivotDamping:
    """Torques at the pivot: viscous, air drag and dry friction in a ball joint.

    Parameters
    ----------
    viscous : float
        Viscous coefficient (N m s): a torque ``-viscous * omega``.
    drag : float
        Air-drag coefficient (N m s^2): a torque ``-drag * |omega| * omega``.
    dry : float
        Dry (Coulomb) friction coefficient of the ball joint (1): a torque of magnitude up
        to ``dry * pivot_radius * |R|`` against the rotation, R the pivot's force on the top;
        the top sticks when it is at rest relative to the pivot and the torque that keeps it
        so is within that bound. ``dry * pivot_radius * m * |com| / min(I)`` must be < 1
        (else the friction would not be determined by the motion, as in Painleve's paradox).
    pivot_radius : float
        Radius of the ball joint (m).

    All are >= 0; omega is the angular velocity relative to the pivot (which does not turn).

    Examples
    --------
    >>> from kreisel import PivotDamping
    >>> PivotDamping(viscous=1e-4)
    PivotDamping(viscous=0.0001, drag=0.0, dry=0.0, pivot_radius=0.0)
    """

    viscous: float
    drag: float
    dry: float
    pivot_radius: float

    def __init__(
        self, viscous: float = 0.0, drag: float = 0.0, dry: float = 0.0, pivot_radius: float = 0.0
    ) -> None:
        for name, value in (
            ("viscous", viscous),
            ("drag", drag),
            ("dry", dry),
            ("pivot_radius", pivot_radius),
        ):
            v = real(name, value)
            # the core's range of every parameter: 0, or within [1e-100, 1e100]
            if not (v == 0.0 or 1e-100 <= v <= 1e100):
                raise ParameterError(
                    f"{name} = {v!r} is not allowed: it must be 0 or a finite number within "
                    "[1e-100, 1e+100]"
                )
            object.__setattr__(self, name, abs(v))

    def __repr__(self) -> str:
        return (
            f"PivotDamping(viscous={self.viscous!r}, drag={self.drag!r}, dry={self.dry!r}, "
            f"pivot_radius={self.pivot_radius!r})"
        )

    @property
    def any(self) -> bool:
        """Whether any torque acts."""
        return self.viscous > 0 or self.drag > 0 or self.dry * self.pivot_radius > 0

    def to_dict(self) -> dict[str, float]:
        """The TOML table of this damping (``[damping]``).

        Examples
        --------
        >>> from kreisel import PivotDamping
        >>> PivotDamping(drag=1e-6).to_dict()
        {'viscous': 0.0, 'drag': 1e-06, 'dry': 0.0, 'pivot_radius': 0.0}
        """
        return {
            "viscous": self.viscous,
            "drag": self.drag,
            "dry": self.dry,
            "pivot_radius": self.pivot_radius,
        }


def pivot_from_dict(d: dict[str, Any]) -> _Pivot:
    """A pivot from its TOML table (``kind`` = "fixed", "harmonic" or "path"; a table with an
    ``amplitude`` is harmonic without saying so).

    Examples
    --------
    >>> from kreisel.pivots import pivot_from_dict
    >>> pivot_from_dict({"kind": "harmonic", "amplitude": [0, 0, 0.01], "omega": 100.0})
    Harmonic(amplitude=[0.0, 0.0, 0.01], omega=100.0, phase=0.0)
    """
    if not isinstance(d, dict):
        raise ParameterError(f"the pivot must be a table, not {type(d).__name__}")
    kind = d.get("kind", "harmonic" if "amplitude" in d else "fixed")
    keys = {
        "fixed": {"kind"},
        "harmonic": {"kind", "amplitude", "omega", "phase"},
        "path": {"kind", "t", "position"},
    }
    if kind not in keys:
        raise ParameterError(f'kind = {kind!r} is not allowed: use "fixed", "harmonic" or "path"')
    extra = sorted(set(d) - keys[kind])
    if extra:
        raise ParameterError(
            f"{extra[0]} is not allowed for a {kind} pivot: its fields are "
            + ", ".join(sorted(keys[kind]))
        )
    if kind == "fixed":
        return Fixed()
    if kind == "harmonic":
        missing = [k for k in ("amplitude", "omega") if k not in d]
        if missing:
            raise ParameterError(f"{missing[0]} is missing: a harmonic pivot needs it")
        return Harmonic(d["amplitude"], d["omega"], d.get("phase", 0.0))
    missing = [k for k in ("t", "position") if k not in d]
    if missing:
        raise ParameterError(f"{missing[0]} is missing: a path pivot needs it")
    return Path(d["t"], d["position"])


# Any pivot (for annotations).
Pivot = _Pivot


def _check_pivot(pivot) -> _Pivot:
    """The pivot argument of a top, checked (None: fixed)."""
    if pivot is None:
        return Fixed()
    if isinstance(pivot, _Pivot):
        return pivot
    raise ParameterError(
        f"pivot = {pivot!r} is not allowed: use kreisel.pivots.Fixed(), Harmonic(...) or Path(...)"
    )


def _check_damping(damping) -> PivotDamping | None:
    """The damping argument of a top, checked (None: none)."""
    if damping is None or isinstance(damping, PivotDamping):
        return damping
    raise ParameterError(
        f"damping = {damping!r} is not allowed: use kreisel.PivotDamping(viscous=..., "
        "drag=..., dry=..., pivot_radius=...)"
    )
