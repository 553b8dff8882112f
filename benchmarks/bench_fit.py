"""Benchmark F1: fitting a heavy top to a phone's gyroscope, kreisel.fit against scipy's
least_squares with finite differences over solve_ivp.

    python benchmarks/bench_fit.py [--rounds R] [--out PATH]

The recording: a symmetric heavy top (I1 = I2 = 1, I3 = 0.5 about the pivot, m = 0.1, centre of
mass at l = 1 on the figure axis, g = 10, SI: I3/I1 = 0.5 and m g l / I1 = 1, the L1 top's
ratios) from L1's start (theta = 1, theta_dot = 0.3, phi_dot = 0.7, psi_dot = 9), its body
rates at 100 Hz for 20 s (2000 samples per axis), integrated here by solve_ivp (DOP853, rtol
1e-13) on the unit-quaternion and body-rate equations, with Gaussian noise of 0.01 rad/s. Five
unknowns: I3/I1 and m g l / I1 (as I3 and com[2] with I1, m, g known) and theta, phi_dot,
psi_dot; both start from the same guess, 0.5 % to 4 % off (20 s of a fast top wind the
phases up: from 10 % off both solvers end in local minima). kreisel.fit (trust-region least
squares; its Jacobian from the core's sensitivities where the core has them, else central
differences over kreisel.simulate) against scipy.optimize.least_squares (trust-region, its
default forward-difference Jacobian) over solve_ivp(method="DOP853"), both runs at rtol 1e-10,
atol 1e-12. The two are timed side by side in R rounds (default 2; _common.paired), and their
estimates and errors compared. The result goes to benchmarks/results-fit.json (or --out).
"""

from __future__ import annotations

import argparse
import math
import os
import pathlib

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import paired, paired_summary, print_table, write_results
from bench_simulate import make_rhs
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

import kreisel

CASE = "F1"
TRUE = {"I3": 0.5, "com[2]": 1.0, "theta": 1.0, "phi_dot": 0.7, "psi_dot": 9.0}
START = {"I3": 0.52, "com[2]": 0.96, "theta": 0.98, "phi_dot": 0.72, "psi_dot": 8.95}
THETA_DOT = 0.3
I1, M, G = 1.0, 0.1, 10.0
RATE, T_END, SIGMA = 100.0, 20.0, 0.01
RTOL, ATOL = 1e-10, 1e-12
OUT = pathlib.Path(__file__).resolve().parent / "results-fit.json"


def start_state(theta, phi_dot, psi_dot):
    """(q, omega_body) for z-x-z Euler angles phi = psi = 0 and these rates."""
    q = np.array([math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0])  # Rx(theta)
    omega = np.array([THETA_DOT, phi_dot * math.sin(theta), phi_dot * math.cos(theta) + psi_dot])
    return q, omega


def body_rates(p, t, rtol, atol):
    """Body rates (n, 3) at times t for p = (I3, l, theta, phi_dot, psi_dot)."""
    i3, lever, theta, phi_dot, psi_dot = p
    q, w = start_state(theta, phi_dot, psi_dot)
    rhs = make_rhs({"I1": I1, "I3": i3, "m": M, "g": G, "l": lever})  # L1's equations
    sol = solve_ivp(rhs, (0.0, t[-1]), np.concatenate([q, w]), t_eval=t, method="DOP853",
                    rtol=rtol, atol=atol)  # fmt: skip
    return sol.y[4:].T


def recording(seed=2026):
    t = np.arange(int(RATE * T_END)) / RATE
    clean = body_rates([TRUE[k] for k in TRUE], t, 1e-13, 1e-15)
    rng = np.random.default_rng(seed)
    return t, clean + rng.normal(0.0, SIGMA, clean.shape)


def fit_kreisel(t, data):
    top = kreisel.HeavyTop(I1=I1, I2=I1, I3=START["I3"], m=M, com=[0.0, 0.0, START["com[2]"]],
                           g=G)  # fmt: skip
    state = top.state(theta=START["theta"], theta_dot=THETA_DOT, phi_dot=START["phi_dot"],
                      psi_dot=START["psi_dot"])  # fmt: skip
    obs = kreisel.Observations(t, data, "body_rates", sigma=SIGMA)
    return kreisel.fit(top, state, obs, free=list(TRUE), rtol=RTOL, atol=ATOL)


def fit_scipy(t, data):
    def residuals(p):
        return ((body_rates(p, t, RTOL, ATOL) - data) / SIGMA).ravel()

    sol = least_squares(residuals, [START[k] for k in TRUE], method="trf", x_scale="jac")
    J = sol.jac
    cov = np.linalg.inv(J.T @ J)
    return sol, np.sqrt(np.diag(cov))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--out", type=pathlib.Path, default=OUT)
    args = parser.parse_args(argv)
    t, data = recording()
    timing = paired(lambda: fit_kreisel(t, data), lambda: fit_scipy(t, data), args.rounds)
    res = timing["fast_out"]
    sol, scipy_err = timing["slow_out"]
    rows = [
        {"name": k, "true": v, "kreisel": res.values[k], "k_err": res.errors[k],
         "scipy": sol.x[i], "s_err": scipy_err[i]}
        for i, (k, v) in enumerate(TRUE.items())
    ]  # fmt: skip
    print(f"F1: 5 unknowns from {data.size} samples; kreisel's Jacobian: {res.jacobian}")
    print_table(
        rows,
        [
            ("name", 8, lambda r: r["name"]),
            ("true", 8, lambda r: f"{r['true']:.4g}"),
            ("kreisel", 12, lambda r: f"{r['kreisel']:.7g}"),
            ("+-", 9, lambda r: f"{r['k_err']:.2g}"),
            ("scipy", 12, lambda r: f"{r['scipy']:.7g}"),
            ("+-", 9, lambda r: f"{r['s_err']:.2g}"),
        ],
    )
    print(f"chi2/dof: kreisel {res.chi2 / res.dof:.4f}, scipy {2 * sol.cost / res.dof:.4f}")
    line, fields = paired_summary(timing, args.rounds, "least_squares over solve_ivp")
    print(line + f" (kreisel's Jacobian: {res.jacobian})")
    return write_results(
        args.out,
        {
            "case": CASE,
            "kreisel_jacobian": res.jacobian,
            "samples": int(data.size),
            "estimates": rows,
            "chi2_kreisel": res.chi2,
            "chi2_scipy": 2 * sol.cost,
            "nfev_scipy": int(sol.nfev),
            **fields,
        },
    )


if __name__ == "__main__":
    main()
