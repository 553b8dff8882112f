"""Writes the two synthetic recordings the fitting tutorials read.

    python docs/tutorials/data/make_examples.py

They are made by kreisel itself (a simulation plus Gaussian noise), not measured: they stand
for what phyphox and Tracker export, in the layout each tool writes (see the API page of
kreisel.io for where those layouts come from).

- wheel_gyroscope.csv: phyphox's "Raw Data" export of its gyroscope experiment (comma, decimal
  point), a phone taped to the rim side of a bicycle wheel spinning on one end of its axle
  (a heavy symmetric top, axle horizontal at the start), 100 Hz for 10 s, 0.02 rad/s noise;
  the phone's axes turned against the wheel's by the rotation vector (0.05, -0.03, 0.6) rad.
- top_from_above.txt: Tracker's data export (tab, decimal point) of a mark on the crown of a
  toy top, 5 cm from its tip along the axis, filmed from above at 60 frames/s for 2 s; x, y in
  cm with Tracker's origin on the tip, 1 mm noise, two frames without a mark.
"""

from __future__ import annotations

import pathlib

import numpy as np

import kreisel
from kreisel._fit_model import rotation_matrix

HERE = pathlib.Path(__file__).resolve().parent

WHEEL = dict(I1=0.17, I3=0.18, m=2.0, l=0.2)  # kg m^2 about the pivot, kg, m
WHEEL_STATE = dict(theta=np.pi / 2, phi_dot=1.1, psi_dot=20.0)
PHONE = np.array([0.05, -0.03, 0.6])

TOP = dict(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04)
TOP_STATE = dict(theta=0.6, psi_dot=300.0)
MARK = 0.05


def sci(x: float) -> str:
    """Java's DecimalFormat("0.000000000E0"), as both tools write unformatted numbers."""
    if np.isnan(x):
        return "NaN"
    mantissa, exponent = f"{x:.9E}".split("E")
    return f"{mantissa}E{int(exponent)}"


def wheel(rng) -> None:
    top = kreisel.LagrangeTop(**WHEEL)
    t = np.arange(1000) / 100.0 + 0.0031  # phyphox's clock starts when the sensor does
    run = kreisel.simulate(top, top.state(**WHEEL_STATE), t[-1], t_eval=t)
    w = run.omega @ rotation_matrix(PHONE) + rng.normal(0.0, 0.02, (len(t), 3))
    names = ["Time (s)", "Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)",
             "Absolute (rad/s)"]  # fmt: skip
    lines = [",".join(f'"{n}"' for n in names)]
    for ti, wi in zip(t, w):
        lines.append(",".join(sci(v) for v in (ti, *wi, float(np.linalg.norm(wi)))))
    (HERE / "wheel_gyroscope.csv").write_text("\n".join(lines) + "\n")


def top_from_above(rng) -> None:
    top = kreisel.LagrangeTop(**TOP)
    t = np.arange(120) / 60.0
    run = kreisel.simulate(top, top.state(**TOP_STATE), t[-1], t_eval=t)
    st, sp, cp = np.sin(run.theta), np.sin(run.phi), np.cos(run.phi)
    xy = 100 * MARK * np.stack([st * sp, -st * cp], axis=1) + rng.normal(0.0, 0.1, (len(t), 2))
    lines = ["crown_mark", "t\tx\ty"]
    for i, (ti, (x, y)) in enumerate(zip(t, xy)):
        cells = [sci(ti)] + (["", ""] if i in (37, 38) else [sci(x), sci(y)])
        lines.append("\t".join(cells))
    (HERE / "top_from_above.txt").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    rng = np.random.default_rng(26)
    wheel(rng)
    top_from_above(rng)
