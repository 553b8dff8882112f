"""What the page asks of the server, as plain functions of plain data (no web framework):
the form's tables checked by kreisel's own rules, the motion, the atlas, sweep stores and
exports. Every mistake is a :class:`~kreisel.ParameterError` (or :class:`RequestError`) whose
message the page shows as it is; :func:`field_of` says which field it is about."""

from __future__ import annotations

import re
import tempfile
import time
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from .._config import (
    DAMPING_FIELDS,
    DEFAULT_T_END,
    DRIVE_TABLES,
    FRICTIONS,
    KINDS,
    SIMULATION_FIELDS,
    STATE_FIELDS,
    TABLES,
    TOP_FIELDS,
    Problem,
    from_tables,
    read_toml,
    to_toml,
)
from .._errors import ParameterError
from .._presets import PRESETS
from .._run import compute, write_trajectory
from ._fields import field_info, part_fields
from ._geometry import axis_tip, body_parts

# The fields of a [pivot] table the form shows (a path comes from a TOML file).
PIVOT_FORM = ("kind", "amplitude", "omega", "phase")

# The work one request may ask for (the page says so when a request asks for more).
MAX_SAMPLES = 20_001  # points of a run sent to the page
DEFAULT_SAMPLES = 2001  # points of a run that names none
MAX_T_END = 600.0  # s of motion in one run
MAX_FIXED_STEPS = 2_000_000  # steps of a fixed-step method (t_end / dt)
MAX_SWEEP_CELLS = 250_000  # cells of a sweep sent to the page
MAX_BODY = 64 * 1024  # bytes of a request body
MAX_STORE_NAME = 1024  # characters of a store's path under the store folder
# the (alpha, gamma) plane of the atlas view
ATLAS_ALPHA = (0.02, 1.6)
ATLAS_GAMMA = (0.2, 2.2)


class RequestError(ValueError):
    """A request the server does not serve (malformed, too big, a path outside the store);
    ``status`` is its HTTP status."""

    def __init__(self, message: str, status: int = 400) -> None:
        super().__init__(message)
        self.status = status


class File(NamedTuple):
    """A file the page downloads: its content, name and media type."""

    content: bytes | str
    name: str
    media: str


_FIELD = re.compile(r"^\[(top|state|simulation)\] (\w+)\b")


def field_of(message: str) -> tuple[str | None, str | None, str]:
    """(table, field, the API's own message) of a checked mistake: ``"[top] m = -1 is not
    allowed: ..."`` is about the field m of [top], and its message is what the constructor
    (``PlayTop(m=-1, ...)``) says.

    Examples
    --------
    >>> from kreisel.explore._api import field_of
    >>> field_of("[top] m = -1.0 is not allowed: it must be > 0 kg")
    ('top', 'm', 'm = -1.0 is not allowed: it must be > 0 kg')
    >>> field_of("samples = 3 is too many")
    (None, None, 'samples = 3 is too many')
    """
    m = _FIELD.match(message)
    if m is None:
        return None, None, message
    return m.group(1), m.group(2), message[m.end(1) + 2 :]


def schema() -> dict:
    """The forms (fields of each kind of top), the presets and the limits."""
    presets = [
        {
            "name": p.name,
            "kind": p.kind,
            "summary": p.summary,
            "tables": {
                "top": dict(p.top),
                **{t: dict(getattr(p, t)) for t in DRIVE_TABLES if getattr(p, t)},
                "state": dict(p.state),
                "simulation": dict(p.simulation),
            },
        }
        for p in PRESETS.values()
    ]
    return {
        "kinds": list(KINDS),
        "fields": {
            k: {
                "top": list(TOP_FIELDS[k]),
                "pivot": [] if k == "play" else list(PIVOT_FORM),
                "damping": [] if k == "play" else list(DAMPING_FIELDS),
                "state": list(STATE_FIELDS[k]),
                "simulation": list(SIMULATION_FIELDS),
            }
            for k in KINDS
        },
        "frictions": list(FRICTIONS),
        "info": field_info(),
        "parts": part_fields(),
        "presets": presets,
        "default_t_end": DEFAULT_T_END,
        "limits": {
            "samples": MAX_SAMPLES,
            "t_end": MAX_T_END,
            "fixed_steps": MAX_FIXED_STEPS,
            "sweep_cells": MAX_SWEEP_CELLS,
            "body_bytes": MAX_BODY,
        },
    }


