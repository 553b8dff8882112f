"""kreisel: the dynamics of spinning tops.

The Lagrange top solved exactly (:class:`LagrangeTop`); more tops follow. SI units and
radians throughout; arrays are numpy arrays.
"""

from ._core import __version__
from ._errors import KreiselError, NumericalError, ParameterError
from ._lagrange import LagrangeTop
from ._state import EulerState, Invariants, NutationAnalysis
from ._trajectory import Trajectory

__all__ = [
    "EulerState",
    "Invariants",
    "KreiselError",
    "LagrangeTop",
    "NumericalError",
    "NutationAnalysis",
    "ParameterError",
    "Trajectory",
    "__version__",
]
