"""Stroboscopic (Poincare) sections: the state once per pivot period, or at an event."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._errors import ParameterError
from ._simulate import Event, simulate
from ._trajectory import Trajectory
from ._validate import real

if TYPE_CHECKING:
    from ._simulate import Model, State


def poincare(
    top: Model,
    state: State,
    n: int,
    *,
    period: float | None = None,
    event: Event | None = None,
    t_end: float | None = None,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> Trajectory:
    """The states of a motion on a section: once per period, or at an event's crossings.

    Parameters
    ----------
    top : HeavyTop, LagrangeTop or PlayTop
    state : the initial state (t = 0)
    n : int
        Number of section points after the start (1 <= n <= 10**7).
    period : float, optional
        The sampling period (s); default: the period of the top's pivot
        (:class:`kreisel.pivots.Harmonic`). The section is then stroboscopic: the states at
        t = k * period, k = 0 .. n, from one run (its dense output), so the section is that
        of the time-periodic flow.
    event : Event, optional
        Instead of a period: the states at the event's crossings (any top), the first ``n``
        of them up to ``t_end`` (required with ``event``).
    method, rtol, atol
        As for :func:`simulate`.

    Returns
    -------
    Trajectory
        The section's states, with every column of :func:`simulate`.

    Examples
    --------
    >>> from kreisel import LagrangeTop, pivots, poincare
    >>> top = LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0,
    ...                   pivot=pivots.Harmonic([0.0, 0.0, 0.05], omega=20.0))
    >>> sec = poincare(top, top.state(theta=0.5, psi_dot=2.0), 50)
    >>> len(sec), round(float(sec.t[1]), 6)
    (51, 0.314159)
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 10**7:
        raise ParameterError(f"n = {n!r} is not allowed: it must be an integer in [1, 10**7]")
    n = int(n)
    if event is not None:
        if period is not None:
            raise ParameterError(
                "period and event are not allowed together: a section is taken once per "
                "period or at an event's crossings"
            )
        if not isinstance(event, Event):
            raise ParameterError(f"event = {event!r} is not allowed: use a kreisel Event")
        if t_end is None:
            raise ParameterError("t_end is missing: a section at an event needs the time to run")
        t_end = real("t_end", t_end)
        run = simulate(top, state, t_end, method=method, rtol=rtol, atol=atol, events=[event])
        times = np.array([e.t for e in run.events if e.name == event.name][:n])
        if times.size == 0:
            raise ParameterError(
                f"event {event.name!r} does not occur before t_end = {t_end!r}: no section"
            )
        return simulate(
            top, state, float(times[-1]), method=method, rtol=rtol, atol=atol, t_eval=times
        )
    if period is None:
        pivot = getattr(top, "pivot", None)
        period = getattr(pivot, "period", None)
        if period is None:
            raise ParameterError(
                "period is missing: this top has no periodic pivot (give period=..., or "
                "event=... with t_end=... for a section at an event)"
            )
    period = real("period", period)
    if not period > 0:
        raise ParameterError(f"period = {period!r} is not allowed: it must be > 0")
    times = period * np.arange(n + 1)
    return simulate(top, state, float(times[-1]), method=method, rtol=rtol, atol=atol, t_eval=times)
