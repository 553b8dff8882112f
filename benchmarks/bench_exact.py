"""Benchmark X1: kreisel's exact Lagrange-top solution against bare scipy.special.ellipj.

    python benchmarks/bench_exact.py [--n N] [--repeats R]

kreisel evaluates the full motion (theta, phi, psi and their rates) at n times; the peer is
scipy.special.ellipj alone (sn, cn, dn, am) at the same number of arguments, i.e. only the
Jacobi-function core of an elliptic-function solution of the same top.  Both are timed in
the same run, best of R repeats, with time.perf_counter.  The result is written to
benchmarks/results-exact.json.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib

# No BLAS is timed here; idle OpenBLAS threads would only spin against kreisel's workers.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import best_of
from scipy.special import ellipj

import kreisel

CASE = "X1"
PARAMS = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 1.0, "g": 1.0}
STATE = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 9.0}
T_END = 500.0
OUT = pathlib.Path(__file__).resolve().parent / "results-exact.json"


def elliptic_arguments(t):
    """Arguments and parameter of sn for this top, from the roots of f(u) (numpy only)."""
    p = PARAMS
    th, thd, phd, psd = (STATE[k] for k in ("theta", "theta_dot", "phi_dot", "psi_dot"))
    c, s = math.cos(th), math.sin(th)
    omega3 = psd + phd * c
    m3 = p["I3"] * omega3
    mz = p["I1"] * phd * s * s + m3 * c
    mgl = p["m"] * p["g"] * p["l"]
    energy = 0.5 * p["I1"] * (thd**2 + (phd * s) ** 2) + 0.5 * p["I3"] * omega3**2 + mgl * c
    a, b = m3 / p["I1"], mz / p["I1"]
    beta = 2 * mgl / p["I1"]
    alpha = 2 * (energy - m3 * m3 / (2 * p["I3"])) / p["I1"]
    roots = np.sort(np.roots([beta, -(alpha + a * a), 2 * a * b - beta, alpha - b * b]).real)
    u1, u2, u3 = roots
    k2 = (u2 - u1) / (u3 - u1)
    rate = math.sqrt(beta * (u3 - u1)) / 2
    return rate * t, k2


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=10**6, help="number of times (default 1e6)")
    parser.add_argument("--repeats", type=int, default=5, help="best of this many (default 5)")
    args = parser.parse_args(argv)
    if args.n < 1 or args.repeats < 1:
        parser.error("--n and --repeats must be positive")

    top = kreisel.LagrangeTop(**PARAMS)
    state = top.state(STATE["theta"], **{k: v for k, v in STATE.items() if k != "theta"})
    t = np.linspace(0.0, T_END, args.n)
    args_sn, k2 = elliptic_arguments(t)

    # warm-up (first-call costs are not what we measure)
    top.exact(state, t[: min(args.n, 1000)])
    ellipj(args_sn[: min(args.n, 1000)], k2)

    kreisel_s, _ = best_of(lambda: top.exact(state, t), args.repeats)
    peer_s, _ = best_of(lambda: ellipj(args_sn, k2), args.repeats)
    ratio = kreisel_s / peer_s

    print(f"case {CASE}: n = {args.n}, t in [0, {T_END:g}] s, best of {args.repeats}")
    print(f"{'implementation':<34} {'seconds':>10} {'ns/point':>10}")
    print(f"{'kreisel LagrangeTop.exact':<34} {kreisel_s:>10.4f} {kreisel_s / args.n * 1e9:>10.1f}")
    print(f"{'scipy.special.ellipj (alone)':<34} {peer_s:>10.4f} {peer_s / args.n * 1e9:>10.1f}")
    print(f"ratio kreisel / ellipj = {ratio:.3f}  (kreisel {1 / ratio:.1f}x faster)")

    result = {"case": CASE, "n": args.n, "kreisel_s": kreisel_s, "peer_s": peer_s, "ratio": ratio}
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")
    return result


if __name__ == "__main__":
    main()
