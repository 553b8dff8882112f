"""Recordings of a top's motion: what was measured, when, and how well."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._errors import ParameterError
from ._validate import floats, real, shown
from ._validate import vector as _vector

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: kind -> (allowed frames, default frame, column names, unit)
KINDS = {
    "body_rates": (("principal", "sensor"), "principal", ("omega_1", "omega_2", "omega_3"),
                   "rad/s"),
    "axis_tip": (("space",), "space", ("x", "y"), "m"),
    "euler_angles": (("space",), "space", ("theta", "phi", "psi"), "rad"),
}  # fmt: skip
ANGLES = ("theta", "phi", "psi")


class Observations:
    """A time series of what was measured on a top: body rates, the tip of its figure axis
    seen from above, or Euler angles.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times (s), strictly increasing, >= 0. The state given to :func:`kreisel.fit` is
        the state at t = 0 of this clock.
    values : array_like, shape (n, k) (or (n,) when k = 1)
        The measurements; NaN marks a missing sample (skipped by the fit). Columns by kind:

        - ``"body_rates"``: angular velocity (rad/s) about the sensor's three axes, k = 3;
        - ``"axis_tip"``: x, y (k = 2) of a point on the figure axis seen from above, in
          metres, or in any unit (pixels) with ``scale`` metres per unit;
        - ``"euler_angles"``: the z-x-z Euler angles (rad, theta from the upward vertical)
          named by ``columns``, any subset of ``("theta", "phi", "psi")``.
    kind : str
        ``"body_rates"``, ``"axis_tip"`` or ``"euler_angles"``.
    sigma : float or array_like, optional
        Standard deviation of one sample, in the units of ``values``: one number, one per
        column (k,), or one per sample (n, k). None: unknown; the fit then estimates it from
        the scatter of the residuals (its covariance is scaled by chi^2 / dof).
    frame : str, optional
        ``"body_rates"``: ``"principal"`` (default: the sensor's axes are the top's principal
        axes) or ``"sensor"`` (a fixed unknown rotation between them, the fit parameter
        ``"sensor_rotation"``, a rotation vector taking sensor-frame vectors to the principal
        frame, starting from ``rotation``). Other kinds: ``"space"``.
    columns : sequence of str, optional
        ``"euler_angles"`` only: which angles the columns hold (default all three).
    scale : float
        ``"axis_tip"``: metres per unit of ``values``, ``origin`` and ``sigma`` (1: metres).
    axis_point : float
        ``"axis_tip"``: distance (m) along the figure axis from the pivot (for a top on a
        floor: from its centre of mass) to the tracked point; required for this kind.
    origin : sequence of 2 floats
        ``"axis_tip"``: where the pivot (the centre of mass's start, on a floor) appears, in
        the units of ``values``.
    rotation : sequence of 3 floats
        ``frame="sensor"``: the starting rotation vector (rad) for ``"sensor_rotation"``.
    name : str, optional
        A label for plots.

    Phi and psi data may be wrapped to any interval: their residuals are taken modulo 2 pi.

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel import Observations
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> obs = Observations(t, np.zeros((101, 3)), "body_rates", sigma=0.01)
    >>> obs
    Observations(kind='body_rates', n=101, columns=('omega_1', 'omega_2', 'omega_3'), sigma=0.01)
    >>> Observations(t, 0.3 + 0 * t, "euler_angles", columns=["theta"]).values.shape
    (101, 1)
    """

    __slots__ = ("t", "values", "kind", "sigma", "frame", "columns", "scale", "axis_point",
                 "origin", "rotation", "name", "_sigma_given")  # fmt: skip

    def __init__(
        self,
        t: ArrayLike,
        values: ArrayLike,
        kind: str,
        sigma: float | ArrayLike | None = None,
        frame: str | None = None,
        *,
        columns: tuple[str, ...] | list[str] | None = None,
        scale: float = 1.0,
        axis_point: float | None = None,
        origin: ArrayLike = (0.0, 0.0),
        rotation: ArrayLike = (0.0, 0.0, 0.0),
        name: str | None = None,
    ) -> None:
        if not isinstance(kind, str) or kind not in KINDS:
            raise ParameterError(
                f"kind = {kind!r} is not allowed: use one of {', '.join(map(repr, KINDS))}"
            )
        frames, default_frame, default_columns, _ = KINDS[kind]
        frame = default_frame if frame is None else frame
        if frame not in frames:
            raise ParameterError(
                f"frame = {frame!r} is not allowed for kind {kind!r}: use one of "
                f"{', '.join(map(repr, frames))}"
            )
        tt = _times(t)
        n = len(tt)
        if kind == "euler_angles":
            cols = tuple(ANGLES if columns is None else columns)
            bad = [c for c in cols if c not in ANGLES]
            if not cols or bad or len(set(cols)) != len(cols):
                raise ParameterError(
                    f"columns = {columns!r} is not allowed: give distinct names among "
                    "'theta', 'phi', 'psi'"
                )
        else:
            if columns is not None:
                raise ParameterError(
                    f"columns = {columns!r} is not allowed for kind {kind!r}: its columns are "
                    f"{default_columns}"
                )
            cols = default_columns
        k = len(cols)
        v = floats("values", values)
        if v.ndim == 1 and k == 1:
            v = v.reshape(-1, 1)
        if v.shape != (n, k):
            raise ParameterError(
                f"values has shape {v.shape}, which is not allowed: kind {kind!r} with "
                f"{n} times needs shape ({n}, {k}) (columns {', '.join(cols)})"
            )
        if np.isinf(v).any():
            i, j = np.argwhere(np.isinf(v))[0]
            raise ParameterError(
                f"values[{i}, {j}] = {v[i, j]} is not allowed: a sample is a finite number, or "
                "NaN where it is missing"
            )
        for j, c in enumerate(cols):
            if np.isnan(v[:, j]).all():
                raise ParameterError(
                    f"values[:, {j}] (column {c!r}) is all NaN, which is not allowed: every "
                    "column needs at least one sample (leave out a column never measured)"
                )
        self.scale = real("scale", scale)
        if not self.scale > 0:
            raise ParameterError(f"scale = {self.scale} is not allowed: it must be > 0")
        self._sigma_given = sigma is not None
        s = np.ones((n, k)) if sigma is None else _sigma(sigma, n, k)
        if kind == "axis_tip":
            if axis_point is None:
                raise ParameterError(
                    "axis_point = None is not allowed for kind 'axis_tip': give the distance (m) "
                    "along the figure axis from the pivot to the tracked point"
                )
            self.axis_point: float | None = real("axis_point", axis_point)
            o = np.array(_vector("origin", origin, 2))
            v = (v - o) * self.scale
            if sigma is not None:
                s = s * self.scale
            self.origin = o
        else:
            self.axis_point, self.origin = None, np.zeros(2)
        self.rotation = np.array(_vector("rotation", rotation, 3))
        self.t, self.values, self.kind, self.frame, self.columns = tt, v, kind, frame, cols
        self.sigma = s
        self.name = name if name is not None else kind.replace("_", " ")

    @property
    def sigma_given(self) -> bool:
        """Whether the samples' standard deviation was given (else it is estimated)."""
        return self._sigma_given

    @property
    def unit(self) -> str:
        """The unit of ``values`` as stored (axis tips are stored in metres)."""
        return KINDS[self.kind][3]

    def window(self, t_min: float = 0.0, t_max: float = np.inf) -> Observations:
        """The samples with t_min <= t <= t_max (s), as new Observations of the same kind.

        A fit of a long recording of a fast top has many local minima (its phases wind up);
        fitting a short window first and then the whole gives a start inside the right one.

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import Observations
        >>> obs = Observations(np.arange(10) * 0.1, np.zeros((10, 3)), "body_rates")
        >>> len(obs.window(0.0, 0.45))
        5
        """
        keep = (self.t >= real("t_min", t_min)) & (self.t <= float(t_max))
        if not keep.any():
            raise ParameterError(
                f"t_min = {t_min!r}, t_max = {t_max!r} is not allowed: no sample lies between"
            )
        out = object.__new__(Observations)
        for name in self.__slots__:
            setattr(out, name, getattr(self, name))
        out.t, out.values, out.sigma = self.t[keep], self.values[keep], self.sigma[keep]
        for j, c in enumerate(out.columns):
            if np.isnan(out.values[:, j]).all():
                raise ParameterError(
                    f"t_min = {t_min!r}, t_max = {t_max!r} is not allowed: column {c!r} has no "
                    "sample between"
                )
        return out

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        s = self.sigma
        sig = "None" if not self._sigma_given else (
            f"{s.flat[0]:g}" if np.all(s == s.flat[0]) else "per sample"
        )  # fmt: skip
        extra = "" if self.frame == KINDS[self.kind][1] else f", frame={self.frame!r}"
        return (
            f"Observations(kind={self.kind!r}, n={len(self.t)}, columns={self.columns}"
            f"{extra}, sigma={sig})"
        )


def _times(t) -> np.ndarray:
    arr = floats("t", t)
    if arr.ndim != 1 or len(arr) < 1:
        raise ParameterError(
            f"t has shape {arr.shape}, which is not allowed: it must be 1-D with at least one time"
        )
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        raise ParameterError(f"t[{i}] = {arr[i]} is not allowed: every time must be finite")
    if arr[0] < 0:
        raise ParameterError(
            f"t[0] = {float(arr[0])!r} is not allowed: times are >= 0 (the fitted state is the "
            "one at t = 0; shift the recording's clock)"
        )
    d = np.diff(arr)
    if (d <= 0).any():
        i = int(np.argmax(d <= 0)) + 1
        what = "repeats" if d[i - 1] == 0 else "is earlier than"
        raise ParameterError(
            f"t[{i}] = {float(arr[i])!r} is not allowed: it {what} t[{i - 1}] = "
            f"{float(arr[i - 1])!r}; times must be strictly increasing (sort the samples, drop "
            "duplicates)"
        )
    return np.ascontiguousarray(arr)


def _sigma(sigma, n: int, k: int) -> np.ndarray:
    s = floats("sigma", sigma)
    if s.ndim == 0 or s.shape == (k,) or s.shape == (n, k):
        s = np.broadcast_to(s, (n, k)).astype(float)
    else:
        raise ParameterError(
            f"sigma has shape {s.shape}, which is not allowed: give one number, {k} numbers (one "
            f"per column) or shape ({n}, {k})"
        )
    bad = ~(np.isfinite(s) & (s > 0))
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise ParameterError(
            f"sigma = {shown(float(s[i, j]))} (sample {i}, column {j}) is not allowed: every "
            "standard deviation must be a finite number > 0"
        )
    return s
