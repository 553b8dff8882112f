"""A tippe top turning over onto its peg: Leine and Glocker's top over 8 s
=======================================================================

Figure: Leine and Glocker's tippe top (a 15 mm ball with a 5 mm peg, Coulomb-Contensou
friction mu = 0.3 over a 0.5 mm patch; theory: bodies of revolution) spun at 180 rad/s near hanging:
u = cos(theta), the normal force at each part, the spin and the energy, with the parts in
contact shaded (ball, both, peg).

    python examples/tippe_top_peg.py [OUT_DIR]

It turns over on its ball, the peg touches at 1.37 s and the ball leaves the floor at that
instant; it spins on its peg while the drilling friction wears its spin down, falls back
when the spin drops below the peg's sleeping threshold (J below J_R(1) of the one-sphere
theory applied to the peg, the dotted line), rocks between ball and peg, rests on both (the
critical moment of a top with a peg) and ends on its ball. Writes tippe_top_peg.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
import kreisel.plot
from kreisel.shapes import Sphere

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
M, A, C = 6e-3, 8e-7, 7e-7
top = kreisel.PlayTop(
    M, A, C,
    shape=[Sphere(0.015, z=-0.003, name="ball"), Sphere(0.005, z=-0.016, name="peg")],
    friction=kreisel.CoulombContensou(mu=0.3, radius=5e-4),
)  # fmt: skip
run = kreisel.simulate(top, top.state(theta=np.pi - 0.1, psi_dot=180.0), 8.0,
                       t_eval=np.linspace(0.0, 8.0, 4001))  # fmt: skip
# the spin at which standing on the peg stops being stable: J_R(1) of the peg as a tip sphere
threshold = kreisel.PlayTop(M, A, C, s=0.016, rho=0.005).J_R(1.0) / (C * (0.016 + 0.005))

fig, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
colours = {(True, False): "#f2d7b6", (True, True): "#c9b3e6", (False, True): "#b6d7f2"}
kreisel.plot.parts_panels(axes, run, colours, ["ball", "peg"], M * 9.81)
axes[2].axhline(threshold, color="k", ls=":", lw=0.8)
fig.suptitle("tippe top with its peg: ball (tan), both (violet), peg (blue) on the floor")
fig.tight_layout()
fig.savefig(out / "tippe_top_peg.png", dpi=100)
print(f"wrote {out / 'tippe_top_peg.png'}")
