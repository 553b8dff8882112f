"""Euler's disk: the precession speeds up without bound as it settles, and it lies flat
====================================================================================

Figure: the steel disk of benchmark T4 (``kreisel.bodies.disk(0.0375, 0.0125, 0.4335)``,
Coulomb-Contensou friction mu = 0.3 over a 0.57 mm patch, rolling resistance 0.2 mm) started
rolling with its centre at rest at 0.3 rad on its steady law.

    python examples/euler_disk.py [OUT_DIR]

Left: the precession rate Omega (the turning rate of the axis about the vertical) against the
inclination alpha, on log scales, with the steady law of the thick disk, Omega^2 sin(alpha)
(A cos(alpha) - C k sin(alpha)) = m g a (cos(alpha) - k sin(alpha)), k = h / (2 a)
(theory: bodies of revolution at k = 0; kreisel.bodies.disk_rolling_rates): as the disk settles it
follows the
law, Omega ~ alpha^(-1/2) towards flat (Moffatt, Nature 404 (2000) 833). Right: alpha and
the energy against time; the disk lies flat (the event "flat", sin(alpha) = 1e-4) at a finite
time, then spins down on its face and rests (the event "rest" ends the run). Writes
euler_disk.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
from kreisel import bodies

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
a, h, m = 0.0375, 0.0125, 0.4335
patch = 1e-4 * 16 / (3 * np.pi * 0.3)  # mu 3 pi R / 16 = 0.1 mm, as benchmark T4
disk = bodies.disk(a, h, m, friction=kreisel.CoulombContensou(0.3, patch),
                   rolling_resistance=2e-4)  # fmt: skip
alpha0 = 0.3
state = bodies.disk_rolling_state(disk, alpha0)
run = kreisel.simulate(disk, state, 30.0, rtol=1e-8, events=[kreisel.events.rest()])
flat = next(e.t for e in run.events if e.name == "flat")
print(f"flat at {flat:.4f} s after {run.stats['steps']} steps")

# the precession rate from the axis's azimuth, over whole turns
alpha = run.theta
turn = np.unwrap(run.phi) / (2 * np.pi)
ends = np.searchsorted(turn, np.arange(np.ceil(turn[0]), np.floor(turn[-1]) + 1))
t_turn = run.t[ends]
rate = 2 * np.pi / np.diff(t_turn)
alpha_turn = np.interp(0.5 * (t_turn[1:] + t_turn[:-1]), run.t, alpha)

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
left.loglog(alpha_turn, rate, ".", ms=3, label="kreisel, per turn of the axis")
grid = np.geomspace(alpha_turn.min(), alpha0, 200)
left.loglog(
    grid,
    [bodies.disk_rolling_rates(disk, x)[0] for x in grid],
    color="k",
    lw=0.8,
    label="steady law of the thick disk",
)
left.set_xlabel("inclination alpha (rad)")
left.set_ylabel("precession rate Omega (rad/s)")
left.legend(loc="upper right")
right.semilogy(run.t, np.sin(alpha), color="k", label="sin(alpha)")
right.set_xlabel("t (s)")
right.set_ylabel("sin(alpha)")
twin = right.twinx()
twin.plot(run.t, run.energy * 1e3, color="tab:red", label="E (mJ)")
twin.plot(run.t, (run.energy + run.dissipated) * 1e3, color="tab:red", ls="--",
          label="E + dissipated")  # fmt: skip
twin.set_ylabel("energy (mJ)", color="tab:red")
right.axvline(flat, color="grey", ls=":", lw=0.8)
right.set_title(f"lies flat at {flat:.3f} s", fontsize=10)
fig.suptitle("Euler's disk (steel, 75 mm): the precession speeds up as it settles")
fig.tight_layout()
fig.savefig(out / "euler_disk.png", dpi=100)
print(f"wrote {out / 'euler_disk.png'}")
