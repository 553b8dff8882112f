"""The ``kreisel`` command line (click).

Bad input (an unknown field or flag, a value out of range, malformed TOML, an unknown
preset) ends with exit code 2 and one line on stderr that names the field and what is
allowed; a computation that fails ends with exit code 1 and one line.
"""

from __future__ import annotations

import sys
from pathlib import Path

import click
import numpy as np

from ._config import FRICTIONS, known_presets
from ._errors import NumericalError, ParameterError
from ._run import ANIMATIONS, FORMATS

_CONTEXT = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


def _opt(name, dest, help, **kw):
    return click.option(name, dest, default=None, help=help, show_default=False, **kw)


def _apply(f, options):
    for o in reversed(options):
        f = o(f)
    return f


def _euler_options(f):
    return _apply(f, [
        _opt("--theta", "theta", "nutation angle from the upward vertical (rad), in [0, pi]",
             type=float),
        _opt("--phi", "phi", "precession angle (rad) [0]", type=float),
        _opt("--psi", "psi", "spin angle (rad) [0]", type=float),
        _opt("--theta-dot", "theta_dot", "nutation rate (rad/s) [0]", type=float),
        _opt("--phi-dot", "phi_dot", "precession rate (rad/s) [0]", type=float),
        _opt("--psi-dot", "psi_dot", "spin rate (rad/s) [0]", type=float),
    ])  # fmt: skip


def _drive_options(f):
    """The flags of a moving or damped pivot ([pivot] and [damping] of a TOML file)."""
    return _apply(f, [
        _opt("--pivot-amplitude", "pivot_amplitude", "pivot shaken as amplitude * cos(omega t "
             "+ phase): amplitude X Y Z (m)", nargs=3, type=float),
        _opt("--pivot-omega", "pivot_omega", "angular frequency of the shaking (rad/s)",
             type=float),
        _opt("--pivot-phase", "pivot_phase", "phase of the shaking (rad) [0]", type=float),
        _opt("--viscous", "viscous", "viscous torque at the pivot, -c omega: c (N m s)",
             type=float),
        _opt("--drag", "drag", "air-drag torque -k |omega| omega: k (N m s^2)", type=float),
        _opt("--dry", "dry", "dry friction coefficient of the ball joint", type=float),
        _opt("--pivot-radius", "pivot_radius", "radius of the ball joint (m)", type=float),
    ])  # fmt: skip


def _drive_tables(kw: dict) -> dict:
    """The [pivot] and [damping] tables of the drive flags given."""
    out: dict = {}
    amp, omega, phase = (kw.pop(k) for k in ("pivot_amplitude", "pivot_omega", "pivot_phase"))
    if amp is not None or omega is not None or phase is not None:
        out["pivot"] = {"kind": "harmonic"}
        if amp is not None:
            out["pivot"]["amplitude"] = list(amp)
        if omega is not None:
            out["pivot"]["omega"] = omega
        if phase is not None:
            out["pivot"]["phase"] = phase
    damping = {k: kw.pop(k) for k in ("viscous", "drag", "dry", "pivot_radius")}
    damping = {k: v for k, v in damping.items() if v is not None}
    if damping:
        out["damping"] = damping
    return out


def _run_options(kind):
    return lambda f: _apply(f, [
        _opt("--preset", "preset", f"start from a built-in {kind} top: {known_presets(kind)}",
             type=str),
        _opt("--t-end", "t_end", "duration (s) [2; play 5; a preset's own]", type=float),
        _opt("--rtol", "rtol", "relative tolerance of dop853 [1e-10]", type=float),
        _opt("--atol", "atol", "absolute tolerance of dop853 [1e-12]", type=float),
        _opt("--samples", "samples", "output at this many equal time steps [every step; exact "
             "2001]", type=int),
        click.option("--out", type=click.Path(file_okay=False, path_type=Path), default=None,
                     help="output folder [kreisel-out/<preset or kind>]"),
        click.option("--format", "fmt", type=click.Choice(FORMATS), default="netcdf",
                     show_default=True, help="trajectory file: NetCDF (xarray) or CSV"),
        click.option("--animate", "animation", type=click.Choice(ANIMATIONS), default=None,
                     help="also write an animation: GIF, MP4 or interactive HTML"),
        click.option("--frames", type=click.IntRange(2, 5000), default=60, show_default=True,
                     help="frames of the animation"),
        click.option("--fps", type=click.FloatRange(0, 120, min_open=True), default=15.0,
                     show_default=True, help="frames per second of the animation"),
        click.option("--no-figures", is_flag=True, help="write no PNG figures"),
    ])  # fmt: skip


