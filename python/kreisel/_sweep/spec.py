"""The sweep spec: its tables checked, the swept values, the chunks, and the names of the
summaries (see :mod:`kreisel._sweep` for the tables)."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _config, _core
from .._errors import ParameterError

# Every name below is the core's (kreisel._core.names(), declared once in
# crates/kreisel-core/src/simulate/names.rs): summaries with their descriptions and units,
# contact modes, kinds of motion.
_NAMES = _core.names()
_FIELDS = _NAMES["summaries"]


def _of(model: str, default_only: bool = False) -> tuple:
    return tuple(
        f["name"] for f in _FIELDS if f["model"] == model and (f["default"] or not default_only)
    )


SUMMARIES = {"play": _of("play"), "heavy": _of("heavy")}
SUMMARIES["lagrange"] = SUMMARIES["heavy"]
# kept unless the spec says otherwise (the Lyapunov exponent costs two more runs: on request)
DEFAULT_KEEP = {k: _of("heavy" if k == "lagrange" else k, True) for k in SUMMARIES}
DESCRIPTIONS = {f["name"]: f["description"] for f in _FIELDS}
# a part's first touchdown by the part's name: first_touchdown_time_<name>
TOUCHDOWN = "first_touchdown_time_"


def part_names(top: dict) -> list[str]:
    """The names of a play top's parts in a [top] table: its shape's, else the tip sphere's."""
    shape = top.get("shape")
    if not isinstance(shape, list):
        return ["tip"]
    return [
        p.get("name") or f"part{i}" if isinstance(p, dict) else f"part{i}"
        for i, p in enumerate(shape)
    ]


def part_summary(name: str, top: dict) -> str | None:
    """The core's summary behind ``first_touchdown_time_<part name>`` (the part by its
    position), None where ``name`` is no such summary of this top."""
    if not name.startswith(TOUCHDOWN):
        return None
    names = part_names(top)
    part = name[len(TOUCHDOWN) :]
    return f"{TOUCHDOWN}{names.index(part)}" if part in names else None


def description(name: str) -> str:
    """A summary's description, a part's touchdown included."""
    if name in DESCRIPTIONS:
        return DESCRIPTIONS[name]
    return f"first touchdown of part {name[len(TOUCHDOWN) :]!r} (s), NaN if none"


UNITS = {f["name"]: f["unit"] for f in _FIELDS}
MODES = tuple(_NAMES["modes"])
MOTION_KINDS = tuple(_NAMES["motion_kinds"])
# summaries with a few named values, stored as small integer codes (CF flag convention)
CATEGORIES = {f["name"]: tuple(_NAMES[f["category"]]) for f in _FIELDS if f["category"]}
MODE_PENDING, MODE_ERROR = -1, _NAMES["category_error"]
# the exact Lagrange top: no integration, the analysis of each state
EXACT_SUMMARIES = _of("exact")
SWEEP_TABLES = (*_config.TABLES, "grid", "random", "output")
OUTPUT_FIELDS = ("keep", "chunk", "inversion_level", "lyapunov_tau")
DEFAULT_CHUNK = 1024  # runs per store chunk: each chunk written costs ~10 ms of CPU (8 arrays)
MAX_RUNS = 100_000_000


