"""Figures of the play top's stationary motions: the (alpha, gamma) atlas of the eight zones,
the vertical-axis diagram and J_R(u). matplotlib is imported only when a figure is made.

Source: Rauch-Wojciechowski, Skoldstam and Glad, Regul. Chaotic Dyn. 10 (2005) 333; zone
numbers as on the theory page (play top). Every function draws into ``ax`` when given one and
returns the axes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import numpy as np

from . import _atlas
from ._plot_base import _pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ._play import PlayTop

# One colour per zone (light enough for labels and curves on top).
ZONE_COLOURS = {
    1: "#cfe3f5",
    2: "#f6cfd8",
    3: "#fbe3b8",
    4: "#d7ecc9",
    5: "#e6d6f2",
    6: "#fff2a8",
    7: "#cdeee9",
    8: "#f2d0b5",
}
_TYPE = {1: "Ia", 2: "Ib", 3: "IIa", 4: "IIa", 5: "IIa", 6: "IIa", 7: "IIb", 8: "IIb"}
LENS_TIP = 7.0 - 4.0 * np.sqrt(3.0)  # where the closed curve u_m = 1 ends (on gamma = 1 - alpha)

_CURVES = [
    # key, label, style
    ("1+alpha", r"$\gamma = 1 + \alpha$", dict(color="k", lw=1.4)),
    ("1-alpha^2", r"$\gamma = 1 - \alpha^2$", dict(color="#1f3a93", lw=1.4)),
    ("1-alpha", r"$\gamma = 1 - \alpha$", dict(color="k", lw=1.2, ls="--")),
    ("u_m=1", r"$u_m = 1$", dict(color="#b03a2e", lw=1.2, ls="-.")),
    ("u_m=-1", r"$u_m = -1$", dict(color="#7d3c98", lw=1.2, ls="-.")),
    ("J_R(1)=J_R(-1)", r"$J_R(1) = J_R(-1)$", dict(color="#117a65", lw=1.4, ls=":")),
]


def _alpha_grid(a_max):
    # Dense everywhere, denser where the closed curve u_m = 1 lives.
    a = np.concatenate(
        [
            LENS_TIP * (1 - np.cos(np.linspace(0, np.pi / 2, 1500))),
            np.linspace(0, a_max, 3000),
        ]
    )
    a = np.unique(np.clip(a, 1e-6, a_max))
    return a


def _zone_bands(a, y_lo, y_hi):
    """For each zone, the band lower(alpha) < gamma < upper(alpha) it fills (nan where the
    zone is absent), from the exact boundary curves."""
    b = _atlas.zone_boundaries(a)
    lp, lm, l1 = b["1+alpha"], b["1-alpha"], b["1-alpha^2"]
    ulo, uhi, um, eq = b["u_m=1 lower"], b["u_m=1 upper"], b["u_m=-1"], b["J_R(1)=J_R(-1)"]
    lens = np.isfinite(ulo)
    nan = np.full_like(a, np.nan)
    top, bot = np.full_like(a, y_hi), np.full_like(a, y_lo)
    iia_top = np.where(np.isfinite(um), um, l1)  # top of zones 4 and 5 when there is no 6
    bands = {
        2: (np.maximum(lp, bot), top),
        1: (np.maximum(l1, bot), np.minimum(lp, top)),
        6: (np.where(np.isfinite(um), um, nan), np.where(np.isfinite(um), l1, nan)),
        5: (eq, iia_top),
        4: (np.where(lens, np.maximum(lm, uhi), lm), np.where(np.isfinite(eq), eq, nan)),
        3: (np.where(lens, np.maximum(lm, ulo), nan), np.where(lens, uhi, nan)),
        8: (np.where(lens, ulo, nan), np.where(lens, np.minimum(lm, uhi), nan)),
        7: (bot, np.where(lens, np.minimum(ulo, lm), np.minimum(lm, l1))),
    }
    return bands


def _draw_plane(ax, a_max, y_lo, y_hi, *, legend):
    a = _alpha_grid(a_max)
    bands = _zone_bands(a, y_lo, y_hi)
    for z, (lo, hi) in bands.items():
        lo, hi = np.clip(lo, y_lo, y_hi), np.clip(hi, y_lo, y_hi)
        ok = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        ax.fill_between(a, lo, hi, where=ok, color=ZONE_COLOURS[z], lw=0, zorder=0,
                        interpolate=True)  # fmt: skip
    b = _atlas.zone_boundaries(a)
    b["u_m=1"] = np.concatenate([b["u_m=1 lower"], b["u_m=1 upper"][::-1]])
    for key, label, style in _CURVES:
        x = np.concatenate([a, a[::-1]]) if key == "u_m=1" else a
        ax.plot(x, b[key], label=label if legend else None, zorder=2, **style)
    # gamma < 1/2 means C > 2A: no rigid body.
    ax.axhspan(y_lo, 0.5, facecolor="white", edgecolor="0.6", hatch="///", lw=0, zorder=1,
               alpha=0.85)  # fmt: skip
    ax.set_xlim(0, a_max)
    ax.set_ylim(y_lo, y_hi)
    return a, bands


def _label_point(a, lo, hi, x_range, y_range):
    """Where a zone's band is widest on the plot (in axes units), and its middle there."""
    lo = np.where(np.isfinite(lo), lo, np.nan)
    inside = (a > x_range[0]) & (a < x_range[1])
    h = np.clip(hi, *y_range) - np.clip(lo, *y_range)
    h = np.where(inside & np.isfinite(h), h / (y_range[1] - y_range[0]), -1)
    i = int(np.argmax(h))
    return a[i], 0.5 * (np.clip(lo[i], *y_range) + np.clip(hi[i], *y_range))


