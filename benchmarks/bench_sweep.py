"""Benchmark S1: a sweep of 10^4 play-top runs, locally on 1 and 2 cores and through Dask.

    python benchmarks/bench_sweep.py [--runs N] [--t-end T] [--chunk C] [--rounds R]

A tippe top (case T1's top: m = 0.02 kg, rho = 0.02 m, s = 0.006 m, C = 0.4 m rho^2,
A = 0.8 C, viscous friction mu = 1 s/m) swept on a square grid of theta (2.8 to 3.1 rad)
and psi_dot (100 to 250 rad/s), each run integrated for T = 3 s at rtol 1e-8, every summary
kept, into a fresh Zarr store on disk. The same kreisel.sweep call is timed three ways in
one run, with time.perf_counter:

- local on 1 core (the whole process pinned to one CPU with sched_setaffinity, threads=1)
  and on 2 cores (threads=2): the scaling is their ratio;
- through Dask: a scheduler process and two worker processes with one thread each (as a
  cluster is deployed; a LocalCluster would keep the scheduler inside this process, where
  it shares the GIL with the store writes), started and warmed up with one small sweep
  before the clock starts, so the overhead measured is that of the scheduling, the
  transfers and the writes. The cluster is started twice: as `kreisel scheduler` and
  `kreisel worker` start it (Dask's profiler off, slow event-loop ticks), and with Dask's
  default settings (`dask scheduler`, `dask worker`), for comparison.

The machine's speed changes from second to second, so the comparisons are made in paired
rounds (--rounds, default 7): each round times one of each, one right after the other (in
alternating order, so that an effect of the order cancels), and
the result is the median over the rounds of their ratio (the best times are reported too).
First the local runs on 1 and 2 cores, with no cluster (its idle processes would share the
CPU): the scaling. Then, with a cluster started, a local 2-core run and a Dask run per
round: the Dask overhead, against local runs beside the same idle cluster; then the same
with the other cluster. The store chunks hold 1000 runs (10 chunks, so 80 writes); the runs go
out as tasks of up to 1024 runs, which may span chunks, shrinking toward the end (guided,
so that the cores finish together; 2 lanes both locally and on Dask; the count is
printed). All the datasets must agree bit for bit.
Result: benchmarks/results-sweep.json.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import cpu_counters, steal_share

import kreisel

CASE = "S1"
M, RHO, S = 0.02, 0.02, 0.006
C = 0.4 * M * RHO**2
A = 0.8 * C
OUT = pathlib.Path(__file__).resolve().parent / "results-sweep.json"


def spec(runs: int, t_end: float, chunk: int) -> dict:
    side = int(round(math.sqrt(runs)))
    return {
        "top": {"kind": "play", "m": M, "A": A, "C": C, "s": S, "rho": RHO,
                "friction": "viscous", "mu": 1.0},
        "state": {},
        "simulation": {"t_end": t_end, "rtol": 1e-8, "atol": 1e-12},
        "grid": {"theta": {"start": 2.8, "stop": 3.1, "num": side},
                 "psi_dot": {"start": 100.0, "stop": 250.0, "num": runs // side}},
        "output": {"chunk": chunk},
    }  # fmt: skip


@contextlib.contextmanager
def dask_processes(tmp: pathlib.Path, workers: int, tuned: bool = True):
    """A Dask cluster as one deploys it: a scheduler process and `workers` worker processes
    of one thread each, on loopback; yields the scheduler's address. `tuned`: started by
    `kreisel scheduler` and `kreisel worker`, else by Dask's own commands."""
    log = open(tmp / "dask.log", "w")  # noqa: SIM115
    file = tmp / "scheduler.json"
    file.unlink(missing_ok=True)

    def spawn(role, *args):
        if tuned:
            cmd = [sys.executable, "-m", "kreisel", role, *args]
        else:
            cmd = [sys.executable, "-m", f"distributed.cli.dask_{role}", *args]
        return subprocess.Popen(cmd, stdout=log, stderr=log)

    procs = [
        spawn("scheduler", "--host", "127.0.0.1", "--port", "0",
              "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(file))
    ]  # fmt: skip
    try:
        deadline = time.time() + 60
        while True:
            try:
                address = json.loads(file.read_text())["address"]
                break
            except (OSError, ValueError, KeyError):
                if time.time() > deadline:
                    raise RuntimeError(f"no Dask scheduler: see {log.name}") from None
                time.sleep(0.1)
        procs += [spawn("worker", address, "--nthreads", "1", "--no-nanny",
                        "--dashboard-address", "127.0.0.1:0") for _ in range(workers)]  # fmt: skip
        from distributed import Client

        with Client(address, timeout=60) as c:
            c.wait_for_workers(workers, timeout=60)
        yield address
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        log.close()


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return time.perf_counter() - start, out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10_000)
    parser.add_argument("--t-end", type=float, default=3.0)
    parser.add_argument("--chunk", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args(argv)
    from distributed import Client

    sp = kreisel.SweepSpec.from_tables(spec(args.runs, args.t_end, args.chunk))
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="kreisel-bench-sweep-"))
    cores = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    if cores is not None and len(cores) < 2:
        raise SystemExit(f"S1 needs 2 cores; this process may use {cores}")

    def run(name, **kw):
        store = tmp / f"{name}.zarr"
        shutil.rmtree(store, ignore_errors=True)
        return timed(lambda: kreisel.sweep(sp, store, progress=False, **kw))

    def one_core():
        # the whole process on one core: the runs, the Python around them, the store writes
        if cores is None:  # pragma: no cover (not Linux): one thread only
            return run("one", threads=1)
        os.sched_setaffinity(0, cores[:1])
        try:
            return run("one", threads=1)
        finally:
            os.sched_setaffinity(0, cores)

    def rounds(first, second):
        """Paired rounds of `first` and `second`, in alternating order (so that an effect of
        the order, such as a host that slows a VM under sustained load, cancels): the best
        time of each, the median over the rounds of second / first (each pair sees the
        same state of the machine), the ratios, and the last results."""
        a, b, ratios = [], [], []
        for i in range(args.rounds):
            if i % 2 == 0:
                (s1, out1), (s2, out2) = first(), second()
            else:
                (s2, out2), (s1, out1) = second(), first()
            a.append(s1)
            b.append(s2)
            ratios.append(s2 / s1)
        return min(a), min(b), float(np.median(ratios)), ratios, out1, out2

    counters = cpu_counters()
    clusters = {}  # tuned or not: (local beside it, Dask, median ratio, ratios, start-up)
    dask_runs = []
    try:
        run("two", threads=2)  # warm-up: first-call costs are not what we measure
        t2, t1, scaling, scalings, two, one = rounds(lambda: run("two", threads=2), one_core)
        # the clusters only now: their idle processes would take CPU from the local runs
        for tuned in (True, False):
            start = time.perf_counter()
            with dask_processes(tmp, 2, tuned) as address, Client(address) as client:
                warm = kreisel.SweepSpec.from_tables(spec(16, 0.1, 4))
                kreisel.sweep(warm, None, client, progress=False)
                startup = time.perf_counter() - start
                t2c, td, ratio, ratios, _, dk = rounds(
                    lambda: run("two", threads=2), lambda: run("dask", scheduler=client)
                )
                dask_runs.append(dk)
            clusters[tuned] = (t2c, td, ratio, ratios, startup)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for name in one.data_vars:
        for other in (two, *dask_runs):
            a, b = one[name].values, other[name].values
            if not np.array_equal(a, b, equal_nan=a.dtype.kind == "f"):
                raise SystemExit(f"{name} differs between the runs: not bit for bit")
    steal = steal_share(counters, cpu_counters())
    (t2c, td, ratio, ratios, startup) = clusters[True]
    (t2d, tdd, ratio_d, ratios_d, _) = clusters[False]
    inverted = int(np.isfinite(one["inversion_time"].values).sum())
    from kreisel import _sweep

    tasks = len(_sweep._tasks(sp, list(range(sp.n_chunks)), {}, lanes=2))
    res = {
        "case": CASE,
        "runs": sp.size,
        "chunks": sp.n_chunks,
        "tasks": tasks,
        "t_end": args.t_end,
        "rounds": args.rounds,
        "local_1_core_best_s": t1,
        "local_2_cores_best_s": t2,
        "scaling": scaling,
        "scaling_rounds": scalings,
        "local_2_cores_beside_cluster_best_s": t2c,
        "dask_2_workers_best_s": td,
        "dask_startup_s": startup,
        "dask_overhead": ratio - 1,
        "dask_overhead_rounds": [r - 1 for r in ratios],
        "local_2_cores_beside_dask_defaults_best_s": t2d,
        "dask_defaults_2_workers_best_s": tdd,
        "dask_defaults_overhead": ratio_d - 1,
        "dask_defaults_overhead_rounds": [r - 1 for r in ratios_d],
        "steal_share": steal,
        "bit_for_bit": True,
        "inverted": inverted,
        "steps_mean": float(one["steps"].values.mean()),
    }
    OUT.write_text(json.dumps(res, indent=2))
    print(f"S1: {sp.size} play-top runs of {args.t_end} s in {sp.n_chunks} chunks, {tasks} tasks")

    def spread(rs):
        return f"rounds {100 * (min(rs) - 1):+.1f} to {100 * (max(rs) - 1):+.1f} %"

    print(f"  {args.rounds} paired rounds; best times, and the median of the rounds' ratios")
    print(f"  local, 1 core     {t1:8.2f} s")
    print(f"  local, 2 cores    {t2:8.2f} s   scaling {scaling:.2f}x "
          f"(rounds {min(scalings):.2f}-{max(scalings):.2f}x)")  # fmt: skip
    print("  Dask, 2 workers, started by kreisel scheduler / kreisel worker:")
    print(f"    local, 2 cores, the idle cluster beside it {t2c:8.2f} s")
    print(f"    Dask                {td:8.2f} s   overhead {100 * (ratio - 1):+.1f} % "
          f"({spread(ratios)}; cluster start-up {startup:.1f} s, not counted)")  # fmt: skip
    print("  the same with Dask's default settings (dask scheduler / dask worker):")
    print(f"    local, 2 cores, the idle cluster beside it {t2d:8.2f} s")
    print(f"    Dask                {tdd:8.2f} s   overhead {100 * (ratio_d - 1):+.1f} % "
          f"({spread(ratios_d)})")  # fmt: skip
    if steal is not None:
        print(f"  steal time (the hypervisor's share of the CPU) throughout: {100 * steal:.1f} %")
    print(f"  bit for bit equal: yes; {inverted} of {sp.size} tops turned over")
    return res


if __name__ == "__main__":
    main()