@click.group(context_settings=_CONTEXT)
@click.version_option(package_name="kreisel", prog_name="kreisel", message="%(prog)s %(version)s")
def cli():
    """kreisel: the dynamics of spinning tops (SI units, radians).

    Every command writes into --out a JSON summary, the trajectory (NetCDF or CSV), figures
    and, with --animate, an animation. `kreisel demo` is a tour; `kreisel presets` lists the
    built-in tops.
    """


@cli.command(context_settings=_CONTEXT)
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("kreisel-out"),
    show_default=True,
    help="output folder",
)
@click.option("--no-animation", is_flag=True, help="skip the GIF of the tippe top")  # fmt: skip
def demo(out, no_animation):
    """A tour: built-in tops, figures, a GIF and report.md."""
    from ._demo import DEMO_FRAMES, demo

    if no_animation:
        demo(out, animation=False)
        return
    with _Progress(DEMO_FRAMES, "kreisel demo") as bar:
        demo(out, animation=True, progress=lambda n: bar.update(n, "rendering the tippe top"))


@cli.command(context_settings=_CONTEXT)
@click.option("--toml", "as_toml", metavar="NAME", default=None,
              help="print this preset as a TOML file for `kreisel run`")  # fmt: skip
def presets(as_toml):
    """List the built-in tops (for --preset NAME)."""
    from ._config import preset
    from ._presets import PRESETS

    if as_toml is not None:
        click.echo(_to_toml(as_toml, preset(as_toml)), nl=False)
        return
    width = max(len(n) for n in PRESETS)
    for name, p in PRESETS.items():
        click.echo(f"{name:<{width}}  {p.kind:<8}  {p.summary}")


@cli.command(context_settings=_CONTEXT)
@_run_options("lagrange")
@_opt("--method", "method", "integrate instead of the exact solution: dop853, rk4, splitting, "
      "splitting4, splitting6, verlet, midpoint, gauss4", type=str)  # fmt: skip
@click.option("--exact", is_flag=True, help="the exact solution (the default without --method)")
@_opt("--dt", "dt", "step (s) of a fixed-step method", type=float)
@_euler_options
@_opt("--I1", "I1", "moment about the pivot, perpendicular to the axis (kg m^2)", type=float)
@_opt("--I3", "I3", "moment about the figure axis (kg m^2)", type=float)
@_opt("--m", "m", "mass (kg), > 0", type=float)
@_opt("--l", "l", "pivot to centre of mass along the axis (m)", type=float)
@_opt("--g", "g", "gravitational acceleration (m/s^2) [9.81]", type=float)
@_drive_options
def lagrange(**kw):
    """Symmetric top on a pivot: exact solution, analysis (integrated on a moving or damped
    pivot)."""
    exact = kw.pop("exact")
    top = _take(kw, "I1", "I3", "m", "l", "g")
    sim = _take(kw, "t_end", "method", "rtol", "atol", "dt", "samples")
    sim["exact"] = True if exact else None
    _go("lagrange", top, _take(kw, *_EULER), sim, kw, _drive_tables(kw))


@cli.command(context_settings=_CONTEXT)
@_run_options("heavy")
@_opt("--method", "method", "dop853 [default], rk4, splitting, splitting4, splitting6, verlet, "
      "midpoint, gauss4", type=str)  # fmt: skip
@_opt("--dt", "dt", "step (s) of a fixed-step method", type=float)
@_opt("--quaternion", "quaternion", "orientation (w x y z), instead of Euler angles", nargs=4,
      type=float)  # fmt: skip
@_opt("--omega", "omega", "body angular velocity (rad/s), with --quaternion", nargs=3, type=float)
@_euler_options
@_opt("--I1", "I1", "principal moment about body axis 1 at the pivot (kg m^2)", type=float)
@_opt("--I2", "I2", "principal moment about body axis 2 (kg m^2)", type=float)
@_opt("--I3", "I3", "principal moment about body axis 3 (kg m^2)", type=float)
@_opt("--m", "m", "mass (kg), > 0", type=float)
@_opt("--com", "com", "centre of mass in the body frame from the pivot (m): X Y Z", nargs=3,
      type=float)  # fmt: skip