def _mark_top(ax, pt, *, label=True):
    c = pt.classify()
    ax.plot(pt.alpha, pt.gamma, marker="*", ms=16, mfc="#e74c3c", mec="k", mew=0.8, ls="none",
            zorder=5, label=f"this top: zone {c.zone} ({c.type})" if label else None)  # fmt: skip


SMALL_ALPHA = (0.08, (0.72, 1.01))  # the enlarged region of zones 3 and 8: alpha, gamma


def _small_alpha_panel(ax, pt, *, main):
    """Zones 3 and 8 (and slivers of 1, 4-7) at alpha <= 0.08, into ``ax``."""
    a_max, (y_lo, y_hi) = SMALL_ALPHA
    _draw_plane(ax, a_max, y_lo, y_hi, legend=main)
    fs = 12 if main else 10
    for z, spot in {3: (0.012, 0.975), 8: (0.02, 0.86), 7: (0.065, 0.78),
                    4: (0.074, 0.965)}.items():  # fmt: skip
        ax.annotate(str(z), spot, ha="center", va="center", fontsize=fs, fontweight="bold",
                    zorder=4)  # fmt: skip
    ax.annotate("1, 5, 6: thin bands\nup to $\\gamma = 1-\\alpha^2$", (0.055, 0.996),
                xytext=(0.041, 0.905), fontsize=fs - 2.5, zorder=4,
                arrowprops=dict(arrowstyle="->", lw=0.6))  # fmt: skip
    if pt is not None and pt.alpha <= a_max and y_lo <= pt.gamma <= y_hi:
        _mark_top(ax, pt, label=main)


