"""Parameter sweeps: many runs over a grid or random samples, written chunk by chunk to a Zarr
store, computed locally by the core's parallel batch or on a Dask cluster.

A sweep spec has the tables of a ``kreisel run`` file ([top], [state], [simulation], where
[top] may name a preset) and three more:

``[grid]``
    Swept on a grid (the outer product, in the order given). Each entry is a list of values,
    or ``{start, stop, num}`` (evenly spaced) with ``scale = "log"`` for geometric spacing.
``[random]``
    ``n`` random samples (crossed with the grid if both are given) drawn with ``seed``
    (default 0); each entry ``{low, high}``, uniform, or log-uniform with ``scale = "log"``.
``[output]``
    ``keep``: the per-run summaries to store (default: all of the model's but
    ``lyapunov``); ``chunk``: runs per store chunk (default 1024; whatever the chunks, the
    runs are computed as tasks of at most 1024 runs, shorter toward the end of the sweep so
    that the cores finish together); ``inversion_level`` (play tops, default 0.9);
    ``lyapunov_tau`` (heavy tops keeping ``lyapunov``: the renormalisation interval, s).

With ``[simulation] exact = true`` a Lagrange-top sweep keeps the analysis of each state
(``motion_kind``, ``theta_min``, ``theta_max``, ``nutation_period``,
``mean_precession_rate``) and integrates nothing.

Any scalar field of [top] (not ``friction``) or Euler field of [state] can be swept; a
heavy top's centre of mass is swept by component (``com_x``, ``com_y``, ``com_z``).

The store holds one array per kept summary, indexed by the swept parameters, a ``status``
per run (0 pending, 1 done, 2 failed; the messages are in the attribute ``run_errors``),
and one completion flag per chunk, written after the chunk's data. A crash loses at most the
chunks in flight; the same call again computes only the chunks not flagged. Every run is
computed exactly as :func:`kreisel.simulate_many` computes it alone, so the results do not
depend on the chunking, the threads or the machines: local and Dask runs agree bit for bit.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from contextlib import closing
from typing import TYPE_CHECKING, Any

import numpy as np

from .._errors import ParameterError
from . import schedule
from .run import compute_chunk
from .schedule import DASK_ENV, _client, _Work, dask_command
from .spec import SweepSpec, load_spec
from .store import _create, _is_path, _open_existing, _Writer, open_sweep, shown

if TYPE_CHECKING:
    import os

    import xarray as xr

# what the package, its command line and its tests take from here
__all__ = [
    "DASK_ENV",
    "SweepSpec",
    "compute_chunk",
    "dask_command",
    "load_spec",
    "open_sweep",
    "sweep",
]

# The sizes of the tasks, read at each call (a test sets TASK_RUNS here to cut small tasks)
# and handed to the schedule, which holds no copy of them.
TASK_RUNS = 1024  # at most this many runs per task: a store chunk may be split into tasks
TAIL_RUNS = 16  # the least: toward the end of a sweep the tasks shrink to this size
TASK_SHARE = 2  # a task takes at most 1/(TASK_SHARE lanes) of the runs still to hand out


def _limits() -> tuple:
    return TASK_RUNS, TAIL_RUNS, TASK_SHARE


def _tasks(sp: SweepSpec, todo: list, samples: dict, lanes: int = 1) -> list:
    """The tasks of the chunks `todo` for `lanes` cores or workers: see
    :func:`kreisel._sweep.schedule._tasks`."""
    return schedule._tasks(sp, todo, samples, lanes, _limits())


def sweep(
    spec: SweepSpec | dict[str, Any] | str | os.PathLike[str],
    store: str | os.PathLike[str] | Any | None = None,
    scheduler: str | Any | None = None,
    *,
    threads: int | None = None,
    progress: bool = True,
    callback: Callable[[int, int, int], object] | None = None,
    overwrite: bool = False,
    retry_failed: bool = False,
    connect_timeout: float = 10.0,
) -> xr.Dataset:
    """Runs a sweep and returns its results as an ``xarray.Dataset``.

    Parameters
    ----------
    spec : SweepSpec, dict of tables, or path of a TOML file
        See the module documentation (``kreisel.SweepSpec``) for the tables.
    store : path or zarr store, optional
        Where the results go, chunk by chunk (a Zarr directory). If it already holds this
        sweep, only the chunks not yet done are computed; if it holds another sweep, the call
        fails unless ``overwrite``. None: an in-memory store (nothing kept on disk).
    scheduler : str or dask.distributed.Client, optional
        None: the address in the environment variable ``KREISEL_SCHEDULER`` if it is set (so
        a script moves to a cluster with no change), else the core's parallel batch on this
        machine (also ``"local"``). An address (``"tcp://host:8786"``) or a client: chunks
        go to that Dask cluster, whose workers need only kreisel.
    threads : int, optional
        Local runs: the number of threads (default: all cores).
    progress : bool
        Show a progress bar (runs done).
    callback : callable, optional
        ``callback(chunk, done, total)`` after each chunk is written; an exception raised in
        it stops the sweep (the chunks written so far stay).
    overwrite : bool
        Replace a store that holds another sweep.
    retry_failed : bool
        Compute again the chunks that hold failed runs (after a fix, say); their messages
        are dropped from ``run_errors`` as the chunks are rewritten.
    connect_timeout : float
        Seconds to wait for the scheduler.

    Examples
    --------
    Three exact Lagrange tops, kept in memory (``store=None``; give a path to keep them):

    >>> import kreisel
    >>> ds = kreisel.sweep({
    ...     "top": {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1},
    ...     "state": {"psi_dot": 150.0},
    ...     "simulation": {"exact": True},
    ...     "grid": {"theta": [0.3, 0.5, 0.7]},
    ... }, store=None, progress=False)
    >>> ds["motion_kind"].values.tolist()
    ['cusps', 'cusps', 'cusps']
    >>> [round(float(x), 6) for x in ds["theta_max"].values]
    [0.306651, 0.51076, 0.714403]
    >>> ds["status"].values.tolist()
    [1, 1, 1]
    """
    import zarr

    if progress:
        from tqdm.auto import tqdm
    else:  # tqdm.auto warns in a notebook without ipywidgets, even for a bar never shown
        from tqdm.std import tqdm

    from .._batch import _threads

    sp = load_spec(spec)
    threads = _threads(threads)
    if callback is not None and not callable(callback):
        raise ParameterError(f"callback = {callback!r} is not allowed: it must be callable")
    # everything that can fail before work starts fails here, before the store is touched
    client, own_client = _client(scheduler, connect_timeout)
    try:
        if store is None:
            store = zarr.storage.MemoryStore()
        root = _open_existing(store)
        if root is not None and root.attrs.get("spec") != sp.canonical():
            if not overwrite:
                raise ParameterError(
                    f"store = {shown(store)} holds another sweep (its spec differs): give a "
                    "new store, or overwrite=True (kreisel sweep --overwrite) to replace it"
                )
            if _is_path(store):
                shutil.rmtree(store)
            root = None
        samples = sp.random_values() if sp.random else {}
        todo = list(range(sp.n_chunks))
        if root is not None:
            done = root["chunk_done"][:]
            if retry_failed:
                failed = root["status"][:] == 2
                for k in range(sp.n_chunks):
                    if done[k] and failed[sp.chunk_slices(k)].any():
                        done[k] = 0
            todo = [k for k in todo if not done[k]]
        runs = {k: int(np.prod([s.stop - s.start for s in sp.chunk_slices(k)])) for k in todo}
        finished = sp.n_chunks - len(todo)
        # the runs start
        work = _Work(sp, sp.as_dict(), runs, samples, client, threads, _limits())
        bar = tqdm(total=sum(runs.values()), unit="run", desc="sweep", disable=not progress)
        with bar, closing(work):
            if root is None:  # a new store is made while the first tasks run
                root = _create(store, sp, samples)
            writer = _Writer(root, sp)
            for k, result in work:
                writer.write(k, result)
                finished += 1
                bar.update(runs[k])
                if callback is not None:
                    callback(k, finished, sp.n_chunks)
    finally:
        if own_client:
            client.close()
    return open_sweep(store)
