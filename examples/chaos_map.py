"""Where a heavy top is chaotic
============================

Where a heavy top is chaotic: the largest Lyapunov exponent over the position of the
centre of mass, for a body with I1 = 2 I3 = I2 (Kovalevskaya's ratios, K-top at com_z = 0)
and a slightly asymmetric one, from a sweep of 2 x 13 x 13 tops. Writes chaos_map.png.

    python examples/chaos_map.py [OUT]
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

import kreisel
from kreisel import plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
spec = {
    "top": {"kind": "heavy", "I1": 2.0, "I3": 1.0, "m": 1.0, "g": 1.0},
    "state": {"theta": 1.0, "phi_dot": 0.3, "psi_dot": 1.0},
    "simulation": {"t_end": 150.0, "rtol": 1e-9},
    "grid": {
        "I2": [2.0, 1.9],
        "com_x": {"start": 0.0, "stop": 0.6, "num": 13},
        "com_z": {"start": 0.0, "stop": 0.6, "num": 13},
    },
    "output": {"keep": ["lyapunov", "energy_drift"], "chunk": 26},
}
ds = kreisel.sweep(spec, progress=False)

fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
for ax, i2 in zip(axes, (2.0, 1.9)):
    plot.sweep(ds, "lyapunov", ax, x="com_x", y="com_z", I2=i2)
    ax.set_title(f"I2 = {i2}: largest Lyapunov exponent (1/s) over 150 s")
fig.suptitle(
    "heavy top I1 = 2, I3 = 1 from theta = 1 rad: integrable on the axes (Lagrange at com_x = 0;\n"
    "Kovalevskaya at com_z = 0 when I2 = 2; Euler at the origin), chaotic between"
)
fig.savefig(out / "chaos_map.png", dpi=110)
print(f"wrote {out / 'chaos_map.png'}")
