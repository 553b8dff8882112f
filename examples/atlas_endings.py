"""Where simulated play tops end, over the atlas
=============================================

Figure: where simulated play tops end, drawn over the (alpha, gamma) atlas.

    python examples/atlas_endings.py [OUT_DIR | OUT.png] [--full]

Tops of mass 20 g with a tip sphere of radius 2 cm, C = 0.4 m rho^2 and A = gamma C, are
placed on a grid of the (alpha, gamma) plane, and at small alpha in zones 3 and 8 (right
panel). Each is started three ways: tilted 0.3 rad and spun fast (5 w), nearly hanging
(2.8 rad) and spun (2.5 w), tilted 1.2 rad and spun slowly (1 w), with w = sqrt(m g rho /
C), about 35 rad/s. kreisel.simulate_many runs them all with viscous friction
(kreisel.Viscous: with Coulomb friction a top whose slip dies out rolls on without
dissipation and need not reach a stationary motion) for 400 s (1500 s with weaker friction
at small alpha, where the gravity torque is tiny). Each run is a glyph for the motion it
is in at the end (down triangle: upright, up triangle: hanging, circle: precession or still
moving): green where it is the ending PlayTop.predict gives (final u within 1e-3), red
where it is another stationary motion at the same J (a contradiction), orange where the
top has not settled yet, grey where the prediction left two endings open. By default a
sixth of the grid is run (a few seconds); --full runs it all (about 20 s). Writes
atlas_endings.png (into kreisel-out/ unless a folder or a file name is given).
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import kreisel
import kreisel.plot as kp

M, RHO = 0.02, 0.02
C = 0.4 * M * RHO**2
W = np.sqrt(M * 9.81 * RHO / C)
STARTS = ((0.3, 5.0), (2.8, 2.5), (1.2, 1.0))  # (theta, spin in units of W)
OFFSETS = (-1.0, 0.0, 1.0)
MAIN = [(a, g) for a in np.arange(0.1, 1.0, 0.12) for g in np.arange(0.55, 1.9, 0.15)]
SMALL = [(0.015, 0.99), (0.03, 0.985), (0.05, 0.965), (0.02, 0.9), (0.04, 0.84), (0.05, 0.9)]
COLOURS = {"ok": "#1e8449", "elsewhere": "#c0392b", "unsettled": "#f39c12", "open": "0.55"}


def run(tops_ag, mu, t_end):
    tops, states, preds = [], [], []
    for a, g in tops_ag:
        pt = kreisel.PlayTop(m=M, A=g * C, C=C, s=a * RHO, rho=RHO, friction=kreisel.Viscous(mu))
        for th, k in STARTS:
            st = pt.state(theta=th, psi_dot=k * W)
            tops.append(pt)
            states.append(st)
            preds.append(pt.predict(st))
    out = kreisel.simulate_many(tops, states, t_end, rtol=1e-9)
    rows = []
    for i, (pt, p) in enumerate(zip(tops, preds)):
        u = out.final_u[i]
        kind = "upright" if u > 1 - 1e-3 else "hanging" if u < -1 + 1e-3 else "precession"
        near = [m for m in pt.stationary_motions(p.J) if abs(m.u - u) < 1e-3]
        if p.ending is None:
            verdict = "open"
        elif abs(u - p.ending.u) < 1e-3:
            verdict = "ok"
        else:
            verdict = "elsewhere" if near else "unsettled"
        rows.append((pt.alpha, pt.gamma, i % len(STARTS), kind, verdict, out.errors[i]))
    return rows


def draw(ax, rows, dx):
    marks = {"upright": "v", "hanging": "^", "precession": "o"}
    for a, g, j, kind, verdict, _err in rows:
        ax.plot(a + OFFSETS[j] * dx, g, marker=marks[kind], ms=6, mfc=COLOURS[verdict],
                mec="k", mew=0.4, ls="none", zorder=6)  # fmt: skip


def main(argv=None) -> pathlib.Path:
    # the script's arguments (none in a notebook, whose kernel has its own)
    argv = (sys.argv[1:] if "ipykernel" not in sys.modules else []) if argv is None else argv
    full = "--full" in argv
    paths = [a for a in argv if a != "--full"]
    out = pathlib.Path(paths[0]) if paths else pathlib.Path("kreisel-out")
    if out.suffix != ".png":
        out = out / "atlas_endings.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    rows = run(MAIN if full else MAIN[::6], 0.1, 400.0)
    small = run(SMALL if full else SMALL[::3], 0.05, 1500.0)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(17, 7.5), layout="constrained",
                                  gridspec_kw={"width_ratios": [1.35, 1]})  # fmt: skip
    kp.atlas(ax=ax, inset=False)
    kp.atlas(ax=ax2, small_alpha=True)
    draw(ax, rows, 0.018)
    draw(ax2, small, 0.0015)
    handles = [ax.plot([], [], m, mfc="w", mec="k", ls="none")[0] for m in ("v", "^", "o")] + [
        ax.plot([], [], "s", color=c, ls="none")[0] for c in COLOURS.values()
    ]
    labels = ["ends upright", "ends hanging", "ends precessing (or still moving)",
              "as predicted", "in another stationary motion", "not settled at the end",
              "two endings open"]  # fmt: skip
    ax2.legend(handles, labels, loc="lower left", fontsize=8.5, framealpha=0.95,
               title="simulated runs", title_fontsize=8.5)  # fmt: skip
    every = rows + small
    count = {v: sum(r[4] == v for r in every) for v in COLOURS}
    n_err = sum(r[5] is not None for r in every)
    fig.suptitle(
        f"Simulated endings over the atlas (viscous friction, {len(every)} runs, {n_err} "
        f"failed): {count['ok']} as predicted, {count['elsewhere']} elsewhere, "
        f"{count['unsettled']} not settled, {count['open']} with two endings open"
    )
    fig.savefig(out, dpi=120)
    print(", ".join(f"{k}: {v}" for k, v in count.items()))
    print(f"wrote {out}")
    return out


if __name__ == "__main__":
    main()
