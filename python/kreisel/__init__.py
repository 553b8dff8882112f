"""kreisel: the dynamics of spinning tops.

- :class:`LagrangeTop`: the heavy symmetric top on a pivot, solved exactly.
- :class:`HeavyTop`: any rigid body on a pivot (Euler, Lagrange, Kovalevskaya, chaotic).
- :class:`PlayTop`: a top with a spherical tip on a plane, with friction (tippe tops).
- :func:`simulate`, :func:`simulate_many`: structure-preserving and adaptive integration.
- :func:`fit`, :class:`Observations`, :mod:`io`: a top's parameters and state from a
  recording (phyphox, Tracker), with honest errors.
- :mod:`pivots`, :class:`PivotDamping`: a moving pivot and friction at it; :func:`poincare`:
  stroboscopic sections.

SI units and radians throughout; arrays are numpy arrays.
"""

from . import bodies, events, io, pivots, shapes
from ._atlas import Classification, Prediction, RegularPrecession, StationaryMotion
from ._batch import BatchSummary, HeavyBatchSummary, simulate_many
from ._core import __version__
from ._errors import FitWarning, KreiselError, NumericalError, ParameterError
from ._fit import FitResult, fit
from ._heavy import HeavyTop, RigidState
from ._lagrange import LagrangeTop
from ._observations import Observations
from ._play import Coulomb, CoulombContensou, Frictionless, PlayState, PlayTop, Viscous
from ._poincare import poincare
from ._simulate import Event, EventRecord, MethodInfo, methods, simulate
from ._state import EulerState, Invariants, NutationAnalysis
from ._sweep import SweepSpec, open_sweep, sweep
from ._trajectory import Trajectory
from .pivots import PivotDamping

__all__ = [
    "BatchSummary",
    "Classification",
    "Coulomb",
    "CoulombContensou",
    "Event",
    "EventRecord",
    "EulerState",
    "FitResult",
    "FitWarning",
    "Frictionless",
    "HeavyBatchSummary",
    "HeavyTop",
    "Invariants",
    "KreiselError",
    "LagrangeTop",
    "MethodInfo",
    "NumericalError",
    "NutationAnalysis",
    "Observations",
    "ParameterError",
    "PivotDamping",
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
    "fit",
    "io",
    "methods",
    "pivots",
    "poincare",
    "shapes",
    "simulate",
    "simulate_many",
    "sweep",
    "open_sweep",
]
