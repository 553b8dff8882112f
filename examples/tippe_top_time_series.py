"""A tippe top turning over: its time series
=========================================

Figure: a tippe top turning over: u = cos(theta), the normal force, the slip speed,
Jellett's integral and the energy, with the contact modes shaded.

    python examples/tippe_top_time_series.py [OUT_DIR]

A 20 g ball of radius 2 cm with its centre of mass 6 mm off centre (alpha = 0.3,
gamma = 0.8), viscous friction mu = 1 s/m, spun at 150 rad/s near hanging. Writes
tippe_top_time_series.png.
"""

import sys
from pathlib import Path

import numpy as np

import kreisel
import kreisel.plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
c = 0.4 * 0.02 * 0.02**2
top = kreisel.PlayTop(m=0.02, A=0.8 * c, C=c, s=0.006, rho=0.02, friction=kreisel.Viscous(1.0))
run = kreisel.simulate(top, top.state(theta=np.pi - 0.1, psi_dot=150.0), 8.0, rtol=1e-9)
fig = kreisel.plot.play_time_series(run)
fig.suptitle("tippe top turning over (viscous friction; slip shaded)")
fig.tight_layout()
fig.savefig(out / "tippe_top_time_series.png", dpi=100)
print(f"wrote {out / 'tippe_top_time_series.png'}")
