"""``kreisel demo``: a tour of built-in tops that writes figures, an animation and a short
Markdown report."""

from __future__ import annotations

from pathlib import Path

DEMO_FRAMES = 60


def demo(out: Path, *, animation: bool = True, progress=None) -> Path:
    """Analyses built-in tops, writes figures, a GIF of a tippe top and report.md into
    ``out``; returns the report's path."""
    import numpy as np

    from . import LagrangeTop

    out.mkdir(parents=True, exist_ok=True)
    # A toy top: 100 g, centre of mass 4 cm above the tip, spun at 400 rad/s (about 64 Hz).
    top = LagrangeTop(I1=1.75e-4, I3=2.0e-5, m=0.1, l=0.04, g=9.81)
    theta0, spin = 0.6, 300.0
    print(f"kreisel demo: {top!r}")
    print(f"  sleeping threshold: omega3 > {top.sleeping_threshold():.2f} rad/s")
    rates = top.steady_precession(theta0, spin)
    print(f"  steady precession at theta = {theta0} rad, omega3 = {spin} rad/s:")
    for r in rates:
        w = top.nutation_frequency(theta0, spin, r)
        print(f"    Omega = {r:10.4f} rad/s, small nutations at {w:9.3f} rad/s")
    cases = {
        "waves": top.state(theta0, phi_dot=0.3 * rates[0], psi_dot=spin),
        "cusps": top.state(theta0, psi_dot=spin),
        "loops": top.state(theta0, phi_dot=-0.5 * rates[0], psi_dot=spin),
    }
    rows = []
    for name, st in cases.items():
        a = top.analyse(st)
        inv = top.invariants(st)
        rows.append((name, st, a))
        print(f"  start {name}: {st}")
        print(f"    E = {inv.E:.6g} J, Mz = {inv.Mz:.6g}, M3 = {inv.M3:.6g} kg m^2/s")
        print(
            f"    kind {a.kind}; theta in [{a.theta_min:.5f}, {a.theta_max:.5f}] rad; "
            f"nutation period {a.nutation_period:.5f} s; "
            f"mean precession {a.mean_precession_rate:.5f} rad/s"
        )
    from . import plot

    plt = plot._pyplot()
    fig = plt.figure(figsize=(13, 8.5))
    for i, (_name, st, a) in enumerate(rows):
        ax = fig.add_subplot(2, 3, i + 1, projection="3d")
        # One revolution of the mean precession.
        t = np.linspace(0.0, 2.0 * np.pi / abs(a.mean_precession_rate), 6000)
        traj = top.exact(st, t)
        plot.axis_path_on_sphere(traj, ax=ax, color=f"C{i}")
        ax.set_title(f"{a.kind}: tip of the figure axis")
        ax.view_init(elev=40, azim=-60)
        ax2 = fig.add_subplot(2, 3, i + 4)
        plot.axis_path_plan(traj, ax=ax2, color=f"C{i}")
        ax2.set_title(f"{a.kind}, seen from above (one precession turn)")
    fig.tight_layout()
    path = out / "lagrange_axis_paths.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6, 4))
    plot.effective_potential(top, cases["cusps"], ax=ax)
    ax.set_title("Effective potential, cusp start")
    fig.tight_layout()
    path2 = out / "lagrange_effective_potential.png"
    fig.savefig(path2, dpi=110)
    plt.close(fig)
    print(f"wrote {path} and {path2}")
    tippe = _demo_tippe(out, animation=animation, progress=progress)
    tippe["atlas"] = _demo_atlas(out)
    tippe["sweep"] = _demo_sweep(out, progress=progress)
    report = _report(out, top, rows, tippe)
    print(f"wrote {report}")
    return report


