"""One run of the command line: compute the motion of a checked problem, then write the JSON
summary, the trajectory (NetCDF or CSV), the figures and an animation."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ._config import Problem
from ._simulate import names

FORMATS = ("netcdf", "csv")
ANIMATIONS = ("gif", "mp4", "html")


def compute(problem: Problem):
    """The trajectory of ``problem``: the exact solution or a simulation."""
    from . import events, simulate

    s = problem.settings
    t_eval = None if s.samples is None else np.linspace(0.0, s.t_end, s.samples)
    if s.exact:
        return problem.model.exact(problem.state, t_eval)
    # a play top's run ends when it has stopped (the kinetic energy at 1e-12 of its start)
    evs = [events.inversion(0.9), events.rest()] if problem.kind == "play" else None
    return simulate(
        problem.model, problem.state, s.t_end, method=s.method, rtol=s.rtol, atol=s.atol,
        dt=s.dt, t_eval=t_eval, events=evs,
    )  # fmt: skip


def _clean(x):
    """JSON-safe: numpy scalars to Python, nan to null, inf to "inf"."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, np.ndarray):
        return _clean(x.tolist())
    if isinstance(x, (np.floating, float)):
        x = float(x)
        if math.isnan(x):
            return None
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return x
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.str_):
        return str(x)
    return x


def summary(problem: Problem, traj) -> dict:
    """What the run found, as plain JSON-ready data."""
    from . import __version__
    from ._diagnostics import conserved, relative_drift
    from ._trajectory import COLUMNS

    model, state = problem.model, problem.state
    out: dict[str, Any] = {
        "kreisel": __version__,
        "kind": problem.kind,
        "preset": problem.preset,
        "top": {"repr": repr(model), **problem.tables["top"]},
        "state": {"repr": repr(state), **problem.tables["state"]},
        "simulation": problem.settings.as_dict(),
    }
    if problem.kind in ("lagrange", "heavy") and model.driven:
        out["analysis"] = {
            "kind": getattr(model, "kind", "lagrange"),
            "pivot": repr(model.pivot),
            "damping": repr(model.damping),
        }
    elif problem.kind == "lagrange":
        a = model.analyse(state)
        inv = model.invariants(state)
        omega3 = state.psi_dot + state.phi_dot * math.cos(state.theta)
        # A steady precession has 0 < theta < pi; at the vertical (a sleeping or hanging
        # top) the sleeping threshold says what there is to say.
        at_vertical = state.theta in (0.0, math.pi)
        rates = None if at_vertical else list(model.steady_precession(state.theta, omega3))
        out["analysis"] = {
            "motion": a.kind,
            "theta_min": a.theta_min,
            "theta_max": a.theta_max,
            "nutation_period": a.nutation_period,
            "mean_precession_rate": a.mean_precession_rate,
            "invariants": {"E": inv.E, "Mz": inv.Mz, "M3": inv.M3},
            "sleeping_threshold": model.sleeping_threshold(),
            "omega3": omega3,
            "steady_precession_rates": rates,
        }
    elif problem.kind == "heavy":
        out["analysis"] = {"kind": model.kind, "invariants": model.invariants(state)}
    elif model._p["rho"] > 0:
        a, g = model.alpha, model.gamma
        out["analysis"] = {
            "alpha": a,
            "gamma": g,
            "tippe_top": bool(a < 1 and 1 - a < g < 1 + a),
            "J_beta": model.J_beta,
            "jellett": model.jellett(state),
            "energy": model.energy(state),
        }
    else:
        # a body whose first part is no tip sphere: the one-sphere theory does not apply
        out["analysis"] = {"parts": list(model.part_names), "energy": model.energy(state)}
    t = traj.t
    res: dict[str, Any] = {"samples": len(t), "t_end": float(t[-1]) if len(t) else 0.0}
    stats = getattr(traj, "stats", None)
    if stats:
        res["stats"] = dict(stats)
    evs = getattr(traj, "events", None) or []
    res["events"] = [
        {"name": e.name, "t": e.t, **({"part": e.part} if getattr(e, "part", None) else {})}
        for e in evs[:1000]
    ]
    if len(evs) > 1000:
        res["events_left_out"] = len(evs) - 1000
    res["final"] = {k: traj[k][-1] for k in ("theta", "phi", "psi") if k in traj.columns}
    if problem.kind == "play":
        res["final"].update(u=traj.u[-1], mode=str(traj.mode[-1]), com=traj.com[-1])
        inv = [e.t for e in evs if e.name == "inversion"]
        res["inversion_time"] = inv[0] if inv else None
        res["dissipated"] = traj.dissipated[-1]
        res["modes"] = {m: int(np.count_nonzero(traj.mode == m)) for m in names()["modes"]}
        if len(traj):
            touching = traj.part_in_contact[-1]
            states = traj.part_modes or {}
            res["parts"] = {
                name: {
                    "in_contact_at_end": bool(touching[i]),
                    # the part's contact state at the end and its samples in each state
                    "state_at_end": str(states[name][-1]) if name in states else None,
                    "states": {
                        s: int(np.count_nonzero(states[name] == s))
                        for s in names()["part_modes"]
                        if name in states and np.any(states[name] == s)
                    },
                    "first_touchdown": next(
                        (e.t for e in evs if e.name == "touchdown" and e.part == name), None
                    ),
                    "first_lift_off": next(
                        (e.t for e in evs if e.name == "lift_off" and e.part == name), None
                    ),
                }
                for i, name in enumerate(traj.part_names)
            }
    if "balance" in traj.columns:
        res["work_by_pivot"] = traj.work_by_pivot[-1]
        res["dissipated"] = traj.dissipated[-1]
        res["final"]["energy"] = traj.energy[-1]
    res["invariant_drift"] = {
        k: float(relative_drift(y, scale).max()) for k, _l, y, scale in conserved(traj)
    }
    out["result"] = res
    out["columns"] = {k: COLUMNS.get(k, ("", ""))[0] for k in traj.columns}
    return _clean(out)


