"""Benchmark T1: a tippe top with viscous friction, kreisel.simulate against scipy's DOP853.

    python benchmarks/bench_play.py [--rounds R] [--t-end T]

The tippe top of docs/benchmarks.md case T1 (m = 0.02 kg, rho = 0.02 m, s = 0.006 m, C = 0.4 m
rho^2, A = 0.8 C, viscous friction: tangential force -mu N v_T with mu = 1 s/m), started at
theta = pi - 0.1 with psi_dot = 150 rad/s and everything else zero, is integrated for 12 s
with rtol = 1e-9, atol = 1e-12 by kreisel.simulate (DOP853, every accepted step returned)
and by scipy.integrate.solve_ivp(method="DOP853") on the same Newton-Euler equations
(right-hand side below, plain Python floats). They are timed side by side in R rounds
(default 7): one scipy run, then kreisel runs for as long; the ratio is the median over the
rounds of scipy's time over kreisel's median time in that round (_common.paired), which
keeps the machine's changes of speed out of it. Reported: the best times and the ratio,
the inversion time of both (the first accepted step with u = cos(theta) > 0, and the
crossing interpolated linearly between the two steps around it), and the largest relative
drift of Jellett's integral J = L.(s e3 + rho ez), which the sliding friction must keep.
Result: benchmarks/results-play.json.

The peer's equations (theory: play top): G's horizontal position and velocity, the unit
quaternion q (body -> space) and the body angular velocity omega are integrated; G's height
and vertical velocity follow from the contact (z_G = rho + s u, dz_G/dt = s du/dt). The
contact force is N (ez - mu v_T) at T = Z - rho ez, a = GT = -s e3 - rho ez; N comes from
the constraint m s d^2u/dt^2 = N - m g, which is affine in N.
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
from _common import drift, paired, paired_summary
from scipy.integrate import solve_ivp

import kreisel

CASE = "T1"
M, RHO, S = 0.02, 0.02, 0.006
C = 0.4 * M * RHO**2
A = 0.8 * C
G = 9.81
MU = 1.0
THETA0, PSI_DOT0 = math.pi - 0.1, 150.0
RTOL, ATOL = 1e-9, 1e-12
T_END = 12.0
OUT = pathlib.Path(__file__).resolve().parent / "results-play.json"


# --------------------------------------------------------------------------------------
# the peer: the same Newton-Euler equations for scipy
# --------------------------------------------------------------------------------------


def initial_state():
    """(x, y, vx, vy, q, omega_body) for theta = THETA0, phi = psi = 0, psi_dot = PSI_DOT0."""
    q = [math.cos(THETA0 / 2), math.sin(THETA0 / 2), 0.0, 0.0]  # Rx(theta)
    return np.array([0.0, 0.0, 0.0, 0.0, *q, 0.0, 0.0, PSI_DOT0])


def rhs(_t, y):
    _, _, vx, vy, qw, qx, qy, qz, w1, w2, w3 = y
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    a0, a1, a2, a3 = qw / n, qx / n, qy / n, qz / n
    r00 = 1 - 2 * (a2 * a2 + a3 * a3)
    r01 = 2 * (a1 * a2 - a0 * a3)
    r02 = 2 * (a1 * a3 + a0 * a2)
    r10 = 2 * (a1 * a2 + a0 * a3)
    r11 = 1 - 2 * (a1 * a1 + a3 * a3)
    r12 = 2 * (a2 * a3 - a0 * a1)
    r20 = 2 * (a1 * a3 - a0 * a2)
    r21 = 2 * (a2 * a3 + a0 * a1)
    r22 = 1 - 2 * (a1 * a1 + a2 * a2)
    e3x, e3y, e3z = r02, r12, r22
    # angular velocity in space
    ox = r00 * w1 + r01 * w2 + r02 * w3
    oy = r10 * w1 + r11 * w2 + r12 * w3
    oz = r20 * w1 + r21 * w2 + r22 * w3
    # de3/dt = omega x e3
    dx = oy * e3z - oz * e3y
    dy = oz * e3x - ox * e3z
    # a = GT = -s e3 - rho ez; slip velocity v_T = v + omega x a (horizontal)
    ax, ay, az = -S * e3x, -S * e3y, -S * e3z - RHO
    vtx = vx + oy * az - oz * ay
    vty = vy + oz * ax - ox * az
    fx, fy = -MU * vtx, -MU * vty  # friction per unit N; F = N (fx, fy, 1)
    # torque per unit N, a x (fx, fy, 1), into the body frame
    tx = ay - az * fy
    ty = az * fx - ax
    tz = ax * fy - ay * fx
    b1 = (r00 * tx + r10 * ty + r20 * tz) / A
    b2 = (r01 * tx + r11 * ty + r21 * tz) / A
    b3 = (r02 * tx + r12 * ty + r22 * tz) / C
    k = (C - A) / A
    g1, g2 = -k * w2 * w3, k * w1 * w3  # Euler's gyroscopic part; wdot = g + N b
    # d^2u/dt^2 = (omega' x e3)_z + (omega x de3/dt)_z = u0 + N u1
    o0x, o0y = r00 * g1 + r01 * g2, r10 * g1 + r11 * g2
    o1x = r00 * b1 + r01 * b2 + r02 * b3
    o1y = r10 * b1 + r11 * b2 + r12 * b3
    u0 = o0x * e3y - o0y * e3x + ox * dy - oy * dx
    u1 = o1x * e3y - o1y * e3x
    nf = (G + S * u0) / (1.0 / M - S * u1)
    return [
        vx,
        vy,
        nf * fx / M,
        nf * fy / M,
        0.5 * (-qx * w1 - qy * w2 - qz * w3),
        0.5 * (qw * w1 + qy * w3 - qz * w2),
        0.5 * (qw * w2 + qz * w1 - qx * w3),
        0.5 * (qw * w3 + qx * w2 - qy * w1),
        g1 + nf * b1,
        g2 + nf * b2,
        nf * b3,
    ]


def peer_u_and_jellett(ys):
    """u and Jellett's J for the (11, n) solution array of the peer."""
    q = ys[4:8] / np.linalg.norm(ys[4:8], axis=0)
    qw, qx, qy, qz = q
    e3 = np.array([2 * (qx * qz + qw * qy), 2 * (qy * qz - qw * qx), 1 - 2 * (qx * qx + qy * qy)])
    # L . e3 = C omega3;  L . ez = A omega . ez + (C - A) omega3 u, omega . ez = omega_b . (R^T ez)
    w = ys[8:11]
    gz = np.array([2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)])
    u = e3[2]
    wz = np.sum(w * gz, axis=0)
    lz = A * wz + (C - A) * w[2] * u
    return u, S * C * w[2] + RHO * lz


