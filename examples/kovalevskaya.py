"""The Kovalevskaya top and its four integrals
===========================================

Figure: the Kovalevskaya top, integrated with the 6th-order splitting, and how well its
four integrals are kept.

    python examples/kovalevskaya.py [OUT_DIR]

I1 = I2 = 2e-3, I3 = 1e-3 kg m^2, m = 0.5 kg, centre of mass 2 cm from the pivot in the
equatorial plane; from q = (1, 0.2, 0, 0), omega = (1, -2, 3) rad/s; 20 s at dt = 1 ms.
Writes kovalevskaya.png.
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
top = kreisel.HeavyTop(I1=2e-3, I2=2e-3, I3=1e-3, m=0.5, com=[0.02, 0.0, 0.0])
st = top.state_from_quaternion([1.0, 0.2, 0.0, 0.0], omega=[1.0, -2.0, 3.0])
run = kreisel.simulate(top, st, 20.0, method="splitting6", dt=1e-3, t_eval=np.linspace(0, 20, 4001))
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 4.5))
kreisel.plot.axis_path_phi_theta(run, ax=ax1)
ax1.set_title("figure axis in the (phi, theta) plane")
kreisel.plot.invariant_drift(run, ax=ax2)
fig.suptitle(f"{top.kind} top, splitting6 at dt = 1 ms")
fig.tight_layout()
fig.savefig(out / "kovalevskaya.png", dpi=100)
print(f"wrote {out / 'kovalevskaya.png'}")
