"""Benchmark T3: MuJoCo's tutorial tippe top with its stem colliding, against kreisel's top of
two spheres under Coulomb-Contensou friction.

    python benchmarks/bench_tippe_peg_mujoco.py [--repeats R] [--t-end T]

The body of case T2 (benchmarks/bench_tippe_mujoco.py: a sphere of radius 0.02 m, a stem and
a ballast box, density 1000 kg/m^3), but the stem collides as a capsule (radius 0.004 m,
half-length 0.008 m, centred 0.02 m above the sphere centre: its end is a sphere of radius
0.004 m whose centre is 0.028 m from the ball's centre); the ballast box does not collide.
MuJoCo: condim 4 (torsional friction), an elliptic cone, friction "0.3 8.8e-5 0.0001", RK4 with
a 2 ms step, 7 s, start as in T2 (docs/benchmarks.md case T3). m, the centre of mass and the inertia
are read from MuJoCo's compiled model.

kreisel: the same body as two spheres, ball Sphere(0.02, z=-s) and peg Sphere(0.004,
z=-(s + 0.028)) (e3 points from the ball's centre to the centre of mass, away from the stem),
with CoulombContensou(mu=0.3, R), where mu 3 pi R / 16 = 8.8e-5 m: MuJoCo's torsional
coefficient is the largest drilling torque per newton, Contensou's mu Rbar.

Compared, in one run: wall time (best of R; MuJoCo as one mj_step(..., nstep=N) call after a
reset, kreisel as one simulate call returning every step), whether and when each first
touches the floor with its stem, whether each ends on its stem (the stem touching, the ball
not), and the energy (never rising: its largest rise between samples). Results:
benchmarks/results-tippe-peg-mujoco.json. Needs `pip install mujoco`; without it the script
says so and exits 0.
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
    cpu_counters,
    mujoco_or_none,
    print_table,
    repeats_and_t_end,
    steal_share,
    write_results,
)
from bench_tippe_mujoco import (
    DT,
    LEVEL,
    OMEGA_BODY,
    RHO,
    G,
    compiled_body,
    compiled_top,
    first_above,
)

import kreisel
from kreisel.shapes import Sphere

CASE = "T3"
MU, TORSION = 0.3, 8.8e-5
PATCH = TORSION * 16 / (3 * math.pi * MU)  # m: mu * 3 pi R / 16 = the torsional coefficient
STEM_R, STEM_END = 0.004, 0.028  # m: the stem end's sphere and its centre from the ball's
T_END = 7.0
# kreisel's default tolerance, and looser ones (still far tighter than a 2 ms RK4 step)
RTOLS = (1e-10, 1e-8, 1e-6)
OUT = pathlib.Path(__file__).resolve().parent / "results-tippe-peg-mujoco.json"

MJCF = f"""
<mujoco model="tippe top with its stem">
  <option integrator="RK4" timestep="{DT!r}" gravity="0 0 {-G!r}" cone="elliptic">
    <flag energy="enable"/>
  </option>
  <default><geom condim="4" friction="{MU!r} {TORSION!r} 0.0001"/></default>
  <worldbody>
    <geom name="floor" size=".2 .2 .01" type="plane"/>
    <body name="top" pos="0 0 {RHO!r}">
      <freejoint/>
      <geom name="ball" type="sphere" size="{RHO!r}" density="1000"/>
      <geom name="stem" type="capsule" pos="0 0 .02" size="{STEM_R!r} .008" density="1000"/>
      <geom name="ballast" type="box" size=".023 .023 0.005" pos="0 0 -.015" density="1000"
            contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>
