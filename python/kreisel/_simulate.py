"""``kreisel.simulate``: one entry point for every top and every method."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from . import _core
from ._errors import ParameterError
from ._heavy import RigidState, _Rigid, rigid_state
from ._play import PlayTop, simulate_play
from ._trajectory import Deferred, Trajectory
from ._validate import real, times


@dataclass(frozen=True)
class MethodInfo:
    """What an integration method is and can do."""

    name: str
    order: int
    adaptive: bool
    symplectic: bool
    events: bool
    summary: str


@functools.cache
def methods() -> tuple[MethodInfo, ...]:
    """Every method :func:`simulate` knows, with its order and properties."""
    # Cached: the list is fixed in the core, and simulate() consults it on every call.
    return tuple(MethodInfo(*m) for m in _core.methods())


@functools.cache
def _methods_by_name() -> dict[str, MethodInfo]:
    return {m.name: m for m in methods()}


@dataclass(frozen=True)
class EventRecord:
    """An event that happened: its name, time (s) and index in the ``events`` list."""

    name: str
    t: float
    index: int


class Event:
    """An event function for :func:`simulate`: ``function(t, state) -> float``; the event is
    where it changes sign.

    Parameters
    ----------
    function : callable
        ``function(t: float, state: RigidState) -> float``.
    name : str, optional
        Reported name (default: the function's name).
    direction : {-1, 0, +1}
        Only crossings from negative to positive (+1), positive to negative (-1), or both (0).
    terminal : bool
        Stop the simulation at the first such event.
    """

    __slots__ = ("function", "name", "direction", "terminal", "_builtin")

    def __init__(self, function, *, name=None, direction=0, terminal=False, _builtin=None):
        if function is None and _builtin is None:
            raise ParameterError("function = None is not allowed: give a callable")
        if function is not None and not callable(function):
            raise ParameterError(f"function = {function!r} is not allowed: it must be callable")
        if direction not in (-1, 0, 1):
            raise ParameterError(f"direction = {direction!r} is not allowed: use -1, 0 or +1")
        self.function = function
        self.name = name or getattr(function, "__name__", "event")
        self.direction = int(direction)
        self.terminal = bool(terminal)
        self._builtin = _builtin

    def __repr__(self) -> str:
        return f"Event({self.name!r}, direction={self.direction}, terminal={self.terminal})"


def _native_event(ev: Event):
    if ev._builtin is not None:
        kind, value = ev._builtin
        return (ev.name, kind, None, value, ev.direction, ev.terminal)

    def call(t, q, w):
        return float(ev.function(t, RigidState(np.asarray(q), np.asarray(w))))

    return (ev.name, "user", call, 0.0, ev.direction, ev.terminal)


def simulate(
    model,
    state,
    t_end,
    *,
    method="dop853",
    rtol=1e-10,
    atol=1e-12,
    dt=None,
    t_eval=None,
    events=None,
    reduced=False,
) -> Trajectory:
    """Integrates the motion of a top from ``state`` (at t = 0) to ``t_end`` (s).

    Parameters
    ----------
    model : HeavyTop, LagrangeTop or PlayTop
    state : EulerState or RigidState (PlayState for a PlayTop)
    t_end : float
        End time (s), >= 0.
    method : str
        One of :func:`methods`: ``"dop853"`` (adaptive, default), ``"rk4"``, ``"splitting"``,
        ``"splitting4"``, ``"splitting6"``, ``"verlet"``, ``"midpoint"``, ``"gauss4"``.
    rtol, atol : float
        Tolerances of the adaptive method.
    dt : float
        Step (s) of the fixed-step methods (required by them).
    t_eval : array_like, optional
        Output times (ascending, in [0, t_end]); default: every step.
    events : list of Event, optional
        Event functions (see :mod:`kreisel.events`); adaptive method only.
    reduced : bool
        LagrangeTop only: integrate theta and p_theta alone and rebuild phi and psi from the
        conserved momenta (the seed's route).

    Returns
    -------
    Trajectory
        Columns ``t`` (n,), ``quaternion`` (n, 4), ``omega`` (n, 3, body frame), ``theta``,
        ``phi``, ``psi`` (unwrapped), ``energy``, ``Mz`` and, where they are integrals,
        ``M3`` and ``kovalevskaya``; attributes ``events`` (list of EventRecord) and ``stats``.
    """
    if isinstance(model, PlayTop):
        return simulate_play(
            model, state, t_end, method=method, rtol=rtol, atol=atol, t_eval=t_eval, events=events
        )
    if not isinstance(model, _Rigid):
        raise TypeError(
            f"model must be a HeavyTop, LagrangeTop or PlayTop, not {type(model).__name__}"
        )
    s = rigid_state(state)
    t_end = real("t_end", t_end)
    if t_end < 0:
        raise ParameterError(f"t_end = {t_end} is not allowed: it must be >= 0")
    if not isinstance(method, str):
        raise ParameterError(f"method = {method!r} is not allowed: give a method name")
    known = _methods_by_name()
    if method not in known:
        raise ParameterError(
            f"method = {method!r} is not allowed: known methods are {', '.join(known)}"
        )
    info = known[method]
    rtol, atol = real("rtol", rtol), real("atol", atol)
    if dt is not None:
        dt = real("dt", dt)
    te = None if t_eval is None else times("t_eval", t_eval)
    evs = list(events or [])
    for e in evs:
        if not isinstance(e, Event):
            raise ParameterError(f"events contains {e!r}, which is not allowed: use kreisel.Event")
    if evs and not info.events:
        raise ParameterError(
            f"events = {evs!r} is not allowed with method {method!r}: "
            "event location needs dense output; use method='dop853'"
        )
    if reduced:
        from ._lagrange import LagrangeTop

        if not isinstance(model, LagrangeTop):
            raise ParameterError("reduced = True is not allowed: it needs a LagrangeTop")
    native = model._heavy_native()
    out = native.simulate(
        np.asarray(s.quaternion).tolist(),
        np.asarray(s.omega).tolist(),
        t_end,
        method,
        rtol,
        atol,
        dt,
        te,
        [_native_event(e) for e in evs],
        bool(reduced),
    )
    stats = out.pop("stats")
    hits = out.pop("events")
    # Copies: the diagnostics stay those of the simulated states if a column is edited in place.
    q, w = out["quaternion"].copy(), out["omega"].copy()
    out.update(dict.fromkeys(out.pop("derived"), Deferred(lambda: native.columns(q, w))))
    records = [EventRecord(evs[i].name, t, i) for i, t in hits]
    return Trajectory(out, model=model, state=state, method=method, stats=stats, events=records)
