"""Built-in events for :func:`kreisel.simulate` (located in the core, no Python calls)."""

from __future__ import annotations

import math

from ._errors import ParameterError
from ._simulate import Event
from ._validate import real


def turning_points(*, direction=0, terminal=False) -> Event:
    """Turning points of the nutation: theta_dot = 0. ``direction=+1`` selects minima of
    theta (theta_dot from - to +), ``-1`` maxima."""
    return Event(
        None,
        name="turning_point",
        direction=direction,
        terminal=terminal,
        _builtin=("turning_points", 0.0),
    )


def theta_crossing(value, *, direction=0, terminal=False) -> Event:
    """theta crossing ``value`` (rad, in [0, pi]); ``direction=+1`` while theta increases."""
    value = real("value", value)
    if not 0.0 <= value <= math.pi:
        raise ParameterError(f"value = {value} is not allowed: theta lies in [0, pi]")
    return Event(
        None,
        name=f"theta={value:g}",
        direction=direction,
        terminal=terminal,
        _builtin=("theta_crossing", value),
    )
