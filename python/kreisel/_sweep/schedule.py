"""Where the tasks of a sweep run: cut from the chunks to do, handed to the local thread
pool or a Dask cluster, and gathered back into whole chunks."""

from __future__ import annotations

import os
import uuid
from typing import Any

import numpy as np

from .._errors import ParameterError
from .run import compute_chunk
from .spec import SweepSpec

SCHEDULER_ENV = "KREISEL_SCHEDULER"

# Dask settings for the processes of a cluster that runs kreisel's tasks (long, CPU-bound,
# the GIL released): no statistical profiler (it samples every worker thread each 10 ms),
# event-loop ticks each second instead of every 20 ms, system metrics every 2 s. Measured
# on 2 cores: an idle scheduler and two workers take 0.18 s of CPU in 10 s instead of 0.97 s.
# `kreisel scheduler` and `kreisel worker` start Dask's processes with them; settings made
# in the environment or a Dask configuration file come first.
DASK_ENV = {
    "DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED": "False",
    "DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL": "1s",
    "DASK_DISTRIBUTED__ADMIN__SYSTEM_MONITOR__INTERVAL": "2s",
}


def dask_command(role: str, args) -> tuple[list, dict]:
    """The command line and environment of a Dask process (``role``: "scheduler" or
    "worker") tuned for kreisel (:data:`DASK_ENV`); ``args`` go to Dask's command as they
    are."""
    import sys

    module = f"distributed.cli.dask_{role}"
    env = dict(os.environ)
    for k, v in DASK_ENV.items():
        env.setdefault(k, v)
    return [sys.executable, "-m", module, *args], env


def _client(scheduler, timeout):
    if scheduler is None:
        scheduler = os.environ.get(SCHEDULER_ENV) or None
    if scheduler is None or scheduler == "local":
        return None, False
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover
        raise ParameterError(
            "scheduler is given but dask.distributed is not installed: pip install 'kreisel[sweep]'"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str):
        raise ParameterError(
            f"scheduler = {scheduler!r} is not allowed: give an address like "
            "'tcp://host:8786' or a dask.distributed.Client"
        )
    try:
        return Client(scheduler, timeout=timeout, set_as_default=False), True
    except (OSError, TimeoutError, ValueError) as e:
        raise ParameterError(
            f"scheduler = {scheduler!r} is not reachable within {timeout} s: {e}"
        ) from None


