"""Benchmark D1: a shaken, damped heavy top, kreisel.simulate (DOP853) against scipy's solve_ivp.

    python benchmarks/bench_driven.py [--rounds R] [--t-end T] [--out PATH]

The L1 top as a HeavyTop (I1 = I2 = 1, I3 = 0.5 about the pivot, m = 1, centre of mass at
l = 1 on the figure axis, g = 1, SI), its pivot shaken vertically, r_O = (0, 0, 0.05 cos(20 t)),
with viscous pivot damping 0.01 N m s, from L1's start (theta = 1, theta_dot = 0.3,
phi_dot = 0.7, psi_dot = 9), is integrated for 100 s with rtol = 1e-10, atol = 1e-12 by
kreisel.simulate(method="dop853") and by scipy.integrate.solve_ivp(method="DOP853") on the
same equations (unit quaternion + body angular velocity; in the frame that moves with the
pivot the top feels gravity and the inertial force -m a_O(t) at its centre of mass; the
right-hand side in plain Python below). Both return every accepted step. kreisel also integrates
the pivot's work and the dissipated energy along (two more components, whose errors its error
norm measures against the motion's energy scale, so they take no extra steps: the same 4915 as
scipy on the motion alone), so there are two peers: scipy on the motion alone (the ratio
reported first, the target's) and scipy on the same nine components with its plain error norm
(which their absolute tolerance near zero drives to 7175 steps). Each is timed against kreisel
side by side in R rounds (default 9): one scipy run, then kreisel runs for as long; the ratio is
the median over the rounds of scipy's time over kreisel's median time in that round
(_common.paired). The final states of both are compared with a tight scipy run (rtol 1e-13, atol
1e-15; the motion is regular, its Lyapunov estimate decays like ln(t)/t, so the comparison at
100 s means something). The result is written to benchmarks/results-driven.json (or --out).
"""

from __future__ import annotations

import argparse
import math
import os
import pathlib

# No BLAS is timed here; idle OpenBLAS threads would only spin against the integrators.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import paired, paired_summary, print_table, quat_to_matrix, write_results
from bench_simulate import STATE, initial_state  # L1's start
from scipy.integrate import solve_ivp

import kreisel
from kreisel import pivots

CASE = "D1"
TOP = {"I1": 1.0, "I2": 1.0, "I3": 0.5, "m": 1.0, "com": (0.0, 0.0, 1.0), "g": 1.0}
SHAKE = {"amplitude": 0.05, "omega": 20.0}  # vertical: r_O = (0, 0, a cos(omega t))
VISCOUS = 0.01  # N m s
RTOL, ATOL = 1e-10, 1e-12
T_END = 100.0
OUT = pathlib.Path(__file__).resolve().parent / "results-driven.json"


def kreisel_top():
    pivot = pivots.Harmonic([0.0, 0.0, SHAKE["amplitude"]], SHAKE["omega"])
    return kreisel.HeavyTop(**TOP, pivot=pivot, damping=kreisel.PivotDamping(viscous=VISCOUS))


# --------------------------------------------------------------------------------------
# the peer: the same equations for scipy
# --------------------------------------------------------------------------------------


