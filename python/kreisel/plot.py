"""Figures (matplotlib, imported only when a figure is made).

Every function draws into ``ax`` when given one and returns the axes it drew into.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._plot_atlas import J_R_plot, atlas, vertical_axis_diagram  # noqa: F401
from ._plot_base import _pyplot
from ._plot_quantum import classical_vs_quantum, spectrum, stark_map  # noqa: F401
from ._plot_sweep import sweep  # noqa: F401

if TYPE_CHECKING:
    from collections.abc import Sequence

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D
    from numpy.typing import ArrayLike, NDArray

    from ._lagrange import LagrangeTop
    from ._state import EulerState
    from ._trajectory import Trajectory


def figure_axis(theta: ArrayLike, phi: ArrayLike) -> NDArray[np.float64]:
    """Unit figure axis e3 in the space frame from Euler angles (z-x-z), shape (n, 3)."""
    theta, phi = np.asarray(theta), np.asarray(phi)
    st = np.sin(theta)
    return np.stack([st * np.sin(phi), -st * np.cos(phi), np.cos(theta)], axis=-1)


def axis_path_on_sphere(
    traj: Trajectory,
    ax: Axes3D | None = None,
    *,
    color: str = "C0",
    label: str | None = None,
    sphere: bool = True,
) -> Axes3D:
    """The path of the figure axis's tip on the unit sphere (3D axes).

    Parameters
    ----------
    traj : Trajectory
        Needs columns ``theta`` and ``phi`` (rad).
    """
    plt = _pyplot()
    if ax is None:
        fig = plt.figure(figsize=(5, 5))
        ax = fig.add_subplot(projection="3d")
    e = figure_axis(traj.theta, traj.phi)
    if sphere:
        uu, vv = np.meshgrid(np.linspace(0, 2 * np.pi, 37), np.linspace(0, np.pi, 19))
        ax.plot_wireframe(
            np.cos(uu) * np.sin(vv),
            np.sin(uu) * np.sin(vv),
            np.cos(vv),
            color="0.85",
            linewidth=0.4,
        )
        ax.plot([0, 0], [0, 0], [-1.1, 1.1], color="0.5", linewidth=0.8, linestyle="--")
    ax.plot(e[:, 0], e[:, 1], e[:, 2], color=color, linewidth=1.0, label=label)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (up)")
    ax.set_box_aspect((1, 1, 1))
    lim = 1.05
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(-lim, lim)
    ticks = [-1.0, -0.5, 0.0, 0.5, 1.0]  # matplotlib's default crowds a small 3D box
    ax.set_xticks(ticks)
    ax.set_yticks(ticks)
    ax.set_zticks(ticks)
    return ax


def axis_path_plan(
    traj: Trajectory, ax: Axes | None = None, *, color: str = "C0", label: str | None = None
) -> Axes:
    """The path of the figure axis's tip seen from above: the unit sphere's (x, y) plane."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5))
    e = figure_axis(traj.theta, traj.phi)
    ax.plot(e[:, 0], e[:, 1], color=color, linewidth=1.0, label=label)
    ax.plot([0], [0], marker="+", color="0.4")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (unit sphere)")
    ax.set_ylabel("y (unit sphere)")
    return ax


def effective_potential(
    top: LagrangeTop, state: EulerState, ax: Axes | None = None, *, n: int = 800
) -> Axes:
    """The effective potential Veff(theta) (J) with the energy line and the turning points."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    inv = top.invariants(state)
    tmin, tmax = top.turning_points(state)
    theta = np.linspace(1e-3, np.pi - 1e-3, n)
    v = np.asarray(top.effective_potential(theta, inv.Mz, inv.M3))
    lo = min(v.min(), inv.E)
    span = max(inv.E - v.min(), 1e-12)
    ax.plot(theta, v, color="C0", label=r"$V_\mathrm{eff}(\theta)$")
    ax.axhline(inv.E, color="C3", linewidth=1, label="energy E")
    for th in (tmin, tmax):
        ax.axvline(th, color="0.5", linestyle=":", linewidth=1)
    ax.set_ylim(lo - 0.2 * span, inv.E + 2.0 * span)
    ax.set_xlabel(r"$\theta$ (rad)")
    ax.set_ylabel("energy (J)")
    ax.legend(loc="upper right")
    return ax


_MODE_COLOURS = {"slip": "#f3d9b1", "roll": "#cfe3f5", "flight": "#d9f0d3"}


def shade_modes(ax: Axes, traj: Trajectory) -> Axes:
    """Shades the contact modes (slip, roll, flight) of a play-top trajectory behind ``ax``:
    the top's ``mode`` (slip where a part slides, roll where parts touch and none slides);
    each part's own state is drawn by :func:`part_states`."""
    t, mode = traj.t, traj.mode
    if len(t) == 0:
        return ax
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or mode[i] != mode[start]:
            end = float(t[min(i, len(t) - 1)])
            ax.axvspan(float(t[start]), end, color=_MODE_COLOURS[str(mode[start])], lw=0,
                       zorder=0)  # fmt: skip
            start = i
    return ax


