"""Helpers shared by the benchmark scripts (timing, rotations, drift)."""

from __future__ import annotations

import math
import time

import numpy as np


def best_of(fn, repeats):
    """(best wall time in s over ``repeats`` calls of ``fn``, the last result)."""
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def quat_to_matrix(q):
    """Rotation matrices (..., 3, 3) of quaternions (..., 4), scalar first."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def drift(x):
    """Largest |x - x[0]| / |x[0]|."""
    x = np.asarray(x)
    return float(np.max(np.abs(x - x[0])) / abs(x[0]))
