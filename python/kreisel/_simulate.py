"""``kreisel.simulate``: one entry point for every top and every method."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Union, cast

import numpy as np

from . import _core
from ._errors import ParameterError, ParameterTypeError
from ._heavy import RigidState
from ._trajectory import Deferred, Trajectory
from ._validate import real, times

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ._heavy import HeavyTop
    from ._lagrange import LagrangeTop
    from ._play import PlayState, PlayTop
    from ._state import EulerState

    #: a top :func:`simulate` integrates, and a state of it
    Model = Union[HeavyTop, LagrangeTop, PlayTop]
    State = Union[EulerState, RigidState, PlayState]


@dataclass(frozen=True)
class MethodInfo:
    """What an integration method is and can do.

    Examples
    --------
    >>> from kreisel import methods
    >>> info = {m.name: m for m in methods()}["splitting4"]
    >>> info.order, info.adaptive, info.symplectic, info.events
    (4, False, True, False)
    """

    name: str
    order: int
    adaptive: bool
    symplectic: bool
    events: bool
    summary: str


@functools.cache
def methods() -> tuple[MethodInfo, ...]:
    """Every method :func:`simulate` knows, with its order and properties.

    Examples
    --------
    >>> from kreisel import methods
    >>> [m.name for m in methods()][:3]
    ['dop853', 'rk4', 'splitting']
    >>> m = methods()[0]
    >>> m.name, m.order, m.adaptive
    ('dop853', 8, True)
    """
    # Cached: the list is fixed in the core, and simulate() consults it on every call.
    return tuple(MethodInfo(*m) for m in _core.methods())


@functools.cache
def _methods_by_name() -> dict[str, MethodInfo]:
    return {m.name: m for m in methods()}


@dataclass(frozen=True)
class EventRecord:
    """An event that happened: its name, time (s) and index in the ``events`` list (-1 for
    the model's own events: a play top's contact switches ``lift_off``, ``touchdown``,
    ``slip_to_roll``, ``roll_to_slip``, ``tangential_impact``, ``flat``, ``creep`` and
    ``creep_end`` around a part sliding at the edge of its friction cone, and ``drill_end``
    where a part rolling with its Coulomb-Contensou patch drilling stops drilling).

    Examples
    --------
    >>> from kreisel import LagrangeTop, events, simulate
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> ev = events.turning_points()
    >>> traj = simulate(top, top.state(theta=0.5, psi_dot=150.0), 0.1, events=[ev])
    >>> rec = traj.events[0]
    >>> rec.name, round(rec.t, 6), rec.index
    ('turning_point', 0.053387, 0)
    """

    name: str
    t: float
    index: int
    part: str | None = None


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

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel import Event, LagrangeTop, simulate
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> ev = Event(lambda t, s: s.omega[0], name="omega1_zero", direction=1)
    >>> ev
    Event('omega1_zero', direction=1, terminal=False)
    >>> traj = simulate(top, top.state(theta=0.5, psi_dot=150.0), 0.1, events=[ev])
    >>> [(e.name, round(e.t, 6)) for e in traj.events][:2]
    [('omega1_zero', 0.03927), ('omega1_zero', 0.09163)]
    """

    __slots__ = ("function", "name", "direction", "terminal", "_builtin")

    def __init__(
        self,
        function: Callable[[float, RigidState], float] | None,
        *,
        name: str | None = None,
        direction: int = 0,
        terminal: bool = False,
        _builtin: tuple[str, float] | None = None,
    ) -> None:
        if function is None and _builtin is None:
            raise ParameterError("function = None is not allowed: give a callable")
        if function is not None and not callable(function):
            raise ParameterError(f"function = {function!r} is not allowed: it must be callable")
        if isinstance(direction, bool) or not isinstance(direction, (int, np.integer)):
            raise ParameterError(f"direction = {direction!r} is not allowed: use -1, 0 or +1")
        self.function = function
        self.name: str = cast(str, name or getattr(function, "__name__", "event"))
        self.direction = int(direction) if abs(direction) < 128 else 2
        self.terminal = bool(terminal)
        self._builtin = _builtin
        # the event's rules (direction, the range of a built-in event's value): the core's
        kind, value = _builtin if _builtin is not None else ("user", 0.0)
        _core.check_event((self.name, kind, None, value, self.direction, self.terminal))

    def __repr__(self) -> str:
        return f"Event({self.name!r}, direction={self.direction}, terminal={self.terminal})"