@_opt("--g", "g", "gravitational acceleration (m/s^2) [9.81]", type=float)
@_drive_options
def heavy(**kw):
    """Any rigid body on a pivot, integrated; the pivot may move and be damped."""
    top = _take(kw, "I1", "I2", "I3", "m", "com", "g")
    state = _take(kw, *_EULER, "quaternion", "omega")
    for table, k in ((top, "com"), (state, "quaternion"), (state, "omega")):
        if table.get(k) is not None:
            table[k] = list(table[k])
    sim = _take(kw, "t_end", "method", "rtol", "atol", "dt", "samples")
    _go("heavy", top, state, sim, kw, _drive_tables(kw))


@cli.command(context_settings=_CONTEXT)
@_run_options("play")
@_opt("--vx", "vx", "horizontal velocity of the centre of mass, x (m/s) [0]", type=float)
@_opt("--vy", "vy", "horizontal velocity of the centre of mass, y (m/s) [0]", type=float)
@_opt("--height", "height", "drop from this gap between tip and floor (m) [in contact]",
      type=float)  # fmt: skip
@_euler_options
@_opt("--m", "m", "mass (kg), > 0", type=float)
@_opt("--A", "A", "equatorial moment about the centre of mass (kg m^2)", type=float)
@_opt("--C", "C", "axial moment (kg m^2), 0 < C <= 2 A", type=float)
@_opt("--s", "s", "tip-sphere centre to centre of mass (m), >= 0", type=float)
@_opt("--rho", "rho", "radius of the tip sphere (m), > 0", type=float)
@_opt("--g", "g", "gravitational acceleration (m/s^2) [9.81]", type=float)
@_opt("--friction", "friction", "contact law [coulomb]", type=click.Choice(FRICTIONS))
@_opt("--mu", "mu", "friction coefficient (Coulomb: 1; viscous: s/m) [0.3; viscous 1]",
      type=float)  # fmt: skip
@_opt("--patch-radius", "patch_radius",
      "contact patch radius of coulomb_contensou friction (m) [5e-4]", type=float)  # fmt: skip
@_opt("--restitution", "restitution", "of impacts after a flight, in [0, 1] [0]", type=float)
@_opt("--rolling-resistance", "rolling_resistance", "rolling loss length (m) [0]", type=float)
@_opt("--drilling-resistance", "drilling_resistance", "drilling loss length (m) [0]",
      type=float)  # fmt: skip
@_opt("--air-drag", "air_drag", "air torque per rad/s (N m s) [0]", type=float)
def play(**kw):
    """Top on a floor: a spherical tip, or the parts of a preset (tippe top with its peg)."""
    top = _take(kw, "m", "A", "C", "s", "rho", "g", "friction", "mu", "patch_radius",
                "restitution", "rolling_resistance", "drilling_resistance", "air_drag")  # fmt: skip
    state = _take(kw, *_EULER, "vx", "vy", "height")
    sim = _take(kw, "t_end", "rtol", "atol", "samples")
    _go("play", top, state, sim, kw)


@cli.command(context_settings=_CONTEXT)
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="output folder [kreisel-out/<file name>]",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    default="netcdf",
    show_default=True,
    help="trajectory file: NetCDF (xarray) or CSV",
)
@click.option(
    "--animate",
    "animation",
    type=click.Choice(ANIMATIONS),
    default=None,
    help="also write an animation: GIF, MP4 or interactive HTML",
)
@click.option(
    "--frames",
    type=click.IntRange(2, 5000),
    default=60,
    show_default=True,
    help="frames of the animation",
)
@click.option(
    "--fps",
    type=click.FloatRange(0, 120, min_open=True),
    default=15.0,
    show_default=True,
    help="frames per second of the animation",
)
@click.option("--no-figures", is_flag=True, help="write no PNG figures")  # fmt: skip
def run(file, **kw):
    """Run the top a TOML file describes.

    \b
    [top]          kind = "lagrange" | "heavy" | "play", its parameters (or preset = NAME)
    [state]        theta, phi, psi, theta_dot, phi_dot, psi_dot (heavy: or quaternion,
                   omega; play: also vx, vy, height)
    [simulation]   t_end, method or exact, rtol, atol, dt, samples
    `kreisel presets --toml NAME` prints a preset as such a file.
    """
    from ._config import from_tables, read_toml

    tables = read_toml(file)
    problem = from_tables(tables, prefix="table", source=file.name)
    out = kw.pop("out") or Path("kreisel-out") / file.stem
    _execute(problem, out, **kw)


