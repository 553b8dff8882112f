"""Figures of the quantum symmetric top (kreisel.quantum): a Stark map, a rotational spectrum,
and the semiclassical (EBK) levels of the classical top beside the quantum ones. matplotlib is
imported only when a figure is made.

Every function draws into ``ax`` (or ``fig``) when given one and returns what it drew into.
Energies and strengths are shown in units of the rotational constant ``B = hbar^2 / (2 I1)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._plot_base import _pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .quantum import Spectrum, StarkMap, SymmetricTop


def stark_map(smap: StarkMap, top: SymmetricTop, ax: Axes | None = None) -> Axes:
    """The levels of a :class:`~kreisel.quantum.StarkMap` against the field: ``E / B`` over
    ``-P / B`` (= mu E / B for a dipole mu in a field E), one colour per field-free J, solid
    for K M >= 0 and dashed for K M < 0 (blocks (K, M) and (-K, -M) coincide and are drawn once).

    Parameters
    ----------
    smap : StarkMap
        From ``top.stark_map(J, strength)``.
    top : SymmetricTop
        The top of the map (for B).
    """
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 5))
    b = top.energy_scale
    x = -np.asarray(smap.strength) / b
    order = np.argsort(x)
    seen = set()
    for (k, m), levels in smap.blocks.items():
        if (-k, -m) in seen:
            continue
        seen.add((k, m))
        j0 = max(abs(k), abs(m))
        for i in range(levels.shape[1]):
            ax.plot(x[order], levels[order, i] / b, color=f"C{j0 + i}", lw=0.9,
                    ls="-" if k * m >= 0 else "--")  # fmt: skip
    for j in range(smap.J + 1):
        ax.plot([], [], color=f"C{j}", label=f"J = {j} at zero field")
    ax.set_xlabel(r"field $-P/B = \mu E / B$")
    ax.set_ylabel(r"energy $E / B$")
    ax.legend(loc="lower left", fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def spectrum(spec: Spectrum, ax: Axes | None = None, *, unit: str = "GHz") -> Axes:
    """A stick spectrum of a :class:`~kreisel.quantum.Spectrum`: the relative intensity of
    every line against its frequency (``unit`` "MHz", "GHz" or "THz"); the K components of a
    rigid top coincide and are summed into one stick."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5))
    scale = {"MHz": 1e6, "GHz": 1e9, "THz": 1e12}[unit]
    f = np.asarray(spec.frequency)
    order = np.argsort(f)
    f, inten = f[order], np.asarray(spec.intensity)[order]
    # lines within 1e-9 of each other are one (round-off of E(J+1, K) - E(J, K))
    group = np.concatenate([[0], np.cumsum(np.diff(f) > 1e-9 * f[1:])]) if len(f) else f
    total = np.bincount(group.astype(int), weights=inten) if len(f) else inten
    freq = f[np.unique(group, return_index=True)[1]] if len(f) else f
    if len(f):
        total /= total.max()
    ax.vlines(freq / scale, 0.0, total, color="C0", lw=1.5)
    ax.set_xlabel(f"frequency ({unit})")
    ax.set_ylabel("relative intensity")
    ax.set_ylim(0, 1.08)
    ax.set_title(f"T = {spec.temperature:g} K", fontsize=9, loc="right")
    ax.grid(alpha=0.3)
    return ax


def classical_vs_quantum(
    top: SymmetricTop,
    K: int,
    M: int,
    strength: float,
    *,
    n_max: int = 30,
    fig: Figure | None = None,
) -> Figure:
    """The quantum levels of one (K, M) block beside the semiclassical (EBK) levels of the
    classical Lagrange top with the same Mz = M hbar, M3 = K hbar (left, ``E / B`` over J), and
    their relative difference ``|E_EBK - E_quantum| / (E_quantum + |P|)`` on log scales (right),
    with the free top's ``1 / (4 J (J+1))`` for comparison, for the lowest ``n_max`` + 1 levels
    (J_max raised until they are converged). ``fig`` may be a figure or a subfigure.
    """
    plt = _pyplot()
    if fig is None:
        fig = plt.figure(figsize=(10, 4.2), layout="constrained")
    left, right = fig.subplots(1, 2)
    b = top.energy_scale
    j0 = max(abs(K), abs(M))
    n = np.arange(n_max + 1)
    js = j0 + n
    j_max = int(js[-1]) + 40
    q = top.levels(K, M, j_max, strength)[: n_max + 1]
    while not top.convergence(K, M, j_max, strength).converged(n_max + 1):
        j_max += max(20, j_max // 2)
        q = top.levels(K, M, j_max, strength)[: n_max + 1]
    e = np.array([top.ebk_levels(K, M, int(i), strength) for i in n])
    left.plot(js, q / b, "o", ms=4, mfc="none", color="C0", label="quantum")
    left.plot(js, e / b, "x", ms=4, color="C3", label="EBK (classical actions)")
    left.set_xlabel("J (the level's field-free J)")
    left.set_ylabel(r"energy $E / B$")
    left.set_title(f"(K, M) = ({K}, {M}), P = {strength / b:g} B", fontsize=9)
    left.legend(loc="upper left", fontsize=8)
    left.grid(alpha=0.3)
    rel = np.abs(e - q) / (q + abs(strength))
    ok = js > 0
    right.loglog(js[ok], rel[ok], "o-", ms=3, color="C3", label="EBK vs quantum")
    right.loglog(js[ok], 1 / (4 * js[ok] * (js[ok] + 1.0)), color="0.5", ls="--",
                 label=r"free top: $1/(4J(J+1))$")  # fmt: skip
    right.set_xlabel("J")
    right.set_ylabel("relative difference")
    right.legend(loc="lower left", fontsize=8)
    right.grid(alpha=0.3, which="both")
    return fig
