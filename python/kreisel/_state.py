"""States of tops: plain immutable values, separate from the models."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class EulerState:
    """Orientation and rates in Euler angles (z-x-z; theta from the upward vertical).

    Parameters
    ----------
    theta : float
        Nutation angle from the upward vertical, in [0, pi] (rad).
    phi, psi : float
        Precession and spin angles (rad).
    theta_dot, phi_dot, psi_dot : float
        Their rates (rad/s).

    Examples
    --------
    >>> from kreisel import EulerState
    >>> s = EulerState(theta=0.5, psi_dot=150.0)
    >>> s
    EulerState(theta=0.5, phi=0.0, psi=0.0, theta_dot=0.0, phi_dot=0.0, psi_dot=150.0)
    >>> s.theta, s.psi_dot
    (0.5, 150.0)
    """

    theta: float
    phi: float = 0.0
    psi: float = 0.0
    theta_dot: float = 0.0
    phi_dot: float = 0.0
    psi_dot: float = 0.0

    def as_tuple(self) -> tuple[float, float, float, float, float, float]:
        """(theta, phi, psi, theta_dot, phi_dot, psi_dot).

        Examples
        --------
        >>> from kreisel import EulerState
        >>> EulerState(theta=0.5, phi_dot=0.7, psi_dot=150.0).as_tuple()
        (0.5, 0.0, 0.0, 0.0, 0.7, 150.0)
        """
        return (self.theta, self.phi, self.psi, self.theta_dot, self.phi_dot, self.psi_dot)


@dataclass(frozen=True)
class Invariants:
    """The integrals of a Lagrange top: energy E (J), Mz and M3 (kg m^2/s).

    Examples
    --------
    >>> from kreisel import LagrangeTop
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> inv = top.invariants(top.state(theta=0.5, psi_dot=150.0))
    >>> print(f"E = {inv.E:.6f} J, Mz = {inv.Mz:.6f}, M3 = {inv.M3:.6f} kg m^2/s")
    E = 56.680454 J, Mz = 0.658187, M3 = 0.750000 kg m^2/s
    """

    E: float
    Mz: float
    M3: float


@dataclass(frozen=True)
class NutationAnalysis:
    """What the exact solution says about a motion before any time is evaluated.

    Attributes
    ----------
    kind : str
        One of ``"sleeping"``, ``"hanging"``, ``"regular_precession"``, ``"waves"``,
        ``"cusps"``, ``"loops"``, ``"through_vertical"``, ``"asymptotic"``.
    theta_min, theta_max : float
        Turning points of the nutation (rad).
    nutation_period : float
        Period of theta (s); ``inf`` on the separatrix.
    mean_precession_rate : float
        Mean of phi_dot over a nutation period (rad/s).

    Examples
    --------
    >>> from kreisel import LagrangeTop
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> a = top.analyse(top.state(theta=0.5, psi_dot=150.0))
    >>> a.kind, round(a.nutation_period, 6), round(a.mean_precession_rate, 6)
    ('cusps', 0.106773, 0.66034)
    """

    kind: str
    theta_min: float
    theta_max: float
    nutation_period: float
    mean_precession_rate: float