@cli.command(context_settings=_CONTEXT)
@click.option("--preset", default=None, help="a play-top preset to mark (see `kreisel presets`)")
@_opt("--m", "m", "mass (kg), > 0", type=float)
@_opt("--A", "A", "equatorial moment about the centre of mass (kg m^2)", type=float)
@_opt("--C", "C", "axial moment about the centre of mass (kg m^2)", type=float)
@_opt("--s", "s", "tip-sphere centre to centre of mass (m)", type=float)
@_opt("--rho", "rho", "tip-sphere radius (m)", type=float)
@_opt("--g", "g", "gravitational acceleration (m/s^2) [9.81]", type=float)
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("kreisel-out") / "atlas",
    show_default=True,
    help="output folder",
)
def atlas(preset, out, **top):
    """The (alpha, gamma) atlas of play tops and the vertical-axis diagram, a top marked."""
    from ._config import from_tables, overlay
    from ._config import preset as get_preset

    given = {k: v for k, v in top.items() if v is not None}
    pt = None
    if preset is not None or given:
        if preset is not None:
            base = get_preset(preset)
            if base["top"]["kind"] != "play":
                raise ParameterError(
                    f"preset = {preset!r} is not allowed here: it is a {base['top']['kind']} "
                    "top; the atlas is of play tops"
                )
        else:
            base = {"top": {"kind": "play"}, "state": {}, "simulation": {}}
        tables = overlay(base, {"top": given, "state": {}, "simulation": {}}, preset)
        if preset is None:
            missing = [k for k in ("m", "A", "C", "s", "rho") if k not in given]
            if missing:
                raise ParameterError(
                    f"{', '.join(missing)} missing: give --m, --A, --C, --s and --rho, "
                    "or a --preset"
                )
            tables["state"] = {"theta": 0.1}
        pt = from_tables(tables).model
    from . import plot

    plt = plot._pyplot()
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []

    def figure(name, size, draw, bar):
        written.append(out / name)
        bar.update(0, f"drawing {name}")
        fig, ax = plt.subplots(figsize=size)
        draw(ax)
        fig.tight_layout()
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
        bar.update(1, f"drawing {name}")

    with _Progress(2 if pt is None else 3, "kreisel atlas") as bar:
        figure("atlas.png", (9, 6.5), lambda ax: plot.atlas(pt, ax=ax), bar)
        figure("vertical_axis.png", (7, 6), lambda ax: plot.vertical_axis_diagram(pt, ax=ax), bar)
        if pt is not None:
            figure("J_R.png", (8, 5), lambda ax: plot.J_R_plot(pt, ax=ax), bar)
    if pt is not None:
        c = pt.classify()
        click.echo(
            f"{pt!r}\n  alpha = {pt.alpha:.4g}, gamma = {pt.gamma:.4g}: type {c.type}, "
            f"zone {c.zone}, Fig. 3 area {c.fig3}"
        )
    click.echo(f"wrote {out}/: {', '.join(p.name for p in written)}")


@cli.command("sweep", context_settings=_CONTEXT)
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--store",
    type=click.Path(path_type=Path),
    default=None,
    help="Zarr store of the results [kreisel-out/<file name>.zarr]; rerun to finish it",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="a Dask scheduler (tcp://host:8786) [$KREISEL_SCHEDULER, else local cores]",
)
@click.option("--threads", type=click.IntRange(1), default=None,
              help="threads on this machine [all cores]")  # fmt: skip