def _demo_tippe(out: Path, *, animation: bool, progress) -> dict:
    import numpy as np

    from . import events, plot, simulate
    from ._config import from_tables, preset

    # Leine and Glocker's tippe top (the preset "tippe"): a ball with a peg, Coulomb-Contensou
    # friction, spun at 180 rad/s near hanging on its ball.
    tables = preset("tippe")
    problem = from_tables(tables)
    pt, st = problem.model, problem.state
    tr = simulate(pt, st, problem.settings.t_end, rtol=problem.settings.rtol,
                  events=[events.inversion(0.9)])  # fmt: skip
    inv = [e.t for e in tr.events if e.name == "inversion"]
    on_peg = next((e.t for e in tr.events if e.name == "touchdown" and e.part == "peg"), None)
    back = next((e.t for e in tr.events if e.name == "touchdown" and e.part == "ball"
                 and on_peg is not None and e.t > on_peg), None)  # fmt: skip
    drift = float(np.max(np.abs(tr.energy + tr.dissipated - tr.energy[0])) / tr.energy[0])
    print(f"kreisel demo: Leine and Glocker's tippe top, {pt!r}")
    print(
        f"  spun at {tables['state']['psi_dot']:g} rad/s from u = {tr.u[0]:.4f} on its ball: "
        + (f"the peg touches down at t = {on_peg:.3f} s, " if on_peg is not None else "")
        + (f"u rises through 0.9 at t = {inv[0]:.3f} s" if inv else "it does not turn over")
        + (f"; it falls back onto its ball at t = {back:.3f} s" if back is not None else "")
        + f"; ends at u = {tr.u[-1]:.4f}"
    )
    print(
        f"  energy {tr.energy[0]:.5g} J -> {tr.energy[-1]:.5g} J, dissipated "
        f"{tr.dissipated[-1]:.5g} J (balance kept to {drift:.1e} of the start)"
    )
    plt = plot._pyplot()
    fig = plot.play_time_series(tr)
    fig.suptitle("Leine and Glocker's tippe top: onto its peg and back")
    fig.tight_layout()
    path = out / "tippe_top.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    plot.contact_track(tr, ax=ax)
    ax.set_title("Tippe top: the contact point's track on the floor")
    fig.tight_layout()
    track = out / "tippe_track.png"
    fig.savefig(track, dpi=100)
    plt.close(fig)
    print(f"wrote {path} and {track}")
    gif = None
    if animation:
        from . import animate

        gif = out / "tippe_top.gif"
        # 60 frames over the first 6 s: onto the peg at 1.4 s, back onto the ball at 4.6 s
        animate.to_gif(tr, gif, frames=DEMO_FRAMES, fps=10, t_stop=6.0,
                       title="tippe top with its peg", progress=progress)  # fmt: skip
        print(f"wrote {gif}")
    return {
        "model": pt, "traj": tr, "inversion": inv[0] if inv else None, "on_peg": on_peg,
        "back": back, "drift": drift, "figure": path.name, "track": track.name,
        "gif": gif.name if gif else None,
    }  # fmt: skip


def _demo_atlas(out: Path) -> str:
    import numpy as np

    from . import PlayTop, Viscous, plot

    # The atlas is of tops on one tip sphere: the tippe top's ball alone (the preset
    # "tippe-ball", benchmark T1), placed in the (alpha, gamma) plane.
    m, rho, s = 0.02, 0.02, 0.006
    c = 0.4 * m * rho**2
    pt = PlayTop(m=m, A=0.8 * c, C=c, s=s, rho=rho, friction=Viscous(mu=1.0))
    cl = pt.classify()
    p = pt.predict(pt.state(theta=np.pi - 0.1, psi_dot=150.0))
    end = p.ending
    print(
        f"kreisel demo: a tippe top's ball alone lies in zone {cl.zone} (type {cl.type}, "
        f"Fig. 3 area {cl.fig3}); spun at 150 rad/s near hanging it has J = {p.J:.4g} "
        f"kg m^2/s and must end {end.kind if end else 'in one of several motions'}"
        + (f" with omega3 = {end.omega3:.4g} rad/s" if end else "")
    )
    plt = plot._pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(16, 6.5), gridspec_kw={"width_ratios": [1.25, 1]})
    plot.atlas(pt, ax=axes[0])
    plot.J_R_plot(pt, J=p.J, ax=axes[1])
    fig.tight_layout()
    path = out / "atlas.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")
    return path.name


def _demo_sweep(out: Path, *, progress) -> dict:
    import shutil

    import numpy as np

    from . import plot
    from ._sweep import sweep

    # The same tippe top over a grid of centre-of-mass offsets and spins: which turn over?
    m, rho = 0.02, 0.02
    c = 0.4 * m * rho**2
    spec = {
        "top": {"kind": "play", "m": m, "A": 0.8 * c, "C": c, "rho": rho,
                "friction": "viscous", "mu": 1.0},
        "state": {"theta": np.pi - 0.1},
        "simulation": {"t_end": 5.0, "rtol": 1e-8},
        "grid": {"s": {"start": 0.001, "stop": 0.012, "num": 12},
                 "psi_dot": {"start": 30.0, "stop": 250.0, "num": 12, "scale": "log"}},
        "output": {"chunk": 24},
    }  # fmt: skip
    store = out / "tippe_sweep.zarr"
    shutil.rmtree(store, ignore_errors=True)
    ds = sweep(spec, store, progress=progress is not None)
    turned = int(np.isfinite(ds["inversion_time"].values).sum())
    print(
        f"kreisel demo: swept {ds['final_u'].size} tippe tops over (s, psi_dot) into {store}: "
        f"{turned} turn over within 5 s"
    )
    plt = plot._pyplot()
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    plot.sweep(ds, "inversion_time", ax, x="psi_dot", y="s")
    ax.set_xscale("log")
    path = out / "tippe_sweep.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")
    return {"figure": path.name, "store": store.name, "runs": int(ds["final_u"].size),
            "turned": turned}  # fmt: skip