def _tasks(sp: SweepSpec, todo: list, samples: dict, lanes: int, limits: tuple) -> list:
    """(pieces, values) for every task, where `pieces` lists (chunk, offset, runs): the runs
    of the chunks to do, in order (C order within each chunk's block), cut into contiguous
    tasks that may end inside a chunk or span several, so the tasks' size does not depend
    on the store's chunks (few writes, or small chunks, alike). `limits` is (TASK_RUNS,
    TAIL_RUNS, TASK_SHARE) of :mod:`kreisel._sweep`: a task takes at most TASK_RUNS runs and
    at most a 1/(TASK_SHARE lanes) share of the runs not yet handed out, but no fewer than
    TAIL_RUNS (guided scheduling, in the manner of factoring: half of what is left goes out
    in `lanes` equal tasks): the last tasks of a sweep are short, so the `lanes` cores or
    workers finish together, and there are few tasks, as each costs Dask a few ms of CPU
    (scheduler, worker and this process: about 6 ms each on a 2-core VM, measured with
    /proc/PID/stat)."""
    task_runs, tail_runs, task_share = limits
    chunks = [(k, sp.chunk_values(k, samples)) for k in todo]
    sizes = [len(next(iter(v.values()))) for _, v in chunks]
    left = sum(sizes)
    out = []
    c, at = 0, 0  # the next run to hand out: chunk index, offset in it
    while left > 0:
        size = min(task_runs, max(tail_runs, -(-left // (task_share * lanes))), left)
        left -= size
        pieces = []
        while size > 0:
            k, n = chunks[c][0], sizes[c]
            m = min(size, n - at)
            pieces.append((c, k, at, m))
            size -= m
            at += m
            if at == n:
                c, at = c + 1, 0
        values = {
            name: np.concatenate([chunks[i][1][name][a : a + m] for i, _, a, m in pieces])
            for name in chunks[0][1]
        }
        out.append(([(k, a, m) for _, k, a, m in pieces], values))
    return out


def _piece(result: dict, start: int, runs: int) -> dict:
    """The part of a task's result for its runs start .. start + runs (errors renumbered)."""
    out = {name: v[start : start + runs] for name, v in result.items() if name != "errors"}
    out["errors"] = {i - start: msg for i, msg in result["errors"].items()
                     if start <= i < start + runs}  # fmt: skip
    return out


def _join(parts: list) -> dict:
    """The result of a whole chunk from those of its parts (in order, with their offsets)."""
    out = {}
    for name in parts[0][1]:
        if name != "errors":
            out[name] = np.concatenate([r[name] for _, r in parts])
    out["errors"] = {a + int(i): msg for a, r in parts for i, msg in r["errors"].items()}
    return out


class _Work:
    """The tasks of a sweep, all handed out at once (the runs start); iterating gives
    (chunk, result) pairs as whole chunks finish. close() cancels the tasks not yet started
    (after an exception or an interrupt) and waits for the local ones already running."""

    def __init__(self, sp: SweepSpec, payload: dict, runs: dict, samples: dict, client,
                 threads, limits: tuple):  # fmt: skip
        """`runs`: the chunks to do, with their numbers of runs; `limits`: the tasks' sizes
        (see :func:`_tasks`)."""
        self.client, self.pool = client, None
        self.parts: dict[Any, Any] = {}
        self.futures = {}  # (task, future) by position (local) or Dask key
        self.missing = dict(runs)  # runs still to come in, by chunk
        todo = list(runs)
        if not todo:
            return
        if client is None:
            cores = threads or os.cpu_count() or 1
        else:
            cores = max(1, sum(client.nthreads().values()))
        tasks = _tasks(sp, todo, samples, cores, limits)
        if client is None:
            from concurrent.futures import ThreadPoolExecutor

            # `threads` tasks in flight, each on its own core (the GIL is released while
            # the core's batch runs, so one task's set-up in Python overlaps the others'
            # runs); fewer tasks than cores: the cores are shared out inside each task
            # instead. (Two tasks each on every core was measured slower: two pools on two
            # cores.)
            lanes = max(1, min(cores, len(tasks)))
            inner = max(1, cores // lanes)
            self.pool = ThreadPoolExecutor(lanes)
            for i, tk in enumerate(tasks):
                self.futures[i] = (tk, self.pool.submit(compute_chunk, payload, tk[1], inner))
        else:
            token = uuid.uuid4().hex[:12]
            keys = [f"kreisel-sweep-{token}-{i}" for i in range(len(tasks))]
            submitted = client.map(compute_chunk, [payload] * len(tasks),
                                   [tk[1] for tk in tasks], [1] * len(tasks), key=keys,
                                   pure=False)  # fmt: skip
            self.futures = {f.key: (tk, f) for tk, f in zip(tasks, submitted)}

    def _finished(self, task, result) -> list:
        """The chunks (chunk, result) that this task's result completes."""
        whole, start = [], 0
        for k, a, m in task[0]:
            self.parts.setdefault(k, []).append((a, _piece(result, start, m)))
            start += m
            self.missing[k] -= m
            if self.missing[k] == 0:
                whole.append((k, _join(sorted(self.parts.pop(k), key=lambda p: p[0]))))
        return whole

    def __iter__(self):
        if self.pool is not None:
            from concurrent.futures import FIRST_COMPLETED, wait

            task = {f: (i, tk) for i, (tk, f) in self.futures.items()}
            pending = set(task)
            while pending:
                ready, pending = wait(pending, return_when=FIRST_COMPLETED)
                for f in sorted(ready, key=lambda f: task[f][0]):
                    yield from self._finished(task[f][1], f.result())
            return
        if not self.futures:
            return
        from distributed import as_completed

        # results come back in batches: one gather for all the tasks finished meanwhile
        batches = as_completed([f for _, f in self.futures.values()], loop=self.client.loop)
        for batch in batches.batches():
            for f, result in zip(batch, self.client.gather(batch)):
                tk = self.futures.pop(f.key)[0]
                f.release()
                yield from self._finished(tk, result)

    def close(self):
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
        elif self.futures:
            self.client.cancel([f for _, f in self.futures.values()])
            self.futures = {}
