"""Benchmark T4: Euler's disk, MuJoCo's cylinder on a plane against kreisel.bodies.disk.

    python benchmarks/bench_euler_disk_mujoco.py [--repeats R] [--t-end T]

A uniform steel disk (density 7850 kg/m^3) of radius a = 0.0375 m and thickness h = 0.0125 m
(the toy's size), started rolling with its centre at rest at inclination alpha0 = 0.3 rad of
its axis to the vertical (docs/benchmarks.md, case T4; theory: bodies of revolution). Run to the
time it lies flat
(sin(alpha) < 1e-4, kreisel's event "flat") or to 30 s.

Friction, the same coefficients in both: sliding mu = 0.3, torsional (drilling) 1e-4 m,
rolling 2e-4 m. MuJoCo's torsional and rolling coefficients are the largest torques per newton
of normal force about the contact normal and about the tangent axes (lengths in m); kreisel's
``drilling_resistance`` is the torque -c N sign(omega_z) ez and ``rolling_resistance`` the
torque -c N omega_h/|omega_h| (omega_h the horizontal angular velocity): the same meaning.
MuJoCo's elliptic cone puts force and torques in one budget, kreisel's losses are separate;
the rolling loss sets the time to flat (about 8.5 s here: energy 3/2 m g a alpha lost at
c m g Omega alpha).

Start. Rolling with G at rest needs omega parallel to GT (T the lowest point of the lower rim,
GT = a d - h/2 e3), which gives psi_dot = -Omega (cos(alpha) - k sin(alpha)), k = h / (2 a)
(the thin disk's -Omega cos(alpha) of kreisel's preset "euler-disk" at k = 0). The balance
of the gravity torque with the turning of L gives the steady precession of the thick disk,

    Omega^2 sin(alpha) (A cos(alpha) - C k sin(alpha)) = m g a (cos(alpha) - k sin(alpha)),

which is the thin disk's Omega^2 sin(alpha) = m g a / A at k = 0 (theory: bodies of revolution;
2.6 % below it at 0.3 rad
here); the thin formula would start the thick disk off its steady motion. Both programs get
the same state: MuJoCo's qpos is kreisel's centre of mass and quaternion (the cylinder's axis
is the body z axis, e3), its qvel kreisel's body angular velocity (a free joint's angular
velocity is in the body frame) and zero linear velocity; checked below (the lowest point's
velocity is 0 to rounding).

MuJoCo: a cylinder geom on a plane, condim 6, elliptic cone, friction "0.3 1e-4 2e-4", RK4 at
2 ms (as T2 and T3) and at 0.2 ms, with its default soft contact (solref 0.02 s) and, at
0.2 ms, with a stiff one (solref 0.001 s). m and the inertia are read from the compiled model
and checked against kreisel.bodies.disk's uniform cylinder (C = m a^2 / 2, A = m (3 a^2 +
h^2) / 12). Its flat time is the first sin(alpha) < 1e-4 too.

Which MuJoCo run is fair: a 2 ms step cannot follow a precession that grows without bound
(Omega ~ 1000 rad/s, a turn in 6 ms, at sin(alpha) = 1e-3), 0.2 ms can to about that. With the
default contact the step does not matter: the rolling rim sinks about 1 cm into the floor and
the disk falls flat from about 0.2 rad (the same at 2 and 0.2 ms). Only the stiff contact at
0.2 ms follows the precession law down to sin(alpha) = 1e-3, so it is the fair match for
kreisel's rigid contact; the 2 ms run is what a user gets by default, and the cheapest.

Compared, in one run: wall time (best of R; MuJoCo one mj_step(..., nstep=N) call to its flat
time, or to t_end, after a reset; kreisel one simulate call sampled every 2 ms), the time to
flat, the precession rate against the inclination (slope of log Omega against log sin(alpha),
Omega = 2 pi / the time of one turn of the axis; theory -1/2), the energy (largest rise between
samples, and the largest rise over any interval), the largest penetration of MuJoCo's disk,
and where kreisel's time goes: steps, rejected steps and right-hand-side evaluations, steps
per precession turn in each decade of sin(alpha), per contact mode, at rtol 1e-6, 1e-8, 1e-10.
Results: benchmarks/results-euler-disk-mujoco.json. Needs `pip install mujoco`; without it the
script says so and exits 0.
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
    quat_to_matrix,
    repeats_and_t_end,
    steal_share,
    write_results,
)
from bench_tippe_mujoco import compiled_body

import kreisel
from kreisel import bodies

CASE = "T4"
RADIUS, THICKNESS, DENSITY = 0.0375, 0.0125, 7850.0  # m, m, kg/m^3
ALPHA0 = 0.3  # rad
MU, TORSION, ROLLING = 0.3, 1e-4, 2e-4  # 1, m, m
G = 9.81
T_END = 30.0
FLAT = 1e-4  # sin(alpha) below which the disk lies flat (kreisel's event "flat")
SAMPLE = 1e-4  # s, the output grid of the timed kreisel runs (20 samples a turn near flat)
EVERY_STEP_LIMIT = 3_000_000  # steps: above it no run returning every step (memory)
# (step s, solref time constant s or None for MuJoCo's default 0.02 s)
MUJOCO_RUNS = ((0.002, None), (0.0002, None), (0.0002, 0.001))
# kreisel's friction: Coulomb-Contensou over the patch whose largest drilling torque per
# newton, mu 3 pi R / 16, is MuJoCo's torsional coefficient (as in T3), and point Coulomb
# friction with the torsional coefficient as a drilling resistance; and their tolerances
PATCH = TORSION * 16 / (3 * math.pi * MU)  # m
KREISEL_RUNS = (("contensou", (1e-6, 1e-8, 1e-10)), ("coulomb", (1e-6, 1e-8)))
# sin(alpha) windows of the precession fits: early (rolling) and late (towards flat)
EARLY, LATE = (0.1, 0.3), (1e-3, 3e-2)
DECADES = (0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3, 3e-4, 1e-4)
OUT = pathlib.Path(__file__).resolve().parent / "results-euler-disk-mujoco.json"


def mjcf(dt, solref):
    ref = "" if solref is None else f' solref="{solref!r} 1"'
    return f"""