def tables_of(body: Any) -> dict:
    """The ``tables`` of a request body, shaped as ``{"top": {...}, "state": {...},
    "simulation": {...}}``; the values are checked by :func:`problem`."""
    if not isinstance(body, dict) or not isinstance(body.get("tables"), dict):
        raise RequestError(
            'the request must be a JSON object with "tables": {top, state, simulation}'
        )
    tables = body["tables"]
    for key, table in tables.items():
        if key not in TABLES:
            raise RequestError(
                f"[{key}] is not a known table: allowed are " + ", ".join(f"[{t}]" for t in TABLES)
            )
        if not isinstance(table, dict):
            raise RequestError(f"[{key}] must be an object of fields")
    # a pivot's tables only where given (a play top has none)
    return {k: dict(tables.get(k, {})) for k in TABLES if k not in DRIVE_TABLES or tables.get(k)}


def problem(tables: dict) -> Problem:
    """The checked problem of ``tables``, with the page's limits: a run names its number of
    samples (``DEFAULT_SAMPLES`` when it names none, so that its TOML reproduces it), and
    asks for at most ``MAX_T_END`` s, ``MAX_SAMPLES`` samples and ``MAX_FIXED_STEPS`` steps."""
    sim = tables.setdefault("simulation", {})
    if sim.get("samples") is None:
        sim["samples"] = DEFAULT_SAMPLES
    p = from_tables(tables, prefix="table")
    s = p.settings
    if s.t_end > MAX_T_END:
        raise ParameterError(
            f"[simulation] t_end = {s.t_end} is not allowed here: kreisel explore runs at most "
            f"{MAX_T_END:g} s of motion at a time (kreisel run has no such limit)"
        )
    if s.samples is not None and s.samples > MAX_SAMPLES:
        raise ParameterError(
            f"[simulation] samples = {s.samples} is not allowed here: the page shows at most "
            f"{MAX_SAMPLES} samples of a run"
        )
    if s.dt is not None and not s.exact and s.t_end / s.dt > MAX_FIXED_STEPS:
        raise ParameterError(
            f"[simulation] dt = {s.dt} is not allowed here: t_end / dt = {s.t_end / s.dt:.3g} "
            f"steps, more than the {MAX_FIXED_STEPS:.0e} of one run of kreisel explore"
        )
    return p


def _column(x) -> list:
    """A numpy column as JSON lists (nan and inf as null)."""
    a = np.asarray(x, dtype=float)
    if np.isfinite(a).all():
        return a.tolist()
    o = a.astype(object)
    o[~np.isfinite(a)] = None
    return o.tolist()


def _quaternions(traj) -> np.ndarray:
    """The orientation at each sample; an exact Lagrange solution has Euler angles only."""
    if "quaternion" in traj.columns:
        return np.asarray(traj.quaternion)
    from .. import _core

    return np.asarray(
        _core.quaternions_from_euler(
            np.ascontiguousarray(traj.phi),
            np.ascontiguousarray(traj.theta),
            np.ascontiguousarray(traj.psi),
        )
    )


