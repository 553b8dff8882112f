"""Special functions of kreisel's core, for users and for checking.

Parameter convention ``m = k**2`` throughout (as scipy.special). Array arguments may have
any shape; the result has the same shape.

- :func:`ellipj` -- Jacobi elliptic functions sn, cn, dn and the amplitude am.
- :func:`ellipk` -- complete elliptic integral of the first kind K(m).
- :func:`ellipf` -- incomplete first kind F(phi | m).
- :func:`ellippi` -- third kind, complete Pi(n | m) or incomplete Pi(n; phi | m), any real
  n != 1 (the Cauchy principal value where the integrand has a pole).
- :func:`cubic_roots` -- real roots of a cubic.
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._errors import ParameterError
from ._validate import real


def _apply(fn, x, *args):
    arr = np.asarray(x, dtype=np.float64)
    out = fn(np.ascontiguousarray(arr.ravel()), *args)
    if isinstance(out, tuple):
        return tuple(o.reshape(arr.shape) if arr.ndim else float(o[0]) for o in out)
    return out.reshape(arr.shape) if arr.ndim else float(out[0])


def _parameter(m, upper=1.0):
    m = real("m", m)
    if not 0.0 <= m <= upper:
        raise ParameterError(f"m = {m} is not allowed: the parameter must lie in [0, {upper}]")
    return m


def ellipj(u, m):
    """Jacobi elliptic functions (sn, cn, dn, am) of ``u`` for parameter ``m`` in [0, 1].

    The amplitude is continuous in u: am(u + 2K) = am(u) + pi. Method: arithmetic-geometric
    mean and descending Landen transformation (Abramowitz and Stegun 16.4).
    """
    return _apply(_core.ellipj, u, _parameter(m))


def ellipk(m):
    """Complete elliptic integral of the first kind K(m), m <= 1 (infinite at m = 1)."""
    m = real("m", m)
    if m > 1.0:
        raise ParameterError(f"m = {m} is not allowed: K(m) is real only for m <= 1")
    return _core.ellipk(m)


def ellipf(phi, m):
    """Incomplete elliptic integral of the first kind F(phi | m)."""
    return _apply(_core.ellipf, phi, real("m", m))


def ellippi(n, phi=None, m=None):
    """Elliptic integral of the third kind: ``ellippi(n, m)`` complete or
    ``ellippi(n, phi, m)`` incomplete; principal value where ``n sin^2 phi > 1``."""
    if m is None:
        phi, m = None, phi
    n, m = real("n", n), real("m", m)
    if n == 1.0:
        raise ParameterError("n = 1.0 is not allowed: the integral diverges at n = 1")
    if phi is None:
        return _core.ellippi(n, m)
    return _apply(lambda p, nn, mm: _core.ellippiinc(nn, p, mm), phi, n, m)


def cubic_roots(c0, c1, c2, c3):
    """Real roots, ascending and with multiplicity, of ``c0 + c1 x + c2 x^2 + c3 x^3``."""
    c = [real(f"c{i}", v) for i, v in enumerate((c0, c1, c2, c3))]
    return tuple(_core.cubic_roots(*c))