@click.option("--var", default=None, help="the summary in the figure [inversion time or theta_max]")
@click.option("--overwrite", is_flag=True, help="replace a store that holds another sweep")
@click.option("--retry-failed", is_flag=True, help="compute the chunks with failed runs again")
@click.option("--no-figure", is_flag=True, help="write no PNG figure")
@click.option("--quiet", is_flag=True, help="no progress bar")
def sweep_command(file, store, scheduler, threads, var, overwrite, retry_failed, no_figure, quiet):
    """Run the sweep a TOML file describes into a Zarr store, and draw it.

    \b
    [top], [state], [simulation]   as for `kreisel run` (no samples; exact = true: the
                                   analysis of each lagrange top, no integration)
    [grid]     NAME = [values] or {start, stop, num, scale = "linear" | "log"}
    [random]   n, seed, NAME = {low, high, scale}
    [output]   keep = [summaries], chunk = runs per chunk, inversion_level, lyapunov_tau
    An interrupted sweep resumes where it stopped when run again.
    """
    import json
    import time

    from ._sweep import load_spec, sweep

    spec = load_spec(file)
    store = store or Path("kreisel-out") / f"{file.stem}.zarr"
    start = time.perf_counter()
    ds = sweep(
        spec,
        store,
        scheduler,
        threads=threads,
        progress=not quiet,
        overwrite=overwrite,
        retry_failed=retry_failed,
    )
    took = time.perf_counter() - start
    status = ds["status"].values
    click.echo(
        f"{spec.size} runs of a {spec.kind} top over {', '.join(spec.dims)} "
        f"({' x '.join(map(str, spec.shape))}): {int((status == 1).sum())} done, "
        f"{int((status == 2).sum())} failed, {took:.1f} s; store {store}"
    )
    for i, msg in list(json.loads(ds.attrs["run_errors"]).items())[:3]:
        click.echo(f"  run [{i}] failed: {msg}")
    if "inversion_time" in ds:
        inv = np.isfinite(ds["inversion_time"].values)
        click.echo(f"  turned over: {int(inv.sum())} of {inv.size} runs")
    if not no_figure:
        from . import plot

        plt = plot._pyplot()
        fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
        plot.sweep(ds, var, ax=ax)
        png = Path(store).with_suffix(".png")
        fig.savefig(png, dpi=110)
        plt.close(fig)
        click.echo(f"  figure {png}")


@cli.command(context_settings=_CONTEXT)
@click.option(
    "--port",
    type=click.IntRange(0, 65535),
    default=8765,
    show_default=True,
    help="port on 127.0.0.1 (0: any free port)",
)
@click.option("--no-browser", is_flag=True, help="open no browser; print the address only")
@click.option(
    "--store",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="folder of sweep stores the page may open (none outside it)",
)
def explore(port, no_browser, store):
    """The tops in a browser: a local page (127.0.0.1 only) with a live 3D view, charts,
    the atlas, sweeps and export. Ctrl+C stops it."""
    from .explore import serve

    def ready(url):
        click.echo(f"kreisel explore: serving {url} (Ctrl+C stops)", err=True)

    serve(port, open_browser=not no_browser, store=store, ready=ready)


def _dask_process(role, args):
    import os

    from ._sweep import dask_command

    try:
        import distributed  # noqa: F401
    except ImportError:  # pragma: no cover
        raise click.UsageError(
            "dask.distributed is not installed: pip install 'kreisel[sweep]'"
        ) from None
    cmd, env = dask_command(role, args)
    sys.stdout.flush()
    os.execve(cmd[0], cmd, env)


_PASS_ON = {**_CONTEXT, "ignore_unknown_options": True, "allow_extra_args": True}


@cli.command(context_settings=_PASS_ON, add_help_option=False)
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
def scheduler(args):
    """A Dask scheduler for sweeps: `dask scheduler` with settings for kreisel's tasks.

    Every argument goes to `dask scheduler` (see `kreisel scheduler --help`). Settings made in
    the environment (DASK_*) or a Dask configuration file come first.
    """
    _dask_process("scheduler", args)


@cli.command(context_settings=_PASS_ON, add_help_option=False)
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
def worker(args):
    """A Dask worker for sweeps: `dask worker ADDRESS` with settings for kreisel's tasks.

    \b
    Every argument goes to `dask worker` (see `kreisel worker --help`), e.g.
        kreisel worker tcp://host:8786 --nthreads 8
    kreisel's tasks are long, CPU-bound and release the GIL: Dask's profiler and its frequent
    event-loop ticks only take CPU from them, so they are turned down. Settings made in the
    environment (DASK_*) or a Dask configuration file come first.
    """
    _dask_process("worker", args)


_EULER = ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")


