"""The figure axis on the unit sphere
==================================

Figure: the tip of a Lagrange top's figure axis on the unit sphere (cusps).

    python examples/axis_on_sphere.py [OUT_DIR]

The toy top released at rest in theta and phi at theta = 0.6 rad, spun at 300 rad/s, over
one turn of its mean precession (0.84 s). Writes axis_on_sphere.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
import kreisel.plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.LagrangeTop(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04)
st = top.state(0.6, psi_dot=300.0)
turn = 2 * np.pi / top.mean_precession_rate(st)
fig = plt.figure(figsize=(6, 6))
ax = fig.add_subplot(projection="3d")
kreisel.plot.axis_path_on_sphere(top.exact(st, np.linspace(0, turn, 4001)), ax=ax)
ax.view_init(elev=35, azim=-60)
ax.set_title(f"cusps: one precession turn ({turn:.2f} s)")
fig.tight_layout()
fig.savefig(out / "axis_on_sphere.png", dpi=100)
print(f"wrote {out / 'axis_on_sphere.png'}")