def make_rhs(balance=False):
    """dq/dt = 1/2 q (x) (0, omega);  I domega/dt = (I omega) x omega + tau - c omega with
    tau = m l (g + a_Oz(t)) (Gamma x e3), a_Oz = -a omega^2 cos(omega t) the pivot's
    acceleration and Gamma = R(q)^T e_z the upward vertical in the body (I1 = I2, centre of
    mass on the 3-axis: the vertical inertial force adds to gravity).

    With ``balance``, two more components as kreisel integrates them: the pivot's work,
    d/dt = R_z v_Oz with R_z = m (a_Oz + Gamma . b + g) the pivot's vertical force (b = domega
    x com + omega x (omega x com), body frame), and the dissipated energy, d/dt = c |omega|^2.
    """
    i1, i3 = TOP["I1"], TOP["I3"]
    m, arm, g = TOP["m"], TOP["com"][2], TOP["g"]
    a, w = SHAKE["amplitude"], SHAKE["omega"]
    aw2 = a * w * w
    k12 = (i1 - i3) / i1  # Euler: I1 w1dot = (I2 - I3) w2 w3 + torque, with I2 = I1
    c1, c3 = VISCOUS / i1, VISCOUS / i3

    def motion(t, y):
        qw, qx, qy, qz, w1, w2, w3 = y[:7]
        g1 = 2.0 * (qx * qz - qw * qy)
        g2 = 2.0 * (qy * qz + qw * qx)
        az = -aw2 * math.cos(w * t)
        mgl = m * arm * (g + az) / i1
        d1 = k12 * w2 * w3 + mgl * g2 - c1 * w1
        d2 = -k12 * w3 * w1 - mgl * g1 - c1 * w2
        dy = [
            0.5 * (-qx * w1 - qy * w2 - qz * w3),
            0.5 * (qw * w1 + qy * w3 - qz * w2),
            0.5 * (qw * w2 + qz * w1 - qx * w3),
            0.5 * (qw * w3 + qx * w2 - qy * w1),
            d1,
            d2,
            -c3 * w3,
        ]
        return dy, (g1, g2, 1.0 - 2.0 * (qx * qx + qy * qy)), az, (w1, w2, w3, d1, d2)

    def rhs(t, y):
        return np.array(motion(t, y)[0])

    def rhs_balance(t, y):
        dy, (g1, g2, g3), az, (w1, w2, w3, d1, d2) = motion(t, y)
        b = (arm * (d2 + w1 * w3), arm * (-d1 + w2 * w3), -arm * (w1 * w1 + w2 * w2))
        force_z = m * (az + g1 * b[0] + g2 * b[1] + g3 * b[2] + g)
        v_z = -a * w * math.sin(w * t)
        return np.array([*dy, force_z * v_z, VISCOUS * (w1 * w1 + w2 * w2 + w3 * w3)])

    return rhs_balance if balance else rhs