<mujoco model="Euler's disk">
  <option integrator="RK4" timestep="{dt!r}" gravity="0 0 {-G!r}" cone="elliptic">
    <flag energy="enable"/>
  </option>
  <default><geom condim="6" friction="{MU!r} {TORSION!r} {ROLLING!r}"{ref}/></default>
  <worldbody>
    <geom name="floor" size="1 1 .01" type="plane"/>
    <body name="disk">
      <freejoint/>
      <geom name="disk" type="cylinder" size="{RADIUS!r} {THICKNESS / 2!r}" density="{DENSITY!r}"/>
    </body>
  </worldbody>
</mujoco>
"""


def lowest_point_offset(axis):
    """Vectors (n, 3) from G to the lowest point of the lower rim, axis (n, 3) the unit e3."""
    axis = np.atleast_2d(axis)
    u = axis[:, 2:3]
    d = (-np.array([0.0, 0.0, 1.0]) + u * axis) / np.sqrt(np.maximum(1 - u * u, 1e-300))
    return RADIUS * d - THICKNESS / 2 * axis


def axis_series(quaternions):
    """(sin(alpha), unwrapped azimuth of e3) of the axis e3 = the body z axis, (n,) each."""
    e3 = quat_to_matrix(quaternions)[:, :, 2]
    sin_alpha = np.hypot(e3[:, 0], e3[:, 1])
    return sin_alpha, np.unwrap(np.arctan2(e3[:, 1], e3[:, 0]))


def precession(t, sin_alpha, azimuth):
    """(sin(alpha), Omega) per full turn of the axis: Omega = 2 pi / the turn's duration."""
    turns = np.floor((azimuth - azimuth[0]) / (2 * math.pi))
    starts = np.flatnonzero(np.diff(turns) > 0) + 1
    if len(starts) < 2:
        return np.empty(0), np.empty(0)
    omega = 2 * math.pi / np.diff(t[starts])
    alpha = [math.exp(np.mean(np.log(sin_alpha[i:j]))) for i, j in zip(starts[:-1], starts[1:])]
    return np.array(alpha), omega


