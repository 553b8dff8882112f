"""kreisel: the dynamics of spinning tops.

- :class:`LagrangeTop`: the heavy symmetric top on a pivot, solved exactly.
- :class:`HeavyTop`: any rigid body on a pivot (Euler, Lagrange, Kovalevskaya, chaotic).
- :func:`simulate`: structure-preserving and adaptive integration of either.

SI units and radians throughout; arrays are numpy arrays.
"""

from . import events
from ._core import __version__
from ._errors import KreiselError, NumericalError, ParameterError
from ._heavy import HeavyTop, RigidState
from ._lagrange import LagrangeTop
from ._simulate import Event, EventRecord, MethodInfo, methods, simulate
from ._state import EulerState, Invariants, NutationAnalysis
from ._trajectory import Trajectory

__all__ = [
    "Event",
    "EventRecord",
    "EulerState",
    "HeavyTop",
    "Invariants",
    "KreiselError",
    "LagrangeTop",
    "MethodInfo",
    "NumericalError",
    "NutationAnalysis",
    "ParameterError",
    "RigidState",
    "Trajectory",
    "__version__",
    "events",
    "methods",
    "simulate",
]
