"""A tippe top turning over (GIF)
==============================

Animation (GIF): a tippe top turning over.

    python examples/tippe_top_gif.py [OUT_DIR]

The tippe top of tippe_top_time_series.py over its first 4 s, 40 frames at 10 per second.
The ball is drawn full on the heavy side, its stem inside the ball's outline (the model's
only contact is the sphere). Writes tippe_top.gif.
"""

import sys
from pathlib import Path

import numpy as np

import kreisel
import kreisel.animate

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
c = 0.4 * 0.02 * 0.02**2
top = kreisel.PlayTop(m=0.02, A=0.8 * c, C=c, s=0.006, rho=0.02, friction=kreisel.Viscous(1.0))
run = kreisel.simulate(top, top.state(theta=np.pi - 0.1, psi_dot=150.0), 4.0, rtol=1e-9)
kreisel.animate.to_gif(run, out / "tippe_top.gif", frames=40, fps=10, title="tippe top")
print(f"wrote {out / 'tippe_top.gif'}")