def run(tables: dict) -> dict:
    """Everything the page shows of the motion of ``tables``: the checked tables and their TOML,
    the body to draw, the orientation (and, for play tops, the centre of mass and contact
    point) at each sample, the charts' series, the events and the atlas of play tops."""
    from .._simulate import names

    p = problem(tables)
    start = time.perf_counter()
    traj = compute(p)
    elapsed = time.perf_counter() - start
    parts = body_parts(p.model)
    out: dict[str, Any] = {
        "kind": p.kind,
        "preset": p.preset,
        "tables": p.tables,
        "toml": toml(p),
        "top": repr(p.model),
        "state": repr(p.state),
        "body": {
            "parts": parts,
            "axis": axis_tip(parts),
            "origin": "com" if p.kind == "play" else "pivot",
        },
        "t": _column(traj.t),
        "quaternion": _column(_quaternions(traj)),
        "elapsed": elapsed,
    }
    u = traj.u if "u" in traj.columns else np.cos(traj.theta)
    series: dict[str, list] = {"u": _column(u)}
    evs = list(getattr(traj, "events", None) or [])
    out["events"] = [{"name": e.name, "t": float(e.t), "part": getattr(e, "part", None)}
                     for e in evs[:1000]]  # fmt: skip
    if "pivot_position" in traj.columns:
        # the body's origin, the pivot, moves: the view follows it as a play top's centre
        out["com"] = _column(traj.pivot_position)
    if p.kind == "play":
        modes = list(names()["modes"])
        out["modes"] = modes
        out["com"] = _column(traj.com)
        out["contact_point"] = _column(traj.contact_point)
        series["mode"] = [modes.index(str(m)) for m in traj.mode]
        out["contacts"] = contacts_of(p, traj)
        for i, codes in enumerate(out["contacts"]["state"]):
            series[f"part_state_{i}"] = codes
        for k in (
            "normal_force",
            "energy",
            "energy_translation",
            "energy_rotation",
            "energy_potential",
            "dissipated",
            "jellett",
        ):
            series[k] = _column(traj[k])
        inv = [e.t for e in evs if e.name == "inversion"]
        out["inversion_time"] = float(inv[0]) if inv else None
        try:
            out["atlas"] = atlas_of(p)
        except ParameterError as e:  # a top the atlas does not cover (several contact parts)
            out["atlas"], out["atlas_note"] = None, str(e)
    else:
        for k in ("energy", "potential", "Mz", "M3", "kovalevskaya", "work_by_pivot",
                  "dissipated", "balance"):  # fmt: skip
            if k in traj.columns:
                series[k] = _column(traj[k])
        if "energy" in series and "potential" in series:
            series["kinetic"] = _column(np.asarray(traj.energy) - np.asarray(traj.potential))
    out["series"] = series
    return out


def contacts_of(p: Problem, traj) -> dict:
    """Each contact part's state and forces for the page's contact-state chart and the 3D
    view's arrows: the parts' names, the state names (``names()["part_modes"]``), per part
    the state code, the contact point (m), the normal force (N) and the friction force (x, y;
    N) at each sample, and the weight m g (N) the arrows are scaled by."""
    from .._simulate import names

    states = list(names()["part_modes"])
    code = {s: k for k, s in enumerate(states)}
    modes = traj.part_modes or {}
    parts = list(modes)
    return {
        "parts": parts,
        "states": states,
        "state": [[code[str(s)] for s in modes[name]] for name in parts],
        "point": [_column(traj.part_contact_point[:, i]) for i in range(len(parts))],
        "normal": [_column(traj.part_normal_force[:, i]) for i in range(len(parts))],
        "friction": [_column(traj.part_friction_force[:, i]) for i in range(len(parts))],
        "weight": float(p.model.m * p.model.g),
    }


def toml(p: Problem) -> str:
    """The TOML file that ``kreisel run`` reproduces the run of ``p`` from."""
    what = p.preset or f"a {p.kind} top"
    return to_toml(p.tables, [f"{what}, from kreisel explore", "kreisel run FILE.toml"])


def atlas_plane() -> dict:
    """The (alpha, gamma) plane of play tops: the zone (1..8) of each cell of a grid and the
    zone boundaries gamma(alpha), for the page to paint."""
    from .._atlas import zone_boundaries, zones

    alpha = np.linspace(*ATLAS_ALPHA, 241)
    gamma = np.linspace(*ATLAS_GAMMA, 201)
    aa, gg = np.meshgrid(alpha, gamma)
    return {
        "alpha": alpha.tolist(),
        "gamma": gamma.tolist(),
        "zones": zones(aa, gg).astype(int).tolist(),
        "boundaries": {k: _column(v) for k, v in zone_boundaries(alpha).items()},
    }


