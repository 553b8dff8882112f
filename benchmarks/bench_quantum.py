"""Benchmark Q1: kreisel.quantum's levels of one (K, M) block against numpy.linalg.eigvalsh.

    python benchmarks/bench_quantum.py [--rounds R] [--strengths N] [--chunk C]

The (K, M) = (1, 1) block of the quantum symmetric top I1 = 1, I3 = 0.5 (hbar = 1, so the
rotational constant B = hbar^2 / (2 I1) = 1/2) in the potential P cos(theta), J = 1 .. 200
(200 levels), at N = 10^4 strengths P evenly spaced in [-1000, 1000] B: from the free rotor
to the pendular regime. kreisel: ``SymmetricTop.levels(1, 1, 200, P)`` (the tridiagonal block,
its eigenvalues on all cores). The peer: the same blocks as dense 200 x 200 matrices
(``SymmetricTop.hamiltonian`` at P = 0 and P = 1 give H0 and C; H(P) = H0 + P C), formed in
chunks of C = 100 strengths and passed to ``numpy.linalg.eigvalsh`` chunk by chunk (it loops
over the stack in LAPACK's dsyevd) with one BLAS thread: its fastest setting here (two
threads gain nothing at 200 x 200 on a quiet machine, and their busy waiting made it 7x slower
while other tenants loaded the 2 cores); kreisel uses its pool on all cores. Forming the
chunks is timed with numpy and reported apart. Both in the same run, in R paired rounds
(default 3; _common.paired): one numpy run, then kreisel runs for as long; the ratio is the
median of the rounds' ratios. The levels must agree to round-off. The hypervisor's steal
time over the measurement is reported. The result is written to benchmarks/results-quantum.json.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import time

# One BLAS thread for numpy's LAPACK (see above); set before numpy is imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import paired, paired_summary

from kreisel.quantum import SymmetricTop

CASE = "Q1"
K, M, J_MAX = 1, 1, 200
TOP = {"I1": 1.0, "I3": 0.5, "hbar": 1.0}
P_RANGE = (-1000.0, 1000.0)  # in units of B = 1/2
OUT = pathlib.Path(__file__).resolve().parent / "results-quantum.json"


def dense_peer(top, strengths, chunk):
    """numpy.linalg.eigvalsh on the dense blocks, chunk by chunk: (levels, seconds spent
    forming the matrices)."""
    h0 = top.hamiltonian(K, M, J_MAX, 0.0)
    c = top.hamiltonian(K, M, J_MAX, 1.0) - h0
    out = np.empty((len(strengths), h0.shape[0]))
    forming = 0.0
    for i in range(0, len(strengths), chunk):
        p = strengths[i : i + chunk]
        start = time.perf_counter()
        stack = h0[None, :, :] + p[:, None, None] * c[None, :, :]
        forming += time.perf_counter() - start
        out[i : i + chunk] = np.linalg.eigvalsh(stack)
    return out, forming


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3, help="timing rounds (default 3)")
    parser.add_argument("--strengths", type=int, default=10**4, help="(default 1e4)")
    parser.add_argument("--chunk", type=int, default=100, help="numpy's stack (default 100)")
    args = parser.parse_args(argv)
    if min(args.rounds, args.strengths, args.chunk) < 1:
        parser.error("--rounds, --strengths and --chunk must be positive")

    top = SymmetricTop(**TOP)
    b = top.energy_scale
    strengths = np.linspace(P_RANGE[0] * b, P_RANGE[1] * b, args.strengths)
    forming = []

    def run_kreisel():
        return top.levels(K, M, J_MAX, strengths)

    def run_numpy():
        levels, seconds = dense_peer(top, strengths, args.chunk)
        forming.append(seconds)
        return levels

    # warm-up (first-call costs are not what we measure)
    top.levels(K, M, J_MAX, strengths[:64])
    dense_peer(top, strengths[:64], args.chunk)

    timing = paired(run_kreisel, run_numpy, args.rounds)
    ours, theirs = timing["fast_out"], timing["slow_out"]
    scale = float(np.abs(theirs).max())
    diff = float(np.abs(ours - theirs).max())
    assert diff <= 1e-12 * scale, f"the levels differ by {diff:.3g} (scale {scale:.3g})"
    conv = top.convergence(K, M, J_MAX, strengths[:: max(1, args.strengths // 50)])

    n = ours.shape[1]
    print(
        f"case {CASE}: SymmetricTop({TOP}), block (K, M) = ({K}, {M}), J <= {J_MAX} ({n} levels), "
        f"{args.strengths} strengths P in [{P_RANGE[0]:g}, {P_RANGE[1]:g}] B, "
        f"{args.rounds} timing rounds"
    )
    print(f"{'implementation':<44} {'best s':>9} {'us/strength':>12}")
    for name, sec in (
        ("kreisel SymmetricTop.levels (tridiagonal)", timing["fast_s"]),
        (f"numpy.linalg.eigvalsh (dense, chunks of {args.chunk})", timing["slow_s"]),
    ):
        print(f"{name:<44} {sec:>9.4f} {sec / args.strengths * 1e6:>12.1f}")
    share = min(forming) / timing["slow_s"]
    print(f"  of numpy's time, forming the dense matrices: {100 * share:.1f} %")
    print(f"largest difference of the levels: {diff:.2e} (levels up to {scale:.3g})")
    print(f"convergence in J_max (a sample of 50 strengths): {conv}")
    line, fields = paired_summary(timing, args.rounds, "numpy.linalg.eigvalsh")
    print(line)
    cores = os.cpu_count() or 1
    print(
        f"  (numpy on {os.environ['OPENBLAS_NUM_THREADS']} BLAS thread(s), kreisel on {cores} "
        f"cores: per core kreisel is at least {timing['ratio'] / cores:.0f}x faster)"
    )

    result = {
        "case": CASE,
        "K": K,
        "M": M,
        "J_max": J_MAX,
        "strengths": args.strengths,
        "chunk": args.chunk,
        **fields,
        "numpy_forming_share": share,
        "numpy_blas_threads": os.environ["OPENBLAS_NUM_THREADS"],
        "cores": os.cpu_count(),
        "max_level_difference": diff,
        "level_scale": scale,
        "levels_converged": conv.n_converged,
    }
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")
    return result


if __name__ == "__main__":
    main()
