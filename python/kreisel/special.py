"""Special functions of kreisel's core, for users and for checking.

Parameter convention ``m = k**2`` throughout (as :mod:`scipy.special`). Array arguments may
have any shape; the result has the same shape.

- :func:`ellipj` -- Jacobi elliptic functions sn, cn, dn and the amplitude am.
- :func:`ellipk` -- complete elliptic integral of the first kind K(m).
- :func:`ellipf` -- incomplete first kind F(phi | m).
- :func:`ellippi` -- third kind, complete Pi(n | m) or incomplete Pi(n; phi | m), any real
  n != 1 (the Cauchy principal value where the integrand has a pole).
- :func:`cubic_roots` -- real roots of a cubic.

Every rule on the arguments is the core's: a value outside what is allowed raises
:class:`kreisel.ParameterError` naming the argument, the value and what is allowed. The
results are finite, except the complete integrals at m = 1, where K and Pi are infinite.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Union

import numpy as np

from . import _core
from ._validate import floats, real

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    #: a float for a scalar argument, else an array of its shape
    FloatOrArray = Union[float, NDArray[np.float64]]


def _apply(fn, x, name, *args):
    arr = floats(name, x)
    out = fn(np.ascontiguousarray(arr.ravel()), *args)
    if isinstance(out, tuple):
        return tuple(o.reshape(arr.shape) if arr.ndim else float(o[0]) for o in out)
    return out.reshape(arr.shape) if arr.ndim else float(out[0])


def ellipj(u: ArrayLike, m: float) -> tuple[FloatOrArray, FloatOrArray, FloatOrArray, FloatOrArray]:
    """Jacobi elliptic functions (sn, cn, dn, am) of ``u`` for parameter ``m`` in [0, 1].

    The amplitude is continuous in u: am(u + 2K) = am(u) + pi. Method: arithmetic-geometric
    mean and descending Landen transformation (Abramowitz and Stegun 16.4).

    Examples
    --------
    >>> from kreisel.special import ellipj
    >>> [round(x, 6) for x in ellipj(0.5, 0.3)]
    [0.474216, 0.880409, 0.965679, 0.494073]
    >>> sn, cn, dn, am = ellipj([0.0, 1.0], 0.5)
    >>> sn.shape, round(float(sn[1] ** 2 + cn[1] ** 2), 12)
    ((2,), 1.0)
    """
    return _apply(_core.ellipj, u, "u", real("m", m))


def ellipk(m: float) -> float:
    """Complete elliptic integral of the first kind K(m), m <= 1 (infinite at m = 1).

    Examples
    --------
    >>> from kreisel.special import ellipk
    >>> round(ellipk(0.0), 12), round(ellipk(0.5), 6)
    (1.570796326795, 1.854075)
    >>> ellipk(1.0)
    inf
    """
    return _core.ellipk(real("m", m))


def ellipf(phi: ArrayLike, m: float) -> FloatOrArray:
    """Incomplete elliptic integral of the first kind F(phi | m); for m >= 1 only
    ``|phi| < asin(1/sqrt(m))``, where it is real and finite."""
    return _apply(_core.ellipf, phi, "phi", real("m", m))


def ellippi(n: float, phi: ArrayLike | None = None, m: float | None = None) -> FloatOrArray:
    """Elliptic integral of the third kind: ``ellippi(n, m)`` complete (m <= 1, infinite at
    m = 1) or ``ellippi(n, phi, m)`` incomplete (phi as for :func:`ellipf`); n != 1, the
    principal value where ``n sin^2 phi > 1``."""
    if m is None:
        phi, m = None, phi
    n, m = real("n", n), real("m", m)
    if phi is None:
        return _core.ellippi(n, m)
    return _apply(lambda p, nn, mm: _core.ellippiinc(nn, p, mm), phi, "phi", n, m)


def cubic_roots(c0: float, c1: float, c2: float, c3: float) -> tuple[float, ...]:
    """Real roots, ascending and with multiplicity, of ``c0 + c1 x + c2 x^2 + c3 x^3``, for
    finite coefficients of any size; ParameterError for the zero polynomial and where a root
    lies beyond the range of floats (it names the leading coefficient)."""
    c = [real(f"c{i}", v) for i, v in enumerate((c0, c1, c2, c3))]
    return tuple(_core.cubic_roots(*c))