def _take(kw: dict, *names) -> dict:
    return {n: kw.pop(n) for n in names if n in kw}


def _go(kind: str, top: dict, state: dict, sim: dict, kw: dict, drive: dict | None = None):
    from ._config import from_tables, overlay, preset

    name = kw.pop("preset")
    if name is not None:
        base = preset(name)
        if base["top"]["kind"] != kind:
            raise ParameterError(
                f"preset = {name!r} is not allowed here: it is a {base['top']['kind']} top; "
                f"use `kreisel {base['top']['kind']} --preset {name}`"
            )
    else:
        base = {"top": {"kind": kind}, "state": {}, "simulation": {}}
    tables = overlay(base, {"top": top, "state": state, "simulation": sim}, name)
    for t, given in (drive or {}).items():
        tables[t] = {**tables.get(t, {}), **given}
    problem = from_tables(tables)
    problem.preset = name
    out = kw.pop("out") or Path("kreisel-out") / (name or kind)
    _execute(problem, out, **kw)


class _Progress:
    """Progress on stderr: on a terminal click's bar; elsewhere (a pipe, a log, a notebook)
    one line per stage and one per tenth of a long stage, with the seconds since the start,
    so that the seconds figures and animations take are never silent."""

    def __init__(self, length: int, label: str):
        import time

        self.length, self.label, self.done = length, label, 0
        self.stage: str | None = None
        self.start, self.clock = time.perf_counter(), time.perf_counter
        self.bar = None
        if sys.stderr.isatty():
            self.bar = click.progressbar(length=length, label=label, file=sys.stderr,
                                         show_eta=False, item_show_func=lambda s: s)  # fmt: skip

    def __enter__(self):
        if self.bar is not None:
            self.bar.__enter__()
        return self

    def __exit__(self, *exc):
        if self.bar is not None:
            return self.bar.__exit__(*exc)
        if exc[0] is None:
            self._line("done")
        return None

    def _line(self, what: str):
        took = self.clock() - self.start
        print(f"{self.label}: {what} ({took:.1f} s)", file=sys.stderr, flush=True)

    def update(self, n: int, stage: str | None = None):
        if self.bar is not None:
            self.bar.update(n, stage)
            return
        before, self.done = self.done, min(self.done + n, self.length)
        if stage is not None and stage != self.stage:
            self.stage = stage
            self._line(stage)
        elif self.stage is not None and self.length >= 20:
            tenth = self.length / 10
            if int(self.done / tenth) > int(before / tenth):
                self._line(f"{self.stage}, {100 * self.done // self.length}%")


def _execute(problem, out: Path, *, fmt, animation, frames, fps, no_figures):
    from ._run import run, work_units

    driven = getattr(problem.model, "driven", False)
    units = work_units(problem.kind, not no_figures, animation, frames, driven)
    with _Progress(units, f"kreisel {problem.kind}") as bar:
        data = run(problem, out, fmt=fmt, figures=not no_figures, animation=animation,
                   frames=frames, fps=fps, progress=bar.update)  # fmt: skip
    _report(problem, data, out)


