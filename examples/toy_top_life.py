"""The whole life of a toy top: it precesses, falls on its shoulder and rolls to rest
====================================================================================

Figure and animation (GIF): the toy top of ``kreisel.bodies.toy_top`` (a 5 cm solid cone on a
1 mm tip with a handle; Coulomb-Contensou friction mu = 0.3 over a 0.2 mm patch; rolling
resistance 0.1 mm) released 0.3 rad off the vertical at 120 rad/s, below Routh's sleeping
threshold of about 127 rad/s (C^2 w^2 = 4 A_tip m g l about the tip; with its friction it tips
slowly up to about 201 rad/s, see ``kreisel.bodies.toy_top``).

    python examples/toy_top_life.py [OUT_DIR]

It precesses and nutates on its tip while friction at the tip wears its spin down and lets it
sink; its shoulder strikes the floor at 2.25 s; it slides on tip and shoulder until both
stick at 3.16 s, then rolls on them in circles about its tip: a rotation about the line
through the two contact points, whose rate rolling resistance brings linearly to zero (at
c m g / I_n, I_n the moment about that line; tests/test_toy_top.py checks it). It stops at
4.02 s (the event ``rest``) at the tilt its tip and shoulder fix (u = 0.6697). Writes
toy_top_life.png and toy_top_life.gif.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
import kreisel.animate
import kreisel.plot
from kreisel import bodies, events

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = bodies.toy_top(rolling_resistance=1e-4)
state = top.state(theta=0.3, psi_dot=120.0)
run = kreisel.simulate(top, state, 6.0, rtol=1e-9, events=[events.rest()])
story = [(e.name, e.part, e.t) for e in run.events]
print("\n".join(f"{when:8.4f} s  {name} {part or ''}" for name, part, when in story))

fig, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
colours = {(True, False): "#f2d7b6", (True, True): "#c9b3e6"}
kreisel.plot.parts_panels(
    axes, run, colours, ["tip", "shoulder"], top.m * 9.81, legend="center left"
)
axes[2].plot(run.t, np.linalg.norm(run.omega, axis=1), color="grey", ls="--", label="|omega|")
axes[2].legend(loc="upper right")
for ax in axes:
    for name, _, when in story:
        if name in ("slip_to_roll", "rest"):
            ax.axvline(when, color="grey", lw=0.6, ls=":")
fig.suptitle("toy top: on its tip (tan), on tip and shoulder (violet); dotted: rolling, rest")
fig.tight_layout()
fig.savefig(out / "toy_top_life.png", dpi=100)
print(f"wrote {out / 'toy_top_life.png'}")
kreisel.animate.to_gif(run, out / "toy_top_life.gif", frames=61, fps=15, title="toy top")
print(f"wrote {out / 'toy_top_life.gif'}")
