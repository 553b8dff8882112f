"""Shared by the gallery scripts: where to write, and a non-interactive matplotlib."""

from __future__ import annotations

import pathlib
import sys


def out_dir(argv=None) -> pathlib.Path:
    """The folder given as the first argument, else kreisel-out/ (created)."""
    argv = sys.argv[1:] if argv is None else argv
    out = pathlib.Path(argv[0]) if argv else pathlib.Path("kreisel-out")
    out.mkdir(parents=True, exist_ok=True)
    return out


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def parts_panels(axes, run, colours, names, weight, legend="upper right"):
    """Four panels of a top of several parts against t: the parts touching shaded by
    ``colours`` ({(touching, ...): colour}), u, the normal force of the parts ``names`` (with
    the weight ``weight``), |omega_3|, and the energy with E + dissipated (mJ). Returns the
    axes, for more lines."""
    t, touch = run.t, run.part_in_contact
    for ax in axes:
        for key, colour in colours.items():
            on = (touch[:, : len(key)] == key).all(axis=1)
            ax.fill_between(t, 0, 1, where=on, color=colour, transform=ax.get_xaxis_transform(),
                            linewidth=0)  # fmt: skip
    axes[0].plot(t, run.u, color="k")
    axes[0].set_ylabel("u = cos(theta)")
    for i, name in enumerate(names):
        axes[1].plot(t, run.part_normal_force[:, i], label=name)
    axes[1].axhline(weight, color="grey", lw=0.6)
    axes[1].set_ylabel("normal force (N)")
    axes[1].legend(loc=legend)
    axes[2].plot(t, abs(run.omega[:, 2]), color="k", label="|omega_3|")
    axes[2].set_ylabel("|omega_3| (rad/s)")
    axes[3].plot(t, run.energy * 1e3, color="k", label="E")
    axes[3].plot(t, (run.energy + run.dissipated) * 1e3, color="grey", ls="--",
                 label="E + dissipated")  # fmt: skip
    axes[3].set_ylabel("energy (mJ)")
    axes[3].set_xlabel("t (s)")
    axes[3].legend(loc=legend)
    return axes