def _native_event(ev: Event):
    if ev._builtin is not None:
        kind, value = ev._builtin
        return (ev.name, kind, None, value, ev.direction, ev.terminal)

    def call(t, q, w):
        fn = cast(Callable[..., float], ev.function)
        return float(fn(t, RigidState(np.asarray(q), np.asarray(w))))

    return (ev.name, "user", call, 0.0, ev.direction, ev.terminal)


def _settings(t_end, method, rtol, atol, dt, events):
    """The settings' types, converted (the core checks their values)."""
    if not isinstance(method, str):
        raise ParameterError(f"method = {method!r} is not allowed: give a method name")
    evs = list(events or [])
    for e in evs:
        if not isinstance(e, Event):
            raise ParameterError(f"events contains {e!r}, which is not allowed: use kreisel.Event")
    return (
        real("t_end", t_end),
        method,
        real("rtol", rtol),
        real("atol", atol),
        None if dt is None else real("dt", dt),
        evs,
    )


def native_model(model, name="model"):
    """The native model of a top and the function that gives its native states."""
    to_native = getattr(model, "_native_state", None)
    if to_native is None:
        raise ParameterTypeError(
            f"{name} must be a HeavyTop, LagrangeTop or PlayTop, not {type(model).__name__}"
        )
    return model._native_model(), to_native


