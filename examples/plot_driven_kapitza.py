"""A shaken top: regular and chaotic stroboscopic sections, and a damped gyroscope that falls
==========================================================================================

Top row: stroboscopic (Poincare) sections of a Lagrange top (I1 = 1, I3 = 0.5 about the
pivot, m = 1, l = 0.5, g = 2, spin 2 rad/s) whose pivot is shaken up and down at 3 rad/s,
near the top's own frequencies: the state once per shaking period (``kreisel.poincare``),
drawn in the (theta, theta_dot) plane (``kreisel.plot.poincare``), from theta = 1 rad with
five nutation rates. Vertical shaking keeps Mz and the symmetric top keeps M3, so what is
left is theta and time: each motion's section is a curve where it is regular and fills an
area where it is chaotic. Shaken by 2 cm the motions stay on closed curves (the Lagrange top
is integrable, and a small periodic push keeps most of its tori); shaken by 40 cm they
scatter over a chaotic sea (tests/test_driven_top.py: a positive largest Lyapunov
exponent, ~0.2 /s).

Bottom row: a toy gyroscope (rotor at 600 rad/s, axis horizontal, precessing steadily) with
viscous friction at its pivot, c = I3 / 5 s: its spin decays exactly as exp(-c t / I3) (for a
symmetric top the axial equation decouples), and as it slows, the friction that also brakes
its precession lets it sink, and it falls. Writes plot_driven_kapitza.png.

    python examples/plot_driven_kapitza.py [OUT_DIR]
"""

import math
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
import kreisel.plot
from kreisel import pivots

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))

# -- stroboscopic sections of the shaken top -----------------------------------------------
TOP = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.5, "g": 2.0}
SHAKE = 3.0  # rad/s
PERIODS = 250
for ax, amplitude, kind in ((axes[0, 0], 0.02, "regular"), (axes[0, 1], 0.4, "chaotic")):
    top = kreisel.LagrangeTop(**TOP, pivot=pivots.Harmonic([0.0, 0.0, amplitude], SHAKE))
    for k, theta_dot in enumerate((0.0, 0.3, 0.6, 0.9, 1.2)):
        section = kreisel.poincare(top, top.state(1.0, theta_dot=theta_dot, psi_dot=2.0), PERIODS)
        kreisel.plot.poincare(section, ax, color=f"C{k}", size=3.0,
                              label=f"theta_dot(0) = {theta_dot:+.1f}")  # fmt: skip
    ax.set_title(f"shaken {100 * amplitude:.0f} cm at {SHAKE:g} rad/s: {kind}")
axes[0, 1].get_legend().remove()
axes[0, 0].set_ylim(-1.7, 2.4)
axes[0, 0].legend(loc="upper center", fontsize=7, frameon=False, ncol=3, markerscale=3)

# -- a damped toy gyroscope slows and falls ------------------------------------------------
GYRO = {"I1": 3.712e-4, "I3": 1.024e-4, "m": 0.2, "l": 0.04, "g": 9.81}
viscous = GYRO["I3"] / 5.0  # N m s: the spin's decay time I3 / c is 5 s
gyro = kreisel.LagrangeTop(**GYRO, damping=kreisel.PivotDamping(viscous=viscous))
spin = 600.0
precession = GYRO["m"] * GYRO["g"] * GYRO["l"] / (GYRO["I3"] * spin)  # steady, horizontal
t = np.linspace(0.0, 25.0, 2501)
run = kreisel.simulate(gyro, gyro.state(math.pi / 2, phi_dot=precession, psi_dot=spin), 25.0,
                       t_eval=t, rtol=1e-9)  # fmt: skip
axes[1, 0].plot(t, run.theta, color="k")
axes[1, 0].axhline(math.pi / 2, color="grey", lw=0.6, ls=":")
axes[1, 0].set_ylabel("theta (rad): pi/2 horizontal, pi hanging")
axes[1, 0].set_title("damped toy gyroscope: the axis sinks as the rotor slows")
axes[1, 1].semilogy(t, run.omega[:, 2], color="k", label="omega_3 (simulated)")
axes[1, 1].semilogy(t, spin * np.exp(-viscous * t / GYRO["I3"]), color="C3", ls="--",
                    label="omega_3(0) exp(-c t / I3)")  # fmt: skip
axes[1, 1].set_ylabel("omega_3 (rad/s)")
axes[1, 1].set_title("its spin decays exactly exponentially")
axes[1, 1].legend(loc="upper right", frameon=False)
for ax in axes[1]:
    ax.set_xlabel("t (s)")
gap = np.abs(run.omega[:, 2] / (spin * np.exp(-viscous * t / GYRO["I3"])) - 1.0).max()
print(f"gyroscope: theta from {run.theta[0]:.3f} to {run.theta[-1]:.3f} rad in 25 s; "
      f"omega_3 against the exponential: {gap:.1e} at most (relative)")  # fmt: skip

fig.tight_layout()
fig.savefig(out / "plot_driven_kapitza.png", dpi=100)
print(f"wrote {out / 'plot_driven_kapitza.png'}")