# Colours of the parts' contact states (``Trajectory.part_modes``): sliding in the tan of
# "slip", rolling and drilling in blues like "roll", flight in the green of "flight".
PART_STATE_COLOURS = {
    "flight": "#d9f0d3",
    "rolling": "#7fb2e0",
    "drilling": "#1f5fa8",
    "sliding": "#e0a050",
    "flat": "#9a9a9a",
}


def part_states(ax: Axes, traj: Trajectory, *, legend: bool = True) -> Axes:
    """One horizontal band per contact part of a play-top trajectory (named on the y axis,
    the first part of the top's ``shape`` at the top), coloured by the part's contact state
    over time (``traj.part_modes``: flight, rolling, drilling, sliding, flat), with a legend
    of the states that occur. Returns ``ax``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from kreisel import plot, simulate
    >>> from kreisel._config import from_tables, preset
    >>> p = from_tables(preset("tippe"))
    >>> run = simulate(p.model, p.state, 2.0, rtol=1e-9)
    >>> ax = plot.part_states(plt.figure().gca(), run)
    >>> [t.get_text() for t in ax.get_yticklabels()]
    ['peg', 'ball']
    >>> sorted(t.get_text() for t in ax.get_legend().get_texts())
    ['drilling', 'flight', 'sliding']
    """
    modes = traj.part_modes
    if not modes:
        return ax
    t = np.asarray(traj.t, dtype=float)
    names = list(modes)
    seen: list[str] = []
    for row, name in enumerate(names):
        y = len(names) - 1 - row
        label = np.asarray(modes[name])
        start = 0
        for i in range(1, len(t) + 1):
            if i == len(t) or label[i] != label[start]:
                end = float(t[min(i, len(t) - 1)])
                state = str(label[start])
                ax.broken_barh([(float(t[start]), end - float(t[start]))], (y - 0.4, 0.8),
                               color=PART_STATE_COLOURS.get(state, "k"), lw=0)  # fmt: skip
                if state not in seen:
                    seen.append(state)
                start = i
    ax.set_yticks(range(len(names)), names[::-1])
    ax.set_ylim(-0.6, len(names) - 0.4)
    if len(t):
        ax.set_xlim(float(t[0]), float(t[-1]))
    if legend and seen:
        from matplotlib.patches import Patch

        order = [s for s in PART_STATE_COLOURS if s in seen]
        ax.legend(handles=[Patch(color=PART_STATE_COLOURS[s], label=s) for s in order],
                  loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8,
                  title="contact state", title_fontsize=8)  # fmt: skip
    return ax