def slope(alpha, omega, window):
    """[slope, turns, lowest and highest sin(alpha)] of the least-squares fit of log Omega
    against log sin(alpha) over the turns inside a window of sin(alpha); the slope is NaN where
    fewer than 5 turns span less than a fifth of a decade."""
    sel = (alpha >= window[0]) & (alpha <= window[1])
    if sel.sum() < 2:
        return [math.nan, int(sel.sum()), math.nan, math.nan]
    lo, hi = float(alpha[sel].min()), float(alpha[sel].max())
    if sel.sum() < 5 or math.log10(hi / lo) < 0.2:
        return [math.nan, int(sel.sum()), lo, hi]
    fit = float(np.polyfit(np.log(alpha[sel]), np.log(omega[sel]), 1)[0])
    return [fit, int(sel.sum()), lo, hi]


def theory_slope(top, window):
    """The slope of the steady law (bodies.disk_rolling_rates) over a window."""
    x = np.geomspace(*window, 50)
    y = [bodies.disk_rolling_rates(top, math.asin(v))[0] for v in x]
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def energy_rises(energy):
    """(largest rise between two samples, largest rise over any interval) of an energy series."""
    energy = np.asarray(energy)
    return float(np.diff(energy).max()), float((energy - np.minimum.accumulate(energy)).max())


def first_below(t, x, level):
    below = np.flatnonzero(np.asarray(x) < level)
    return float(t[below[0]]) if len(below) else math.nan


def compiled_disk(mujoco, model):
    """(m, inertia about the centre of mass in the body frame) of the disk."""
    mass, com, inertia = compiled_body(mujoco, model, "disk")
    assert np.allclose(com, 0.0, atol=1e-15), com
    return mass, inertia


def check_start(mujoco, model, data, state):
    """MuJoCo's start is kreisel's: the same angular velocity in space, the lowest point at
    rest and on the floor. Returns the lowest point's speed (m/s)."""
    b = model.body("disk").id
    mujoco.mj_forward(model, data)
    rot = data.xmat[b].reshape(3, 3)
    vel = np.zeros(6)  # (angular, linear) at the body's origin, world frame
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, b, vel, 0)
    spatial = quat_to_matrix(state.quaternion) @ state.omega
    np.testing.assert_allclose(vel[:3], spatial, rtol=0, atol=1e-12 * np.abs(spatial).max())
    offset = lowest_point_offset(rot[:, 2])[0]
    speed = float(np.linalg.norm(vel[3:] + np.cross(vel[:3], offset)))
    assert speed < 1e-12 and abs(data.xpos[b][2] + offset[2]) < 1e-15, (speed, offset)
    return speed


def run_mujoco(mujoco, state, dt, solref, t_end, repeats):
    model = mujoco.MjModel.from_xml_string(mjcf(dt, solref))
    data = mujoco.MjData(model)
    steps = round(t_end / dt)
    qpos0 = np.concatenate([state.com, state.quaternion])
    qvel0 = np.concatenate([np.zeros(3), state.omega])

    def reset():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = qpos0
        data.qvel[:] = qvel0

    reset()
    contact_speed = check_start(mujoco, model, data, state)
    # recording pass (untimed): the attitude, the height of G and the energy after every step
    quats = np.empty((steps + 1, 4))
    height = np.empty(steps + 1)
    energy = np.empty(steps + 1)
    ncon = np.zeros(steps + 1, dtype=int)
    quats[0], height[0], energy[0] = qpos0[3:], qpos0[2], data.energy.sum()
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        quats[k], height[k], ncon[k] = data.qpos[3:7], data.qpos[2], data.ncon
        energy[k] = data.energy.sum()  # computed at the step's start: one step late
    t = np.arange(steps + 1) * dt
    sin_alpha, azimuth = axis_series(quats)
    t_flat = first_below(t, sin_alpha, FLAT)
    timed = steps if math.isnan(t_flat) else round(t_flat / dt)
    best = best_mujoco_run(mujoco, model, data, reset, timed, repeats)
    best_full = best_mujoco_run(mujoco, model, data, reset, steps, 1)
    axis = quat_to_matrix(quats)[:, :, 2]
    penetration = -(height + lowest_point_offset(axis)[:, 2])
    return {
        "model": model,
        "t": t,
        "sin_alpha": sin_alpha,
        "azimuth": azimuth,
        "energy": energy,
        "penetration": penetration,
        "ncon": ncon,
        "t_flat": t_flat,
        "steps": timed,
        "seconds": best,
        "seconds_to_t_end_once": best_full,
        "contact_speed_at_start": contact_speed,
        "version": mujoco.__version__,
    }


