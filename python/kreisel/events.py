"""Built-in events for :func:`kreisel.simulate` (located in the core, no Python calls)."""

from __future__ import annotations

from ._simulate import Event
from ._validate import real


def turning_points(*, direction: int = 0, terminal: bool = False) -> Event:
    """Turning points of the nutation: theta_dot = 0. ``direction=+1`` selects minima of
    theta (theta_dot from - to +), ``-1`` maxima.

    Examples
    --------
    >>> from kreisel import LagrangeTop, events, simulate
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> ev = events.turning_points(direction=-1)
    >>> ev
    Event('turning_point', direction=-1, terminal=False)
    >>> traj = simulate(top, top.state(theta=0.5, psi_dot=150.0), 0.5, events=[ev])
    >>> [round(e.t, 6) for e in traj.events[:3]]
    [0.053387, 0.16016, 0.266933]
    """
    return Event(
        None,
        name="turning_point",
        direction=direction,
        terminal=terminal,
        _builtin=("turning_points", 0.0),
    )


def theta_crossing(value: float, *, direction: int = 0, terminal: bool = False) -> Event:
    """theta crossing ``value`` (rad, in [0, pi]); ``direction=+1`` while theta increases.
    The range is the core's rule, checked when the event is made."""
    value = real("value", value)
    return Event(
        None,
        name=f"theta={value:g}",
        direction=direction,
        terminal=terminal,
        _builtin=("theta_crossing", value),
    )


def inversion(level: float = 0.9, *, terminal: bool = False) -> Event:
    """Play top: u = cos(theta) rising through ``level`` (the top turning over)."""
    level = real("level", level)
    return Event(
        None, name="inversion", direction=1, terminal=terminal, _builtin=("inversion", level)
    )


def rest(*, terminal: bool = True) -> Event:
    """Play top: the kinetic energy falls below 1e-12 of its start (the top has stopped)."""
    return Event(None, name="rest", direction=-1, terminal=terminal, _builtin=("rest", 0.0))
