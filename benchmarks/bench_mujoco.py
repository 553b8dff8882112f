"""Benchmark M1: long-time integrals of a Lagrange top, kreisel against MuJoCo at equal step.

    python benchmarks/bench_mujoco.py [--steps N] [--dt DT] [--repeats R]

A toy top on a fixed frictionless pivot (MuJoCo: a ball joint, no contacts, no damping,
no armature) is integrated for N = 10^5 steps of dt = 1e-3 s by MuJoCo's RK4 and implicitfast
integrators (and, for reference, its full "implicit" one, which also linearises the gyroscopic
forces) and by kreisel.simulate with "splitting" and "rk4". For every run the table
shows the relative error of the vertical angular momentum Mz and of the energy E at the end
and the largest over the run, the error of the figure axis at the end against the exact
solution (kreisel.LagrangeTop.exact), and the wall time (best of R; MuJoCo timed as one
mj_step(..., nstep=N) call, kreisel as one simulate call returning every step).

MuJoCo's <inertial> takes the mass, the centre-of-mass position and the principal moments
ABOUT THE CENTRE OF MASS; kreisel takes moments about the pivot: I1 = I1_cm + m l^2.
MuJoCo's ball-joint qpos is the body quaternion (w, x, y, z) and qvel the angular velocity
in the body frame, the same variables as kreisel's. Results: benchmarks/results-mujoco.json.
Needs `pip install mujoco` (requirements-bench.txt); without it the script says so and exits 0.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import best_mujoco_run, mujoco_or_none, quat_to_matrix

import kreisel

CASE = "M1"
MASS = 0.3  # kg
L_COM = 0.04  # m, pivot to centre of mass along the body z axis
I1_CM = 2.0e-4  # kg m^2, transverse, about the centre of mass
I3 = 1.5e-4  # kg m^2, axial
G = 9.81  # m/s^2
I1 = I1_CM + MASS * L_COM**2  # about the pivot
# tilted 0.3 rad, spinning at ~100 rad/s (below the sleeping threshold sqrt(4 I1 m g l)/I3
# ~ 119 rad/s, so gravity matters), precessing at 2 rad/s
START = {"theta": 0.3, "theta_dot": 0.0, "phi_dot": 2.0, "psi_dot": 100.0}
OUT = pathlib.Path(__file__).resolve().parent / "results-mujoco.json"

MJCF = """
<mujoco model="lagrange top">
  <option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 {gz!r}">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="top">
      <joint name="pivot" type="ball" damping="0" armature="0" frictionloss="0"/>
      <inertial pos="0 0 {l!r}" mass="{m!r}" diaginertia="{i1!r} {i1!r} {i3!r}"/>
    </body>
  </worldbody>