def figure_names(kind: str, driven: bool = False) -> list[str]:
    names = ["time_series", "axis_path", "invariant_drift"]
    if kind == "lagrange" and not driven:
        names.append("effective_potential")
    if kind == "play":
        names.append("contact_track")
    return names


def _title(problem: Problem) -> str:
    return problem.preset or f"{problem.kind} top"


def write_figure(name: str, problem: Problem, traj, path: Path):
    from . import plot

    plt = plot._pyplot()
    title = _title(problem)
    if name == "time_series":
        if problem.kind == "play":
            fig = plot.play_time_series(traj)
            fig.suptitle(
                f"{title}: the top's contact mode shaded (slip tan, roll blue, flight green), "
                "each part's state above",
                fontsize=10,
            )
        else:
            fig = plot.rigid_time_series(traj)
            fig.suptitle(f"{title}: {repr(problem.model)}", fontsize=9)
        fig.tight_layout()
    elif name == "axis_path":
        fig = plt.figure(figsize=(12, 5))
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        plot.axis_path_on_sphere(traj, ax=ax)
        ax.set_title("tip of the figure axis on the unit sphere")
        ax.view_init(elev=30, azim=-60)
        ax2 = fig.add_subplot(1, 2, 2)
        plot.axis_path_phi_theta(traj, ax=ax2)
        ax2.set_title(r"the figure axis in the ($\phi$, $\theta$) plane")
        fig.suptitle(title)
        fig.tight_layout()
    elif name == "invariant_drift":
        fig, ax = plt.subplots(figsize=(8, 4.5))
        plot.invariant_drift(traj, ax=ax)
        solver = problem.settings.as_dict()["solver"]
        fig.suptitle(f"{title}: drift of the conserved quantities ({solver})")
        fig.tight_layout()
    elif name == "effective_potential":
        fig, ax = plt.subplots(figsize=(7, 4.5))
        plot.effective_potential(problem.model, problem.state, ax=ax)
        ax.set_title(f"{title}: effective potential, energy and turning points")
        fig.tight_layout()
    elif name == "contact_track":
        fig, ax = plt.subplots(figsize=(6.5, 6.5))
        plot.contact_track(traj, ax=ax)
        ax.set_title(f"{title}: the contact point's track on the floor")
        fig.tight_layout()
    else:  # pragma: no cover
        raise ValueError(name)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_trajectory(problem: Problem, traj, path: Path, fmt: str):
    if fmt == "netcdf":
        from . import __version__

        ds = traj.to_xarray()
        ds.attrs.update(kreisel=__version__, kind=problem.kind, preset=problem.preset or "")
        ds.to_netcdf(path, engine="scipy")
    else:
        traj.to_pandas().to_csv(path)


def write_animation(problem: Problem, traj, path: Path, kind: str, frames: int, fps: float,
                    progress=None):  # fmt: skip
    from . import animate

    title = _title(problem)
    if kind == "gif":
        animate.to_gif(traj, path, frames=frames, fps=fps, title=title, progress=progress)
    elif kind == "mp4":
        animate.to_mp4(traj, path, frames=frames, fps=fps, title=title, progress=progress)
    else:
        animate.to_html(traj, path, frames=frames, title=title)
        if progress is not None:
            progress(frames)


def run(problem: Problem, out: Path, *, fmt="netcdf", figures=True, animation=None, frames=60,
        fps=15.0, progress=None) -> dict:  # fmt: skip
    """Computes and writes everything; returns the summary (with ``files``).

    ``progress(n, label)`` is called as the work advances (n units: 1 for the motion, 1 for
    the trajectory file, 1 per figure, 1 per animation frame).
    """

    def step(n, label):
        if progress is not None:
            progress(n, label)

    out.mkdir(parents=True, exist_ok=True)
    step(0, "computing the motion")
    traj = compute(problem)
    step(1, "writing the trajectory")
    files: dict[str, Any] = {}
    ext = {"netcdf": "nc", "csv": "csv"}[fmt]
    path = out / f"trajectory.{ext}"
    write_trajectory(problem, traj, path, fmt)
    files["trajectory"] = path.name
    step(1, "writing the trajectory")
    if figures:
        files["figures"] = []
        for name in figure_names(problem.kind, getattr(problem.model, "driven", False)):
            p = out / f"{name}.png"
            step(0, f"drawing {p.name}")
            write_figure(name, problem, traj, p)
            files["figures"].append(p.name)
            step(1, f"drawing {p.name}")
    if animation is not None:
        p = out / f"animation.{animation}"
        rendered = [0]

        def frame(n):
            # the last frame rendered, the file is encoded and written
            rendered[0] += n
            last = rendered[0] >= frames
            step(n, f"writing {p.name}" if last else f"rendering {p.name}")

        write_animation(problem, traj, p, animation, frames, fps, progress=frame)
        files["animation"] = p.name
    data = summary(problem, traj)
    files["summary"] = "summary.json"
    data["files"] = files
    (out / "summary.json").write_text(json.dumps(data, indent=2) + "\n")
    return data


def work_units(kind: str, figures: bool, animation, frames: int, driven: bool = False) -> int:
    n_fig = len(figure_names(kind, driven)) if figures else 0
    return 2 + n_fig + (frames if animation else 0)
