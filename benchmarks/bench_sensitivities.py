"""Forward sensitivities of the heavy top: what they cost, and whether DOP853's step control
should measure them.

1. Step control. A general heavy top (asymmetric, centre of mass off every axis) over 3 s
   with all 14 sensitivities (8 parameters, 6 fields of its Euler-angle state), at several
   tolerances, once with the sensitivities left out of the error estimate (kreisel's choice:
   the steps of a plain run) and once with them in it. Each is compared with a reference run
   at rtol = 1e-14 that measures them, and with what central differences of two plain runs
   per name give at the same tolerance (the step h = rtol^(1/3), relative). "error" is the
   largest deviation of a sensitivity (body rates and orientation) relative to its largest
   value, over the names; "run error" that of the body rates of the run itself.
2. Cost. The same top over 10 s at rtol = 1e-10: a plain run against runs with 1, 5 and 14
   sensitivities, and against the 10 plain runs of central differences in 5 names.

Run: ``.venv/bin/python benchmarks/bench_sensitivities.py``.
"""

from __future__ import annotations

import numpy as np
from _common import best_of

import kreisel
from kreisel import _core

GENERAL = {"I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0, "com": [0.3, 0.2, 0.4], "g": 9.81}
START = {"theta": 0.8, "phi": 0.3, "psi": -0.4, "theta_dot": 0.5, "phi_dot": 1.0, "psi_dot": 8.0}
NAMES = ["I1", "I2", "I3", "m", "g", "com[0]", "com[1]", "com[2]", *START]
T_END = 3.0
T_EVAL = np.linspace(0.0, T_END, 31)


def run(names, rtol, control, t_end=T_END, t_eval=T_EVAL):
    """A run with sensitivities through the binding (which takes `control`)."""
    top = kreisel.HeavyTop(**GENERAL)
    state = top.state(**START)
    return _core.simulate_sensitivities(
        top._native_model(), top._native_state(state), t_end, "dop853", rtol, rtol * 1e-2,
        None, t_eval, [], False, names, False, list(state.as_tuple()), control,
    )  # fmt: skip


def stacked(out, name):
    s = out["sensitivities"][name]
    return np.hstack([s["omega"], s["orientation"]])


def error(a, ref):
    """Largest deviation over the names, each relative to its reference's largest value."""
    return max(
        np.abs(stacked(a, n) - stacked(ref, n)).max() / np.abs(stacked(ref, n)).max() for n in NAMES
    )


def run_error(a, ref):
    """The error of the run itself (body rates), relative to their largest value."""
    return np.abs(a["omega"] - ref["omega"]).max() / np.abs(ref["omega"]).max()


def plain(p, start, rtol):
    top = kreisel.HeavyTop(p["I1"], p["I2"], p["I3"], p["m"], p["com"], p["g"])
    return kreisel.simulate(
        top, top.state(**start), T_END, t_eval=T_EVAL, rtol=rtol, atol=rtol * 1e-2
    )


def differences(rtol, ref):
    """The error of central differences of plain runs at `rtol`, as `error` measures it."""
    worst = 0.0
    for name in NAMES:
        runs = []
        for sign in (1, -1):
            p, s = {**GENERAL, "com": list(GENERAL["com"])}, dict(START)
            x = p["com"][int(name[4])] if name.startswith("com") else p.get(name, s.get(name))
            h = rtol ** (1 / 3) * max(abs(x), 1.0)
            if name.startswith("com"):
                p["com"][int(name[4])] += sign * h
            elif name in p:
                p[name] += sign * h
            else:
                s[name] += sign * h
            runs.append(plain(p, s, rtol))
        a, b = runs
        q0 = plain(GENERAL, START, rtol).quaternion
        dq = (a.quaternion - b.quaternion) / (2 * h)
        # xi = 2 vec(conj(q) dq)
        w, v = q0[:, :1], q0[:, 1:]
        xi = 2 * (w * dq[:, 1:] - dq[:, :1] * v - np.cross(v, dq[:, 1:]))
        fd = np.hstack([(a.omega - b.omega) / (2 * h), xi])
        r = stacked(ref, name)
        worst = max(worst, np.abs(fd - r).max() / np.abs(r).max())
    return worst


def main():
    ref = run(NAMES, 1e-14, True)
    print(f"1. step control: {len(NAMES)} sensitivities, general heavy top, t_end = {T_END} s")
    print(
        f"{'rtol':>8} {'control':>8} {'steps':>6} {'rhs':>7} {'time ms':>8} {'error':>9} "
        f"{'run error':>9}"
    )
    for rtol in (1e-6, 1e-8, 1e-10, 1e-12):
        for control in (False, True):
            t, out = best_of(lambda r=rtol, c=control: run(NAMES, r, c), 3)
            st = out["stats"]
            on = "on" if control else "off"
            print(
                f"{rtol:8.0e} {on:>8} {st['steps']:6d} {st['rhs_evals']:7d} {t * 1e3:8.2f} "
                f"{error(out, ref):9.2e} {run_error(out, ref):9.2e}"
            )
        fd = differences(rtol, ref)
        print(f"{rtol:8.0e} {'central differences of plain runs':>33} {fd:9.2e}")

    print("\n2. cost: general heavy top, t_end = 10 s, rtol = 1e-10, every step kept")
    top = kreisel.HeavyTop(**GENERAL)
    s = top.state(**START)
    t0, base = best_of(lambda: kreisel.simulate(top, s, 10.0), 5)
    print(f"plain run: {t0 * 1e3:.2f} ms, {base.stats['steps']} steps")
    for k in (1, 5, 14):
        names = NAMES[:k]
        t, _ = best_of(lambda n=names: kreisel.simulate(top, s, 10.0, sensitivities=n), 5)
        print(f"{k:2d} sensitivities: {t * 1e3:.2f} ms ({t / t0:.2f} x the plain run)")
    print(f"central differences in 5 names: 10 plain runs, {10 * t0 * 1e3:.2f} ms")


if __name__ == "__main__":
    main()