def _report(problem, data: dict, out: Path):
    res = data["result"]
    a = data.get("analysis", {})
    click.echo(f"{data['top']['repr']}")
    click.echo(f"  from {data['state']['repr']}")
    sim = data["simulation"]
    click.echo(f"  {sim['solver']} to t = {_num(sim['t_end'])} s: {res['samples']} samples")
    if "pivot" in a:
        fin = res["final"]
        click.echo(
            f"  pivot: {a['pivot']}; damping: {a['damping']}\n"
            f"  theta at the end {_num(fin.get('theta'), '.5f')} rad; energy "
            f"{_num(fin.get('energy'))} J; work by the pivot {_num(res.get('work_by_pivot'))} J;"
            f" dissipated {_num(res.get('dissipated'))} J"
        )
    elif problem.kind == "lagrange":
        click.echo(
            f"  motion: {a['motion']}; theta in [{_num(a['theta_min'], '.5f')}, "
            f"{_num(a['theta_max'], '.5f')}] rad;"
            f" nutation period {_num(a['nutation_period'])} s;"
            f" mean precession {_num(a['mean_precession_rate'])} rad/s"
        )
    elif problem.kind == "heavy":
        click.echo(f"  kind: {a['kind']}")
    else:
        inv = res.get("inversion_time")
        head = (
            f"  alpha = {_num(a['alpha'], '.4g')}, gamma = {_num(a['gamma'], '.4g')}"
            + (" (a tippe top)" if a["tippe_top"] else "")
            if "alpha" in a
            else f"  parts: {', '.join(a['parts'])}"
        )
        ends = [e for e in res["events"] if e["name"] in ("flat", "rest")]
        # A run that ends at rest is at rest, whatever contact mode its last step was in.
        at_rest = bool(res["events"]) and res["events"][-1]["name"] == "rest"
        click.echo(
            head
            + f"; final u = {_num(res['final']['u'], '.5f')} "
            + f"({'at rest' if at_rest else res['final']['mode']})"
            + (f"; u rose through 0.9 at t = {_num(inv, '.4f')} s" if inv is not None else "")
            + "".join(f"; {e['name']} at t = {_num(e['t'], '.4f')} s" for e in ends)
        )
        parts = res.get("parts", {})
        if len(parts) > 1:
            words = {"touchdown": "touches", "lift_off": "leaves"}
            steps = [e for e in res["events"] if e.get("part") and e["name"] in words]
            shown = ", ".join(f"{e['part']} {words[e['name']]} {_num(e['t'], '.4f')} s"
                              for e in steps[:6])  # fmt: skip
            more = f" (+{len(steps) - 6} more)" if len(steps) > 6 else ""
            end = (
                ", ".join(
                    n + (f" ({p['state_at_end']})" if p.get("state_at_end") else "")
                    for n, p in parts.items()
                    if p["in_contact_at_end"]
                )
                or "none"
            )
            click.echo(f"  contacts: {shown or 'no change'}{more}; on the floor at the end: {end}")
        total = max(1, res["samples"])
        shares = [
            f"{name} " + ", ".join(f"{k} {100 * v / total:.0f}%" for k, v in p["states"].items())
            for name, p in parts.items()
            if p.get("states")
        ]
        if shares:
            click.echo(f"  contact states (share of samples): {'; '.join(shares)}")
    drift = ", ".join(f"{k} {_num(v, '.1e')}" for k, v in res["invariant_drift"].items())
    if drift:
        click.echo(f"  largest relative drift: {drift}")
    files = data["files"]
    listed = [files["summary"], files["trajectory"], *files.get("figures", [])]
    if "animation" in files:
        listed.append(files["animation"])
    click.echo(f"wrote {out}/: {', '.join(listed)}")


def _num(x, spec=".6g"):
    """A number of the JSON summary: a float, or "inf" / "-inf" (a string), or None (nan)."""
    if x is None:
        return "nan"
    return x if isinstance(x, str) else format(x, spec)


def _to_toml(name: str, tables: dict) -> str:
    from ._config import to_toml
    from ._presets import PRESETS

    return to_toml(tables, [PRESETS[name].summary, "kreisel run FILE.toml"])


def _fail(message: str, code: int, command: str | None = None) -> int:
    line = " ".join(str(message).split())
    where = f"kreisel {command}" if command else "kreisel"
    print(f"{where}: error: {line}", file=sys.stderr)
    return code


# click >= 8.2 raises this for a bare `kreisel`; older versions print the help themselves
_NO_ARGS = getattr(click.exceptions, "NoArgsIsHelpError", ())


def main(argv=None) -> int:
    """The console script: runs the command line, returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    try:
        rv = cli.main(args=argv, prog_name="kreisel", standalone_mode=False)
    except _NO_ARGS as e:
        click.echo(e.ctx.get_help() if e.ctx else str(e))
        return 0
    except click.UsageError as e:
        hint = f" (see `{e.ctx.command_path} --help`)" if e.ctx is not None else ""
        return _fail(e.format_message() + hint, 2, command if command in cli.commands else None)
    except click.Abort:
        return _fail("aborted", 1, command)
    except ParameterError as e:
        return _fail(str(e), 2, command)
    except NumericalError as e:
        return _fail(str(e), 1, command)
    except ModuleNotFoundError as e:
        if e.name is None or e.name.split(".")[0] == "kreisel":
            raise
        from ._extras import missing_message

        return _fail(missing_message(e.name), 1, command)
    return rv if isinstance(rv, int) else 0


if __name__ == "__main__":
    sys.exit(main())
