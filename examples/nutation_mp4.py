"""A toy top nutating in loops (MP4)
=================================

Animation (MP4): a toy top nutating in loops, in slow motion.

    python examples/nutation_mp4.py [OUT_DIR]

The toy top (loops: theta = 0.6 rad, phi_dot = -4.07 rad/s, spin 300 rad/s) over 0.5 s,
exact solution, 48 frames at 24 per second: about 1/4 real speed. The spin (48 rev/s) is
far faster than the frame rate, so the stripes jump as under a stroboscope. Writes
nutation.mp4.
"""

import sys
from pathlib import Path

import numpy as np

import kreisel
import kreisel.animate

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.LagrangeTop(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04)
st = top.state(0.6, phi_dot=-4.07, psi_dot=300.0)
traj = top.exact(st, np.linspace(0.0, 0.5, 1001))
kreisel.animate.to_mp4(traj, out / "nutation.mp4", frames=48, fps=24, title="loops", trail=1.0)
print(f"wrote {out / 'nutation.mp4'}")