def make_disk(mass, law="contensou"):
    if law == "contensou":
        return bodies.disk(RADIUS, THICKNESS, mass, friction=kreisel.CoulombContensou(MU, PATCH),
                           rolling_resistance=ROLLING)  # fmt: skip
    return bodies.disk(
        RADIUS, THICKNESS, mass, friction=kreisel.Coulomb(MU),
        rolling_resistance=ROLLING, drilling_resistance=TORSION,
    )  # fmt: skip


def run_kreisel(top, state, t_end, rtol, repeats):
    """(the run sampled every SAMPLE s, its best wall time, the run returning every step or
    None where it would have more than EVERY_STEP_LIMIT steps)."""
    # The disk lies flat (the event "flat"), spins down on its face and rests: the run ends at
    # rest, as MuJoCo's timed run ends at its flat time (kreisel's face spin-down takes
    # under a millisecond of motion and a few hundred steps).
    grid = np.arange(0.0, t_end + SAMPLE / 2, SAMPLE)
    rest = [kreisel.events.rest()]
    kw = dict(rtol=rtol, atol=rtol * 1e-2, events=rest)
    best, traj = best_of(lambda: kreisel.simulate(top, state, t_end, t_eval=grid, **kw), repeats)
    if traj.stats["steps"] > EVERY_STEP_LIMIT:
        return traj, best, None
    return traj, best, kreisel.simulate(top, state, t_end, **kw)


def cost_by_decade(traj):
    """Steps, precession turns, steps per turn, events and the slipping share of the steps in
    each decade (and half-decade) of sin(alpha) of a run returning every step."""
    t = traj.t
    sin_alpha, azimuth = np.sin(traj.theta), np.unwrap(traj.phi)
    events = np.array([e.t for e in traj.events])
    slipping = np.asarray(traj.mode) == "slip"
    rows = []
    for hi, lo in zip(DECADES[:-1], DECADES[1:]):
        sel = np.flatnonzero((sin_alpha <= hi) & (sin_alpha > lo))
        if len(sel) < 2:
            continue
        i, j = sel[0], sel[-1]
        turns = (azimuth[j] - azimuth[i]) / (2 * math.pi)
        rows.append({
            "sin_alpha": [lo, hi],
            "t": [float(t[i]), float(t[j])],
            "steps": int(j - i),
            "turns": float(turns),
            "steps_per_turn": float((j - i) / turns) if turns > 0 else math.nan,
            "events": int(np.sum((events >= t[i]) & (events <= t[j]))),
            "slipping_share": float(slipping[i:j].mean()),
            "median_step_s": float(np.median(np.diff(t[i : j + 1]))),
        })  # fmt: skip
    return rows