@dataclass(frozen=True)
class SweepSpec:
    """A checked sweep: the fixed tables, the swept values and what to keep.

    Build one with :meth:`from_tables` (a dict of tables) or :meth:`from_toml` (a file).

    Examples
    --------
    >>> from kreisel import SweepSpec
    >>> spec = SweepSpec.from_tables({
    ...     "top": {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1},
    ...     "state": {"psi_dot": 150.0},
    ...     "simulation": {"exact": True},
    ...     "grid": {"theta": [0.3, 0.5, 0.7]},
    ... })
    >>> spec.kind, spec.dims, spec.shape, spec.n_chunks
    ('lagrange', ('theta',), (3,), 1)
    """

    kind: str
    top: dict
    state: dict
    simulation: dict
    grid: dict
    random: dict
    n_samples: int
    seed: int
    keep: tuple
    chunk: int
    inversion_level: float
    lyapunov_tau: float = 1.0

    # ----------------------------------------------------------------------------------
    # construction
    # ----------------------------------------------------------------------------------

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> SweepSpec:
        """The spec in a TOML file (path): the tables of :meth:`from_tables`.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> from kreisel import SweepSpec
        >>> text = '[top]\\npreset = "cusps"\\n[simulation]\\nexact = true\\n'
        >>> text += '[grid]\\ntheta = [0.3, 0.5]\\n'
        >>> tmp = tempfile.TemporaryDirectory()
        >>> path = pathlib.Path(tmp.name) / "sweep.toml"
        >>> _ = path.write_text(text)
        >>> spec = SweepSpec.from_toml(path)
        >>> spec.kind, spec.dims, spec.shape
        ('lagrange', ('theta',), (2,))
        >>> tmp.cleanup()
        """
        return cls.from_tables(_config.read_toml(path), source=str(path))

    @classmethod
    def from_tables(cls, tables: dict, *, source: str = "") -> SweepSpec:
        """The spec from its tables ``top``, ``state``, ``simulation``, ``grid``, ``random`` and
        ``output`` (a dict of dicts); ``source`` names the file in error messages.

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> grid = {"theta": [0.3, 0.5, 0.7], "psi_dot": [100.0, 150.0]}
        >>> spec = SweepSpec.from_tables({"top": top, "simulation": {"exact": True}, "grid": grid})
        >>> spec.dims, spec.shape, spec.size
        (('theta', 'psi_dot'), (3, 2), 6)
        """
        head = f"{source}: " if source else ""
        if not isinstance(tables, dict):
            raise ParameterError(f"{head}a sweep spec must be a table of tables")
        for key in tables:
            if key not in SWEEP_TABLES:
                raise ParameterError(
                    f"{head}[{key}] is not a known table of a sweep: allowed are "
                    + ", ".join(f"[{t}]" for t in SWEEP_TABLES)
                )
        for key in SWEEP_TABLES:
            if not isinstance(tables.get(key, {}), dict):
                raise ParameterError(f"{head}[{key}] must be a table")
        top = dict(tables.get("top", {}))
        state = dict(tables.get("state", {}))
        sim = dict(tables.get("simulation", {}))
        drive = {t: dict(tables[t]) for t in _config.DRIVE_TABLES if t in tables}
        chosen = top.pop("preset", None)
        if chosen is not None:
            base = _config.preset(chosen)
            merged = _config.overlay(base, {"top": top, "state": state, "simulation": sim})
            top, state, sim = merged["top"], merged["state"], merged["simulation"]
            if "samples" not in tables.get("simulation", {}):
                sim.pop("samples", None)  # a preset's output samples: a sweep keeps summaries
            for t in _config.DRIVE_TABLES:
                if t in base and t not in drive:
                    drive[t] = dict(base[t])
        kind = top.pop("kind", None)
        if kind not in _config.KINDS:
            raise ParameterError(
                f"{head}[top] kind = {kind!r} is not allowed: use one of "
                f"{', '.join(_config.KINDS)} (or a preset)"
            )
        if sim.get("samples") is not None:
            raise ParameterError(
                f"{head}[simulation] samples = {sim['samples']!r} is not allowed in a sweep: "
                "sweeps keep summaries, not trajectories"
            )
        exact = sim.get("exact", False)
        if exact is not True:
            sim.pop("exact", None)
            if kind == "lagrange":
                sim.setdefault("method", "dop853")
        elif kind != "lagrange":
            raise ParameterError(
                f"{head}[simulation] exact = true is not allowed: only a lagrange top has an "
                "exact solution"
            )
        swept_names = _sweepable(kind)
        grid = _grid(tables.get("grid", {}), swept_names, f"{head}[grid] ")
        random, n, seed = _random(tables.get("random", {}), swept_names, f"{head}[random] ")
        both = set(grid) & set(random)
        if both:
            raise ParameterError(
                f"{head}{sorted(both)[0]} is swept in both [grid] and [random]: choose one"
            )
        if not grid and not random:
            # a field that is wrong is the first thing to say
            if all(k in top for k in _config.required(kind, top)):
                model = _config._model(kind, dict(top), f"{head}[top] ")
                _config._state(kind, model, dict(state), f"{head}[state] ")
            raise ParameterError(
                f"{head}nothing is swept: give [grid] values or [random] samples of at least "
                f"one of {', '.join(swept_names)}"
            )
        if drive and kind == "play":
            raise ParameterError(
                f"{head}[{next(iter(drive))}] is not allowed for a play top: a moving or damped "
                "pivot belongs to a heavy or lagrange top"
            )
        swept = [*grid, *random]
        for name in swept:
            table, field = _where(kind, name)
            if table in _config.DRIVE_TABLES:
                given = drive.get(table, {})
                if field in given and field != "amplitude":
                    if field in tables.get(table, {}):
                        raise ParameterError(
                            f"{head}{name} is swept and also fixed in [{table}]: give it once"
                        )
                    del given[field]  # a preset's value gives way to the sweep
                continue
            fixed = top if table == "top" else state
            if field in fixed and field != "com":
                if chosen is None or field in tables.get(table, {}):
                    raise ParameterError(
                        f"{head}{name} is swept and also fixed in [{table}]: give it once"
                    )
                del fixed[field]  # a preset's value gives way to the sweep
        # placeholders let the fixed tables be checked field by field now
        top.update(drive)  # the pivot and damping tables travel inside [top]
        probe_top, probe_state = _compose(
            kind, top, state, {k: _first(grid, random, k) for k in swept}
        )
        probe_drive = {t: probe_top.pop(t) for t in _config.DRIVE_TABLES if t in probe_top}
        settings = _config.from_tables(
            {
                "top": {"kind": kind, **probe_top},
                **probe_drive,
                "state": probe_state,
                "simulation": sim,
            },
            prefix="table",
            source=source,
        ).settings
        sim = {
            "t_end": settings.t_end,
            "method": settings.method,
            "rtol": settings.rtol,
            "atol": settings.atol,
            "dt": settings.dt,
            "exact": settings.exact,
        }
        out = dict(tables.get("output", {}))
        _config._check_fields(f"{head}[output] ", out, OUTPUT_FIELDS, "of the output")
        allowed = EXACT_SUMMARIES if sim["exact"] else SUMMARIES[kind]
        what = "the exact solution" if sim["exact"] else f"a {kind} top's run"
        keep = out.get("keep", list(EXACT_SUMMARIES if sim["exact"] else DEFAULT_KEEP[kind]))
        if isinstance(keep, str) or not isinstance(keep, (list, tuple)) or not keep:
            raise ParameterError(
                f"{head}[output] keep = {keep!r} is not allowed: give a non-empty list of "
                f"{', '.join(allowed)}"
            )
        for k in keep:
            if k not in allowed and (kind != "play" or part_summary(k, top) is None):
                named = (
                    ", first_touchdown_time_<part> (a part's name: "
                    + ", ".join(part_names(top)) + ")"
                    if kind == "play" else ""
                )  # fmt: skip
                raise ParameterError(
                    f"{head}[output] keep contains {k!r}, which is not a summary of {what}: "
                    f"allowed are {', '.join(allowed)}{named}"
                )
        chunk = out.get("chunk", DEFAULT_CHUNK)
        if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
            raise ParameterError(
                f"{head}[output] chunk = {chunk!r} is not allowed: give a whole number of runs >= 1"
            )
        level = _config._real(
            f"{head}[output] ", "inversion_level", out.get("inversion_level", 0.9)
        )
        try:  # the inversion event's rule is the core's
            _core.check_event(("inversion", "inversion", None, level, 1, False))
        except ParameterError as e:
            raise ParameterError(f"{head}[output] inversion_{e}") from None
        lyapunov_tau = _config._real(f"{head}[output] ", "lyapunov_tau",
                                     out.get("lyapunov_tau", min(1.0, sim["t_end"])))  # fmt: skip
        if "lyapunov_tau" in out and "lyapunov" not in keep:
            raise ParameterError(
                f"{head}[output] lyapunov_tau is given but lyapunov is not kept: add it to keep"
            )
        if not 0 < lyapunov_tau <= sim["t_end"]:
            raise ParameterError(
                f"{head}[output] lyapunov_tau = {lyapunov_tau} is not allowed: it must lie in "
                f"(0, t_end = {sim['t_end']}]"
            )
        spec = cls(
            kind,
            top,
            state,
            sim,
            grid,
            random,
            n,
            seed,
            tuple(dict.fromkeys(keep)),
            int(chunk),
            level,
            lyapunov_tau,
        )
        if spec.size > MAX_RUNS:
            raise ParameterError(
                f"{head}the sweep has {spec.size} runs, more than {MAX_RUNS}: split it"
            )
        spec._check_models(head)
        return spec

    def _check_models(self, head: str):
        """Every value of every swept top parameter builds a top (the others at their first
        values), so a bad value fails now, not in the middle of the sweep."""
        first = {k: _first(self.grid, self.random_values(), k) for k in self.swept}
        for name in self.swept:
            if _where(self.kind, name)[0] == "state":
                continue
            values = self.grid.get(name)
            if values is None:
                lo, hi, _ = self.random[name]
                values = np.array([lo, hi])
            for v in values:
                top, _ = _compose(self.kind, self.top, self.state, {**first, name: v})
                try:
                    _config._model(self.kind, top, "")
                except ParameterError as e:
                    table = "grid" if name in self.grid else "random"
                    raise ParameterError(f"{head}[{table}] {name} = {v:g}: {e}") from None

    # ----------------------------------------------------------------------------------
    # geometry
    # ----------------------------------------------------------------------------------

    @property
    def swept(self) -> tuple:
        """The names of the swept fields: the grid's, then the random ones."""
        return (*self.grid, *self.random)

    @property
    def dims(self) -> tuple:
        """The dimensions of the results: the grid's fields, then ``"sample"`` if random."""
        return (*self.grid, *(("sample",) if self.random else ()))

    @property
    def shape(self) -> tuple:
        """The number of values along each dimension of :attr:`dims`."""
        return (*(len(v) for v in self.grid.values()), *((self.n_samples,) if self.random else ()))

    @property
    def size(self) -> int:
        """The number of runs."""
        return int(np.prod(self.shape, dtype=np.int64))

    @property
    def block(self) -> tuple:
        """The shape of one chunk: whole trailing dimensions while they fit in ``chunk``
        runs, then a part of the next one, then 1."""
        out, room = [], self.chunk
        for n in reversed(self.shape):
            take = max(1, min(n, room))
            out.append(take)
            room = max(1, room // take) if take == n else 1
        return tuple(reversed(out))

    @property
    def chunk_grid(self) -> tuple:
        """The number of chunks along each dimension."""
        return tuple(-(-n // b) for n, b in zip(self.shape, self.block))

    @property
    def n_chunks(self) -> int:
        """The number of chunks of the store."""
        return int(np.prod(self.chunk_grid, dtype=np.int64))

    def chunk_slices(self, k: int) -> tuple:
        """The slices (one per dimension) of chunk ``k`` (C order over :attr:`chunk_grid`).

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> grid = {"theta": [0.1, 0.2, 0.3, 0.4, 0.5]}
        >>> tables = {"top": top, "simulation": {"exact": True}, "grid": grid}
        >>> spec = SweepSpec.from_tables({**tables, "output": {"chunk": 2}})
        >>> spec.n_chunks, [(int(s.start), int(s.stop)) for s in spec.chunk_slices(2)]
        (3, [(4, 5)])
        """
        idx = np.unravel_index(k, self.chunk_grid)
        return tuple(
            slice(i * b, min((i + 1) * b, n)) for i, b, n in zip(idx, self.block, self.shape)
        )

    def random_values(self) -> dict:
        """The random samples (drawn in the order given, from one generator).

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> rnd = {"n": 3, "seed": 1, "theta": {"low": 0.1, "high": 1.0}}
        >>> spec = SweepSpec.from_tables({"top": top, "simulation": {"exact": True}, "random": rnd})
        >>> spec.dims, [round(float(x), 6) for x in spec.random_values()["theta"]]
        (('sample',), [0.560639, 0.955417, 0.229744])
        """
        rng = np.random.default_rng(self.seed)
        out = {}
        for name, (lo, hi, scale) in self.random.items():
            if scale == "log":
                out[name] = np.exp(rng.uniform(np.log(lo), np.log(hi), self.n_samples))
            else:
                out[name] = rng.uniform(lo, hi, self.n_samples)
        return out

    def chunk_values(self, k: int, samples: dict | None = None) -> dict:
        """The swept values of every run of chunk ``k`` (C order within the block).

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> grid = {"theta": [0.3, 0.5], "psi_dot": [100.0, 150.0]}
        >>> spec = SweepSpec.from_tables({"top": top, "simulation": {"exact": True}, "grid": grid})
        >>> {k: v.tolist() for k, v in spec.chunk_values(0).items()}
        {'theta': [0.3, 0.3, 0.5, 0.5], 'psi_dot': [100.0, 150.0, 100.0, 150.0]}
        """
        sl = self.chunk_slices(k)
        axes = [v[s] for v, s in zip(self.grid.values(), sl)]
        if self.random:
            axes.append(np.arange(self.n_samples)[sl[-1]])
        mesh = np.meshgrid(*axes, indexing="ij")
        out = {name: m.ravel() for name, m in zip(self.grid, mesh)}
        if self.random:
            samples = self.random_values() if samples is None else samples
            pick = mesh[-1].ravel()
            for name in self.random:
                out[name] = samples[name][pick]
        return out

    # ----------------------------------------------------------------------------------
    # identity
    # ----------------------------------------------------------------------------------

    def as_dict(self) -> dict:
        """Plain tables (lists, floats, strings) that rebuild this spec.

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> tables = {"top": top, "simulation": {"exact": True}, "grid": {"theta": [0.3, 0.5]}}
        >>> d = SweepSpec.from_tables(tables).as_dict()
        >>> d["kind"], d["grid"], d["chunk"], d["keep"][:2]
        ('lagrange', {'theta': [0.3, 0.5]}, 1024, ['motion_kind', 'theta_min'])
        """
        return {
            "kind": self.kind,
            "top": _plain(self.top),
            "state": _plain(self.state),
            "simulation": _plain(self.simulation),
            "grid": {k: [float(x) for x in v] for k, v in self.grid.items()},
            "random": {k: [lo, hi, s] for k, (lo, hi, s) in self.random.items()},
            "n_samples": self.n_samples,
            "seed": self.seed,
            "keep": list(self.keep),
            "chunk": self.chunk,
            "inversion_level": self.inversion_level,
            "lyapunov_tau": self.lyapunov_tau,
        }

    def canonical(self) -> str:
        """The spec as sorted JSON: two sweeps are the same sweep iff these are equal.

        Examples
        --------
        >>> from kreisel import SweepSpec
        >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
        >>> a = SweepSpec.from_tables({"top": top, "grid": {"theta": [0.3, 0.5]}})
        >>> rev = dict(reversed(top.items()))
        >>> b = SweepSpec.from_tables({"grid": {"theta": [0.3, 0.5]}, "top": rev})
        >>> a.canonical() == b.canonical(), a.canonical()[:30]
        (True, '{"chunk": 1024, "grid": {"thet')
        """
        return json.dumps(self.as_dict(), sort_keys=True)


def _plain(d: dict) -> dict:
    out: dict[str, Any] = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out[k] = _plain(v)  # a [pivot] or [damping] table
        elif isinstance(v, (list, tuple)) and v and all(isinstance(x, dict) for x in v):
            out[k] = [_plain(x) for x in v]  # a shape: its parts' tables
        elif isinstance(v, (np.ndarray, list, tuple)):
            out[k] = [float(x) for x in v]
        elif isinstance(v, (bool, str)) or v is None:
            out[k] = v
        else:
            out[k] = float(v)
    return out


# Swept fields of a moving or damped pivot: name -> (table, field).
_DRIVE_SWEPT = {
    "pivot_omega": ("pivot", "omega"),
    "pivot_phase": ("pivot", "phase"),
    "pivot_amplitude_x": ("pivot", "amplitude"),
    "pivot_amplitude_y": ("pivot", "amplitude"),
    "pivot_amplitude_z": ("pivot", "amplitude"),
    **{f: ("damping", f) for f in _config.DAMPING_FIELDS},
}


def _sweepable(kind: str) -> tuple:
    top = [f for f in _config.TOP_FIELDS[kind] if f not in ("friction", "com", "shape")]
    if kind == "heavy":
        top += ["com_x", "com_y", "com_z"]
    drive = tuple(_DRIVE_SWEPT) if kind != "play" else ()
    return (*top, *drive, *_config._EULER, *(("vx", "vy", "height") if kind == "play" else ()))


def _where(kind: str, name: str) -> tuple:
    """(table, field) of a swept name: [top], [state], or a pivot's [pivot] or [damping]."""
    if name.startswith("com_"):
        return "top", "com"
    if kind != "play" and name in _DRIVE_SWEPT:
        return _DRIVE_SWEPT[name]
    return ("top", name) if name in _config.TOP_FIELDS[kind] else ("state", name)


def _compose(kind: str, top: dict, state: dict, values: dict) -> tuple:
    """The [top] and [state] tables of one run: the fixed ones with its swept values (a
    swept pivot or damping field in the [pivot] or [damping] table carried in [top])."""
    t, s = dict(top), dict(state)
    for name, v in values.items():
        table, field = _where(kind, name)
        if table in _config.DRIVE_TABLES:
            sub = dict(t.get(table, {}))
            if field == "amplitude":
                amp = list(sub.get("amplitude", (0.0, 0.0, 0.0)))
                amp["xyz".index(name[-1])] = float(v)
                sub["amplitude"] = amp
            else:
                sub[field] = float(v)
            if table == "pivot":
                sub.setdefault("kind", "harmonic")
            t[table] = sub
        elif field == "com":
            com = list(t.get("com", (0.0, 0.0, 0.0)))
            com["xyz".index(name[-1])] = float(v)
            t["com"] = com
        elif table == "top":
            t[field] = float(v)
        else:
            s[field] = float(v)
    return t, s


def _first(grid: dict, random: dict, name: str) -> float:
    """A value of a swept parameter to stand in for it: its first grid value, else the
    first sample (or the low end of the range)."""
    return float((grid[name] if name in grid else random[name])[0])


def _number(where: str, name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ParameterError(f"{where}{name} = {value!r} is not allowed: it must be a number")
    v = float(value)
    if not np.isfinite(v):
        raise ParameterError(f"{where}{name} = {v} is not allowed: it must be finite")
    return v


def _check_name(where: str, name: str, allowed: tuple):
    if name not in allowed:
        raise ParameterError(
            f"{where}{name} is not a parameter that can be swept: allowed are {', '.join(allowed)}"
        )


def _grid(table: dict, allowed: tuple, where: str) -> dict:
    out = {}
    for name, spec in table.items():
        _check_name(where, name, allowed)
        if isinstance(spec, dict):
            extra = set(spec) - {"start", "stop", "num", "scale"}
            missing = {"start", "stop", "num"} - set(spec)
            if extra or missing:
                raise ParameterError(
                    f"{where}{name} = {spec!r} is not allowed: give {{start, stop, num}} and "
                    "optionally scale = 'linear' or 'log'"
                )
            a = _number(where, f"{name}.start", spec["start"])
            b = _number(where, f"{name}.stop", spec["stop"])
            num = spec["num"]
            if isinstance(num, bool) or not isinstance(num, (int, np.integer)) or num < 1:
                raise ParameterError(
                    f"{where}{name}.num = {num!r} is not allowed: it must be a whole number >= 1"
                )
            if num > MAX_RUNS:
                raise ParameterError(
                    f"{where}{name}.num = {num!r} is not allowed: a sweep has at most "
                    f"{MAX_RUNS} runs"
                )
            scale = spec.get("scale", "linear")
            if scale == "log":
                if not (a > 0 and b > 0):
                    raise ParameterError(
                        f"{where}{name} with scale = 'log' is not allowed from {a} to {b}: "
                        "both ends must be > 0"
                    )
                values = np.geomspace(a, b, int(num))
            elif scale == "linear":
                values = np.linspace(a, b, int(num))
            else:
                raise ParameterError(
                    f"{where}{name}.scale = {scale!r} is not allowed: use 'linear' or 'log'"
                )
        elif isinstance(spec, (list, tuple)):
            values = np.array([_number(where, name, v) for v in spec], dtype=float)
        else:
            raise ParameterError(
                f"{where}{name} = {spec!r} is not allowed: give a list of values or "
                "{start, stop, num}; a single value belongs in [top] or [state]"
            )
        if len(values) == 0:
            raise ParameterError(f"{where}{name} is an empty grid: give at least one value")
        if len(np.unique(values)) != len(values):
            raise ParameterError(f"{where}{name} repeats a value: grid values must be distinct")
        out[name] = values
    return out


def _random(table: dict, allowed: tuple, where: str) -> tuple:
    table = dict(table)
    n = table.pop("n", None)
    seed = table.pop("seed", 0)
    if not table:
        if n is not None:
            raise ParameterError(f"{where}n = {n!r} is given but no parameter is sampled")
        return {}, 0, 0
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ParameterError(
            f"{where}n = {n!r} is not allowed: give the number of samples, a whole number >= 1"
        )
    if n > MAX_RUNS:
        raise ParameterError(
            f"{where}n = {n!r} is not allowed: a sweep has at most {MAX_RUNS} runs"
        )
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ParameterError(
            f"{where}seed = {seed!r} is not allowed: it must be a whole number >= 0"
        )
    out = {}
    for name, spec in table.items():
        _check_name(where, name, allowed)
        if (
            not isinstance(spec, dict)
            or set(spec) - {"low", "high", "scale"}
            or not {
                "low",
                "high",
            }
            <= set(spec)
        ):
            raise ParameterError(
                f"{where}{name} = {spec!r} is not allowed: give {{low, high}} and optionally "
                "scale = 'linear' or 'log'"
            )
        lo = _number(where, f"{name}.low", spec["low"])
        hi = _number(where, f"{name}.high", spec["high"])
        scale = spec.get("scale", "linear")
        if scale not in ("linear", "log"):
            raise ParameterError(
                f"{where}{name}.scale = {scale!r} is not allowed: use 'linear' or 'log'"
            )
        if not lo < hi:
            raise ParameterError(f"{where}{name} from {lo} to {hi} is not allowed: need low < high")
        if scale == "log" and lo <= 0:
            raise ParameterError(f"{where}{name}.low = {lo} is not allowed with scale = 'log'")
        out[name] = (lo, hi, scale)
    return out, int(n), int(seed)


def load_spec(spec) -> SweepSpec:
    """A :class:`SweepSpec` from a spec, a dict of tables or the path of a TOML file."""
    if isinstance(spec, SweepSpec):
        return spec
    if isinstance(spec, dict):
        return SweepSpec.from_tables(spec)
    if isinstance(spec, (str, os.PathLike)):
        return SweepSpec.from_toml(spec)
    raise ParameterError(
        f"spec = {spec!r} is not allowed: give a SweepSpec, a dict of tables or a TOML path"
    )
