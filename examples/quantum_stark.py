"""The quantum symmetric top: Stark map, spectrum and the classical bridge
=======================================================================

Figure: a symmetric-top molecule in an electric field and the classical top behind it.

    python examples/quantum_stark.py [OUT_DIR]

Left: the Stark map of CH3F-like levels J <= 2 (energies and the field mu E in units of the
rotational constant B): the K M != 0 levels move linearly (first-order Stark effect), the K M = 0
ones quadratically, and in strong fields all of them fall into the pendular states. Middle: the
pure rotational spectrum of CH3F (A = 155352.7 MHz, B = 25536.15 MHz) at 300 K. Right: the
quantum levels of one (K, M) block of a top in the potential P cos(theta) against the
semiclassical (EBK) levels from the actions of the classical Lagrange top, and their relative
difference falling with J. Writes quantum_stark.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel.plot
from kreisel.quantum import SymmetricTop

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
top = SymmetricTop.from_constants(A=155352.7, B=25536.15, unit="MHz")  # CH3F
b = top.energy_scale
smap = top.stark_map(J=2, strength=-b * np.linspace(0.0, 12.0, 121))

fig = plt.figure(figsize=(15, 4.6), layout="constrained")
left, middle, right = fig.subfigures(1, 3, width_ratios=[1.0, 1.0, 2.0])
kreisel.plot.stark_map(smap, top, ax=left.subplots())
left.suptitle(f"Stark map, J <= 2 (basis J <= {smap.convergence.J_max}, converged)", fontsize=10)
kreisel.plot.spectrum(top.spectrum(J_max=40, temperature=300.0), ax=middle.subplots())
middle.suptitle("CH3F, pure rotational spectrum", fontsize=10)
unit_top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
kreisel.plot.classical_vs_quantum(unit_top, K=1, M=1, strength=-40.0, n_max=40, fig=right)
right.suptitle("quantum vs semiclassical (EBK) levels", fontsize=10)
fig.savefig(out / "quantum_stark.png", dpi=90)
print(f"wrote {out / 'quantum_stark.png'}")
