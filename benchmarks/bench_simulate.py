"""Benchmark L1: kreisel.simulate (DOP853) against scipy's solve_ivp DOP853 on the same top.

    python benchmarks/bench_simulate.py [--rounds R] [--t-end T]

The Lagrange top I1 = 1, I3 = 0.5, m = 1, l = 1, g = 1 (SI) from theta = 1, theta_dot = 0.3,
phi_dot = 0.7, psi_dot = 9 is integrated for 100 s with rtol = 1e-10, atol = 1e-12 by
kreisel.simulate(method="dop853") and by scipy.integrate.solve_ivp(method="DOP853") on the
same equations (unit quaternion + body angular velocity, right-hand side in plain Python /
numpy below). Both return every accepted step. They are timed side by side in R rounds
(default 9): one scipy run, then kreisel runs for as long; the ratio is the median over the
rounds of scipy's time over kreisel's median time in that round (_common.paired), which
keeps the machine's changes of speed out of it. The best time of each is reported too.
The final states are compared with the exact solution
(kreisel.LagrangeTop.exact). The result is written to benchmarks/results-simulate.json.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib

# No BLAS is timed here; idle OpenBLAS threads would only spin against the integrators.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import paired, paired_summary, quat_to_matrix
from scipy.integrate import solve_ivp

import kreisel

CASE = "L1"
PARAMS = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 1.0, "g": 1.0}
STATE = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 9.0}
RTOL, ATOL = 1e-10, 1e-12
T_END = 100.0
OUT = pathlib.Path(__file__).resolve().parent / "results-simulate.json"


# --------------------------------------------------------------------------------------
# the peer: the same equations for scipy
# --------------------------------------------------------------------------------------


def initial_state():
    """(q, omega_body) for z-x-z Euler angles phi = psi = 0 and the rates of STATE."""
    th, thd, phd, psd = (STATE[k] for k in ("theta", "theta_dot", "phi_dot", "psi_dot"))
    q = np.array([math.cos(th / 2), math.sin(th / 2), 0.0, 0.0])  # Rx(theta)
    omega = np.array([thd, phd * math.sin(th), phd * math.cos(th) + psd])  # psi = 0
    return q, omega


def make_rhs(params=None):
    """dq/dt = 1/2 q (x) (0, omega);  I domega/dt = (I omega) x omega + m g l (Gamma x e3),
    Gamma = R(q)^T e_z the upward vertical in the body."""
    p = PARAMS if params is None else params  # another top's (bench_fit.py)
    i1, i3 = p["I1"], p["I3"]
    mgl = p["m"] * p["g"] * p["l"]
    k12 = (i1 - i3) / i1  # Euler: I1 w1dot = (I2 - I3) w2 w3 + torque, with I2 = I1

    def rhs(_t, y):
        qw, qx, qy, qz, w1, w2, w3 = y
        g1 = 2.0 * (qx * qz - qw * qy)
        g2 = 2.0 * (qy * qz + qw * qx)
        return np.array(
            [
                0.5 * (-qx * w1 - qy * w2 - qz * w3),
                0.5 * (qw * w1 + qy * w3 - qz * w2),
                0.5 * (qw * w2 + qz * w1 - qx * w3),
                0.5 * (qw * w3 + qx * w2 - qy * w1),
                k12 * w2 * w3 + mgl * g2 / i1,
                -k12 * w3 * w1 - mgl * g1 / i1,
                0.0,
            ]
        )

    return rhs


def euler_matrix(phi, theta, psi):
    def rz(a):
        c, s = math.cos(a), math.sin(a)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    c, s = math.cos(theta), math.sin(theta)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return rz(phi) @ rx @ rz(psi)


def exact_final(top, state, t_end):
    """Exact rotation matrix and body angular velocity at t_end."""
    ex = top.exact(state, [t_end])
    th, ph, ps = ex.theta[0], ex.phi[0], ex.psi[0]
    thd, phd, psd = ex.theta_dot[0], ex.phi_dot[0], ex.psi_dot[0]
    omega = np.array(
        [
            phd * math.sin(th) * math.sin(ps) + thd * math.cos(ps),
            phd * math.sin(th) * math.cos(ps) - thd * math.sin(ps),
            phd * math.cos(th) + psd,
        ]
    )
    return euler_matrix(ph, th, ps), omega


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=9, help="timing rounds (default 9)")
    parser.add_argument("--t-end", type=float, default=T_END, help="seconds (default 100)")
    args = parser.parse_args(argv)
    if args.rounds < 1 or not args.t_end > 0:
        parser.error("--rounds and --t-end must be positive")
    t_end = args.t_end

    top = kreisel.LagrangeTop(**PARAMS)
    state = top.state(STATE["theta"], **{k: v for k, v in STATE.items() if k != "theta"})
    q0, w0 = initial_state()
    rhs = make_rhs()
    y0 = np.concatenate([q0, w0])

    def run_kreisel():
        return kreisel.simulate(top, state, t_end, method="dop853", rtol=RTOL, atol=ATOL)

    def run_scipy():
        return solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    # warm-up (first-call costs are not what we measure)
    kreisel.simulate(top, state, 1.0, method="dop853", rtol=RTOL, atol=ATOL)
    solve_ivp(rhs, (0.0, 1.0), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    timing = paired(run_kreisel, run_scipy, args.rounds)
    traj, sol = timing["fast_out"], timing["slow_out"]
    assert sol.success, sol.message
    kreisel_s, peer_s = timing["fast_s"], timing["slow_s"]

    r_exact, w_exact = exact_final(top, state, t_end)
    k_rot = float(np.abs(quat_to_matrix(traj.quaternion[-1]) - r_exact).max())
    k_omega = float(np.abs(traj.omega[-1] - w_exact).max())
    s_rot = float(np.abs(quat_to_matrix(sol.y[:4, -1]) - r_exact).max())
    s_omega = float(np.abs(sol.y[4:, -1] - w_exact).max())
    k_steps, s_steps = int(traj.stats["steps"]), len(sol.t) - 1

    print(
        f"case {CASE}: LagrangeTop({PARAMS}), {STATE}, t = [0, {t_end:g}] s, "
        f"rtol {RTOL:g}, atol {ATOL:g}, {args.rounds} timing rounds"
    )
    head = f"{'implementation':<30} {'best s':>9} {'steps':>7} {'rejected':>8} {'f evals':>8}"
    print(f"{head} {'|R - R_exact|':>14} {'|w - w_exact|':>14}")
    rejected, evals = traj.stats["rejected"], traj.stats["rhs_evals"]
    print(
        f"{'kreisel.simulate dop853':<30} {kreisel_s:>9.4f} {k_steps:>7d} "
        f"{rejected:>8d} {evals:>8d} {k_rot:>14.3e} {k_omega:>14.3e}"
    )
    print(
        f"{'scipy solve_ivp DOP853':<30} {peer_s:>9.4f} {s_steps:>7d} {'-':>8} "
        f"{sol.nfev:>8d} {s_rot:>14.3e} {s_omega:>14.3e}"
    )
    line, fields = paired_summary(timing, args.rounds, "scipy")
    print(line)

    result = {
        "case": CASE,
        "t_end": t_end,
        "rtol": RTOL,
        "atol": ATOL,
        **fields,
        "kreisel_steps": k_steps,
        "kreisel_rejected": int(traj.stats["rejected"]),
        "kreisel_rhs_evals": int(traj.stats["rhs_evals"]),
        "peer_steps": s_steps,
        "peer_rhs_evals": int(sol.nfev),
        "kreisel_final_rotation_error": k_rot,
        "kreisel_final_omega_error": k_omega,
        "peer_final_rotation_error": s_rot,
        "peer_final_omega_error": s_omega,
    }
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")
    return result


if __name__ == "__main__":
    main()