def parts_panels(
    axes: Sequence[Axes],
    traj: Trajectory,
    colours: dict[tuple[bool, ...], str],
    names: Sequence[str],
    weight: float,
    legend: str = "upper right",
) -> Sequence[Axes]:
    """Four panels of a top of several parts against t (a column of four axes, ``axes``):
    u; the normal force of each part in ``names`` with the weight ``weight`` (N) as a line;
    ``|omega_3|``; the energy with E + dissipated (mJ). Behind every panel, the times when
    the parts touch as given by a key of ``colours`` (``{(touching, ...): colour}``, a tuple
    of booleans for the first parts, in the order of the top's ``shape``) are shaded in its
    colour. Returns ``axes``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from kreisel import plot, simulate
    >>> from kreisel._config import from_tables, preset
    >>> p = from_tables(preset("tippe"))
    >>> run = simulate(p.model, p.state, 2.0, rtol=1e-9)
    >>> fig, axes = plt.subplots(4, 1, sharex=True)
    >>> colours = {(True, False): "#fde3c8", (False, True): "#cfe3f5"}
    >>> len(plot.parts_panels(axes, run, colours, ["ball", "peg"], p.model.m * 9.81))
    4
    """
    t, touch = traj.t, traj.part_in_contact
    for ax in axes:
        for key, colour in colours.items():
            on = (touch[:, : len(key)] == key).all(axis=1)
            ax.fill_between(t, 0, 1, where=on, color=colour, transform=ax.get_xaxis_transform(),
                            linewidth=0)  # fmt: skip
    axes[0].plot(t, traj.u, color="k")
    axes[0].set_ylabel("u = cos(theta)")
    for i, name in enumerate(names):
        axes[1].plot(t, traj.part_normal_force[:, i], label=name)
    axes[1].axhline(weight, color="grey", lw=0.6)
    axes[1].set_ylabel("normal force (N)")
    axes[1].legend(loc=legend)
    axes[2].plot(t, abs(traj.omega[:, 2]), color="k", label="|omega_3|")
    axes[2].set_ylabel("|omega_3| (rad/s)")
    axes[3].plot(t, traj.energy * 1e3, color="k", label="E")
    axes[3].plot(t, (traj.energy + traj.dissipated) * 1e3, color="grey", ls="--",
                 label="E + dissipated")  # fmt: skip
    axes[3].set_ylabel("energy (mJ)")
    axes[3].set_xlabel("t (s)")
    axes[3].legend(loc=legend)
    return axes


def play_time_series(traj: Trajectory, fig: Figure | None = None) -> Figure:
    """u, normal force, slip speed, Jellett's integral and the energy over time for a
    play-top trajectory, with the top's contact modes shaded (slip tan, roll blue, flight
    green) and, above, one band per contact part coloured by its state (:func:`part_states`).
    """
    plt = _pyplot()
    if fig is None:
        fig = plt.figure(figsize=(9, 11))
    modes = traj.part_modes
    if modes:
        # a strip of one band per part above the five panels
        ratios = [0.3 + 0.25 * len(modes)] + [1] * 5
        strip, *axes = fig.subplots(6, 1, sharex=True, gridspec_kw={"height_ratios": ratios})
        part_states(strip, traj)
        strip.set_title("each part's contact state", fontsize=9, loc="left")
    else:
        axes = list(fig.subplots(5, 1, sharex=True))
    t = traj.t
    rows = [
        (traj.u, r"$u = \cos\theta$"),
        (traj.normal_force, "normal force N (N)"),
        (traj.slip_speed, "slip speed (m/s)"),
        (traj.jellett / traj.jellett[0] - 1.0, r"$J/J_0 - 1$"),
    ]
    for ax, (y, label) in zip(axes, rows):
        shade_modes(ax, traj)
        ax.plot(t, y, color="C0", lw=1.0)
        ax.set_ylabel(label)
    ax = axes[4]
    shade_modes(ax, traj)
    ax.plot(t, traj.energy, color="C3", lw=1.0, label="energy E")
    ax.plot(t, traj.energy_rotation, color="C1", lw=0.8, label="rotation")
    ax.plot(t, traj.energy_potential - traj.energy_potential.min(), color="C2", lw=0.8,
            label="potential (above its minimum)")  # fmt: skip
    ax.plot(t, traj.energy + traj.dissipated, color="k", lw=0.8, ls="--",
            label="E + dissipated")  # fmt: skip
    ax.set_ylabel("energy (J)")
    ax.set_xlabel("time t (s)")
    ax.legend(loc="center right", fontsize=8)
    for a in axes:
        a.grid(alpha=0.3)
    return fig


# -- rigid tops: time series, the (phi, theta) plane, invariants ---------------------------


