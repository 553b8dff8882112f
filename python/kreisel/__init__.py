"""kreisel: the dynamics of spinning tops.

- :class:`LagrangeTop`: the heavy symmetric top on a pivot, solved exactly.
- :class:`HeavyTop`: any rigid body on a pivot (Euler, Lagrange, Kovalevskaya, chaotic).
- :class:`PlayTop`: a top with a spherical tip on a plane, with friction (tippe tops).
- :func:`simulate`, :func:`simulate_many`: structure-preserving and adaptive integration.

SI units and radians throughout; arrays are numpy arrays.
"""

from . import bodies, events, shapes
from ._atlas import Classification, Prediction, RegularPrecession, StationaryMotion
from ._batch import BatchSummary, HeavyBatchSummary, simulate_many
from ._core import __version__
from ._errors import KreiselError, NumericalError, ParameterError
from ._heavy import HeavyTop, RigidState
from ._lagrange import LagrangeTop
from ._play import Coulomb, CoulombContensou, Frictionless, PlayState, PlayTop, Viscous
from ._simulate import Event, EventRecord, MethodInfo, methods, simulate
from ._state import EulerState, Invariants, NutationAnalysis
from ._sweep import SweepSpec, open_sweep, sweep
from ._trajectory import Trajectory

__all__ = [
    "BatchSummary",
    "Classification",
    "Coulomb",
    "CoulombContensou",
    "Event",
    "EventRecord",
    "EulerState",
    "Frictionless",
    "HeavyBatchSummary",
    "HeavyTop",
    "Invariants",
    "KreiselError",
    "LagrangeTop",
    "MethodInfo",
    "NumericalError",
    "NutationAnalysis",
    "ParameterError",
    "PlayState",
    "PlayTop",
    "Prediction",
    "RegularPrecession",
    "RigidState",
    "StationaryMotion",
    "SweepSpec",
    "Trajectory",
    "Viscous",
    "__version__",
    "bodies",
    "events",
    "methods",
    "shapes",
    "simulate",
    "simulate_many",
    "sweep",
    "open_sweep",
]
