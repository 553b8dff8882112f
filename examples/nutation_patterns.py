"""The three nutation patterns
===========================

Figure: the three classic nutation patterns of a Lagrange top in the (phi, theta) plane.

    python examples/nutation_patterns.py [OUT_DIR]

The toy top (I1 = 1.75e-4, I3 = 2e-5 kg m^2, m = 0.1 kg, l = 4 cm) is released at
theta = 0.6 rad with spin 300 rad/s and phi_dot = 0.3 Omega_slow (waves), 0 (cusps) or
-0.5 Omega_slow (loops); Omega_slow = 8.13 rad/s is its slow steady precession. Exact
solution over one second. Writes nutation_patterns.png.
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
slow = top.steady_precession(0.6, 300.0)[0]
t = np.linspace(0.0, 1.0, 4001)
fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), sharey=True)
for ax, factor, colour in zip(axes, (0.3, 0.0, -0.5), ("C0", "C1", "C2")):
    st = top.state(0.6, phi_dot=factor * slow, psi_dot=300.0)
    kreisel.plot.axis_path_phi_theta(top.exact(st, t), ax=ax, color=colour)
    ax.set_title(f"{top.motion_kind(st)}: phi_dot(0) = {factor * slow:.2f} rad/s")
fig.suptitle("Lagrange top: the figure axis in the (phi, theta) plane, exact solution, 1 s")
fig.tight_layout()
fig.savefig(out / "nutation_patterns.png", dpi=100)
print(f"wrote {out / 'nutation_patterns.png'}")
