"""Which tippe tops turn over (a sweep)
====================================

Which tippe tops turn over: a sweep of 552 runs over the centre-of-mass offset s and the
spin (the sweep of examples/tippe_inversion_map.toml), into a Zarr store. Writes
tippe_inversion_map.png: the inversion time over (psi_dot, s), blank where the top does not
turn over within 5 s, and the final u.

    python examples/tippe_inversion_map.py [OUT]
"""

import shutil
import sys
from pathlib import Path

import matplotlib.pyplot as plt

import kreisel
from kreisel import plot

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
# the sweep of examples/tippe_inversion_map.toml (`kreisel sweep` reads that file), here as
# tables so that the script runs on its own
spec = {
    "top": {"kind": "play", "m": 0.02, "A": 2.56e-6, "C": 3.2e-6, "rho": 0.02,
            "friction": "viscous", "mu": 1.0},
    "state": {"theta": 3.0416},  # pi - 0.1: hanging, tilted a little
    "simulation": {"t_end": 5.0, "rtol": 1e-8},
    "grid": {"s": {"start": 0.001, "stop": 0.012, "num": 23},
             "psi_dot": {"start": 30.0, "stop": 250.0, "scale": "log", "num": 24}},
    "output": {"keep": ["final_u", "final_mode", "inversion_time", "jellett_drift",
                        "energy_drift"], "chunk": 48},
}  # fmt: skip
store = out / "tippe_inversion_map.zarr"
shutil.rmtree(store, ignore_errors=True)  # a fresh sweep (the same store would be resumed)
ds = kreisel.sweep(spec, store, progress=False)

fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
plot.sweep(ds, "inversion_time", a, x="psi_dot", y="s")
plot.sweep(ds, "final_u", b, x="psi_dot", y="s")
for ax in (a, b):
    ax.set_xscale("log")
pt = kreisel.PlayTop(0.02, 2.56e-6, 3.2e-6, 0.006, 0.02)
fig.suptitle(
    f"tippe top, C = 0.4 m rho^2, A = 0.8 C (gamma = {pt.gamma:.3g}), viscous friction: "
    f"{int((ds.final_u > 0.9).sum())} of {ds.final_u.size} end upright (u > 0.9)"
)
fig.savefig(out / "tippe_inversion_map.png", dpi=110)
print(f"wrote {out / 'tippe_inversion_map.png'}")
