"""Checksums of every output column of the benchmark cases (L1, T1, T2, M1, S1) and of the
other simulation routes (every heavy-top method, events, t_eval, batches, a sweep).

    python tools/checksums.py > before.json         # record
    python tools/checksums.py --compare before.json # after a change: every column bit for bit

A refactoring that must not change kreisel's behaviour is checked this way: the hashes are
of the raw bytes of each float64 column, so a difference in the last bit shows. The cases
are those of docs/benchmarks.md with the constants of the scripts in benchmarks/ (T2
with the documented compiled body, so MuJoCo is not needed), some shortened.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import sys
import tempfile

import numpy as np

import kreisel


def digest(value) -> str:
    a = np.asarray(value)
    if a.dtype.kind in "OUS":
        a = np.array([str(x) for x in a.ravel()])
        return hashlib.sha256("\x00".join(a.tolist()).encode()).hexdigest()[:16]
    return hashlib.sha256(np.ascontiguousarray(a, dtype=float).tobytes()).hexdigest()[:16]


def trajectory(traj) -> dict:
    out = {k: digest(traj[k]) for k in sorted(traj.columns)}
    out["events"] = [[e.name, e.t.hex()] for e in traj.events]
    out["steps"] = int(traj.stats["steps"])
    return out


def summary(s) -> dict:
    return {k: digest(v) for k, v in sorted(vars(s).items()) if v is not None and k != "errors"} | {
        "errors": [e for e in s.errors]
    }


def cases() -> dict:
    out = {}
    # L1
    top = kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0)
    st = top.state(1.0, theta_dot=0.3, phi_dot=0.7, psi_dot=9.0)
    out["L1"] = trajectory(kreisel.simulate(top, st, 100.0, rtol=1e-10, atol=1e-12))
    out["L1_reduced"] = trajectory(
        kreisel.simulate(top, st, 20.0, rtol=1e-10, atol=1e-12, reduced=True)
    )
    out["L1_reduced_rk4"] = trajectory(
        kreisel.simulate(top, st, 5.0, method="rk4", dt=1e-3, reduced=True)
    )
    out["L1_t_eval_events"] = trajectory(
        kreisel.simulate(
            top,
            st,
            20.0,
            t_eval=np.linspace(0, 20, 101),
            events=[kreisel.events.turning_points(), kreisel.events.theta_crossing(1.2)],
        )
    )
    # M1, and every fixed-step method
    mass, l_com, i3 = 0.3, 0.04, 1.5e-4
    m1 = kreisel.LagrangeTop(I1=2.0e-4 + mass * l_com**2, I3=i3, m=mass, l=l_com, g=9.81)
    s1 = m1.state(0.3, theta_dot=0.0, phi_dot=2.0, psi_dot=100.0)
    for method in ("splitting", "rk4", "splitting4", "splitting6", "verlet", "midpoint", "gauss4"):
        out[f"M1_{method}"] = trajectory(kreisel.simulate(m1, s1, 10.0, method=method, dt=1e-3))
    out["M1_splitting_t_eval"] = trajectory(
        kreisel.simulate(m1, s1, 2.0, method="splitting", dt=1e-3, t_eval=np.linspace(0, 2, 33))
    )
    # a chaotic heavy top and Kovalevskaya's
    heavy = kreisel.HeavyTop(6e-4, 7e-4, 2e-4, m=0.3, com=(0.01, 0.0, 0.03))
    hs = heavy.state(0.7, phi_dot=3.0, psi_dot=40.0)
    out["heavy_dop853"] = trajectory(kreisel.simulate(heavy, hs, 5.0))
    out["heavy_gauss4"] = trajectory(kreisel.simulate(heavy, hs, 2.0, method="gauss4", dt=1e-3))
    kov = kreisel.HeavyTop(2.0, 2.0, 1.0, m=1.0, com=(0.5, 0.0, 0.0), g=1.0)
    ks = kov.state(1.0, theta_dot=0.5, phi_dot=0.3, psi_dot=2.0)
    out["kovalevskaya"] = trajectory(kreisel.simulate(kov, ks, 20.0))
    # T1
    m, rho, s = 0.02, 0.02, 0.006
    c = 0.4 * m * rho**2
    t1 = kreisel.PlayTop(m=m, A=0.8 * c, C=c, s=s, rho=rho, g=9.81, friction=kreisel.Viscous(1.0))
    t1s = t1.state(math.pi - 0.1, psi_dot=150.0)
    out["T1"] = trajectory(kreisel.simulate(t1, t1s, 12.0, rtol=1e-9, atol=1e-12))
    out["T1_events"] = trajectory(
        kreisel.simulate(
            t1,
            t1s,
            12.0,
            rtol=1e-9,
            atol=1e-12,
            t_eval=np.linspace(0, 12, 241),
            events=[kreisel.events.inversion(0.9)],
        )
    )
    # T2 (documented compiled body)
    t2 = kreisel.PlayTop(
        m=0.0554746, A=1.27357e-5, C=1.28305e-5, s=0.00543159, rho=0.02, g=9.81,
        friction=kreisel.Coulomb(mu=1.0),
    )  # fmt: skip
    t2s = t2.state(math.pi, phi=math.pi / 2, psi=math.pi / 2, theta_dot=1.0, psi_dot=-200.0)
    out["T2"] = trajectory(kreisel.simulate(t2, t2s, 7.0))
    # a bouncing, hopping Coulomb top with resistance, and its rest
    hop = kreisel.PlayTop(
        m=0.02, A=2.56e-6, C=3.2e-6, s=0.006, rho=0.02, friction=kreisel.Coulomb(0.3),
        restitution=0.5, rolling_resistance=1e-4, drilling_resistance=1e-4, air_drag=1e-8,
    )  # fmt: skip
    hs0 = hop.state(2.0, theta_dot=5.0, psi_dot=80.0, vx=0.3, height=0.01)
    out["hop"] = trajectory(kreisel.simulate(hop, hs0, 3.0, events=[kreisel.events.rest()]))
    # batches
    states = [t1.state(th, psi_dot=pd) for th in (2.8, 3.0) for pd in (100.0, 200.0)]
    out["play_many"] = summary(kreisel.simulate_many(t1, states, 6.0, rtol=1e-8, atol=1e-12))
    hstates = [m1.state(th, psi_dot=80.0) for th in (0.2, 0.5, 1.0)]
    out["heavy_many_dop853"] = summary(kreisel.simulate_many(m1, hstates, 3.0))
    out["heavy_many_splitting"] = summary(
        kreisel.simulate_many(m1, hstates, 3.0, method="splitting", dt=1e-3)
    )
    # S1, shortened: 400 runs of 2 s
    spec = {
        "top": {"kind": "play", "m": m, "A": 0.8 * c, "C": c, "s": s, "rho": rho,
                "friction": "viscous", "mu": 1.0},
        "state": {},
        "simulation": {"t_end": 2.0, "rtol": 1e-8, "atol": 1e-12},
        "grid": {"theta": {"start": 2.8, "stop": 3.1, "num": 20},
                 "psi_dot": {"start": 100.0, "stop": 250.0, "num": 20}},
        "output": {"chunk": 128},
    }  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        ds = kreisel.sweep(kreisel.SweepSpec.from_tables(spec), f"{tmp}/s1.zarr", progress=False)
        out["S1"] = {k: digest(ds[k].values) for k in sorted(ds.data_vars)}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare", help="a JSON file written by an earlier run")
    args = parser.parse_args(argv)
    now = cases()
    if not args.compare:
        json.dump(now, sys.stdout, indent=1, sort_keys=True)
        print()
        return 0
    with open(args.compare) as f:
        before = json.load(f)
    bad = 0
    for case, cols in before.items():
        for col, h in cols.items():
            got = now.get(case, {}).get(col)
            if got != h:
                bad += 1
                print(f"DIFFERS {case}.{col}: {h} -> {got}")
    print(f"{sum(len(c) for c in before.values())} columns compared, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
