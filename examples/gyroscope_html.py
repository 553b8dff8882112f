"""An interactive gyroscope (HTML)
===============================

Interactive view (HTML, plotly): a gyroscope precessing; drag to turn it, play to run.

    python examples/gyroscope_html.py [OUT_DIR]

A 200 g rotor disc of radius 3.2 cm, 4 cm out on a horizontal axle, spun at 600 rad/s and
started in steady precession (1.28 rad/s): one precession turn, 60 frames. The file
includes plotly.js and opens offline. Writes gyroscope.html.
"""

import sys
from pathlib import Path

import numpy as np

import kreisel
import kreisel.animate

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.LagrangeTop(I1=3.712e-4, I3=1.024e-4, m=0.2, l=0.04)
rate = top.steady_precession(np.pi / 2, 600.0)[0]
st = top.state(np.pi / 2, phi_dot=rate, psi_dot=600.0)
traj = top.exact(st, np.linspace(0.0, 2 * np.pi / rate, 2001))
kreisel.animate.to_html(traj, out / "gyroscope.html", frames=60, title="gyroscope")
print(f"wrote {out / 'gyroscope.html'}")