"""


def run_mujoco(mujoco, steps, repeats):
    model = mujoco.MjModel.from_xml_string(MJCF)
    data = mujoco.MjData(model)
    mass, com, inertia = compiled_body(mujoco, model)
    floor, ball, stem = (model.geom(n).id for n in ("floor", "ball", "stem"))
    qpos0 = np.array([0.0, 0.0, RHO, 1.0, 0.0, 0.0, 0.0])
    qvel0 = np.array([0.0, 0.0, 0.0, *OMEGA_BODY])

    def reset():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = qpos0
        data.qvel[:] = qvel0

    def touching():
        pairs = {tuple(sorted((c.geom1, c.geom2))) for c in data.contact[: data.ncon]}
        return [tuple(sorted((floor, g))) in pairs for g in (ball, stem)]

    # recording pass (untimed): contacts, energy and the axis after every step
    reset()
    mujoco.mj_forward(model, data)
    energy = np.empty(steps + 1)
    contact = np.zeros((steps + 1, 2), dtype=bool)
    up = np.empty(steps + 1)
    energy[0] = data.energy.sum()
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        energy[k] = data.energy.sum()
        contact[k] = touching()
        up[k] = data.xmat[model.body("top").id][8]  # body z (the stem) . ez
    up[0] = 1.0
    best = best_mujoco_run(mujoco, model, data, reset, steps, repeats)
    t = np.arange(steps + 1) * DT
    return {
        "mass": mass,
        "com": com,
        "inertia": inertia,
        "t": t,
        "energy": energy,
        "contact": contact,
        # kreisel's u = e3 . ez, e3 pointing away from the stem: minus the stem's
        "u": -up,
        "seconds": best,
        "version": mujoco.__version__,
    }


def run_kreisel(mass, s, big_a, big_c, t_end, repeats, rtol):
    top = kreisel.PlayTop(
        m=mass, A=big_a, C=big_c, g=G, friction=kreisel.CoulombContensou(MU, PATCH),
        shape=[Sphere(RHO, z=-s, name="ball"), Sphere(STEM_R, z=-(s + STEM_END), name="stem")],
    )  # fmt: skip
    state = top.state(math.pi, phi=math.pi / 2, psi=math.pi / 2, theta_dot=1.0, psi_dot=-200.0)
    best, traj = best_of(
        lambda: kreisel.simulate(top, state, t_end, rtol=rtol, atol=rtol * 1e-2), repeats
    )
    return traj, best


def millijoules(energies):
    return [1e3 * e for e in energies]


def first_true(t, flags):
    on = np.flatnonzero(flags)
    return float(t[on[0]]) if len(on) else math.nan


def main(argv=None):
    args = repeats_and_t_end(__doc__, T_END, argv)
    mujoco = mujoco_or_none("bench_tippe_peg_mujoco")
    if mujoco is None:
        return None

    steps = round(args.t_end / DT)
    t_end = steps * DT
    cpu0 = cpu_counters()
    mj = run_mujoco(mujoco, steps, args.repeats)
    mass, s, big_a, big_c = compiled_top(mj)
    runs = [(rtol, *run_kreisel(mass, s, big_a, big_c, t_end, args.repeats, rtol))
            for rtol in RTOLS]  # fmt: skip
    steal = steal_share(cpu0, cpu_counters())

    rows = [
        {
            "name": f"MuJoCo {mj['version']} RK4 dt={DT:g}",
            "seconds": mj["seconds"],
            "steps": steps,
            "stem_first_touches_s": first_true(mj["t"], mj["contact"][:, 1]),
            "ends_on_stem": bool(mj["contact"][-1, 1] and not mj["contact"][-1, 0]),
            "t_u_above_0.9": first_above(mj["t"], mj["u"], LEVEL),
            "largest_energy_rise_J": float(np.diff(mj["energy"]).max()),
            "energy_J": [float(mj["energy"][0]), float(mj["energy"][-1])],
        },
    ]
    for rtol, traj, k_sec in runs:
        stem = [e.t for e in traj.events if e.name == "touchdown" and e.part == "stem"]
        last = traj.part_in_contact[-1]
        rows.append({
            "name": f"kreisel dop853 rtol={rtol:g}",
            "seconds": k_sec,
            "steps": int(traj.stats["steps"]),
            "stem_first_touches_s": stem[0] if stem else math.nan,
            "ends_on_stem": bool(last[1] and not last[0]),
            "t_u_above_0.9": first_above(traj.t, traj.u, LEVEL),
            "largest_energy_rise_J": float(np.diff(traj.energy).max()),
            "energy_J": [float(traj.energy[0]), float(traj.energy[-1])],
            "events": len(traj.events),
        })  # fmt: skip
    ratios = {r["name"]: mj["seconds"] / r["seconds"] for r in rows[1:]}
    print(
        f"case {CASE}: MuJoCo tutorial tippe top, stem colliding; compiled m = {mass:.7g} kg, "
        f"s = {s:.7g} m, C = {big_c:.6g}, A = {big_a:.6g} kg m^2; mu = {MU}, torsion "
        f"{TORSION} m (kreisel: patch R = {PATCH:.4g} m)"
    )
    print(f"t = [0, {t_end:g}] s, best of {args.repeats}; steal time {steal}")
    print_table(rows, [
        ("implementation", 28, lambda r: r["name"]),
        ("seconds", 9, lambda r: f"{r['seconds']:.4f}"),
        ("steps", 7, lambda r: f"{r['steps']:d}"),
        ("stem at s", 10, lambda r: f"{r['stem_first_touches_s']:.4f}"),
        ("ends on", 8, lambda r: "stem" if r["ends_on_stem"] else "no"),
        ("t(u>0.9)", 9, lambda r: f"{r['t_u_above_0.9']:.4f}"),
        ("max dE", 10, lambda r: f"{r['largest_energy_rise_J']:.2e}"),
        ("E0 -> E1 (mJ)", 18, lambda r: "{:.3f} -> {:.3f}".format(*millijoules(r["energy_J"]))),
    ])  # fmt: skip
    counts = {r["name"]: r["events"] for r in rows[1:]}
    print(f"kreisel contact events per tolerance (the same count: the same story): {counts}")
    for name, ratio in ratios.items():
        print(f"MuJoCo / {name} wall time = {ratio:.4g} (target >= 20)")
    result = {
        "case": CASE,
        "mujoco_version": mj["version"],
        "dt": DT,
        "t_end": t_end,
        "repeats": args.repeats,
        "steal": steal,
        "top": {
            "m": mass,
            "s": s,
            "A": big_a,
            "C": big_c,
            "rho": RHO,
            "mu": MU,
            "torsion": TORSION,
            "patch_radius": PATCH,
            "stem_radius": STEM_R,
            "stem_end": STEM_END,
        },  # fmt: skip
        "runs": rows,
        "ratio_mujoco_over_kreisel": ratios,
    }
    return write_results(OUT, result)


if __name__ == "__main__":
    main()
    sys.exit(0)
