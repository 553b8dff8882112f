"""Figures (matplotlib, imported only when a figure is made).

Every function draws into ``ax`` when given one and returns the axes it drew into.
"""

from __future__ import annotations

import numpy as np


def _pyplot():
    import matplotlib

    if matplotlib.get_backend().lower() not in ("agg", "module://matplotlib_inline.backend_inline"):
        try:
            import matplotlib.pyplot as plt  # noqa: F401
        except ImportError:  # pragma: no cover
            matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def figure_axis(theta, phi):
    """Unit figure axis e3 in the space frame from Euler angles (z-x-z), shape (n, 3)."""
    theta, phi = np.asarray(theta), np.asarray(phi)
    st = np.sin(theta)
    return np.stack([st * np.sin(phi), -st * np.cos(phi), np.cos(theta)], axis=-1)


def axis_path_on_sphere(traj, ax=None, *, color="C0", label=None, sphere=True):
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
    return ax


def axis_path_plan(traj, ax=None, *, color="C0", label=None):
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


def effective_potential(top, state, ax=None, *, n=800):
    """The effective potential Veff(theta) (J) with the energy line and the turning points."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    inv = top.invariants(state)
    tmin, tmax = top.turning_points(state)
    theta = np.linspace(1e-3, np.pi - 1e-3, n)
    v = top.effective_potential(theta, inv.Mz, inv.M3)
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


def shade_modes(ax, traj):
    """Shades the contact modes (slip, roll, flight) of a play-top trajectory behind ``ax``."""
    t, mode = traj.t, traj.mode
    if len(t) == 0:
        return ax
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or mode[i] != mode[start]:
            ax.axvspan(t[start], t[min(i, len(t) - 1)], color=_MODE_COLOURS[str(mode[start])],
                       lw=0, zorder=0)  # fmt: skip
            start = i
    return ax


def play_time_series(traj, fig=None):
    """u, normal force, slip speed, Jellett's integral and the energy over time for a
    play-top trajectory, with the contact modes shaded (slip tan, roll blue, flight green)."""
    plt = _pyplot()
    if fig is None:
        fig = plt.figure(figsize=(9, 10))
    axes = fig.subplots(5, 1, sharex=True)
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


from ._plot_atlas import J_R_plot, atlas, vertical_axis_diagram  # noqa: E402, F401
