"""Benchmark T2: MuJoCo's tutorial tippe top (ball only) against kreisel's PlayTop.

    python benchmarks/bench_tippe_mujoco.py [--repeats R] [--t-end T]

The body of MuJoCo's tutorial "self-inverting tippe top" (docs/benchmarks.md case T2): a sphere
of radius 0.02 m (the only colliding geom), a cylinder stem (radius 0.004 m, half-length
0.008 m, centred 0.02 m above the sphere centre) and a ballast box (half-sizes 0.023, 0.023,
0.005 m, centred 0.015 m below), density 1000 kg/m^3, sliding friction 1, free joint, RK4
with a 2 ms step. MuJoCo compiles it to m = 0.0554746 kg, centre of mass 0.00543159 m below
the sphere centre, C = 1.28305e-5 and A = 1.27357e-5 kg m^2 about the centre of mass; this
script checks that and gives kreisel the compiled values: PlayTop(m, A, C, s = 0.00543159,
rho = 0.02, friction=Coulomb(mu=1)).

Start: the sphere on the floor, stem up, body angular velocity (0, 1, 200) rad/s with the
stem along MuJoCo's body z axis; 7 s. kreisel's figure axis e3 points from the sphere centre
to the centre of mass, i.e. DOWN the stem: the start is hanging (u = -1), and kreisel's body
frame is MuJoCo's turned by pi about x, so kreisel's attitude is Rx(pi) and its body angular
velocity (0, -1, -200); in space both are (0, 1, 200). As Euler angles (z-x-z) that is
theta = pi, phi = psi = pi/2, theta_dot = 1, psi_dot = -200 (checked below).

Compared: wall time (best of R; MuJoCo timed as one mj_step(..., nstep=N) call after a reset,
kreisel as one simulate call returning every step), the largest relative drift of Jellett's
integral J = L.(s e3 + rho ez) (for MuJoCo computed here from its state: L = R I_body omega,
s e3 = R x_com), and the first time u = e3.ez exceeds 0.9 (NaN if never). Results:
benchmarks/results-tippe-mujoco.json. Needs `pip install mujoco`; without it the script says
so and exits 0.

MuJoCo's contact is soft (a small penetration and a regularised friction cone), kreisel's is
rigid with exact Coulomb friction: under exact Coulomb friction the top stops slipping after
a few hundredths of a second and then rolls without slip, which keeps its energy, so it cannot
rise. The two runs need not agree on the inversion.
"""

from __future__ import annotations

import math
import os
import pathlib
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from _common import (
    best_mujoco_run,
    best_of,
    drift,
    mujoco_or_none,
    quat_to_matrix,
    repeats_and_t_end,
    write_results,
)

import kreisel

CASE = "T2"
RHO = 0.02  # m, sphere radius
MU = 1.0
G = 9.81
DT = 0.002  # s
T_END = 7.0
OMEGA_BODY = (0.0, 1.0, 200.0)  # rad/s, MuJoCo body frame (z along the stem)
LEVEL = 0.9
DOCUMENTED = {"m": 0.0554746, "s": 0.00543159, "C": 1.28305e-5, "A": 1.27357e-5}
OUT = pathlib.Path(__file__).resolve().parent / "results-tippe-mujoco.json"

MJCF = f"""
<mujoco model="tippe top, ball only">
  <option integrator="RK4" timestep="{DT!r}" gravity="0 0 {-G!r}"/>
  <worldbody>
    <geom name="floor" size=".2 .2 .01" type="plane"/>
    <body name="top" pos="0 0 {RHO!r}">
      <freejoint/>
      <geom name="ball" type="sphere" size="{RHO!r}" density="1000" friction="{MU!r} 0.005 0.0001"/>
      <geom name="stem" type="cylinder" pos="0 0 .02" size="0.004 .008" density="1000"
            contype="0" conaffinity="0"/>
      <geom name="ballast" type="box" size=".023 .023 0.005" pos="0 0 -.015" density="1000"
            contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>
"""


def first_above(t, u, level=LEVEL):
    above = np.flatnonzero(np.asarray(u) > level)
    return float(t[above[0]]) if len(above) else math.nan


def compiled_body(mujoco, model, body="top"):
    """(m, com in the body frame, inertia about the com in the body frame) of a body."""
    b = model.body(body).id
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, model.body_iquat[b])
    rot = rot.reshape(3, 3)
    inertia = rot @ np.diag(model.body_inertia[b]) @ rot.T
    return float(model.body_mass[b]), np.array(model.body_ipos[b]), inertia


def run_mujoco(mujoco, steps, repeats):
    model = mujoco.MjModel.from_xml_string(MJCF)
    data = mujoco.MjData(model)
    mass, com, inertia = compiled_body(mujoco, model)
    qpos0 = np.array([0.0, 0.0, RHO, 1.0, 0.0, 0.0, 0.0])
    qvel0 = np.array([0.0, 0.0, 0.0, *OMEGA_BODY])  # free joint: angular part in the body frame

    def reset():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = qpos0
        data.qvel[:] = qvel0

    # recording pass (untimed): the state after every step
    reset()
    qs = np.empty((steps + 1, 4))
    ws = np.empty((steps + 1, 3))
    qs[0], ws[0] = qpos0[3:], qvel0[3:]
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        qs[k] = data.qpos[3:7]
        ws[k] = data.qvel[3:6]
    final = data.qpos.copy()
    best = best_mujoco_run(mujoco, model, data, reset, steps, repeats)
    assert np.allclose(data.qpos, final, rtol=0, atol=1e-12), "MuJoCo not deterministic?"

    r = quat_to_matrix(qs)
    s_e3 = r @ com  # from the sphere centre to the centre of mass
    ls = np.einsum("nij,nj->ni", r, ws @ inertia.T)
    lever = s_e3 + np.array([0.0, 0.0, RHO])
    jellett = np.einsum("ni,ni->n", ls, lever)
    u = s_e3[:, 2] / np.linalg.norm(com)
    t = np.arange(steps + 1) * DT
    return {
        "mass": mass,
        "com": com,
        "inertia": inertia,
        "t": t,
        "u": u,
        "jellett": jellett,
        "seconds": best,
        "version": mujoco.__version__,
    }


