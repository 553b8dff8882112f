"""Many runs at once: the core's parallel batch, for play tops and heavy tops."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from . import _core
from ._errors import ParameterError
from ._validate import real

if TYPE_CHECKING:
    from ._simulate import Model, State


@dataclass(frozen=True)
class BatchSummary:
    """Per-run summaries of :func:`simulate_many` for play tops, as arrays (one entry per
    run). A failed run has NaN (mode ``"error"``, steps 0) and its message in ``errors``.

    Examples
    --------
    >>> from kreisel import PlayTop, simulate_many
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> b = simulate_many(pt, [pt.state(theta=0.1, psi_dot=w) for w in (100.0, 150.0)], 0.05)
    >>> len(b), b.final_mode.tolist(), b.errors
    (2, ['roll', 'roll'], (None, None))
    """

    final_u: np.ndarray
    final_mode: np.ndarray
    inversion_time: np.ndarray
    jellett_drift: np.ndarray
    energy_drift: np.ndarray
    errors: tuple
    steps: np.ndarray | None = None
    #: The parts touching at the end, as a bit mask (bit i: part i of the top's ``shape``).
    final_parts_in_contact: np.ndarray | None = None
    #: Each part's first touchdown (s; NaN if none), shape (runs, 4): column i is part i.
    first_touchdown_time: np.ndarray | None = None
    #: When a ring part came down flat, ending the run (s; NaN if none): Euler's disk.
    flat_time: np.ndarray | None = None
    #: When the top came to rest, ending the run (s; NaN if none): the event ``rest``.
    rest_time: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.final_u)


@dataclass(frozen=True)
class HeavyBatchSummary:
    """Per-run summaries of :func:`simulate_many` for heavy tops, as arrays.

    ``final_theta``, ``theta_min``, ``theta_max`` (rad, over the recorded steps);
    ``energy_drift`` (largest ``|E - E0|`` relative to ``T0 + m g |c|``), ``Mz_drift`` and
    ``M3_drift`` (relative to ``|M0|``; M3 NaN unless the top is symmetric),
    ``kovalevskaya_drift`` (relative to ``|K0|``; NaN unless a Kovalevskaya top), ``steps``, and
    ``errors`` (None for runs that went through).

    Examples
    --------
    >>> from kreisel import LagrangeTop, simulate_many
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> b = simulate_many(top, [top.state(theta=th, psi_dot=150.0) for th in (0.3, 0.5)], 0.1)
    >>> len(b), [round(float(x), 6) for x in b.theta_max], b.errors
    (2, [0.306649, 0.510753], (None, None))
    """

    final_theta: np.ndarray
    theta_min: np.ndarray
    theta_max: np.ndarray
    energy_drift: np.ndarray
    Mz_drift: np.ndarray
    M3_drift: np.ndarray
    kovalevskaya_drift: np.ndarray
    steps: np.ndarray
    errors: tuple

    def __len__(self) -> int:
        return len(self.final_theta)


def _threads(threads):
    if threads is None:
        return None
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise ParameterError(
            f"threads = {threads!r} is not allowed: give a whole number >= 1, or None for all cores"
        )
    return int(threads)


def _broadcast(models, states):
    """(models, states) as equal-length lists: one and many broadcast."""
    ms = list(models) if isinstance(models, (list, tuple)) else [models]
    ss = list(states) if isinstance(states, (list, tuple)) else [states]
    if len(ms) == 1 and len(ss) > 1:
        ms = ms * len(ss)
    if len(ss) == 1 and len(ms) > 1:
        ss = ss * len(ms)
    if len(ms) != len(ss):
        raise ParameterError(
            f"models ({len(ms)}) and states ({len(ss)}) are not allowed: give one of each, "
            "one and many, or equally many"
        )
    return ms, ss


def _natives(models, states):
    """(native models, flat native states) of a batch, broadcast and checked."""
    ms, ss = _broadcast(models, states)
    natives, flat = [], []
    for m, s in zip(ms, ss):
        to_native = getattr(m, "_native_state", None)
        if to_native is None:
            raise ParameterError(
                f"models contains {m!r}, which is not allowed: use PlayTop, HeavyTop or "
                "LagrangeTop (one kind per batch)"
            )
        natives.append(m._native_model())
        flat.append(to_native(s))
    heavy = (_core.HeavyTop, _core.DrivenTop)
    kinds = {"heavy" if isinstance(n, heavy) else "play" for n in natives}
    if len(kinds) > 1:
        raise ParameterError(
            "models mixes play tops and heavy tops, which is not allowed: one kind per batch"
        )
    return natives, flat


def simulate_many(
    models: Model | Sequence[Model],
    states: State | Sequence[State],
    t_end: float,
    *,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    dt: float | None = None,
    inversion_level: float = 0.9,
    threads: int | None = None,
    progress: bool = False,
) -> BatchSummary | HeavyBatchSummary:
    """Simulates many tops in parallel (the GIL released) and summarises each run.

    Each run is computed exactly as :func:`simulate` would compute it alone, so the
    summaries do not depend on the batch, the order or the number of threads; each is
    reduced as it goes (no trajectory is kept).

    Parameters
    ----------
    models : PlayTop, HeavyTop or LagrangeTop, or a sequence of one kind
    states : a state or a sequence of states
        Broadcast against ``models``: one model with many states, many models with one
        state, or equal-length sequences.
    t_end : float
        Duration (s).
    method, dt : str, float
        Heavy tops: any of :func:`methods` (``dt`` for the fixed-step ones). Play tops run
        the adaptive ``"dop853"`` only.
    rtol, atol : float
        Tolerances of the adaptive method.
    inversion_level : float
        Play tops: the u level whose first upward crossing is the inversion time.
    threads : int, optional
        Threads to use (default: all cores).
    progress : bool
        Show a progress bar (tqdm): the runs then go in pieces of at least 64, which changes
        no result.

    Returns
    -------
    BatchSummary (play tops) or HeavyBatchSummary (heavy tops)

    Examples
    --------
    >>> from kreisel import PlayTop, simulate_many
    >>> pt = PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    >>> states = [pt.state(theta=0.1, psi_dot=w) for w in (100.0, 150.0)]
    >>> b = simulate_many(pt, states, 0.5)
    >>> b.final_mode.tolist(), [round(float(u), 6) for u in b.final_u]
    (['roll', 'roll'], [0.997299, 0.998387])
    """
    natives, flat = _natives(models, states)
    return _many(natives, flat, t_end, method, rtol, atol, dt, inversion_level, threads, progress)


def _many_raw(natives, flat, t_end, method, rtol, atol, dt, inversion_level, threads, progress):
    """The core's batch on native models and flat states: a column per summary of the model
    (``kreisel._core.names()``; categories as int8 codes, -2 for a failed run; NaN where a
    run failed) and ``errors``."""
    from ._simulate import _settings

    t_end, method, rtol, atol, dt, _ = _settings(t_end, method, rtol, atol, dt, [])
    return _in_pieces(
        _core.many, progress, natives, flat, t_end, method, rtol, atol, dt,
        real("inversion_level", inversion_level), _threads(threads),
    )  # fmt: skip


def _many(natives, flat, t_end, method, rtol, atol, dt, inversion_level, threads, progress):
    """The summaries of a batch as a BatchSummary (play tops) or HeavyBatchSummary."""
    from ._simulate import names

    out = _many_raw(natives, flat, t_end, method, rtol, atol, dt, inversion_level, threads,
                    progress)  # fmt: skip
    steps = np.nan_to_num(out.pop("steps"), nan=0.0).astype(np.int64)
    errors = tuple(out.pop("errors"))
    if "final_mode" in out:
        modes = np.array([*names()["modes"], "error"])
        out["final_mode"] = modes[np.where(out["final_mode"] < 0, -1, out["final_mode"])]
        touch = [out.pop(f"first_touchdown_time_{i}") for i in range(4)]
        out["first_touchdown_time"] = np.stack(touch, axis=1)
        parts = out.pop("final_parts_in_contact")
        out["final_parts_in_contact"] = np.where(np.isnan(parts), -1, parts).astype(np.int64)
        return BatchSummary(**out, steps=steps, errors=errors)
    return HeavyBatchSummary(**out, steps=steps, errors=errors)


PIECE = 64


def _in_pieces(native, progress, tops, states, *args):
    """``native(tops, states, *args)`` -> dict of columns, run in pieces under a progress bar
    when asked (the runs are independent, so the columns are the same)."""
    n = len(tops)
    if not progress or n < 2 * PIECE:
        return native(tops, states, *args)
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover
        raise ParameterError(
            "progress = True is not allowed without tqdm: pip install tqdm"
        ) from None
    size = max(PIECE, -(-n // 100))
    parts = []
    with tqdm(total=n, unit="run", desc="simulate_many") as bar:
        for i in range(0, n, size):
            parts.append(native(tops[i : i + size], states[i : i + size], *args))
            bar.update(min(size, n - i))
    return {
        k: np.concatenate([p[k] for p in parts])
        if isinstance(parts[0][k], np.ndarray)
        else [x for p in parts for x in p[k]]
        for k in parts[0]
    }


def _heavy_runs(models, states):
    """(native tops, (q, omega) states) of a batch of heavy tops, broadcast and checked."""
    natives, flat = _natives(models, states)
    if natives and not isinstance(natives[0], (_core.HeavyTop, _core.DrivenTop)):
        raise ParameterError(
            f"models contains {models!r}, which is not allowed: use HeavyTop or LagrangeTop"
        )
    return natives, [(s[:4], s[4:]) for s in flat]


def _lyapunov_many(models, states, t_end, *, tau, d0, direction, rtol, atol, threads=None):
    """Largest Lyapunov exponents of heavy tops in parallel: (exponents, errors)."""
    tops, runs = _heavy_runs(models, states)
    out = _core.lyapunov_many(
        tops,
        runs,
        real("t_end", t_end),
        real("tau", tau),
        real("d0", d0),
        [real("direction", x) for x in direction],
        real("rtol", rtol),
        real("atol", atol),
        _threads(threads),
    )
    return out["lyapunov"], tuple(out["errors"])