def atlas_of(p: Problem) -> dict:
    """The atlas of a play top at its state: alpha, gamma, its class, J_R(u) on [-1, 1], its
    Jellett integral J and the stationary motions at J."""
    top, state = p.model, p.state
    c = top.classify()
    u = np.linspace(-1.0, 1.0, 401)
    J = float(top.jellett(state))
    motions = [
        {"kind": m.kind, "u": float(m.u), "stable": bool(m.stable), "omega3": float(m.omega3)}
        for m in top.stationary_motions(J)
    ]
    return {
        "alpha": float(top.alpha),
        "gamma": float(top.gamma),
        "type": c.type,
        "zone": int(c.zone),
        "fig3": c.fig3,
        "u": u.tolist(),
        "J_R": _column(top.J_R(u)),
        "J": J,
        "stationary": motions,
    }


# ------------------------------------------------------------------------------------------
# sweep stores under the --store folder
# ------------------------------------------------------------------------------------------


def _is_store(path: Path) -> bool:
    return (path / "zarr.json").is_file() or (path / ".zgroup").is_file()


def store_path(root: Path, name: Any) -> Path:
    """The store ``name`` (a path relative to ``root``), resolved; a path that leaves
    ``root`` (``..``, an absolute path, a symbolic link out of it) is refused."""
    if not isinstance(name, str) or not name:
        raise RequestError('"store" must be the path of a sweep store under the store folder')
    shown = repr(name) if len(name) <= 80 else f"{name[:60]!r}... ({len(name)} characters)"
    if "\x00" in name:
        raise RequestError(f"store = {shown} is not allowed: a path has no NUL character")
    if len(name) > MAX_STORE_NAME:
        raise RequestError(
            f"store = {shown} is not allowed: a store's path has at most {MAX_STORE_NAME} "
            "characters"
        )
    base = root.resolve()
    try:
        path = (base / name).resolve()
        found = _is_store(path)
    except (OSError, ValueError) as e:  # a name the file system refuses (too long a part)
        reason = e.strerror if isinstance(e, OSError) and e.strerror else str(e)
        raise RequestError(f"store = {shown} is not allowed: {reason}") from None
    if path != base and base not in path.parents:
        raise RequestError(
            f"store = {shown} is not allowed: kreisel explore reads stores only under {base}",
            status=403,
        )
    if not found:
        raise RequestError(f"store = {shown} is not allowed: there is no sweep store there", 404)
    return path


def list_stores(root: Path | None) -> list[str]:
    """The sweep stores under ``root`` (up to three folders deep), as relative paths."""
    if root is None:
        return []
    base = root.resolve()
    found: list[str] = []
    todo = [(base, 0)]
    while todo and len(found) < 200:
        folder, depth = todo.pop()
        try:
            children = sorted(folder.iterdir())
        except OSError:
            continue
        for child in children:
            if not child.is_dir() or child.is_symlink():
                continue
            if _is_store(child):
                found.append(str(child.relative_to(base)))
            elif depth < 2:
                todo.append((child, depth + 1))
    return sorted(found)


def _open(path: Path):
    from .._sweep import open_sweep

    return open_sweep(str(path))


