"""The effective potential of the nutation
=======================================

Figure: the effective potential of the nutation, the energy line and the turning points.

    python examples/effective_potential.py [OUT_DIR]

The toy top at theta = 0.6 rad, spin 300 rad/s, released at rest in theta and phi: theta
swings between the two roots of E = Veff(theta). Writes effective_potential.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

import kreisel
import kreisel.plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.LagrangeTop(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04)
st = top.state(0.6, psi_dot=300.0)
fig, ax = plt.subplots(figsize=(7, 4.5))
kreisel.plot.effective_potential(top, st, ax=ax)
lo, hi = top.turning_points(st)
ax.set_title(f"turning points {lo:.3f} and {hi:.3f} rad (dotted)")
fig.tight_layout()
fig.savefig(out / "effective_potential.png", dpi=100)
print(f"wrote {out / 'effective_potential.png'}")