</mujoco>
"""


def initial_state():
    """(q, omega_body) for z-x-z Euler angles phi = psi = 0 and the rates of START."""
    th, thd, phd, psd = (START[k] for k in ("theta", "theta_dot", "phi_dot", "psi_dot"))
    q = np.array([math.cos(th / 2), math.sin(th / 2), 0.0, 0.0])
    omega = np.array([thd, phd * math.sin(th), phd * math.cos(th) + psd])
    return q, omega


def integrals(q, omega):
    """Energy (J) and vertical angular momentum Mz (kg m^2/s), from pivot moments."""
    r = quat_to_matrix(q)
    inertia = np.array([I1, I1, I3])
    big_m = inertia * omega
    gamma3 = r[:, 2, 2]  # e3 . e_z: height of the figure axis
    energy = 0.5 * np.sum(big_m * omega, axis=1) + MASS * G * L_COM * gamma3
    mz = np.einsum("nj,nj->n", r[:, 2, :], big_m)
    return energy, mz


def summarise(name, q, omega, seconds, axis_exact, diverged_at=None):
    """Errors over the run; a diverged run reports its errors up to the divergence, and
    NaN at the end."""
    energy, mz = integrals(q, omega)
    e_err = np.abs(energy - energy[0]) / abs(energy[0])
    mz_err = np.abs(mz - mz[0]) / abs(mz[0])
    axis = quat_to_matrix(q[-1:])[0][:, 2]
    final = math.nan if diverged_at is not None else None
    return {
        "name": name,
        "seconds": seconds,
        "diverged_at": diverged_at,
        "Mz_final": final or float(mz_err[-1]),
        "Mz_max": float(mz_err.max()),
        "energy_final": final or float(e_err[-1]),
        "energy_max": float(e_err.max()),
        "axis_error_final": final or float(np.linalg.norm(axis - axis_exact)),
    }


def run_mujoco(mujoco, integrator, dt, steps, repeats):
    """Returns (q, omega, seconds, diverged_at): the states up to a divergence (MuJoCo warns
    about a bad qacc and resets the data), and its time or None."""
    xml = MJCF.format(dt=dt, integrator=integrator, gz=-G, l=L_COM, m=MASS, i1=I1_CM, i3=I3)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    q0, w0 = initial_state()
    bad = data.warning[int(mujoco.mjtWarning.mjWARN_BADQACC)]

    def reset():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = q0
        data.qvel[:] = w0

    # recording pass (untimed): the state after every step
    reset()
    qs = np.empty((steps + 1, 4))
    ws = np.empty((steps + 1, 3))
    qs[0], ws[0] = q0, w0
    diverged_at = None
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        if bad.number > 0:
            diverged_at = (k - 1) * dt  # the step from here produced the bad qacc
            qs, ws = qs[:k], ws[:k]
            break
        qs[k] = data.qpos
        ws[k] = data.qvel
    # timed passes: one call for all the steps
    best = best_mujoco_run(mujoco, model, data, reset, steps, repeats)
    if diverged_at is None:
        assert np.allclose(data.qpos, qs[-1], rtol=0, atol=1e-12), "MuJoCo not deterministic?"
    return qs, ws, best, diverged_at


def run_kreisel(method, dt, steps, repeats):
    top = kreisel.LagrangeTop(I1=I1, I3=I3, m=MASS, l=L_COM, g=G)
    state = top.state(**START)
    best, traj = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        traj = kreisel.simulate(top, state, steps * dt, method=method, dt=dt)
        best = min(best, time.perf_counter() - start)
    assert len(traj) == steps + 1, (len(traj), steps)
    return traj.quaternion, traj.omega, best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=10**5, help="number of steps (1e5)")
    parser.add_argument("--dt", type=float, default=1e-3, help="step size in s (1e-3)")
    parser.add_argument("--repeats", type=int, default=3, help="best of this many (3)")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.repeats < 1 or not args.dt > 0:
        parser.error("--steps, --repeats and --dt must be positive")
    mujoco = mujoco_or_none("bench_mujoco")
    if mujoco is None:
        return None

    dt, steps = args.dt, args.steps
    t_end = steps * dt
    top = kreisel.LagrangeTop(I1=I1, I3=I3, m=MASS, l=L_COM, g=G)
    state = top.state(**START)
    ex = top.exact(state, [t_end])
    th, ph = ex.theta[0], ex.phi[0]
    axis_exact = np.array([math.sin(th) * math.sin(ph), -math.sin(th) * math.cos(ph), math.cos(th)])

    warnings = {}  # MuJoCo's warnings, each once (it repeats them for every timed pass)
    mujoco.set_mju_user_warning(lambda msg: warnings.setdefault(msg.strip(), None))
    rows = []
    for integrator in ("RK4", "implicitfast", "implicit"):
        q, w, sec, diverged = run_mujoco(mujoco, integrator, dt, steps, args.repeats)
        name = f"MuJoCo {mujoco.__version__} {integrator}"
        rows.append(summarise(name, q, w, sec, axis_exact, diverged))
    for method in ("splitting", "rk4"):
        q, w, sec = run_kreisel(method, dt, steps, args.repeats)
        rows.append(summarise(f"kreisel {method}", q, w, sec, axis_exact))

    analysis = top.analyse(state)
    print(
        f"case {CASE}: Lagrange top m = {MASS} kg, l = {L_COM} m, I1_cm = {I1_CM}, I3 = {I3} "
        f"kg m^2 (I1 about the pivot {I1:.3g}); {START}"
    )
    print(
        f"nutation period {analysis.nutation_period:.4g} s, theta in "
        f"[{analysis.theta_min:.4f}, {analysis.theta_max:.4f}] rad; "
        f"dt = {dt:g} s, {steps} steps ({t_end:g} s), best of {args.repeats}"
    )
    head = (
        f"{'integrator':<26} {'Mz final':>10} {'Mz max':>10} {'E final':>10} {'E max':>10} "
        f"{'axis err':>10} {'seconds':>9}"
    )
    print("relative errors of Mz and E; axis error |e3 - e3_exact| at the end")
    print(head)
    for r in rows:
        print(
            f"{r['name']:<26} {r['Mz_final']:>10.2e} {r['Mz_max']:>10.2e} "
            f"{r['energy_final']:>10.2e} {r['energy_max']:>10.2e} "
            f"{r['axis_error_final']:>10.2e} {r['seconds']:>9.4f}"
        )
    for msg in warnings:
        print(f"MuJoCo warned: {msg}")
    for r in rows:
        if r["diverged_at"] is not None:
            print(
                f"note: {r['name']} diverged at t = {r['diverged_at']:.4g} s (MuJoCo: bad qacc, "
                "data reset); its maxima are over the run up to there, its final values NaN"
            )
    result = {
        "case": CASE,
        "mujoco_version": mujoco.__version__,
        "dt": dt,
        "steps": steps,
        "repeats": args.repeats,
        "top": {"m": MASS, "l": L_COM, "I1_cm": I1_CM, "I3": I3, "g": G, "I1_pivot": I1},
        "start": START,
        "runs": rows,
    }
    OUT.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {OUT}")
    return result


if __name__ == "__main__":
    main()
    sys.exit(0)