# --------------------------------------------------------------------------------------
# measurement
# --------------------------------------------------------------------------------------


def inversion(t, u):
    """(first step time with u > 0, crossing of u = 0 interpolated linearly), nan if none."""
    above = np.flatnonzero(np.asarray(u) > 0.0)
    if len(above) == 0 or above[0] == 0:
        return math.nan, math.nan
    i = int(above[0])
    t0, t1, u0, u1 = t[i - 1], t[i], u[i - 1], u[i]
    return float(t1), float(t0 + (t1 - t0) * (-u0) / (u1 - u0))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7, help="timing rounds (default 7)")
    parser.add_argument("--t-end", type=float, default=T_END, help="seconds (default 12)")
    args = parser.parse_args(argv)
    if args.rounds < 1 or not args.t_end > 0:
        parser.error("--rounds and --t-end must be positive")
    t_end = args.t_end

    top = kreisel.PlayTop(m=M, A=A, C=C, s=S, rho=RHO, g=G, friction=kreisel.Viscous(mu=MU))
    state = top.state(THETA0, psi_dot=PSI_DOT0)
    y0 = initial_state()

    def run_kreisel():
        return kreisel.simulate(top, state, t_end, rtol=RTOL, atol=ATOL)

    def run_scipy():
        return solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    # warm-up (first-call costs are not what we measure)
    kreisel.simulate(top, state, 0.1, rtol=RTOL, atol=ATOL)
    solve_ivp(rhs, (0.0, 0.01), y0, method="DOP853", rtol=RTOL, atol=ATOL)

    timing = paired(run_kreisel, run_scipy, args.rounds)
    traj, sol = timing["fast_out"], timing["slow_out"]
    assert sol.success, sol.message
    kreisel_s, peer_s = timing["fast_s"], timing["slow_s"]

    # the peer's start must be kreisel's start
    np.testing.assert_allclose(state.quaternion, y0[4:8], atol=1e-15)
    np.testing.assert_allclose(state.omega, y0[8:11], atol=1e-13)

    u_p, j_p = peer_u_and_jellett(sol.y)
    k_inv_step, k_inv = inversion(traj.t, traj.u)
    p_inv_step, p_inv = inversion(sol.t, u_p)
    k_drift, p_drift = drift(traj.jellett), drift(j_p)
    k_steps, p_steps = int(traj.stats["steps"]), len(sol.t) - 1
    k_evals, p_evals = int(traj.stats["rhs_evals"]), int(sol.nfev)

    print(
        f"case {CASE}: PlayTop(m={M}, A={A:.4g}, C={C:.4g}, s={S}, rho={RHO}, Viscous(mu={MU})),"
        f" theta = pi - 0.1, psi_dot = {PSI_DOT0}, t = [0, {t_end:g}] s, rtol {RTOL:g},"
        f" atol {ATOL:g}, {args.rounds} timing rounds"
    )
    head = f"{'implementation':<26} {'best s':>9} {'steps':>6} {'f evals':>8}"
    print(f"{head} {'u>0 step (s)':>12} {'u=0 (s)':>9} {'J drift':>10} {'final u':>10}")
    print(
        f"{'kreisel.simulate dop853':<26} {kreisel_s:>9.4f} {k_steps:>6d} {k_evals:>8d} "
        f"{k_inv_step:>12.5f} {k_inv:>9.5f} {k_drift:>10.2e} {traj.u[-1]:>10.7f}"
    )
    print(
        f"{'scipy solve_ivp DOP853':<26} {peer_s:>9.4f} {p_steps:>6d} {p_evals:>8d} "
        f"{p_inv_step:>12.5f} {p_inv:>9.5f} {p_drift:>10.2e} {u_p[-1]:>10.7f}"
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
        "kreisel_rhs_evals": k_evals,
        "peer_steps": p_steps,
        "peer_rhs_evals": p_evals,
        "kreisel_inversion_step_s": k_inv_step,
        "peer_inversion_step_s": p_inv_step,
        "kreisel_inversion_s": k_inv,
        "peer_inversion_s": p_inv,
        "kreisel_jellett_drift": k_drift,
        "peer_jellett_drift": p_drift,
        "kreisel_final_u": float(traj.u[-1]),
        "peer_final_u": float(u_p[-1]),
    }
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")
    return result


if __name__ == "__main__":
    main()
