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


def best_mujoco_run(mujoco, model, data, reset, steps, repeats):
    """Best wall time (s) over ``repeats`` of one ``mj_step(model, data, nstep=steps)`` call,
    each after ``reset()`` (untimed)."""
    best = math.inf
    for _ in range(repeats):
        reset()
        start = time.perf_counter()
        mujoco.mj_step(model, data, nstep=steps)
        best = min(best, time.perf_counter() - start)
    return best


def cpu_counters():
    """The machine's CPU time counters (/proc/stat, first line), None where there are none."""
    try:
        with open("/proc/stat") as f:
            return [int(x) for x in f.readline().split()[1:9]]
    except (OSError, ValueError):
        return None


def steal_share(before, after):
    """The share of CPU time the hypervisor took from this VM between two cpu_counters()
    (steal time): a measure of how noisy a timing was. None where unknown."""
    if before is None or after is None:
        return None
    d = [b - a for a, b in zip(before, after)]
    return d[7] / sum(d) if sum(d) > 0 else 0.0


def paired(fast, slow, rounds):
    """Interleaved timing of a fast and a slow implementation on a noisy machine.

    Shared machines change speed from one second to the next (other tenants, clock
    changes), by more than the differences worth measuring. So the two are timed side by
    side: each round makes one call of ``slow`` and, right after it, calls ``fast`` for about
    as long (at least 5 calls), and compares the slow call with the median fast call of the
    same round. Returns a dict: ``ratio`` (median over the rounds of slow / fast), ``slow_s``
    and ``fast_s`` (the best time of each over all rounds), ``best_ratio`` (their ratio),
    ``round_ratios``, and the last results ``fast_out`` and ``slow_out``.
    """
    ratios, best_fast, best_slow = [], math.inf, math.inf
    fast_out = slow_out = None
    counters = cpu_counters()
    for _ in range(rounds):
        start = time.perf_counter()
        slow_out = slow()
        t_slow = time.perf_counter() - start
        times, spent = [], 0.0
        while len(times) < 5 or spent < t_slow:
            start = time.perf_counter()
            fast_out = fast()
            times.append(time.perf_counter() - start)
            spent += times[-1]
        t_fast = float(np.median(times))
        ratios.append(t_slow / t_fast)
        best_fast, best_slow = min(best_fast, min(times)), min(best_slow, t_slow)
    return {
        "ratio": float(np.median(ratios)),
        "round_ratios": ratios,
        "fast_s": best_fast,
        "slow_s": best_slow,
        "best_ratio": best_slow / best_fast,
        "steal": steal_share(counters, cpu_counters()),
        "fast_out": fast_out,
        "slow_out": slow_out,
    }


def paired_summary(timing, rounds, peer):
    """The printed line and the result fields of a :func:`paired` timing (kreisel fast)."""
    r = timing["round_ratios"]
    line = (
        f"kreisel is {timing['ratio']:.0f}x faster than {peer} (median of the rounds' ratios; "
        f"rounds {min(r):.0f}-{max(r):.0f}x, best times {timing['best_ratio']:.0f}x)"
    )
    if timing["steal"] is not None:
        line += f"; steal time {100 * timing['steal']:.1f} % of the CPU"
    fields = {
        "rounds": rounds,
        "kreisel_best_s": timing["fast_s"],
        "peer_best_s": timing["slow_s"],
        "speedup": timing["ratio"],
        "speedup_rounds": r,
        "speedup_best_times": timing["best_ratio"],
        "steal_share": timing["steal"],
    }
    return line, fields


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


def print_table(rows, columns):
    """Prints rows (dicts) under a header: ``columns`` are (title, width, cell) with cell(row)
    the text of a cell; the first column is left-aligned, the others right-aligned."""
    align = ["<"] + [">"] * (len(columns) - 1)
    print(" ".join(f"{c[0]:{a}{c[1]}}" for c, a in zip(columns, align)))
    for row in rows:
        print(" ".join(f"{c[2](row):{a}{c[1]}}" for c, a in zip(columns, align)))


def write_results(path, result):
    """Writes a benchmark's result dict as JSON (NaN allowed) to ``path`` and says so."""
    import json

    path.write_text(json.dumps(result, indent=2, allow_nan=True) + "\n")
    print(f"wrote {path}")
    return result


def mujoco_or_none(script: str):
    """The mujoco module, or None after saying that ``script`` skips for want of it."""
    try:
        import mujoco
    except ImportError:
        print(
            f"{script}: MuJoCo is not installed; skipping "
            "(pip install -r requirements-bench.txt to run this benchmark)."
        )
        return None
    return mujoco


def repeats_and_t_end(doc: str, t_end: float, argv=None):
    """The command line of a timed run: ``--repeats`` (best of, default 3) and ``--t-end``."""
    import argparse

    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="best of this many (default 3)")
    parser.add_argument("--t-end", type=float, default=t_end, help=f"seconds (default {t_end:g})")
    args = parser.parse_args(argv)
    if args.repeats < 1 or not args.t_end > 0:
        parser.error("--repeats and --t-end must be positive")
    return args