def atlas(
    pt: PlayTop | None = None,
    ax: Axes | None = None,
    *,
    small_alpha: bool = False,
    inset: bool = True,
) -> Axes:
    """The (alpha, gamma) plane of play tops: zones 1-8 shaded and labelled, every boundary
    curve drawn exactly, and ``pt`` (a PlayTop) marked.

    The boundaries are the lines gamma = 1 +- alpha, the parabola gamma = 1 - alpha^2, the
    curves u_m = 1 (closed, alpha < 7 - 4 sqrt 3), u_m = -1 and J_R(1) = J_R(-1) in closed
    form. Zones 3 and 8 lie at alpha < 0.072: they are shown in an enlarged inset, or alone
    with ``small_alpha=True``. gamma < 1/2 (C > 2A) is hatched: no rigid body has it.
    Source: theory: the atlas of play tops.
    """
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(9, 7))
    legend = dict(fontsize=8.5, framealpha=0.95, title_fontsize=8.5,
                  title="types: Ia = 1, Ib = 2, IIa = 3-6, IIb = 7, 8")  # fmt: skip
    ax.set_ylabel(r"$\gamma = A/C$  (equatorial over axial moment of inertia)")
    if small_alpha:
        _small_alpha_panel(ax, pt, main=True)
        ax.set_xlabel(r"$\alpha = s/\rho$")
        ax.set_title("Play tops at small alpha: zones 3 and 8")
        ax.legend(loc="lower right", **legend)
        return ax
    y_lo, y_hi = 0.4, 2.3
    a, bands = _draw_plane(ax, 1.2, y_lo, y_hi, legend=True)
    spots = {2: (0.75, 2.05), 1: (0.95, 1.55), 7: (0.16, 0.62)}
    # Zones 4-6 are labelled where their bands are widest, away from the marked top.
    away = np.ones_like(a, dtype=bool)
    if pt is not None:
        away = np.abs(a - pt.alpha) > 0.05
    for z in (4, 5, 6):
        lo, hi = bands[z]
        spots[z] = _label_point(a[away], lo[away], hi[away], (0.15, 0.62), (0.5, y_hi))
    for z, spot in spots.items():
        ax.annotate(str(z), spot, ha="center", va="center", fontsize=12 if z in (1, 2, 7) else 10,
                    fontweight="bold", zorder=4)  # fmt: skip
    ax.text(0.01, 0.45, "C > 2A: no rigid body", ha="left", va="center", fontsize=8,
            color="0.3", zorder=4, bbox=dict(fc="white", ec="none", pad=1))  # fmt: skip
    if pt is not None:
        _mark_top(ax, pt)
    ax.set_xlabel(r"$\alpha = s/\rho$  (height of the centre of mass over the tip's centre, "
                  "in tip radii)")  # fmt: skip
    ax.set_title("Play tops by the stability of their stationary motions: zones 1-8")
    ax.legend(loc="upper left", **legend)
    if inset:
        ins = ax.inset_axes((0.6, 0.11, 0.38, 0.39))
        _small_alpha_panel(ins, pt, main=False)
        ins.set_xlabel(r"$\alpha$", fontsize=8, labelpad=1)
        ins.set_ylabel(r"$\gamma$", fontsize=8, labelpad=1)
        ins.tick_params(labelsize=7)
        ins.set_title("zones 3 and 8 (small alpha), enlarged", fontsize=8)
        ax.indicate_inset_zoom(ins, edgecolor="0.3")
    return ax


def vertical_axis_diagram(
    pt: PlayTop | None = None,
    ax: Axes | None = None,
    *,
    x_max: float = 2.0,
    y_max: float = 2.6,
) -> Axes:
    """Stability of spins about a vertical figure axis: C/A against h/rho, where h is the
    height of the centre of mass above the floor (upright: h/rho = 1 + alpha; hanging:
    1 - alpha). The line h/rho = 1 and the hyperbola h/rho = A/C split it into the areas of
    the vertical-axis diagram (theory: the atlas of play tops): (a) 1 < h/rho <= A/C,
    (b) A/C <= h/rho < 1, (c) the rest. ``pt`` (a PlayTop) is marked at its upright and
    hanging positions.
    """
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.5, 6))
    x = np.linspace(1e-3, x_max, 2000)
    hyp = 1.0 / x
    one = np.ones_like(x)
    ax.fill_between(x, one, np.minimum(hyp, y_max), where=hyp > 1, color="#f6cfd8", lw=0,
                    label="(a) upright spin always unstable")  # fmt: skip
    ax.fill_between(x, hyp, one, where=hyp < 1, color="#d9e4a6", lw=0,
                    label="(b) hanging spin always stable")  # fmt: skip
    ax.fill_between(x, np.maximum(hyp, one), y_max, color="#cfd8e3", lw=0,
                    label="(c) upright spin stable when fast")  # fmt: skip
    ax.fill_between(x, 0, np.minimum(hyp, one), color="#f8d9b0", lw=0,
                    label="(c) hanging spin stable when slow")  # fmt: skip
    ax.plot(x, hyp, color="k", lw=1.4)
    ax.axhline(1.0, color="k", lw=1.4)
    ax.annotate(r"$h/\rho = A/C$", (0.55, 1 / 0.55), xytext=(0.75, 2.3), fontsize=10,
                arrowprops=dict(arrowstyle="->", lw=0.8))  # fmt: skip
    ax.text(1.97, 1.03, r"$h/\rho = 1$", ha="right", va="bottom", fontsize=10)
    for t, (xx, yy) in {"a": (0.72, 1.17), "b": (1.6, 0.8), "c": (1.3, 1.8)}.items():
        ax.text(xx, yy, t, fontsize=16, fontweight="bold", ha="center", va="center")
    ax.text(0.45, 0.45, "c", fontsize=16, fontweight="bold", ha="center", va="center")
    if pt is not None:
        x0 = 1.0 / pt.gamma
        up, down = 1 + pt.alpha, max(1 - pt.alpha, 0.0)
        ax.plot([x0, x0], [down, up], color="#c0392b", lw=1.0, ls=":")
        ax.plot([x0], [up], marker="v", ms=11, color="#c0392b", ls="none",
                label=f"this top upright, h/rho = {up:.3g}")  # fmt: skip
        area = pt.classify().fig3
        ax.plot([x0], [down], marker="^", ms=11, color="#c0392b", mfc="white", ls="none",
                label=f"this top hanging, h/rho = {down:.3g} (a top of area {area})")  # fmt: skip
    ax.set_xlim(0, x_max)
    ax.set_ylim(0, y_max)
    ax.set_xlabel("C/A  (axial over equatorial moment of inertia)")
    ax.set_ylabel(r"$h/\rho$  (height of the centre of mass over the tip radius)")
    ax.set_title("Spin about a vertical figure axis (vertical-axis diagram)")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.95)
    return ax


