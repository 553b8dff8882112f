"""The Lagrange top: a heavy symmetric top on a fixed pivot, solved exactly."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import _core
from ._errors import ParameterTypeError
from ._heavy import _Rigid, drive, drive_repr
from ._state import EulerState, Invariants, NutationAnalysis
from ._trajectory import Deferred, Trajectory
from ._validate import floats, real, times

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    from .pivots import Pivot, PivotDamping


class LagrangeTop(_Rigid):
    """A heavy symmetric top on a fixed frictionless pivot, centre of mass on the figure axis.

    Parameters
    ----------
    I1 : float
        Moment of inertia about any axis through the pivot perpendicular to the figure
        axis (kg m^2). Must be > 0 and >= m l^2 (parallel-axis theorem).
    I3 : float
        Moment of inertia about the figure axis (kg m^2); 0 < I3 <= 2 I1.
    m : float
        Mass (kg), > 0.
    l : float
        Distance from the pivot to the centre of mass along the figure axis (m). 0 means no
        torque; negative puts the centre of mass below the pivot when theta = 0.
    g : float
        Gravitational acceleration (m/s^2), >= 0.
    pivot : kreisel.pivots.Fixed, Harmonic or Path, optional
        How the pivot moves (default: at rest at the origin).
    damping : kreisel.PivotDamping, optional
        Torques at the pivot.

    The exact methods (invariants, effective potential, analysis, the elliptic-function
    solution, steady precession, sleeping threshold) apply to the top on a fixed, undamped
    pivot only; a top with a moving pivot or damping refuses them and is simulated
    (theory: driven and damped tops).

    Euler angles are z-x-z with theta from the upward vertical, so V = m g l cos(theta).
    Source: Lagrange, *Mecanique analytique* (1788), and theory: Lagrange top.

    Examples
    --------
    >>> import numpy as np
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> s = top.state(theta=0.5, psi_dot=150.0)
    >>> s
    EulerState(theta=0.5, phi=0.0, psi=0.0, theta_dot=0.0, phi_dot=0.0, psi_dot=150.0)
    >>> inv = top.invariants(s)
    >>> print(f"E = {inv.E:.6f} J, Mz = {inv.Mz:.6f}, M3 = {inv.M3:.6f} kg m^2/s")
    E = 56.680454 J, Mz = 0.658187, M3 = 0.750000 kg m^2/s
    >>> a = top.analyse(s)
    >>> a.kind, round(a.theta_max, 6), round(a.nutation_period, 6)
    ('cusps', 0.51076, 0.106773)
    >>> traj = top.exact(s, np.linspace(0.0, 1.0, 5))
    >>> np.round(traj.theta, 6).tolist()
    [0.5, 0.508321, 0.507606, 0.500063, 0.508969]
    """

    __slots__ = ("_I1", "_I3", "_m", "_l", "_g", "_native", "_pivot", "_damping", "_driven")

    def __init__(
        self,
        I1: float,
        I3: float,
        m: float,
        l: float,  # noqa: E741
        g: float = 9.81,
        pivot: Pivot | None = None,
        damping: PivotDamping | None = None,
    ) -> None:
        values = {k: real(k, v) for k, v in dict(I1=I1, I3=I3, m=m, l=l, g=g).items()}
        self._native = _core.LagrangeTop(
            values["I1"], values["I3"], values["m"], values["l"], values["g"]
        )
        self._I1, self._I3, self._m, self._l, self._g = values.values()
        self._pivot, self._damping, self._driven = drive(self._heavy_native(), pivot, damping)

    I1 = property(lambda self: self._I1, doc="Transverse moment about the pivot (kg m^2).")
    I3 = property(lambda self: self._I3, doc="Axial moment (kg m^2).")
    m = property(lambda self: self._m, doc="Mass (kg).")
    l = property(lambda self: self._l, doc="Pivot to centre of mass (m).")  # noqa: E741
    g = property(lambda self: self._g, doc="Gravitational acceleration (m/s^2).")

    def __repr__(self) -> str:
        return (
            f"LagrangeTop(I1={self._I1!r}, I3={self._I3!r}, m={self._m!r}, "
            f"l={self._l!r}, g={self._g!r}{drive_repr(self._pivot, self._damping)})"
        )

    def _repr_html_(self) -> str:
        from ._html import table

        rows = [
            ("I1", self._I1, "kg m²", "transverse moment about the pivot"),
            ("I3", self._I3, "kg m²", "axial moment"),
            ("m", self._m, "kg", "mass"),
            ("l", self._l, "m", "pivot to centre of mass"),
            ("g", self._g, "m/s²", "gravitational acceleration"),
        ]
        if self._driven is None:
            notes = [f"sleeping threshold: ω3 > {self.sleeping_threshold():.6g} rad/s"]
        else:
            rows.append(("pivot", repr(self._pivot), "", "how the pivot moves"))
            rows.append(("damping", repr(self._damping), "", "torques at the pivot"))
            notes = ["a moving or damped pivot: simulate it (no integrals, no exact solution)"]
        return table("Lagrange top (heavy symmetric top on a pivot)", repr(self), rows, notes)

    def __eq__(self, other) -> bool:
        return isinstance(other, LagrangeTop) and repr(self) == repr(other)

    def __hash__(self) -> int:
        return hash(repr(self))

    # -- states and invariants -------------------------------------------------------------

    def _heavy_native(self):
        """The same body as a native heavy top: I = (I1, I1, I3), centre of mass (0, 0, l)."""
        return _core.HeavyTop(self._I1, self._I1, self._I3, self._m, [0.0, 0.0, self._l], self._g)

    def _tuple(self, state) -> tuple:
        if not isinstance(state, EulerState):
            raise ParameterTypeError(
                f"state must be an EulerState (from top.state(...)), not {type(state).__name__}"
            )
        return state.as_tuple()

    def invariants(self, state: EulerState) -> Invariants:  # type: ignore[override]
        """Energy E (J), vertical angular momentum Mz and axial M3 (kg m^2/s) of a state.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> inv = top.invariants(top.state(theta=0.5, psi_dot=150.0))
        >>> round(inv.E, 6), round(inv.Mz, 6), round(inv.M3, 6)
        (56.680454, 0.658187, 0.75)
        """
        self._fixed_only("invariants")
        return Invariants(*self._native.invariants(self._tuple(state)))

    def effective_potential(
        self, theta: ArrayLike, Mz: float, M3: float
    ) -> float | NDArray[np.float64]:
        """Effective potential of the nutation (J), vectorised over ``theta`` (rad).

        ``Veff = m g l cos(theta) + (Mz - M3 cos(theta))^2 / (2 I1 sin^2(theta)) + M3^2/(2 I3)``,
        so that ``E = I1 theta_dot^2 / 2 + Veff(theta)``. (Some texts also subtract
        ``M3^2/(2 I1)``; that term does not belong: it is absent from the energy.)

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> round(top.effective_potential(0.5, Mz=0.658187, M3=0.75), 6)
        56.680454
        >>> [round(float(v), 6) for v in top.effective_potential([0.4, 0.5, 0.6], 0.658187, 0.75)]
        [56.982256, 56.680454, 56.847473]
        """
        self._fixed_only("effective_potential")
        Mz, M3 = real("Mz", Mz), real("M3", M3)
        arr = floats("theta", theta)
        out = self._native.effective_potential(np.ascontiguousarray(arr.ravel()), Mz, M3)
        if arr.ndim == 0:
            return float(out[0])
        return out.reshape(arr.shape)

    # -- analysis of the motion from a state -----------------------------------------------

    def analyse(self, state: EulerState) -> NutationAnalysis:
        """Kind of motion, turning points, nutation period and mean precession rate.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> a = top.analyse(top.state(theta=0.5, psi_dot=150.0))
        >>> a.kind, round(a.theta_min, 6), round(a.theta_max, 6), round(a.mean_precession_rate, 6)
        ('cusps', 0.5, 0.51076, 0.66034)
        """
        self._fixed_only("analyse")
        d = self._native.analyse(self._tuple(state))
        d.pop("segments")
        return NutationAnalysis(**d)

    def turning_points(self, state: EulerState) -> tuple[float, float]:
        """(theta_min, theta_max): the nutation's turning points (rad).

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> lo, hi = top.turning_points(top.state(theta=0.5, psi_dot=150.0))
        >>> round(lo, 6), round(hi, 6)
        (0.5, 0.51076)
        """
        self._fixed_only("turning_points")
        a = self.analyse(state)
        return (a.theta_min, a.theta_max)

    def nutation_period(self, state: EulerState) -> float:
        """Period of the nutation (s); ``inf`` on the separatrix. For a steady motion, the
        limit period of small nutations about it.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> round(top.nutation_period(top.state(theta=0.5, psi_dot=150.0)), 6)
        0.106773
        """
        self._fixed_only("nutation_period")
        return self.analyse(state).nutation_period

    def mean_precession_rate(self, state: EulerState) -> float:
        """Mean of phi_dot over a nutation period (rad/s).

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> round(top.mean_precession_rate(top.state(theta=0.5, psi_dot=150.0)), 6)
        0.66034
        """
        self._fixed_only("mean_precession_rate")
        return self.analyse(state).mean_precession_rate

    def motion_kind(self, state: EulerState) -> str:
        """One of ``"sleeping"`` (theta = 0 always), ``"hanging"`` (theta = pi always),
        ``"regular_precession"``, ``"waves"`` (phi_dot never zero), ``"cusps"`` (phi_dot = 0 at
        a turning point), ``"loops"`` (phi_dot changes sign), ``"through_vertical"`` (the axis
        passes through the vertical: Mz = +-M3), ``"asymptotic"`` (the separatrix: the axis
        creeps up to the vertical in infinite time).

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> top.motion_kind(top.state(theta=0.5, psi_dot=150.0))
        'cusps'
        >>> top.motion_kind(top.state(theta=0.5, phi_dot=2.0, psi_dot=150.0))
        'loops'
        """
        self._fixed_only("motion_kind")
        return self.analyse(state).kind

    def exact(self, state: EulerState, t: ArrayLike, *, direct: bool = False) -> Trajectory:
        """The exact motion from ``state`` (taken at t = 0) at times ``t`` (s, 1-D, any order).

        Returns a :class:`Trajectory` with ``t``, ``theta``, ``phi``, ``psi``, ``theta_dot``,
        ``phi_dot``, ``psi_dot``; phi and psi are continuous (unwrapped), except that where the
        axis passes exactly through the vertical phi jumps by +pi and psi by -pi (Euler
        angles are singular there; the orientation is continuous).

        The solution is u = cos(theta) = uA cn^2 + uB sn^2 in Jacobi functions, phi and psi
        incomplete elliptic integrals of the third kind; these are interpolated once per call
        to round-off, so each time costs tens of nanoseconds. ``direct=True`` evaluates the
        elliptic functions at every time instead (slow; for checks).

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> traj = top.exact(top.state(theta=0.5, psi_dot=150.0), np.linspace(0.0, 0.1, 3))
        >>> np.round(traj.theta, 6).tolist()
        [0.5, 0.510655, 0.500426]
        >>> traj.columns[:4]
        ['t', 'theta', 'phi', 'psi']
        """
        self._fixed_only("exact")
        ts = times("t", t)
        cols = dict(
            zip(
                ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot"),
                self._native.exact(self._tuple(state), ts, direct),
            )
        )
        p = (self._I1, self._I3, self._m, self._l, self._g)
        rates = [cols[k] for k in ("theta", "theta_dot", "phi_dot", "psi_dot")]
        # the invariants at every time, computed by the core when first read
        later = Deferred(lambda: _core.lagrange_columns(*p, *rates))
        cols.update(dict.fromkeys(("energy", "Mz", "M3", "potential"), later))
        return Trajectory({"t": ts, **cols}, model=self, state=state)

    # -- steady precession and the sleeping top --------------------------------------------

    def steady_precession(self, theta0: float, omega3: float) -> tuple[float, ...]:
        """Steady precession rates (rad/s) at inclination ``theta0`` (rad) for axial spin
        ``omega3 = psi_dot + phi_dot cos(theta)`` (rad/s), ascending; ``()`` when none exists.

        They solve ``m g l = Omega (I3 omega3 - I1 Omega cos(theta0))``.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> [round(r, 6) for r in top.steady_precession(0.5, 150.0)]
        [0.660379, 67.709257]
        """
        self._fixed_only("steady_precession")
        return tuple(self._native.steady_precession(real("theta0", theta0), real("omega3", omega3)))

    def nutation_frequency(self, theta0: float, omega3: float, rate: float) -> float:
        """Angular frequency (rad/s) of small nutations about the steady precession at
        ``theta0`` with spin ``omega3`` and precession rate ``rate`` (one of
        :meth:`steady_precession`): ``(a - 2 rate cos theta0)^2 + rate^2 sin^2 theta0`` under the
        root, ``a = I3 omega3 / I1``.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> slow, fast = top.steady_precession(0.5, 150.0)
        >>> round(top.nutation_frequency(0.5, 150.0, slow), 6)
        58.841778
        """
        self._fixed_only("nutation_frequency")
        return self._native.nutation_frequency(
            real("theta0", theta0), real("omega3", omega3), real("rate", rate)
        )

    def sleeping_threshold(self) -> float:
        """Axial spin (rad/s) above which the upright spin is stable: ``sqrt(4 I1 m g l)/I3``
        (``M3^2 > 4 I1 m g l``); 0 when ``m g l <= 0``.

        Examples
        --------
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> round(top.sleeping_threshold(), 6)
        31.32092
        """
        self._fixed_only("sleeping_threshold")
        return self._native.sleeping_threshold()