def compiled_top(mj):
    """(m, s, A, C) of the compiled body of a MuJoCo run: its centre of mass s below the
    sphere's centre on the body z axis, its inertia about it diagonal and symmetric."""
    inertia = mj["inertia"]
    mass, s = mj["mass"], -float(mj["com"][2])
    big_c, big_a = float(inertia[2, 2]), float(inertia[0, 0])
    assert np.allclose(mj["com"][:2], 0.0) and abs(inertia[1, 1] - big_a) < 1e-12 * big_a
    assert np.allclose(inertia - np.diag(np.diag(inertia)), 0.0, atol=1e-20)
    return mass, s, big_a, big_c


def run_kreisel(mass, s, big_a, big_c, t_end, repeats):
    top = kreisel.PlayTop(
        m=mass, A=big_a, C=big_c, s=s, rho=RHO, g=G, friction=kreisel.Coulomb(mu=MU)
    )
    state = top.state(math.pi, phi=math.pi / 2, psi=math.pi / 2, theta_dot=1.0, psi_dot=-200.0)
    # kreisel's attitude is MuJoCo's (identity) turned by pi about the body x axis
    q = np.asarray(state.quaternion)
    assert min(np.abs(q - [0, 1, 0, 0]).max(), np.abs(q + [0, 1, 0, 0]).max()) < 1e-15, q
    np.testing.assert_allclose(state.omega, [0.0, -1.0, -200.0], atol=1e-13)
    np.testing.assert_allclose(state.com, [0.0, 0.0, RHO - s], atol=1e-17)
    best, traj = best_of(lambda: kreisel.simulate(top, state, t_end), repeats)
    return traj, best


def main(argv=None):
    args = repeats_and_t_end(__doc__, T_END, argv)
    mujoco = mujoco_or_none("bench_tippe_mujoco")
    if mujoco is None:
        return None

    steps = round(args.t_end / DT)
    t_end = steps * DT
    mj = run_mujoco(mujoco, steps, args.repeats)
    mass, s, big_a, big_c = compiled_top(mj)
    compiled = {"m": mass, "s": s, "C": big_c, "A": big_a}
    for key, value in DOCUMENTED.items():
        assert abs(compiled[key] - value) <= 1e-5 * value, (key, compiled[key], value)

    traj, k_sec = run_kreisel(mass, s, big_a, big_c, t_end, args.repeats)
    k_inv = first_above(traj.t, traj.u)
    m_inv = first_above(mj["t"], mj["u"])
    rows = [
        {
            "name": f"MuJoCo {mj['version']} RK4 dt={DT:g}",
            "seconds": mj["seconds"],
            "steps": steps,
            "jellett_drift": drift(mj["jellett"]),
            "t_u_above_0.9": m_inv,
            "final_u": float(mj["u"][-1]),
        },
        {
            "name": "kreisel.simulate dop853",
            "seconds": k_sec,
            "steps": int(traj.stats["steps"]),
            "jellett_drift": drift(traj.jellett),
            "t_u_above_0.9": k_inv,
            "final_u": float(traj.u[-1]),
        },
    ]

    print(
        f"case {CASE}: MuJoCo tutorial tippe top, ball only; compiled m = {mass:.7g} kg, "
        f"s = {s:.7g} m, C = {big_c:.6g}, A = {big_a:.6g} kg m^2, rho = {RHO} m, mu = {MU}"
    )
    print(
        f"alpha = {s / RHO:.4f}, gamma = {big_a / big_c:.4f}; start hanging, body omega "
        f"{OMEGA_BODY} rad/s (MuJoCo frame); t = [0, {t_end:g}] s, best of {args.repeats}"
    )
    print(
        f"{'implementation':<28} {'seconds':>9} {'steps':>7} {'J drift':>10} "
        f"{'t(u>0.9) s':>11} {'final u':>9}"
    )
    for r in rows:
        print(
            f"{r['name']:<28} {r['seconds']:>9.4f} {r['steps']:>7d} {r['jellett_drift']:>10.2e} "
            f"{r['t_u_above_0.9']:>11.4f} {r['final_u']:>9.4f}"
        )
    print(f"ratio kreisel / MuJoCo = {k_sec / mj['seconds']:.4g}")
    events = [(e.name, round(e.t, 6)) for e in traj.events]
    print(f"kreisel events: {events[:6]}{' ...' if len(events) > 6 else ''}")
    if math.isnan(k_inv):
        print(
            "kreisel (rigid contact, exact Coulomb friction): the slip stops and the top rolls "
            "without slip, keeping its energy, so it cannot turn over."
        )

    result = {
        "case": CASE,
        "mujoco_version": mj["version"],
        "dt": DT,
        "t_end": t_end,
        "repeats": args.repeats,
        "top": {**compiled, "rho": RHO, "mu": MU, "g": G},
        "omega_body_mujoco": list(OMEGA_BODY),
        "runs": rows,
        "ratio_kreisel_over_mujoco": k_sec / mj["seconds"],
        "kreisel_events": [{"name": n, "t": t} for n, t in events],
    }
    return write_results(OUT, result)


if __name__ == "__main__":
    main()
    sys.exit(0)