def J_R_plot(pt: PlayTop, J: float | None = None, ax: Axes | None = None, *, n: int = 2001) -> Axes:
    """J_R(u)/J_beta, the ``|J|`` of the regular precession at each inclination u = cos(theta):
    stable branches (dJ_R/du > 0) solid, unstable dashed; J_R(+-1) and u_m marked; and, for
    a given J (kg m^2/s), the line ``|J|`` and its stationary motions, filled where stable:
    circles for precessions, triangles for the vertical spins (down: upright, up: hanging).
    """
    plt = _pyplot()
    if ax is None:
        fig, ax = plt.subplots(figsize=(10, 5.5))
        fig.subplots_adjust(right=0.74)
    jb = pt.J_beta
    u = np.linspace(-1, 1, n)
    jr = pt.J_R(u) / jb
    um = pt.u_m
    stable = np.ones_like(u, dtype=bool) if um is None else u > um
    finite = jr[np.isfinite(jr)]
    ends = [x / jb for x in (pt.J_R(-1.0), pt.J_R(1.0)) if np.isfinite(x)]
    lows = [finite.min()] + ends
    y_top = max(1.6 * max(lows), 2.5 * min(lows))
    if J is not None:
        y_top = max(y_top, abs(J) / jb * 1.3)
    for mask, style, label in (
        (stable, dict(color="C0", lw=2.0), "stable precessions"),
        (~stable, dict(color="C3", lw=2.0, ls="--"), "unstable precessions"),
    ):
        ax.plot(u, np.where(mask, jr, np.nan), label=label, **cast("dict[str, Any]", style))
    for x, name in ((-1.0, r"$J_R(-1)$"), (1.0, r"$J_R(1)$")):
        v = pt.J_R(x) / jb
        if np.isfinite(v):
            ax.plot([x], [v], marker="s", color="0.2", ms=6, ls="none", clip_on=False)
            ax.annotate(f"{name} = {v:.3g}", (x, v), xytext=(-0.75 * x * 40 - 20, 8),
                        textcoords="offset points", fontsize=9)  # fmt: skip
    if um is not None and -1 <= um <= 1:
        v = pt.J_R(um) / jb
        ax.axvline(um, color="0.5", lw=0.8, ls=":")
        ax.annotate(f"$u_m$ = {um:.3g}", (um, v), xytext=(6, -16), textcoords="offset points",
                    fontsize=9)  # fmt: skip
    if J is not None:
        j = abs(J) / jb
        ax.axhline(j, color="k", lw=0.9, label=f"|J| = {j:.3g} $J_\\beta$")
        for m in pt.stationary_motions(J):
            marker = {"upright": "v", "hanging": "^", "precession": "o"}[m.kind]
            face = "k" if m.stable else "white"
            ax.plot([m.u], [j], marker=marker, ms=10, mfc=face, mec="k", ls="none", zorder=5,
                    clip_on=False)  # fmt: skip
        ax.plot([], [], "ko", mfc="k", label="stable at this J (filled)")
        ax.plot([], [], "ko", mfc="white", label="unstable at this J (open)")
        ax.plot([], [], "kv", mfc="0.7", label="upright spin (u = 1)")
        ax.plot([], [], "k^", mfc="0.7", label="hanging spin (u = -1)")
    c = pt.classify()
    ax.set_xlim(-1.02, 1.02)
    ax.set_ylim(0, y_top)
    ax.set_xlabel(r"$u = \cos\theta$  (1: upright, -1: hanging)")
    ax.set_ylabel(r"$J_R(u)\,/\,J_\beta$")
    ax.set_title(
        f"Regular precessions: alpha = {pt.alpha:.3g}, gamma = {pt.gamma:.3g}, zone {c.zone} "
        f"({c.type}); $J_\\beta$ = {jb:.3g} kg m$^2$/s",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8.5, borderaxespad=0)
    return ax