def main(argv=None):
    args = repeats_and_t_end(__doc__, T_END, argv)
    mujoco = mujoco_or_none("bench_euler_disk_mujoco")
    if mujoco is None:
        return None

    cpu0, load0 = cpu_counters(), os.getloadavg()
    volume = math.pi * RADIUS**2 * THICKNESS
    model = mujoco.MjModel.from_xml_string(mjcf(MUJOCO_RUNS[0][0], None))
    mass, inertia = compiled_disk(mujoco, model)
    top = make_disk(mass)
    assert abs(mass - DENSITY * volume) < 1e-12 * mass, (mass, DENSITY * volume)
    np.testing.assert_allclose(np.diag(inertia), [top.A, top.A, top.C], rtol=1e-9)
    assert np.allclose(inertia - np.diag(np.diag(inertia)), 0.0, atol=1e-20)
    omega0, psi_dot0 = bodies.disk_rolling_rates(top, ALPHA0)
    thin = math.sqrt(mass * G * RADIUS / (top.A * math.sin(ALPHA0)))
    state = top.state(ALPHA0, phi_dot=omega0, psi_dot=psi_dot0)

    rows, mj_runs = [], []
    for dt, solref in MUJOCO_RUNS:
        mj = run_mujoco(mujoco, state, dt, solref, args.t_end, args.repeats)
        mj_runs.append(mj)
        rolling = mj["t"] < (mj["t_flat"] if not math.isnan(mj["t_flat"]) else math.inf)
        alpha, omega = precession(*(mj[k][rolling] for k in ("t", "sin_alpha", "azimuth")))
        rise_step, rise_any = energy_rises(mj["energy"])
        rows.append({
            "name": f"MuJoCo RK4 dt={dt:g} solref={solref or 0.02:g}",
            "seconds": mj["seconds"],
            "steps": mj["steps"],
            "t_flat": mj["t_flat"],
            "min_sin_alpha": float(mj["sin_alpha"].min()),
            "final_sin_alpha": float(mj["sin_alpha"][-1]),
            "slope_early": slope(alpha, omega, EARLY),
            "slope_late": slope(alpha, omega, LATE),
            "turns": len(omega),
            "largest_energy_rise_step_J": rise_step,
            "largest_energy_rise_J": rise_any,
            "energy_J": [float(mj["energy"][0]), float(mj["energy"][-1])],
            "max_penetration_m": float(mj["penetration"][rolling].max()),
            "max_contacts": int(mj["ncon"].max()),
            "seconds_to_t_end_once": mj["seconds_to_t_end_once"],
            "contact_speed_at_start": mj["contact_speed_at_start"],
        })  # fmt: skip

    cost = {}
    for law, rtols in KREISEL_RUNS:
        for rtol in rtols:
            traj, k_sec, every = run_kreisel(make_disk(mass, law), state, args.t_end, rtol,
                                         args.repeats)  # fmt: skip
            sin_alpha, azimuth = np.sin(traj.theta), np.unwrap(traj.phi)
            alpha, omega = precession(traj.t, sin_alpha, azimuth)
            rise_step, rise_any = energy_rises(traj.energy)
            flat = [e.t for e in traj.events if e.name == "flat"]
            stats = {k: int(v) for k, v in traj.stats.items()}
            rows.append({
            "name": f"kreisel {law} rtol={rtol:g}",
            "seconds": k_sec,
            "steps": stats["steps"],
            "t_flat": flat[0] if flat else math.nan,
            "min_sin_alpha": float(sin_alpha.min()),
            "final_sin_alpha": float(sin_alpha[-1]),
            "slope_early": slope(alpha, omega, EARLY),
            "slope_late": slope(alpha, omega, LATE),
            "turns": len(omega),
            "largest_energy_rise_step_J": rise_step,
            "largest_energy_rise_J": rise_any,
            "energy_J": [float(traj.energy[0]), float(traj.energy[-1])],
            "stats": stats,
            "events": len(traj.events),
        })  # fmt: skip
            if every is not None:
                cost[f"{law} {rtol:g}"] = cost_by_decade(every)
            del traj, every
    steal, load1 = steal_share(cpu0, cpu_counters()), os.getloadavg()

    print(
        f"case {CASE}: Euler's disk, steel, a = {RADIUS} m, h = {THICKNESS} m; compiled m = "
        f"{mass:.7g} kg, A = {top.A:.6g}, C = {top.C:.6g} kg m^2 (= kreisel.bodies.disk)"
    )
    print(
        f"start: alpha = {ALPHA0} rad, Omega = {omega0:.6g} rad/s (thin-disk law {thin:.6g}), "
        f"psi_dot = {psi_dot0:.6g} rad/s; mu = {MU}, torsion {TORSION} m, rolling {ROLLING} m"
    )
    print(
        f"t_end = {args.t_end:g} s, best of {args.repeats}; steal time {steal}; load average "
        f"{load0[0]:.2f} -> {load1[0]:.2f}; theory slopes {theory_slope(top, EARLY):.3f} (early "
        f"{EARLY}), {theory_slope(top, LATE):.3f} (late {LATE})"
    )
    print_table(rows, [
        ("implementation", 32, lambda r: r["name"]),
        ("seconds", 8, lambda r: f"{r['seconds']:.4f}"),
        ("steps", 8, lambda r: f"{r['steps']:d}"),
        ("t flat", 7, lambda r: f"{r['t_flat']:.3f}"),
        ("min sin", 8, lambda r: f"{r['min_sin_alpha']:.1e}"),
        ("slope e", 7, lambda r: f"{r['slope_early'][0]:.3f}"),
        ("slope l", 7, lambda r: f"{r['slope_late'][0]:.3f}"),
        ("dE step", 9, lambda r: f"{r['largest_energy_rise_step_J']:.1e}"),
        ("dE any", 9, lambda r: f"{r['largest_energy_rise_J']:.1e}"),
        ("E0->E1 mJ", 14, lambda r: "{:.2f}->{:.2f}".format(*(1e3 * e for e in r["energy_J"]))),
    ])  # fmt: skip
    for r in rows[: len(MUJOCO_RUNS)]:
        print(
            f"{r['name']}: largest penetration while tilted {1e3 * r['max_penetration_m']:.3f} "
            f"mm, up to {r['max_contacts']} contacts; to t_end (once) "
            f"{r['seconds_to_t_end_once']:.3f} s"
        )
    for r in rows[len(MUJOCO_RUNS) :]:
        print(f"{r['name']}: {r['stats']}, {r['events']} events")
    print("kreisel's steps by decade of sin(alpha) (steps per precession turn, slipping share):")
    for rtol, decades in cost.items():
        cells = [
            f"{d['sin_alpha'][1]:g}: {d['steps_per_turn']:.0f}/{d['slipping_share']:.2f}"
            for d in decades
        ]
        print(f"  rtol {rtol}: " + ", ".join(cells))
    k_rows = rows[len(MUJOCO_RUNS) :]
    ratios = {
        f"{m['name']} / {k['name']}": m["seconds"] / k["seconds"]
        for m in rows[: len(MUJOCO_RUNS)]
        for k in k_rows
    }
    for name, ratio in ratios.items():
        print(f"wall time {name} = {ratio:.3g}")
    result = {
        "case": CASE,
        "mujoco_version": mj_runs[0]["version"],
        "t_end": args.t_end,
        "repeats": args.repeats,
        "steal": steal,
        "load_average": [load0[0], load1[0]],
        "disk": {
            "radius": RADIUS,
            "thickness": THICKNESS,
            "density": DENSITY,
            "m": mass,
            "A": top.A,
            "C": top.C,
            "mu": MU,
            "torsion": TORSION,
            "rolling": ROLLING,
        },
        "start": {"alpha": ALPHA0, "Omega": omega0, "psi_dot": psi_dot0, "Omega_thin": thin},
        "theory_slope": {"early": theory_slope(top, EARLY), "late": theory_slope(top, LATE)},
        "windows": {"early": EARLY, "late": LATE},
        "runs": rows,
        "kreisel_cost_by_decade": cost,
        "ratio_mujoco_over_kreisel": ratios,
    }
    return write_results(OUT, result)


if __name__ == "__main__":
    main()
    sys.exit(0)