def _report(out: Path, top, rows, tippe) -> Path:
    from . import __version__

    lines = [
        "# kreisel demo",
        "",
        f"Written by kreisel {__version__}. SI units, angles in radians.",
        "",
        "## The Lagrange top, solved exactly",
        "",
        f"`{top!r}`: sleeping threshold omega3 > {top.sleeping_threshold():.2f} rad/s.",
        "",
        "| start | kind | theta_min (rad) | theta_max (rad) | nutation period (s) "
        "| mean precession (rad/s) |",
        "|---|---|---|---|---|---|",
    ]
    for name, _st, a in rows:
        lines.append(
            f"| {name} | {a.kind} | {a.theta_min:.5f} | {a.theta_max:.5f} "
            f"| {a.nutation_period:.5f} | {a.mean_precession_rate:.5f} |"
        )
    lines += [
        "",
        "![The figure axis's tip: waves, cusps and loops](lagrange_axis_paths.png)",
        "",
        "![Effective potential of the cusp start](lagrange_effective_potential.png)",
        "",
        "## A tippe top turning over onto its peg",
        "",
        "Leine and Glocker's tippe top (Eur. J. Mech. A/Solids 22 (2003) 193; the preset "
        "`tippe`): a ball of 15 mm with a peg of 5 mm, Coulomb-Contensou friction.",
        "",
        f"`{tippe['model']!r}`",
        "",
    ]
    tr = tippe["traj"]
    inv, on_peg, back = tippe["inversion"], tippe["on_peg"], tippe["back"]
    lines += [
        f"- the peg touches down at t = {on_peg:.3f} s" if on_peg is not None
        else "- the peg never touches the floor",
        f"- u = cos(theta) rises through 0.9 at t = {inv:.3f} s" if inv is not None
        else "- it does not turn over within the run",
        f"- it falls back onto its ball at t = {back:.3f} s" if back is not None
        else "- it stays on its peg",
        f"- final u = {tr.u[-1]:.5f}",
        f"- energy {tr.energy[0]:.5g} J -> {tr.energy[-1]:.5g} J, dissipated "
        f"{tr.dissipated[-1]:.5g} J (balance kept to {tippe['drift']:.1e} of the start)",
        "",
    ]  # fmt: skip
    if tippe["gif"]:
        lines += [f"![The tippe top turning over onto its peg (first 6 s)]({tippe['gif']})", ""]
    lines += [
        f"![Time series, contact modes shaded]({tippe['figure']})",
        "",
        f"![The contact point's track on the floor]({tippe['track']})",
        "",
        "## Where it ends: the atlas of play tops",
        "",
        "The atlas is of tops on one tip sphere: the tippe top's ball alone (the preset "
        "`tippe-ball`) in the (alpha, gamma) plane (theory: the play top), and its "
        "J_R(u) with the stationary motions open to its Jellett integral.",
        "",
        f"![Atlas and J_R]({tippe['atlas']})",
        "",
        "## Which tippe tops turn over: a sweep",
        "",
        f"The ball alone again: {tippe['sweep']['runs']} runs over the centre-of-mass offset s "
        f"and the spin, in the Zarr store `{tippe['sweep']['store']}` (open it with "
        f"`kreisel.open_sweep`); {tippe['sweep']['turned']} turn over within 5 s. Bigger "
        "sweeps: `kreisel sweep spec.toml`, on a Dask cluster with `--scheduler`.",
        "",
        f"![Inversion time over (psi_dot, s)]({tippe['sweep']['figure']})",
        "",
        "More: `kreisel presets`, `kreisel play --preset tippe --animate mp4`, "
        "`kreisel run top.toml`.",
        "",
    ]
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path