def simulate(
    model: Model,
    state: State,
    t_end: float,
    *,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    dt: float | None = None,
    t_eval: ArrayLike | None = None,
    events: Sequence[Event] | None = None,
    reduced: bool = False,
    sensitivities: Sequence[str] | None = None,
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
        Play tops: ``"dop853"`` only.
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
        conserved momenta (the classical reduction to one degree of freedom).
    sensitivities : list of str, optional
        Forward sensitivities to integrate with the motion (method ``"dop853"``, no
        ``events``; a top on a fixed pivot, undamped or with viscous and drag damping): the
        derivatives of every row with respect to each named parameter of the top and field
        of the initial state. HeavyTop: ``"I1"``, ``"I2"``, ``"I3"``, ``"m"``, ``"g"``,
        ``"com[0]"``, ``"com[1]"``, ``"com[2]"``; LagrangeTop: ``"I1"`` (both transverse
        moments), ``"I3"``, ``"m"``, ``"l"``, ``"g"``; with a ``PivotDamping`` also
        ``"viscous"`` and ``"drag"``. An EulerState: ``"theta"``, ``"phi"``,
        ``"psi"``, ``"theta_dot"``, ``"phi_dot"``, ``"psi_dot"``; a RigidState:
        ``"orientation[0]"`` .. ``"orientation[2]"`` (a body-frame rotation of the initial
        orientation, ``q -> q exp(xi / 2)``) and ``"omega[0]"`` .. ``"omega[2]"``. A
        PlayTop: ``"m"``, ``"A"``, ``"C"``, ``"g"``, ``"mu"`` (its friction law's
        coefficient), ``"radius"`` (a CoulombContensou patch), ``"s"``, ``"rho"`` (one tip
        sphere), ``"restitution"``, ``"rolling_resistance"``, ``"drilling_resistance"``,
        ``"air_drag"``; and the fields of ``pt.state(...)``: ``"theta"``, ``"phi"``,
        ``"psi"``, ``"theta_dot"``, ``"phi_dot"``, ``"psi_dot"``, ``"vx"``, ``"vy"``,
        ``"x"``, ``"y"``, ``"height"`` (a dropped top), and ``"orientation[i]"``,
        ``"omega[i]"`` (a moved field builds the state again, so a top in contact stays in
        contact). Its sensitivities cross touchdowns (by the saltation of the variational
        equation); a run that reaches lift-off, a stick or slip switch, a tangential impact
        or a ring lying flat raises an error naming it and its time. The run takes the same
        steps, and gives the same rows, as one without (see the theory page,
        "Sensitivities").

    Returns
    -------
    Trajectory
        Columns ``t`` (n,), ``quaternion`` (n, 4), ``omega`` (n, 3, body frame), ``theta``,
        ``phi``, ``psi`` (unwrapped), and the model's diagnostics: for heavy tops ``energy``,
        ``Mz`` and, where they are integrals, ``M3`` and ``kovalevskaya``; for play tops
        ``com``, ``com_velocity``, ``u``, ``mode``, ``normal_force``, ``jellett``, ... .
        Attributes ``events`` (list of EventRecord), ``stats`` and ``status``
        (``"completed"``, ``"event"`` or ``"interrupted"``). ``sensitivities`` is None
        unless asked for; then a dict from each name to a dict of arrays, one row per row of
        the trajectory: ``"omega"`` (n, 3, d omega_body / dp), ``"orientation"`` (n, 3: the
        body-frame vector xi with R(p + dp) = R(p) exp([xi dp]x)), ``"quaternion"`` (n, 4:
        q (0, xi) / 2), ``"theta"``, ``"phi"``, ``"psi"`` (n,: of the unwrapped angles);
        for a PlayTop also ``"com"``, ``"com_velocity"`` (n, 3), ``"dissipated"`` and ``"u"``
        (n,).

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel import LagrangeTop, events, simulate
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> s = top.state(theta=0.5, psi_dot=150.0)
    >>> traj = simulate(top, s, 1.0, t_eval=np.linspace(0.0, 1.0, 5))
    >>> traj.status, np.round(traj.theta, 6).tolist()
    ('completed', [0.5, 0.508321, 0.507606, 0.500063, 0.508969])
    >>> traj = simulate(top, s, 1.0, events=[events.turning_points()])
    >>> len(traj.events), round(traj.events[0].t, 6)
    (18, 0.053387)
    >>> traj = simulate(top, s, 1.0, t_eval=[0.0, 1.0], sensitivities=["I3", "theta"])
    >>> sorted(traj.sensitivities["theta"])
    ['omega', 'orientation', 'phi', 'psi', 'quaternion', 'theta']
    >>> np.round(traj.sensitivities["theta"]["theta"], 6).tolist()
    [1.0, 1.01889]
    """
    native, to_native = native_model(model)
    y0 = to_native(state)
    t_end, method, rtol, atol, dt, evs = _settings(t_end, method, rtol, atol, dt, events)
    te = None if t_eval is None else times("t_eval", t_eval)
    nevs = [_native_event(e) for e in evs]
    if sensitivities is None:
        out = _core.simulate(native, y0, t_end, method, rtol, atol, dt, te, nevs, bool(reduced))
        sens = None
    else:
        from ._lagrange import LagrangeTop
        from ._state import EulerState

        wanted = _sensitivity_names(sensitivities)
        euler = list(state.as_tuple()) if isinstance(state, EulerState) else None
        out = _core.simulate_sensitivities(
            native, y0, t_end, method, rtol, atol, dt, te, nevs, bool(reduced), wanted,
            isinstance(model, LagrangeTop), euler,
        )  # fmt: skip
        sens = out.pop("sensitivities")
    stats, status = out.pop("stats"), out.pop("status")
    names_of_parts = getattr(model, "part_names", None)

    def part_name(i: int) -> str | None:
        return None if i < 0 or names_of_parts is None else names_of_parts[i]

    records = [EventRecord(name, t, index, part_name(p)) for name, t, index, p in out.pop("events")]
    later = Deferred(functools.partial(_named_columns, out.pop("run")))
    cols = dict.fromkeys(out.pop("derived"), later)
    if "mode" in out:
        cols["mode"] = np.array(names()["modes"])[out.pop("mode")]
    cols.update(out)
    meta: dict[str, Any] = {"sensitivities": sens}
    if names_of_parts is not None:
        meta["part_names"] = names_of_parts
    return Trajectory(
        cols, model=model, state=state, method=method, stats=stats, events=records,
        status=status, **meta,
    )  # fmt: skip


def _named_columns(run) -> dict[str, Any]:
    """The diagnostics columns of a native run, the per-part contact states as names."""
    cols = run.columns()
    if "part_mode" in cols:
        cols["part_mode"] = np.array(names()["part_modes"])[cols["part_mode"]]
    return cols


def _sensitivity_names(value) -> list[str]:
    """The names of ``sensitivities=``, a list of str (the core checks each name)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise ParameterError(
            f'sensitivities = {value!r} is not allowed: give a list of names, e.g. ["I3", "theta"]'
        )
    bad = [v for v in value if not isinstance(v, str)]
    if bad:
        raise ParameterError(
            f"sensitivities contains {bad[0]!r}, which is not allowed: each name is a str"
        )
    return list(value)


@functools.cache
def names() -> dict[str, Any]:
    """Every public name of the core: contact modes, kinds of motion, summaries (with units
    and descriptions) and run statuses."""
    return _core.names()
