"""Trajectories: columns of numpy arrays sharing one time axis."""

from __future__ import annotations

import numpy as np


class Trajectory:
    """A motion sampled at times ``t``: every column is a numpy array of the same length.

    Columns are attributes (``traj.theta``) and items (``traj["theta"]``); ``columns`` lists
    them. Angles are in radians, rates in rad/s, times in s.
    """

    __slots__ = ("_cols", "_meta")

    def __init__(self, columns: dict[str, np.ndarray], **meta):
        n = len(columns["t"])
        for k, v in columns.items():
            if len(v) != n:
                raise ValueError(f"column {k!r} has length {len(v)}, expected {n}")
        object.__setattr__(self, "_cols", dict(columns))
        object.__setattr__(self, "_meta", dict(meta))

    def __getattr__(self, name: str) -> np.ndarray:
        cols = object.__getattribute__(self, "_cols")
        if name in cols:
            return cols[name]
        meta = object.__getattribute__(self, "_meta")
        if name in meta:
            return meta[name]
        raise AttributeError(f"Trajectory has no column {name!r}; columns: {list(cols)}")

    def __setattr__(self, name, value):
        raise AttributeError("Trajectory is read-only")

    def __getitem__(self, name: str) -> np.ndarray:
        return self._cols[name]

    def __len__(self) -> int:
        return len(self._cols["t"])

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._cols) | set(self._meta))

    @property
    def columns(self) -> list[str]:
        """Names of the columns."""
        return list(self._cols)

    def to_dict(self) -> dict[str, np.ndarray]:
        """The columns as a dict of arrays."""
        return dict(self._cols)

    def __repr__(self) -> str:
        t = self._cols["t"]
        span = f"t=[{t.min():.6g}, {t.max():.6g}] s" if len(t) else "empty"
        return f"<Trajectory: {len(t)} samples, {span}, columns {self.columns}>"
