"""A Lagrange top over time (exact solution)
=========================================

Figure: theta, the rates and the energy of a Lagrange top over time (exact solution).

    python examples/lagrange_time_series.py [OUT_DIR]

The toy top in loops (theta = 0.6 rad, phi_dot = -4.07 rad/s, spin 300 rad/s) for one
second: nutation and precession rates, the spin, and the energy shared between kinetic and
potential parts. Writes lagrange_time_series.png.
"""

import sys
from pathlib import Path

import numpy as np

import kreisel
import kreisel.plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.LagrangeTop(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04)
st = top.state(0.6, phi_dot=-4.07, psi_dot=300.0)
fig = kreisel.plot.rigid_time_series(top.exact(st, np.linspace(0, 1, 4001)))
fig.suptitle(f"Lagrange top in {top.motion_kind(st)} (exact solution)")
fig.tight_layout()
fig.savefig(out / "lagrange_time_series.png", dpi=100)
print(f"wrote {out / 'lagrange_time_series.png'}")
