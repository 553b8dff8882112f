"""Parameter sweeps: many runs over a grid or random samples, written chunk by chunk to a Zarr
store, computed locally by the core's parallel batch or on a Dask cluster.

A sweep spec has the tables of a ``kreisel run`` file ([top], [state], [simulation], where
[top] may name a preset) and three more:

``[grid]``
    Swept on a grid (the outer product, in the order given). Each entry is a list of values,
    or ``{start, stop, num}`` (evenly spaced) with ``scale = "log"`` for geometric spacing.
``[random]``
    ``n`` random samples (crossed with the grid if both are given) drawn with ``seed``
    (default 0); each entry ``{low, high}``, uniform, or log-uniform with ``scale = "log"``.
``[output]``
    ``keep``: the per-run summaries to store (default: all of the model's but
    ``lyapunov``); ``chunk``: runs per store chunk (default 1024; whatever the chunks, the
    runs are computed as tasks of at most 1024 runs, shorter toward the end of the sweep so
    that the cores finish together); ``inversion_level`` (play tops, default 0.9);
    ``lyapunov_tau`` (heavy tops keeping ``lyapunov``: the renormalisation interval, s).

With ``[simulation] exact = true`` a Lagrange-top sweep keeps the analysis of each state
(``motion_kind``, ``theta_min``, ``theta_max``, ``nutation_period``,
``mean_precession_rate``) and integrates nothing.

Any scalar field of [top] (not ``friction``) or Euler field of [state] can be swept; a
heavy top's centre of mass is swept by component (``com_x``, ``com_y``, ``com_z``).

The store holds one array per kept summary, indexed by the swept parameters, a ``status``
per run (0 pending, 1 done, 2 failed; the messages are in the attribute ``run_errors``),
and one completion flag per chunk, written after the chunk's data. A crash loses at most the
chunks in flight; the same call again computes only the chunks not flagged. Every run is
computed exactly as :func:`kreisel.simulate_many` computes it alone, so the results do not
depend on the chunking, the threads or the machines: local and Dask runs agree bit for bit.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
from contextlib import closing
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import _config
from .._errors import ParameterError

SUMMARIES = {
    "play": ("final_u", "final_mode", "inversion_time", "jellett_drift", "energy_drift", "steps"),
    "heavy": ("final_theta", "theta_min", "theta_max", "energy_drift", "Mz_drift", "M3_drift",
              "kovalevskaya_drift", "steps"),
}  # fmt: skip
DEFAULT_KEEP = dict(SUMMARIES)
SUMMARIES["heavy"] = (*SUMMARIES["heavy"], "lyapunov")  # on request: it costs two more runs
SUMMARIES["lagrange"] = SUMMARIES["heavy"]
DEFAULT_KEEP["lagrange"] = DEFAULT_KEEP["heavy"]
LYAPUNOV_D0 = 1e-9
LYAPUNOV_DIRECTION = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
DESCRIPTIONS = {
    "final_u": "u = cos(theta) at the end",
    "final_mode": "contact mode at the end",
    "inversion_time": "first upward crossing of the inversion level (s), NaN if none",
    "jellett_drift": "largest relative change of Jellett's integral",
    "energy_drift": "largest relative change of the energy (E + dissipated for play tops)",
    "steps": "accepted steps",
    "final_theta": "theta at the end (rad)",
    "theta_min": "smallest theta over the steps (rad)",
    "theta_max": "largest theta over the steps (rad)",
    "Mz_drift": "largest change of Mz relative to |M0|",
    "M3_drift": "largest change of M3 relative to |M0| (NaN unless symmetric)",
    "kovalevskaya_drift": "largest relative change of Kovalevskaya's K (NaN unless such a top)",
    "lyapunov": "largest Lyapunov exponent (1/s), Benettin's renormalisation over t_end",
    "motion_kind": "kind of motion of the exact solution",
    "nutation_period": "period of theta (s), inf on the separatrix",
    "mean_precession_rate": "mean of phi_dot over a nutation period (rad/s)",
}
MODES = ("slip", "roll", "flight")
MOTION_KINDS = ("sleeping", "hanging", "regular_precession", "waves", "cusps", "loops",
                "through_vertical", "asymptotic")  # fmt: skip
# summaries with a few named values, stored as small integer codes (CF flag convention)
CATEGORIES = {"final_mode": MODES, "motion_kind": MOTION_KINDS}
MODE_PENDING, MODE_ERROR = -1, -2
# the exact Lagrange top: no integration, the analysis of each state
EXACT_SUMMARIES = ("motion_kind", "theta_min", "theta_max", "nutation_period",
                   "mean_precession_rate")  # fmt: skip
SWEEP_TABLES = (*_config.TABLES, "grid", "random", "output")
OUTPUT_FIELDS = ("keep", "chunk", "inversion_level", "lyapunov_tau")
DEFAULT_CHUNK = 1024  # runs per store chunk: each chunk written costs ~10 ms of CPU (8 arrays)
MAX_RUNS = 100_000_000
FORMAT = "kreisel-sweep/1"


@dataclass(frozen=True)
class SweepSpec:
    """A checked sweep: the fixed tables, the swept values and what to keep.

    Build one with :meth:`from_tables` (a dict of tables) or :meth:`from_toml` (a file).
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
    def from_toml(cls, path) -> SweepSpec:
        return cls.from_tables(_config.read_toml(path), source=str(path))

    @classmethod
    def from_tables(cls, tables: dict, *, source: str = "") -> SweepSpec:
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
        chosen = top.pop("preset", None)
        if chosen is not None:
            base = _config.preset(chosen)
            merged = _config.overlay(base, {"top": top, "state": state, "simulation": sim})
            top, state, sim = merged["top"], merged["state"], merged["simulation"]
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
            raise ParameterError(
                f"{head}nothing is swept: give [grid] values or [random] samples of at least "
                f"one of {', '.join(swept_names)}"
            )
        swept = [*grid, *random]
        for name in swept:
            table, field = _where(kind, name)
            fixed = top if table == "top" else state
            if field in fixed and field != "com":
                if chosen is None or field in tables.get(table, {}):
                    raise ParameterError(
                        f"{head}{name} is swept and also fixed in [{table}]: give it once"
                    )
                del fixed[field]  # a preset's value gives way to the sweep
        # placeholders let the fixed tables be checked field by field now
        probe_top, probe_state = _compose(
            kind, top, state, {k: _first(grid, random, k) for k in swept}
        )
        settings = _config.from_tables(
            {"top": {"kind": kind, **probe_top}, "state": probe_state, "simulation": sim},
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
            if k not in allowed:
                raise ParameterError(
                    f"{head}[output] keep contains {k!r}, which is not a summary of {what}: "
                    f"allowed are {', '.join(allowed)}"
                )
        chunk = out.get("chunk", DEFAULT_CHUNK)
        if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
            raise ParameterError(
                f"{head}[output] chunk = {chunk!r} is not allowed: give a whole number of runs >= 1"
            )
        level = _config._real(
            f"{head}[output] ", "inversion_level", out.get("inversion_level", 0.9)
        )
        if not -1 <= level <= 1:
            raise ParameterError(
                f"{head}[output] inversion_level = {level} is not allowed: it must lie in [-1, 1]"
            )
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
            if _where(self.kind, name)[0] != "top":
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
        return (*self.grid, *self.random)

    @property
    def dims(self) -> tuple:
        return (*self.grid, *(("sample",) if self.random else ()))

    @property
    def shape(self) -> tuple:
        return (*(len(v) for v in self.grid.values()), *((self.n_samples,) if self.random else ()))

    @property
    def size(self) -> int:
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
        return tuple(-(-n // b) for n, b in zip(self.shape, self.block))

    @property
    def n_chunks(self) -> int:
        return int(np.prod(self.chunk_grid, dtype=np.int64))

    def chunk_slices(self, k: int) -> tuple:
        idx = np.unravel_index(k, self.chunk_grid)
        return tuple(
            slice(i * b, min((i + 1) * b, n)) for i, b, n in zip(idx, self.block, self.shape)
        )

    def random_values(self) -> dict:
        """The random samples (drawn in the order given, from one generator)."""
        rng = np.random.default_rng(self.seed)
        out = {}
        for name, (lo, hi, scale) in self.random.items():
            if scale == "log":
                out[name] = np.exp(rng.uniform(np.log(lo), np.log(hi), self.n_samples))
            else:
                out[name] = rng.uniform(lo, hi, self.n_samples)
        return out

    def chunk_values(self, k: int, samples: dict | None = None) -> dict:
        """The swept values of every run of chunk ``k`` (C order within the block)."""
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
        """Plain tables (lists, floats, strings) that rebuild this spec."""
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
        return json.dumps(self.as_dict(), sort_keys=True)


def _plain(d: dict) -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, (np.ndarray, list, tuple)):
            out[k] = [float(x) for x in v]
        elif isinstance(v, (bool, str)) or v is None:
            out[k] = v
        else:
            out[k] = float(v)
    return out


def _sweepable(kind: str) -> tuple:
    top = [f for f in _config.TOP_FIELDS[kind] if f not in ("friction", "com")]
    if kind == "heavy":
        top += ["com_x", "com_y", "com_z"]
    return (*top, *_config._EULER, *(("vx", "vy", "height") if kind == "play" else ()))


def _where(kind: str, name: str) -> tuple:
    """(table, field) of a swept name."""
    if name.startswith("com_"):
        return "top", "com"
    return ("top", name) if name in _config.TOP_FIELDS[kind] else ("state", name)


def _compose(kind: str, top: dict, state: dict, values: dict) -> tuple:
    """The [top] and [state] tables of one run: the fixed ones with its swept values."""
    t, s = dict(top), dict(state)
    for name, v in values.items():
        table, field = _where(kind, name)
        if field == "com":
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


# --------------------------------------------------------------------------------------
# one chunk (runs on a worker: needs kreisel only)
# --------------------------------------------------------------------------------------


def compute_chunk(spec: dict, values: dict, threads=None) -> dict:
    """Simulates the runs of one chunk and returns their summaries as flat arrays, with
    ``errors`` {position: message} for runs that could not start or failed.

    ``spec`` is :meth:`SweepSpec.as_dict`, ``values`` the swept values of each run.
    """
    from .._batch import _lyapunov_many, _play_many_packed, simulate_many

    kind = spec["kind"]
    n = len(next(iter(values.values())))
    state_of = _play_packed if kind == "play" else (lambda m, s: _config._state(kind, m, s, ""))
    models, states, where, errors = [], [], [], {}
    # one top per combination of the swept top parameters
    cache = {}
    of_top = [k for k in values if _where(kind, k)[0] == "top"]
    of_state = [k for k in values if k not in of_top]
    for i in range(n):
        key = tuple(float(values[k][i]) for k in of_top)
        _, state = _compose(kind, {}, spec["state"], {k: values[k][i] for k in of_state})
        try:
            if key not in cache:
                top, _ = _compose(kind, spec["top"], {}, dict(zip(of_top, key)))
                cache[key] = _config._model(kind, top, "")
            model = cache[key]
            states.append(state_of(model, state))
            models.append(model)
            where.append(i)
        except ParameterError as e:
            errors[i] = str(e)
    sim = spec["simulation"]
    out = {}
    kept = spec["keep"]
    for name in kept:
        out[name] = np.full(n, MODE_ERROR if name in CATEGORIES else np.nan)
    status = np.full(n, 2, dtype=np.int8)
    if models and sim.get("exact"):
        for i, model, state in zip(where, models, states):
            try:
                a = model.analyse(state)
            except (ParameterError, ArithmeticError, RuntimeError) as e:
                errors[i] = str(e)
                continue
            for name in kept:
                v = getattr(a, "kind" if name == "motion_kind" else name)
                out[name][i] = MOTION_KINDS.index(v) if name == "motion_kind" else v
            status[i] = 1
    elif models:
        kw = dict(rtol=sim.get("rtol", 1e-10), atol=sim.get("atol", 1e-12), threads=threads)
        if kind == "play":
            kw["inversion_level"] = spec["inversion_level"]
        else:
            kw.update(method=sim.get("method", "dop853"), dt=sim.get("dt"))
        t_end = sim.get("t_end", _config.DEFAULT_T_END[kind])
        kept_here = [k for k in kept if k != "lyapunov"]
        if kind == "play":  # states already packed: straight to the core's batch
            res = _play_many_packed([m._native for m in models], states, t_end, kw["rtol"],
                                    kw["atol"], kw["inversion_level"], threads, False)  # fmt: skip
        else:
            res = simulate_many(models, states, t_end, **kw) if kept_here else None
        idx = np.array(where)
        # a run fails if any of its computations does (the first message is kept)
        messages = [res.errors] if res is not None else []
        if "lyapunov" in kept:
            lam, lam_errors = _lyapunov_many(
                models, states, t_end, tau=spec["lyapunov_tau"], d0=LYAPUNOV_D0,
                direction=LYAPUNOV_DIRECTION, rtol=kw["rtol"], atol=kw["atol"], threads=threads,
            )  # fmt: skip
            out["lyapunov"][idx] = lam
            messages.append(lam_errors)
        res_errors = [next((m for m in ms if m), None) for ms in zip(*messages)]
        for name in kept_here:
            col = getattr(res, name)
            if name in CATEGORIES:
                names = CATEGORIES[name]
                col = np.array([names.index(m) if m in names else MODE_ERROR for m in col])
            out[name][idx] = col
        for j, msg in enumerate(res_errors):
            if msg is None:
                status[where[j]] = 1
            else:
                errors[where[j]] = msg
    for name in kept:
        if name in CATEGORIES:
            out[name] = out[name].astype(np.int8)
        elif name == "steps":
            out[name] = np.nan_to_num(out[name], nan=-1).astype(np.int64)
    out["status"] = status
    out["errors"] = errors
    return out


_PLAY_STATE = ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")


def _play_packed(model, state: dict):
    """The packed contact (or dropped) state of a play top from a [state] table: what
    ``model.state(**state)`` gives, with the same checks, without the objects around it."""
    from .. import _core

    unknown = set(state) - {*_PLAY_STATE, "vx", "vy", "height"}
    if unknown or "theta" not in state:
        return model._check(_config._state("play", model, state, ""))  # its messages
    try:
        e = tuple(float(state.get(k, 0.0)) for k in _PLAY_STATE)
        _core.check_euler_state(e)
        q, w = _core.rigid_from_euler(*e)
        h = state.get("height")
        return model._native.state(
            q, w, float(state.get("vx", 0.0)), float(state.get("vy", 0.0)),
            None if h is None else float(h),
        )  # fmt: skip
    except ParameterError:
        raise
    except (TypeError, ValueError) as err:
        raise ParameterError(str(err)) from None


# --------------------------------------------------------------------------------------
# the store
# --------------------------------------------------------------------------------------


def _is_path(store) -> bool:
    return isinstance(store, (str, os.PathLike))


def _open_existing(store):
    """The root group of an existing kreisel sweep store, None if there is none, and an
    error if something else is there."""
    import zarr

    if _is_path(store):
        p = Path(store)
        if not p.exists():
            return None
        if not p.is_dir():
            raise ParameterError(f"store = {str(p)!r} is not allowed: it is a file, not a store")
        if not any(p.iterdir()):
            return None
    try:
        root = zarr.open_group(store, mode="r+")
    except (FileNotFoundError, ValueError, KeyError, zarr.errors.BaseZarrError) as e:
        if _is_path(store):
            raise ParameterError(
                f"store = {str(store)!r} is not allowed: it exists and is not a kreisel sweep "
                f"store ({type(e).__name__}); kreisel leaves it as it is"
            ) from None
        return None
    if root.attrs.get("format") != FORMAT:
        if not _is_path(store) and not list(root.keys()):
            return None
        raise ParameterError(
            f"store = {store!r} is not allowed: it is not a kreisel sweep store; kreisel leaves "
            "it as it is"
        )
    return root


def _create(store, spec: SweepSpec, samples: dict):
    import zarr

    from .._core import __version__

    root = zarr.open_group(store, mode="w")
    root.attrs.update(
        {
            "format": FORMAT,
            "title": f"kreisel sweep of a {spec.kind} top",
            "kreisel_version": __version__,
            "spec": spec.canonical(),
            "run_errors": "{}",
        }
    )
    for name, values in spec.grid.items():
        root.create_array(
            name,
            data=np.asarray(values, dtype=float),
            chunks=(len(values),),
            dimension_names=[name],
        )
    coords = []
    if spec.random:
        n = spec.n_samples
        root.create_array(
            "sample", data=np.arange(n, dtype=np.int64), chunks=(n,), dimension_names=["sample"]
        )
        for name, v in samples.items():
            root.create_array(name, data=v, chunks=(n,), dimension_names=["sample"])
            coords.append(name)
    attrs = {"coordinates": " ".join(coords)} if coords else {}
    for name in spec.keep:
        dtype, fill = ("i8", -1) if name == "steps" else ("f8", np.nan)
        a = dict(attrs, description=DESCRIPTIONS[name])
        if name in CATEGORIES:
            dtype, fill = "i1", MODE_PENDING
            names = CATEGORIES[name]
            a.update(
                flag_values=[*range(len(names)), MODE_ERROR, MODE_PENDING],
                flag_meanings=" ".join([*names, "error", "pending"]),
            )
        root.create_array(
            name,
            shape=spec.shape,
            chunks=spec.block,
            dtype=dtype,
            fill_value=fill,
            dimension_names=list(spec.dims),
            attributes=a,
            # a few numbers per run: compressing them saves little and costs a
            # millisecond per chunk written, on the core the runs need
            compressors=None,
        )
    root.create_array(
        "status",
        shape=spec.shape,
        chunks=spec.block,
        dtype="i1",
        fill_value=0,
        dimension_names=list(spec.dims),
        attributes=dict(attrs, flag_values=[0, 1, 2], flag_meanings="pending done failed"),
    )
    root.create_array(
        "chunk_done",
        shape=(spec.n_chunks,),
        chunks=(1,),
        dtype="u1",
        fill_value=0,
        dimension_names=["chunk"],
        attributes={"description": "1 once the chunk's results are written"},
    )
    return root


class _Writer:
    """Writes finished chunks into the store: the arrays are opened once; a chunk's flag goes
    last, after its data and its run errors."""

    def __init__(self, root, spec: SweepSpec):
        self.root, self.spec = root, spec
        self.arrays = {n: root[n] for n in (*spec.keep, "status", "chunk_done")}
        self.errors = json.loads(root.attrs.get("run_errors", "{}"))

    def write(self, k: int, result: dict):
        sl = self.spec.chunk_slices(k)
        shape = tuple(s.stop - s.start for s in sl)
        for name in (*self.spec.keep, "status"):
            self.arrays[name][sl] = np.asarray(result[name]).reshape(shape)
        # a rewritten chunk's old messages go, its new ones come
        old = [key for key in self.errors
               if all(s.start <= int(a) < s.stop for s, a in zip(sl, key.split(",")))]  # fmt: skip
        for key in old:
            del self.errors[key]
        for i, msg in result["errors"].items():
            at = (s.start + int(j) for s, j in zip(sl, np.unravel_index(int(i), shape)))
            self.errors[",".join(map(str, at))] = msg
        if old or result["errors"]:
            self.root.attrs["run_errors"] = json.dumps(self.errors, sort_keys=True)
        self.arrays["chunk_done"][k] = 1


def open_sweep(store):
    """The results of a sweep store (complete or not) as an ``xarray.Dataset`` in memory:
    one variable per kept summary, ``final_mode`` as strings ("" where pending), ``status``
    (0 pending, 1 done, 2 failed), and the spec and run errors in the attributes."""
    import xarray as xr

    root = _open_existing(store)
    if root is None:
        raise ParameterError(f"store = {store!r} is not allowed: there is no sweep there")
    ds = xr.open_zarr(store, consolidated=False, chunks=None).load()
    done = ds["chunk_done"].values
    ds = ds.drop_vars("chunk_done")
    for name, values in CATEGORIES.items():
        if name not in ds:
            continue
        names = np.array([*values, "error", ""], dtype=object)
        codes = ds[name].values.astype(int)
        k = len(values)
        lookup = np.where(codes >= 0, codes, np.where(codes == MODE_ERROR, k, k + 1))
        ds[name] = (ds[name].dims, names[lookup].astype(str), {"description": DESCRIPTIONS[name]})
    ds = ds[[*json.loads(ds.attrs["spec"])["keep"], "status"]]  # the spec's order
    ds.attrs["chunks_done"] = int(done.sum())
    ds.attrs["chunks"] = int(done.size)
    return ds


# --------------------------------------------------------------------------------------
# the driver
# --------------------------------------------------------------------------------------


SCHEDULER_ENV = "KREISEL_SCHEDULER"

# Dask settings for the processes of a cluster that runs kreisel's tasks (long, CPU-bound,
# the GIL released): no statistical profiler (it samples every worker thread each 10 ms),
# event-loop ticks each second instead of every 20 ms, system metrics every 2 s. Measured
# on 2 cores: an idle scheduler and two workers take 0.18 s of CPU in 10 s instead of 0.97 s.
# `kreisel scheduler` and `kreisel worker` start Dask's processes with them; settings made
# in the environment or a Dask configuration file come first.
DASK_ENV = {
    "DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED": "False",
    "DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL": "1s",
    "DASK_DISTRIBUTED__ADMIN__SYSTEM_MONITOR__INTERVAL": "2s",
}


def dask_command(role: str, args) -> tuple[list, dict]:
    """The command line and environment of a Dask process (``role``: "scheduler" or
    "worker") tuned for kreisel (:data:`DASK_ENV`); ``args`` go to Dask's command as they
    are."""
    import sys

    module = f"distributed.cli.dask_{role}"
    env = dict(os.environ)
    for k, v in DASK_ENV.items():
        env.setdefault(k, v)
    return [sys.executable, "-m", module, *args], env


def _client(scheduler, timeout):
    if scheduler is None:
        scheduler = os.environ.get(SCHEDULER_ENV) or None
    if scheduler is None or scheduler == "local":
        return None, False
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover
        raise ParameterError(
            "scheduler is given but dask.distributed is not installed: pip install 'kreisel[sweep]'"
        ) from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str):
        raise ParameterError(
            f"scheduler = {scheduler!r} is not allowed: give an address like "
            "'tcp://host:8786' or a dask.distributed.Client"
        )
    try:
        return Client(scheduler, timeout=timeout, set_as_default=False), True
    except (OSError, TimeoutError, ValueError) as e:
        raise ParameterError(
            f"scheduler = {scheduler!r} is not reachable within {timeout} s: {e}"
        ) from None


def sweep(
    spec,
    store=None,
    scheduler=None,
    *,
    threads=None,
    progress=True,
    callback=None,
    overwrite=False,
    retry_failed=False,
    connect_timeout=10.0,
):
    """Runs a sweep and returns its results as an ``xarray.Dataset``.

    Parameters
    ----------
    spec : SweepSpec, dict of tables, or path of a TOML file
        See the module documentation (``kreisel.SweepSpec``) for the tables.
    store : path or zarr store, optional
        Where the results go, chunk by chunk (a Zarr directory). If it already holds this
        sweep, only the chunks not yet done are computed; if it holds another sweep, the call
        fails unless ``overwrite``. None: an in-memory store (nothing kept on disk).
    scheduler : str or dask.distributed.Client, optional
        None: the address in the environment variable ``KREISEL_SCHEDULER`` if it is set (so
        a script moves to a cluster with no change), else the core's parallel batch on this
        machine (also ``"local"``). An address (``"tcp://host:8786"``) or a client: chunks
        go to that Dask cluster, whose workers need only kreisel.
    threads : int, optional
        Local runs: the number of threads (default: all cores).
    progress : bool
        Show a progress bar (runs done).
    callback : callable, optional
        ``callback(chunk, done, total)`` after each chunk is written; an exception raised in
        it stops the sweep (the chunks written so far stay).
    overwrite : bool
        Replace a store that holds another sweep.
    retry_failed : bool
        Compute again the chunks that hold failed runs (after a fix, say); their messages
        are dropped from ``run_errors`` as the chunks are rewritten.
    connect_timeout : float
        Seconds to wait for the scheduler.
    """
    import zarr
    from tqdm.auto import tqdm

    from .._batch import _threads

    sp = load_spec(spec)
    threads = _threads(threads)
    if callback is not None and not callable(callback):
        raise ParameterError(f"callback = {callback!r} is not allowed: it must be callable")
    # everything that can fail before work starts fails here, before the store is touched
    client, own_client = _client(scheduler, connect_timeout)
    try:
        if store is None:
            store = zarr.storage.MemoryStore()
        root = _open_existing(store)
        if root is not None and root.attrs.get("spec") != sp.canonical():
            if not overwrite:
                raise ParameterError(
                    f"store = {store!r} holds another sweep (its spec differs): give a new "
                    "store, or overwrite=True to replace it"
                )
            if _is_path(store):
                shutil.rmtree(store)
            root = None
        samples = sp.random_values() if sp.random else {}
        todo = list(range(sp.n_chunks))
        if root is not None:
            done = root["chunk_done"][:]
            if retry_failed:
                failed = root["status"][:] == 2
                for k in range(sp.n_chunks):
                    if done[k] and failed[sp.chunk_slices(k)].any():
                        done[k] = 0
            todo = [k for k in todo if not done[k]]
        runs = {k: int(np.prod([s.stop - s.start for s in sp.chunk_slices(k)])) for k in todo}
        finished = sp.n_chunks - len(todo)
        work = _Work(sp, sp.as_dict(), runs, samples, client, threads)  # the runs start
        bar = tqdm(total=sum(runs.values()), unit="run", desc="sweep", disable=not progress)
        with bar, closing(work):
            if root is None:  # a new store is made while the first tasks run
                root = _create(store, sp, samples)
            writer = _Writer(root, sp)
            for k, result in work:
                writer.write(k, result)
                finished += 1
                bar.update(runs[k])
                if callback is not None:
                    callback(k, finished, sp.n_chunks)
    finally:
        if own_client:
            client.close()
    return open_sweep(store)


TASK_RUNS = 1024  # at most this many runs per task: a store chunk may be split into tasks
TAIL_RUNS = 16  # the least: toward the end of a sweep the tasks shrink to this size
TASK_SHARE = 2  # a task takes at most 1/(TASK_SHARE lanes) of the runs still to hand out


def _tasks(sp: SweepSpec, todo: list, samples: dict, lanes: int = 1) -> list:
    """(pieces, values) for every task, where `pieces` lists (chunk, offset, runs): the runs
    of the chunks to do, in order (C order within each chunk's block), cut into contiguous
    tasks that may end inside a chunk or span several, so the tasks' size does not depend
    on the store's chunks (few writes, or small chunks, alike). A task takes at most
    TASK_RUNS runs and at most a 1/(TASK_SHARE lanes) share of the runs not yet handed out,
    but no fewer than TAIL_RUNS (guided scheduling, in the manner of factoring: half of what
    is left goes out in `lanes` equal tasks): the last tasks of a sweep are short, so the
    `lanes` cores or workers finish together, and there are few tasks, as each costs Dask a
    few ms of CPU (scheduler, worker and this process: about 6 ms each on a 2-core VM,
    measured with /proc/PID/stat)."""
    chunks = [(k, sp.chunk_values(k, samples)) for k in todo]
    sizes = [len(next(iter(v.values()))) for _, v in chunks]
    left = sum(sizes)
    out = []
    c, at = 0, 0  # the next run to hand out: chunk index, offset in it
    while left > 0:
        size = min(TASK_RUNS, max(TAIL_RUNS, -(-left // (TASK_SHARE * lanes))), left)
        left -= size
        pieces = []
        while size > 0:
            k, n = chunks[c][0], sizes[c]
            m = min(size, n - at)
            pieces.append((c, k, at, m))
            size -= m
            at += m
            if at == n:
                c, at = c + 1, 0
        values = {
            name: np.concatenate([chunks[i][1][name][a : a + m] for i, _, a, m in pieces])
            for name in chunks[0][1]
        }
        out.append(([(k, a, m) for _, k, a, m in pieces], values))
    return out


def _piece(result: dict, start: int, runs: int) -> dict:
    """The part of a task's result for its runs start .. start + runs (errors renumbered)."""
    out = {name: v[start : start + runs] for name, v in result.items() if name != "errors"}
    out["errors"] = {i - start: msg for i, msg in result["errors"].items()
                     if start <= i < start + runs}  # fmt: skip
    return out


def _join(parts: list) -> dict:
    """The result of a whole chunk from those of its parts (in order, with their offsets)."""
    out = {}
    for name in parts[0][1]:
        if name != "errors":
            out[name] = np.concatenate([r[name] for _, r in parts])
    out["errors"] = {a + int(i): msg for a, r in parts for i, msg in r["errors"].items()}
    return out


class _Work:
    """The tasks of a sweep, all handed out at once (the runs start); iterating gives
    (chunk, result) pairs as whole chunks finish. close() cancels the tasks not yet started
    (after an exception or an interrupt) and waits for the local ones already running."""

    def __init__(self, sp: SweepSpec, payload: dict, runs: dict, samples: dict, client,
                 threads):  # fmt: skip
        """`runs`: the chunks to do, with their numbers of runs."""
        self.client, self.pool, self.parts = client, None, {}
        self.futures = {}  # (task, future) by position (local) or Dask key
        self.missing = dict(runs)  # runs still to come in, by chunk
        todo = list(runs)
        if not todo:
            return
        if client is None:
            cores = threads or os.cpu_count() or 1
        else:
            cores = max(1, sum(client.nthreads().values()))
        tasks = _tasks(sp, todo, samples, cores)
        if client is None:
            from concurrent.futures import ThreadPoolExecutor

            # `threads` tasks in flight, each on its own core (the GIL is released while
            # the core's batch runs, so one task's set-up in Python overlaps the others'
            # runs); fewer tasks than cores: the cores are shared out inside each task
            # instead. (Two tasks each on every core was measured slower: two pools on two
            # cores.)
            lanes = max(1, min(cores, len(tasks)))
            inner = max(1, cores // lanes)
            self.pool = ThreadPoolExecutor(lanes)
            for i, tk in enumerate(tasks):
                self.futures[i] = (tk, self.pool.submit(compute_chunk, payload, tk[1], inner))
        else:
            token = uuid.uuid4().hex[:12]
            keys = [f"kreisel-sweep-{token}-{i}" for i in range(len(tasks))]
            submitted = client.map(compute_chunk, [payload] * len(tasks),
                                   [tk[1] for tk in tasks], [1] * len(tasks), key=keys,
                                   pure=False)  # fmt: skip
            self.futures = {f.key: (tk, f) for tk, f in zip(tasks, submitted)}

    def _finished(self, task, result) -> list:
        """The chunks (chunk, result) that this task's result completes."""
        whole, start = [], 0
        for k, a, m in task[0]:
            self.parts.setdefault(k, []).append((a, _piece(result, start, m)))
            start += m
            self.missing[k] -= m
            if self.missing[k] == 0:
                whole.append((k, _join(sorted(self.parts.pop(k), key=lambda p: p[0]))))
        return whole

    def __iter__(self):
        if self.pool is not None:
            from concurrent.futures import FIRST_COMPLETED, wait

            task = {f: (i, tk) for i, (tk, f) in self.futures.items()}
            pending = set(task)
            while pending:
                ready, pending = wait(pending, return_when=FIRST_COMPLETED)
                for f in sorted(ready, key=lambda f: task[f][0]):
                    yield from self._finished(task[f][1], f.result())
            return
        if not self.futures:
            return
        from distributed import as_completed

        # results come back in batches: one gather for all the tasks finished meanwhile
        batches = as_completed([f for _, f in self.futures.values()], loop=self.client.loop)
        for batch in batches.batches():
            for f, result in zip(batch, self.client.gather(batch)):
                tk = self.futures.pop(f.key)[0]
                f.release()
                yield from self._finished(tk, result)

    def close(self):
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
        elif self.futures:
            self.client.cancel([f for _, f in self.futures.values()])
            self.futures = {}
