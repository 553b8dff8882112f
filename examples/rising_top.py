"""A blunt tip rises, a pointed one does not
=========================================

Figure: a blunt tip rises to the vertical, a pointed one keeps precessing.

    python examples/rising_top.py [OUT_DIR]

The same 100 g top (A = 1.6e-5, C = 2e-5 kg m^2, centre of mass 3 cm above the tip's
centre, Coulomb mu = 0.05) on a 1 cm and on a 0.5 mm ball tip, released at theta = 0.3 rad
with spin 300 rad/s; sliding friction at the broad tip drives the axis up (Jellett, Routh).
Writes rising_top.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
fig, ax = plt.subplots(figsize=(8, 4.5))
for rho, label, colour in ((0.01, "blunt tip, rho = 10 mm", "C3"),
                           (0.0005, "pointed tip, rho = 0.5 mm", "C0")):  # fmt: skip
    top = kreisel.PlayTop(m=0.1, A=1.6e-5, C=2e-5, s=0.03, rho=rho, friction=kreisel.Coulomb(0.05))
    run = kreisel.simulate(top, top.state(theta=0.3, phi_dot=6.5, psi_dot=300.0), 5.0)
    ax.plot(run.t, np.degrees(run.theta), color=colour, lw=1.0, label=label)
ax.set_xlabel("time t (s)")
ax.set_ylabel("tilt theta (degrees from the vertical)")
ax.set_ylim(0, None)
ax.grid(alpha=0.3)
ax.legend()
ax.set_title("the same top on two tips (Coulomb friction, mu = 0.05)")
fig.tight_layout()
fig.savefig(out / "rising_top.png", dpi=100)
print(f"wrote {out / 'rising_top.png'}")