def euler_rates(
    traj: Trajectory,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(theta_dot, phi_dot, psi_dot) in rad/s of a rigid-top trajectory: its own columns when
    it has them (exact Lagrange solution), else from the body angular velocity ``omega``.

    From omega: ``theta_dot = w1 cos psi - w2 sin psi``, ``phi_dot = (w1 sin psi + w2 cos psi)
    / sin theta``, ``psi_dot = w3 - phi_dot cos theta`` (z-x-z); phi_dot and psi_dot are nan
    where sin theta < 1e-9 (Euler angles are singular at the vertical).
    """
    cols = traj.columns
    if {"theta_dot", "phi_dot", "psi_dot"} <= set(cols):
        return traj.theta_dot, traj.phi_dot, traj.psi_dot
    w = np.asarray(traj.omega)
    th, ps = np.asarray(traj.theta), np.asarray(traj.psi)
    cp, sp = np.cos(ps), np.sin(ps)
    st = np.sin(th)
    theta_dot = w[:, 0] * cp - w[:, 1] * sp
    with np.errstate(divide="ignore", invalid="ignore"):
        phi_dot = np.where(np.abs(st) > 1e-9, (w[:, 0] * sp + w[:, 1] * cp) / st, np.nan)
    psi_dot = w[:, 2] - phi_dot * np.cos(th)
    return theta_dot, phi_dot, psi_dot


def _lagrange_columns(traj):
    from ._diagnostics import lagrange_columns

    return lagrange_columns(traj)


def _potential(traj):
    """Potential energy m g z_G (J) of a rigid-top trajectory (the core's column), or None."""
    if "potential" in traj.columns:
        return traj.potential
    return None


def rigid_time_series(traj: Trajectory, fig: Figure | None = None) -> Figure:
    """Four panels over time for a top on a pivot: theta (rad); the nutation and precession
    rates (rad/s); the spin rate psi_dot (rad/s); the energy and its potential and kinetic
    parts (J).

    ``traj`` is an exact Lagrange trajectory (``LagrangeTop.exact``) or a simulated one
    (:func:`kreisel.simulate` on a LagrangeTop or HeavyTop).
    """
    plt = _pyplot()
    if fig is None:
        fig = plt.figure(figsize=(9, 8.5))
    axes = fig.subplots(4, 1, sharex=True)
    t = traj.t
    theta_dot, phi_dot, psi_dot = euler_rates(traj)
    axes[0].plot(t, traj.theta, color="C0", lw=1.0)
    axes[0].set_ylabel(r"$\theta$ (rad)")
    axes[1].plot(t, theta_dot, color="C1", lw=1.0, label=r"$\dot\theta$")
    axes[1].plot(t, phi_dot, color="C2", lw=1.0, label=r"$\dot\phi$")
    axes[1].set_ylabel("rates (rad/s)")
    axes[1].legend(loc="upper right", fontsize=8)
    axes[2].plot(t, psi_dot, color="C4", lw=1.0, label=r"$\dot\psi$")
    if "omega" in traj.columns:
        axes[2].plot(t, traj.omega[:, 2], color="k", lw=0.8, ls="--", label=r"$\omega_3$")
    axes[2].set_ylabel("spin (rad/s)")
    axes[2].legend(loc="upper right", fontsize=8)
    lag = _lagrange_columns(traj)
    energy = lag["energy"] if lag is not None else getattr(traj, "energy", None)
    pot = _potential(traj)
    ax = axes[3]
    if energy is not None:
        ax.plot(t, energy, color="C3", lw=1.0, label="energy E")
        if pot is not None:
            ax.plot(t, energy - pot, color="C1", lw=0.8, label="kinetic")
            ax.plot(t, pot, color="C2", lw=0.8, label=r"potential $m g z_G$")
        ax.legend(loc="center right", fontsize=8)
    ax.set_ylabel("energy (J)")
    ax.set_xlabel("time t (s)")
    for a in axes:
        a.grid(alpha=0.3)
        # plain numbers: an offset ("1e-6+1.5708") is easy to misread
        a.ticklabel_format(axis="y", useOffset=False)
    return fig


def axis_path_phi_theta(
    traj: Trajectory,
    ax: Axes | None = None,
    *,
    color: str = "C0",
    label: str | None = None,
    turning_points: bool = True,
) -> Axes:
    """The path of the figure axis in the (phi, theta) plane: precession angle phi (rad,
    unwrapped) across, theta (rad) down, so that a more upright axis is higher, as on the
    sphere. Waves, cusps and loops show here as in the textbooks. For an exact Lagrange
    trajectory the turning points are drawn as dotted lines."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4))
    ax.plot(traj.phi, traj.theta, color=color, lw=1.0, label=label)
    model = getattr(traj, "model", None)
    state = getattr(traj, "state", None)
    from ._lagrange import LagrangeTop
    from ._state import EulerState

    if (
        turning_points
        and isinstance(model, LagrangeTop)
        and not model.driven
        and isinstance(state, EulerState)
    ):
        for th in model.turning_points(state):
            ax.axhline(th, color="0.5", ls=":", lw=1)
    ax.invert_yaxis()
    ax.set_xlabel(r"precession angle $\phi$ (rad)")
    ax.set_ylabel(r"$\theta$ (rad from the vertical)")
    ax.grid(alpha=0.3)
    return ax


def invariant_drift(traj: Trajectory, ax: Axes | None = None, *, floor: float = 1e-17) -> Axes:
    """Relative drift ``|X(t) - X(0)| / |X(0)|`` of the conserved quantities on a log scale
    (Mz and M3 against the angular momentum ``|L|`` when they start near zero):
    energy, Mz, M3 and Kovalevskaya's integral where the trajectory carries them (an exact
    Lagrange trajectory: computed from its angles and rates); for a play top, Jellett's
    integral and the energy balance E + dissipated. Exact zeros are drawn at ``floor``."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 4))
    from ._diagnostics import conserved, relative_drift

    series = conserved(traj)
    for i, (key, label, y, scale) in enumerate(series):
        if key in ("Mz", "M3") and scale != abs(y[0]):
            label += r" (against $|L|$)"
        err = np.maximum(relative_drift(y, scale), floor)
        ax.plot(traj.t, err, color=f"C{i}", lw=1.0, label=label)
    ax.set_yscale("log")
    ax.set_ylim(floor / 2, None)
    ax.set_xlabel("time t (s)")
    ax.set_ylabel("relative drift |X(t) − X(0)| / |X(0)|  (1)")
    ax.set_title(f"exact zeros drawn at {floor:g}", fontsize=8, loc="right")
    ax.grid(alpha=0.3, which="major")
    if series:
        ax.legend(loc="lower right", fontsize=8)
    return ax


# -- the play top on the floor ----------------------------------------------------------------

_TRACK_COLOURS = {"slip": "#c0701a", "roll": "#1f5fa8", "flight": "#2e8b3a"}


def contact_track(traj: Trajectory, ax: Axes | None = None, *, unit: str = "mm") -> Axes:
    """The contact point's track on the floor (top view) for a play-top trajectory, coloured by
    contact mode (slip orange, roll blue, flight green: the point below the tip), with the
    start and end marked and the centre of mass's track dashed. ``unit`` is "mm" or "m"."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6))
    scale = {"mm": 1e3, "m": 1.0}[unit]
    p = np.asarray(traj.contact_point)[:, :2] * scale
    g = np.asarray(traj.com)[:, :2] * scale
    mode = np.asarray(traj.mode)
    ax.plot(g[:, 0], g[:, 1], color="0.6", lw=0.8, ls="--", label="centre of mass")
    start = 0
    seen = set()
    n = len(mode)
    for i in range(1, n + 1):
        if i == n or mode[i] != mode[start]:
            m = str(mode[start])
            stop = min(i + 1, n)
            ax.plot(p[start:stop, 0], p[start:stop, 1], color=_TRACK_COLOURS.get(m, "k"), lw=1.4,
                    label=None if m in seen else f"contact, {m}")  # fmt: skip
            seen.add(m)
            start = i
    if n:
        ax.plot(*p[0], marker="o", color="k", ms=5, ls="none", label="start")
        ax.plot(*p[-1], marker="s", color="k", ms=5, ls="none", label="end")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return ax


def poincare(
    section: Trajectory,
    ax: Axes | None = None,
    *,
    color: str = "C0",
    label: str | None = None,
    size: float = 2.0,
) -> Axes:
    """A Poincare section (from :func:`kreisel.poincare`) as points in the (theta, theta_dot)
    plane: a regular motion lies on closed curves, a chaotic one fills an area.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from kreisel import LagrangeTop, pivots, poincare, plot
    >>> top = LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0,
    ...                   pivot=pivots.Harmonic([0.0, 0.0, 0.05], omega=20.0))
    >>> ax = plot.poincare(poincare(top, top.state(theta=0.5, psi_dot=2.0), 20))
    >>> ax.get_xlabel()
    'theta (rad)'
    """
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(5.0, 4.0))
    theta_dot = euler_rates(section)[0]
    ax.scatter(section.theta, theta_dot, s=size, color=color, label=label, linewidths=0)
    ax.set_xlabel("theta (rad)")
    ax.set_ylabel("theta_dot (rad/s)")
    if label is not None:
        ax.legend(loc="best", frameon=False)
    return ax