def final_gaps(q_a, w_a, q_b, w_b):
    """(largest entry of R(q_a) - R(q_b), largest |w_a - w_b|) of two final states."""
    rot = float(np.abs(quat_to_matrix(q_a) - quat_to_matrix(q_b)).max())
    return rot, float(np.abs(np.asarray(w_a) - np.asarray(w_b)).max())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=9, help="timing rounds (default 9)")
    parser.add_argument("--t-end", type=float, default=T_END, help="seconds (default 100)")
    parser.add_argument("--out", type=pathlib.Path, default=OUT, help=f"(default {OUT.name})")
    args = parser.parse_args(argv)
    if args.rounds < 1 or not args.t_end > 0:
        parser.error("--rounds and --t-end must be positive")
    t_end = args.t_end

    top = kreisel_top()
    state = top.state(STATE["theta"], **{k: v for k, v in STATE.items() if k != "theta"})
    q0, w0 = initial_state()
    rhs, rhs_balance = make_rhs(), make_rhs(balance=True)
    y0 = np.concatenate([q0, w0])
    y0_balance = np.concatenate([y0, [0.0, 0.0]])

    def run_kreisel():
        return kreisel.simulate(top, state, t_end, method="dop853", rtol=RTOL, atol=ATOL)

    def run_scipy():
        return solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    def run_scipy_balance():
        return solve_ivp(
            rhs_balance, (0.0, t_end), y0_balance, method="DOP853", rtol=RTOL, atol=ATOL
        )

    # warm-up (first-call costs are not what we measure)
    kreisel.simulate(top, state, 1.0, method="dop853", rtol=RTOL, atol=ATOL)
    solve_ivp(rhs, (0.0, 1.0), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    timing = paired(run_kreisel, run_scipy, args.rounds)
    timing_b = paired(run_kreisel, run_scipy_balance, args.rounds)
    traj, sol, sol_b = timing["fast_out"], timing["slow_out"], timing_b["slow_out"]
    assert sol.success and sol_b.success, (sol.message, sol_b.message)
    # the two start from the same state
    assert np.abs(traj.quaternion[0] - q0).max() < 1e-15, traj.quaternion[0]
    assert np.abs(traj.omega[0] - w0).max() < 1e-14, traj.omega[0]

    tight = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-15)
    assert tight.success, tight.message
    q_ref, w_ref = tight.y[:4, -1], tight.y[4:, -1]
    k_rot, k_omega = final_gaps(traj.quaternion[-1], traj.omega[-1], q_ref, w_ref)
    s_rot, s_omega = final_gaps(sol.y[:4, -1], sol.y[4:, -1], q_ref, w_ref)
    b_rot, b_omega = final_gaps(sol_b.y[:4, -1], sol_b.y[4:7, -1], q_ref, w_ref)
    kk_rot, kk_omega = final_gaps(traj.quaternion[-1], traj.omega[-1], sol.y[:4, -1],
                                  sol.y[4:, -1])  # fmt: skip
    balance = float(np.ptp(traj.balance))
    work_gap = abs(float(traj.work_by_pivot[-1]) - float(sol_b.y[7, -1]))
    diss_gap = abs(float(traj.dissipated[-1]) - float(sol_b.y[8, -1]))

    print(
        f"case {CASE}: HeavyTop({TOP}), pivot r_O = (0, 0, {SHAKE['amplitude']} cos("
        f"{SHAKE['omega']} t)), viscous {VISCOUS}, {STATE}, t = [0, {t_end:g}] s, "
        f"rtol {RTOL:g}, atol {ATOL:g}, {args.rounds} timing rounds per peer"
    )
    rows = [
        {"name": "kreisel.simulate dop853", "s": timing["fast_s"], "steps": traj.stats["steps"],
         "rejected": str(traj.stats["rejected"]), "evals": traj.stats["rhs_evals"],
         "rot": k_rot, "omega": k_omega},
        {"name": "scipy DOP853, motion", "s": timing["slow_s"], "steps": len(sol.t) - 1,
         "rejected": "-", "evals": sol.nfev, "rot": s_rot, "omega": s_omega},
        {"name": "scipy DOP853, + balance", "s": timing_b["slow_s"], "steps": len(sol_b.t) - 1,
         "rejected": "-", "evals": sol_b.nfev, "rot": b_rot, "omega": b_omega},
    ]  # fmt: skip
    print_table(
        rows,
        [
            ("implementation", 26, lambda r: r["name"]),
            ("best s", 9, lambda r: f"{r['s']:.4f}"),
            ("steps", 7, lambda r: f"{r['steps']:d}"),
            ("rejected", 8, lambda r: r["rejected"]),
            ("f evals", 8, lambda r: f"{r['evals']:d}"),
            ("|R - R_tight|", 14, lambda r: f"{r['rot']:.3e}"),
            ("|w - w_tight|", 14, lambda r: f"{r['omega']:.3e}"),
        ],
    )
    print(
        f"final states, kreisel against scipy (motion): |dR| {kk_rot:.3e}, |d omega| "
        f"{kk_omega:.3e} rad/s; against scipy (+ balance): work {work_gap:.3e} J, dissipated "
        f"{diss_gap:.3e} J; kreisel's E + dissipated - work_by_pivot varies by {balance:.3e} J"
    )
    line, fields = paired_summary(timing, args.rounds, "scipy on the motion alone")
    print(line)
    line_b, fields_b = paired_summary(timing_b, args.rounds, "scipy with the balance too")
    print(line_b)

    return write_results(
        args.out,
        {
            "case": CASE,
            "t_end": t_end,
            "rtol": RTOL,
            "atol": ATOL,
            **fields,
            "target_speedup": 300.0,
            "with_balance": {
                k: fields_b[k]
                for k in ("peer_best_s", "speedup", "speedup_rounds", "speedup_best_times")
            },
            "kreisel_steps": int(traj.stats["steps"]),
            "kreisel_rejected": int(traj.stats["rejected"]),
            "kreisel_rhs_evals": int(traj.stats["rhs_evals"]),
            "peer_steps": len(sol.t) - 1,
            "peer_rhs_evals": int(sol.nfev),
            "peer_with_balance_steps": len(sol_b.t) - 1,
            "peer_with_balance_rhs_evals": int(sol_b.nfev),
            "kreisel_final_rotation_error": k_rot,
            "kreisel_final_omega_error": k_omega,
            "peer_final_rotation_error": s_rot,
            "peer_final_omega_error": s_omega,
            "peer_with_balance_final_rotation_error": b_rot,
            "peer_with_balance_final_omega_error": b_omega,
            "final_rotation_gap": kk_rot,
            "final_omega_gap": kk_omega,
            "final_work_gap": work_gap,
            "final_dissipated_gap": diss_gap,
            "kreisel_balance_variation": balance,
        },
    )


if __name__ == "__main__":
    main()
