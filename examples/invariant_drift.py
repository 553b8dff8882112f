"""How integrators keep the invariants
===================================

Figure: how well three integrators keep the energy and Mz of a heavy top over many periods.

    python examples/invariant_drift.py [OUT_DIR | OUT.png]

The Lagrange top I1 = 1, I3 = 0.5 kg m^2, m = 1 kg, l = 1 m, g = 1 m/s^2 from theta = 1 rad,
theta_dot = 0.3, phi_dot = 0.7, psi_dot = 9 rad/s (nutation period 1.41 s) is integrated for
1000 s (~700 nutation periods) with kreisel.simulate:

* "splitting" (2nd order, symplectic) at dt = 0.01 s: the energy error oscillates but stays
  bounded; Mz is kept to round-off;
* "rk4" at the same dt = 0.01 s: both drift, linearly in time;
* "dop853" at its default tolerances (rtol 1e-10, atol 1e-12): small errors that grow too.

Each curve is the largest error within consecutive 2.5 s windows (~2 nutation periods), so
that oscillations within a period do not blur the trend. Writes invariant_drift.png into
OUT_DIR (default kreisel-out/), or to OUT.png.
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import kreisel

PARAMS = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 1.0, "g": 1.0}
STATE = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 9.0}
T_END = 1000.0
DT = 0.01
WINDOW = 50  # samples per window (2.5 s)
FLOOR = 1e-17  # an exact zero is drawn here (log scale)
RUNS = (  # method, dt, label, colour
    ("splitting", DT, f"splitting (symplectic, order 2), dt = {DT:g} s", "tab:blue"),
    ("rk4", DT, f"rk4 (order 4), dt = {DT:g} s", "tab:red"),
    ("dop853", None, "dop853 (order 8, adaptive), rtol = 1e-10", "tab:green"),
)


def main(argv=None) -> pathlib.Path:
    # the script's arguments (none in a notebook, whose kernel has its own)
    argv = (sys.argv[1:] if "ipykernel" not in sys.modules else []) if argv is None else argv
    out = pathlib.Path(argv[0]) if argv else pathlib.Path("kreisel-out")
    if out.suffix != ".png":
        out = out / "invariant_drift.png"
    out.parent.mkdir(parents=True, exist_ok=True)

    top = kreisel.LagrangeTop(**PARAMS)
    state = top.state(**STATE)
    period = top.nutation_period(state)
    inv = top.invariants(state)
    t_eval = np.linspace(0.0, T_END, 20001)

    def envelope(t, err):
        """(window centres, largest |err| in each window), err clipped at FLOOR."""
        n = (len(t) - 1) // WINDOW
        blocks = np.abs(err[1 : n * WINDOW + 1]).reshape(n, WINDOW)
        centres = t[1 : n * WINDOW + 1].reshape(n, WINDOW).mean(axis=1)
        return centres, np.maximum(blocks.max(axis=1), FLOOR)

    fig, (ax_e, ax_mz) = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True, layout="constrained")
    for method, dt, label, colour in RUNS:
        traj = kreisel.simulate(top, state, T_END, method=method, dt=dt, t_eval=t_eval)
        e_err = (traj.energy - inv.E) / abs(inv.E)
        mz_err = (traj.Mz - inv.Mz) / abs(inv.Mz)
        ax_e.plot(*envelope(traj.t, e_err), color=colour, lw=1.6, label=label)
        ax_mz.plot(*envelope(traj.t, mz_err), color=colour, lw=1.6, label=label)
        print(
            f"{method:>10}: max |dE/E| = {np.abs(e_err).max():.2e}, "
            f"max |dMz/Mz| = {np.abs(mz_err).max():.2e}, "
            f"{traj.stats['steps']} steps"
        )

    for ax in (ax_e, ax_mz):
        ax.set_yscale("log")
        ax.set_ylim(1e-17, 1e-2)
        ax.set_yticks(10.0 ** np.arange(-16, -1, 2))
        ax.grid(True, which="major", alpha=0.3)
    ax_e.set_ylabel("energy: $|E(t) - E_0| \\,/\\, |E_0|$\n(relative, dimensionless)")
    ax_mz.set_ylabel("vertical ang. momentum:\n$|M_z(t) - M_{z,0}| \\,/\\, |M_{z,0}|$")
    ax_mz.set_xlabel("time t (s)")
    ax_mz.set_xlim(0.0, T_END)
    ax_e.set_title("largest relative error in 2.5 s windows (~2 nutation periods)", fontsize=10)
    ax_e.legend(loc="lower right", fontsize=9, framealpha=0.9)
    fig.suptitle(
        f"Lagrange top I1 = {PARAMS['I1']:g}, I3 = {PARAMS['I3']:g} kg m², m = {PARAMS['m']:g} kg,"
        f" l = {PARAMS['l']:g} m, g = {PARAMS['g']:g} m/s²: {T_END / period:.0f} nutation periods"
        f" of {period:.2f} s",
        fontsize=11,
    )
    fig.savefig(out, dpi=130)
    plt.close(fig)
    print(f"wrote {out}")
    return out


if __name__ == "__main__":
    main()
