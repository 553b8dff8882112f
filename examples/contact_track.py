"""The contact point's track on the floor
======================================

Figure: the contact point's track on the floor of a top on a blunt tip, coloured by
contact mode (slip, roll, flight).

    python examples/contact_track.py [OUT_DIR]

A 100 g toy top on a 1 cm ball tip, centre of mass 3 cm above the tip's centre, Coulomb
friction mu = 0.05, released at theta = 0.3 rad with spin 300 rad/s: it hops, slips, then
rises to the vertical. Writes contact_track.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

import kreisel
import kreisel.plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = kreisel.PlayTop(m=0.1, A=1.6e-5, C=2e-5, s=0.03, rho=0.01, friction=kreisel.Coulomb(0.05))
run = kreisel.simulate(top, top.state(theta=0.3, phi_dot=6.5, psi_dot=300.0), 3.0)
fig, ax = plt.subplots(figsize=(6.5, 6.5))
kreisel.plot.contact_track(run, ax=ax)
ax.set_title("blunt tip: the contact point on the floor, 3 s")
fig.tight_layout()
fig.savefig(out / "contact_track.png", dpi=100)
print(f"wrote {out / 'contact_track.png'}")