def sweep_view(root: Path, body: Any) -> dict:
    """A summary of the store ``body["store"]`` over its first two swept parameters (further
    ones at their first value): ``var`` (default the first numeric summary), the coordinates
    and the values, with the names of the other summaries."""
    import json

    if not isinstance(body, dict):
        raise RequestError("the request must be a JSON object")
    ds = _open(store_path(root, body.get("store")))
    numeric = [k for k in ds.data_vars if ds[k].dtype.kind in "fiu" and k != "status"]
    # by default the summary `kreisel sweep` draws: the inversion time, or theta_max
    default = next((v for v in ("inversion_time", "theta_max") if v in numeric), None)
    var = body.get("var") or default or (numeric[0] if numeric else "status")
    if var not in (*numeric, "status"):
        raise RequestError(
            f"var = {var!r} is not a summary of this store: it has {', '.join(numeric)}"
        )
    da = ds[var]
    dims = list(da.dims)
    if not dims:
        raise RequestError("this store sweeps no parameter")
    da = da.isel({d: 0 for d in dims[2:]})
    values = np.asarray(da.values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    if values.size > MAX_SWEEP_CELLS:
        raise RequestError(
            f"this sweep has {values.size} cells: the page shows at most {MAX_SWEEP_CELLS}", 413
        )
    coords = {d: np.asarray(ds[d].values, dtype=float).tolist() for d in dims if d in ds.coords}
    spec = json.loads(ds.attrs["spec"])
    return {
        "store": body["store"],
        "var": var,
        "vars": numeric,
        "dims": dims,
        "coords": coords,
        "values": _column(values),
        "kind": spec["kind"],
        "units": ds[var].attrs.get("units", ""),
        "fixed": {d: coords[d][0] for d in dims[2:] if d in coords},
    }


def sweep_cell(root: Path, body: Any) -> dict:
    """The tables of the run at ``body["index"]`` (one index per swept parameter shown) of the
    store ``body["store"]``: the sweep's fixed tables with that cell's values."""
    import json

    from .._sweep.spec import _compose

    if not isinstance(body, dict):
        raise RequestError("the request must be a JSON object")
    ds = _open(store_path(root, body.get("store")))
    spec = json.loads(ds.attrs["spec"])
    dims = list(ds["status"].dims)
    index = body.get("index")
    if (
        not isinstance(index, list)
        or not 1 <= len(index) <= len(dims)
        or not all(isinstance(i, int) and not isinstance(i, bool) for i in index)
    ):
        raise RequestError(
            f'"index" must be a list of up to {len(dims)} integers, one per swept parameter'
        )
    values = {}
    for d, i in zip(dims, [*index, *[0] * (len(dims) - len(index))]):
        coord = np.asarray(ds[d].values, dtype=float)
        if not 0 <= i < len(coord):
            raise RequestError(f"index {i} of {d} is not allowed: it must lie in [0, {len(coord)})")
        values[d] = float(coord[i])
    top, state = _compose(spec["kind"], spec["top"], spec["state"], values)
    sim = {k: v for k, v in spec["simulation"].items() if v is not None}
    return {
        "tables": {"top": {"kind": spec["kind"], **top}, "state": state, "simulation": sim},
        "values": values,
    }


def trajectory_file(tables: dict, fmt: Any) -> tuple[bytes, str, str]:
    """The trajectory of ``tables`` as a file: (content, file name, media type)."""
    if fmt not in ("csv", "netcdf"):
        raise RequestError(f'format = {fmt!r} is not allowed: use "csv" or "netcdf"')
    p = problem(tables)
    traj = compute(p)
    ext, media = {"csv": ("csv", "text/csv"), "netcdf": ("nc", "application/x-netcdf")}[fmt]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"trajectory.{ext}"
        write_trajectory(p, traj, path, fmt)
        return path.read_bytes(), f"{p.preset or p.kind}.{ext}", media


# ------------------------------------------------------------------------------------------
# the requests' work, one function of the request body each (run in a process of its own by
# kreisel.explore._jobs where it computes a motion)
# ------------------------------------------------------------------------------------------


def run_request(body: Any) -> dict:
    """The answer to ``POST /api/run``: :func:`run` of the body's tables."""
    return run(tables_of(body))


def toml_file(body: Any) -> File:
    """The TOML file of the body's tables (``POST /api/export/toml``)."""
    p = problem(tables_of(body))
    return File(toml(p), f"{p.preset or p.kind}.toml", "application/toml")


def trajectory_request(body: Any) -> File:
    """The trajectory of the body's tables as CSV or NetCDF (``POST /api/export/trajectory``)."""
    fmt = body.get("format") if isinstance(body, dict) else None
    return File(*trajectory_file(tables_of(body), fmt))


def import_toml(body: Any) -> dict:
    """The checked tables of a TOML file as ``kreisel run`` reads it (``POST /api/import/toml``
    with ``{"toml": TEXT, "name": FILE NAME}``): the same reader, the same checks and messages,
    so the page runs what ``kreisel run FILE`` would."""
    if not isinstance(body, dict) or not isinstance(body.get("toml"), str):
        raise RequestError('the request must be a JSON object with "toml": the text of the file')
    name = body.get("name") if isinstance(body.get("name"), str) else "file.toml"
    name = Path(name).name[:120] or "file.toml"
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / name
        path.write_text(body["toml"], encoding="utf-8")
        try:
            tables = read_toml(path)
        except ParameterError as e:  # the message names the file as the user knows it
            raise ParameterError(str(e).replace(str(path), name)) from None
    p = from_tables(tables, prefix="table", source=name)
    return {"tables": p.tables, "preset": p.preset}
