"""A top, a state and a simulation from plain tables (a TOML file, command-line flags or a
preset), checked field by field: every mistake is one :class:`ParameterError` naming the
table, the field and what is allowed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._errors import ParameterError
from ._presets import PRESETS

KINDS = ("lagrange", "heavy", "play")
FRICTIONS = ("coulomb", "viscous", "none", "coulomb_contensou")
_EULER = ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")

TOP_FIELDS = {
    "lagrange": ("I1", "I3", "m", "l", "g"),
    "heavy": ("I1", "I2", "I3", "m", "com", "g"),
    "play": ("m", "A", "C", "s", "rho", "shape", "g", "friction", "mu", "patch_radius",
             "restitution", "rolling_resistance", "drilling_resistance", "air_drag",
             "stick_threshold"),
}  # fmt: skip
REQUIRED = {
    "lagrange": ("I1", "I3", "m", "l"),
    "heavy": ("I1", "I2", "I3", "m", "com"),
    "play": ("m", "A", "C"),  # and either s and rho or shape
}
STATE_FIELDS = {
    "lagrange": _EULER,
    "heavy": (*_EULER, "quaternion", "omega"),
    "play": (*_EULER, "vx", "vy", "height"),
}
SIMULATION_FIELDS = ("t_end", "method", "exact", "rtol", "atol", "dt", "samples")
TABLES = ("top", "pivot", "damping", "state", "simulation")
# The tables of a top on a moving or damped pivot (heavy and Lagrange tops).
DRIVE_TABLES = ("pivot", "damping")
DAMPING_FIELDS = ("viscous", "drag", "dry", "pivot_radius")
DEFAULT_T_END = {"lagrange": 2.0, "heavy": 2.0, "play": 5.0}
# a command-line run records every step (with its diagnostics): about 110 bytes each
MAX_RECORDED_STEPS = 2e7
MAX_SAMPLES = 10_000_000


def required(kind: str, top: dict) -> tuple[str, ...]:
    """The fields a top of ``kind`` needs: a play top s and rho unless it has a shape."""
    if kind == "play" and "shape" not in top:
        return (*REQUIRED[kind], "s", "rho")
    return REQUIRED[kind]


def known_presets(kind: str | None = None) -> str:
    """The names of the presets (of tops of ``kind`` only, if given)."""
    return ", ".join(n for n, p in PRESETS.items() if kind is None or p.kind == kind)


def preset(name) -> dict:
    """The tables of a built-in preset (copies)."""
    if not isinstance(name, str) or name not in PRESETS:
        raise ParameterError(f"preset = {name!r} is not known: known presets are {known_presets()}")
    p = PRESETS[name]
    out = {"top": dict(p.top), "state": dict(p.state), "simulation": dict(p.simulation)}
    for t in DRIVE_TABLES:
        if getattr(p, t, None):
            out[t] = dict(getattr(p, t))
    return out


@dataclass
class Settings:
    """How to compute the motion."""

    t_end: float
    exact: bool = False
    method: str = "dop853"
    rtol: float = 1e-10
    atol: float = 1e-12
    dt: float | None = None
    samples: int | None = None
    extra: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        d = {"t_end": self.t_end, "solver": "exact" if self.exact else self.method}
        if not self.exact:
            d.update(rtol=self.rtol, atol=self.atol, dt=self.dt)
        d["samples"] = self.samples
        return d


@dataclass
class Problem:
    """A validated top, state and settings."""

    kind: str
    model: Any  # LagrangeTop, HeavyTop or PlayTop
    state: Any  # its state
    settings: Settings
    tables: dict
    preset: str | None = None


def _real(where: str, name: str, value) -> float:
    from ._validate import real

    try:
        return real(name, value)
    except ParameterError as e:
        raise ParameterError(f"{where}{e}") from None


def _kind_of(value) -> str:
    """What a TOML value is, in TOML's words."""
    if isinstance(value, list):
        if value and all(isinstance(v, dict) for v in value):
            return "an array of tables ([[...]])"
        return "an array"
    if isinstance(value, str):
        return f"the string {value!r}"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    return f"the {type(value).__name__} {value!r}"


def _check_fields(where: str, table: dict, allowed, what: str):
    if not isinstance(table, dict):
        raise ParameterError(f"{where} must be a table of fields, not {type(table).__name__}")
    for key in table:
        if key not in allowed:
            raise ParameterError(
                f"{where}{key} is not a known field {what}: allowed are {', '.join(allowed)}"
            )


def overlay(base: dict, over: dict, name: str | None = None) -> dict:
    """Tables ``over`` laid on ``base`` field by field (None leaves a field as it is). A state
    given as a quaternion replaces one in Euler angles, and back; a friction law given without
    mu takes its own default coefficient. s or rho alone on a base made of parts (preset
    ``name``) is an error that says how to change a part."""
    out = {k: dict(v) for k, v in base.items()}
    for table, values in over.items():
        out.setdefault(table, {})
        given = {k: v for k, v in values.items() if v is not None}
        if table == "state":
            if any(k in given for k in ("quaternion", "omega")):
                out["state"] = {k: v for k, v in out["state"].items() if k not in _EULER}
            elif any(k in given for k in _EULER):
                out["state"] = {
                    k: v for k, v in out["state"].items() if k not in ("quaternion", "omega")
                }
        if table == "top" and "friction" in given and "mu" not in given:
            # another law: the base's coefficient (other units, or none) does not carry over
            out["top"].pop("mu", None)
        if table == "top" and "friction" in given and given["friction"] != "coulomb_contensou":
            out["top"].pop("patch_radius", None)
        if table == "top" and ("s" in given or "rho" in given):
            parts = out["top"].get("shape")
            if parts and "shape" not in given and not ("s" in given and "rho" in given):
                _clash_with_parts(given, parts, name)
            out["top"].pop("shape", None)  # a tip sphere replaces the base's parts
        if table == "top" and "shape" in given:
            out["top"].pop("s", None)
            out["top"].pop("rho", None)
        out[table].update(given)
    return out


def _clash_with_parts(given: dict, parts: list, name: str | None):
    """The error for s or rho alone laid on a top made of parts."""
    alone = "s" if "s" in given else "rho"
    top = "the top" if name is None else f"preset {name!r}"
    names = ", ".join(
        str(p.get("name") or f"shape[{i}]") if isinstance(p, dict) else f"shape[{i}]"
        for i, p in enumerate(parts)
    )
    raise ParameterError(
        f"{alone} = {given[alone]!r} clashes with the shape of {top}: it is made of parts "
        f"({names}), and s and rho describe a single tip sphere instead. Give both s and rho "
        "to replace the parts by one tip sphere, or change a part in a TOML file: "
        f"`kreisel presets --toml {name or 'NAME'} > top.toml`, edit its [[top.shape]] "
        "tables, `kreisel run top.toml`"
    )


def from_tables(tables: dict, *, prefix: str = "", source: str = "") -> Problem:
    """The problem that ``tables`` (``{"top": ..., "state": ..., "simulation": ...}``) describe.

    ``prefix`` selects how fields are named in messages: ``"table"`` gives ``[top] m``, else
    the bare field name (a flag of the same name). ``source`` (a file name) starts every
    message.
    """
    head = f"{source}: " if source else ""
    style_table = prefix == "table"

    def where(table):
        return f"{head}[{table}] " if style_table else head

    for key in tables:
        if key not in TABLES:
            raise ParameterError(
                f"{head}[{key}] is not a known table: allowed are "
                + ", ".join(f"[{t}]" for t in TABLES)
            )
    for name in TABLES:
        t = tables.get(name, {})
        if not isinstance(t, dict):
            raise ParameterError(
                f"{head}[{name}] must be a table of fields ([{name}] NAME = value), not "
                f"{_kind_of(t)}"
            )
    top = dict(tables.get("top", {}))
    state = dict(tables.get("state", {}))
    sim = dict(tables.get("simulation", {}))
    # an empty [pivot] or [damping] table says nothing (a form's empty fields)
    drive = {t: dict(tables[t]) for t in DRIVE_TABLES if tables.get(t)}
    chosen = top.pop("preset", None)
    if chosen is not None:
        base = preset(chosen)
        for t in DRIVE_TABLES:
            if t in base and t not in drive:
                drive[t] = dict(base[t])
        if "kind" in top and top["kind"] != base["top"]["kind"]:
            raise ParameterError(
                f"{where('top')}kind = {top['kind']!r} is not allowed with preset = {chosen!r}, "
                f"a {base['top']['kind']} top"
            )
        merged = overlay(base, {"top": top, "state": state, "simulation": sim}, chosen)
        top, state, sim = merged["top"], merged["state"], merged["simulation"]
    kind = top.pop("kind", None)
    if kind is None:
        raise ParameterError(
            f"{where('top')}kind is missing: give kind = one of {', '.join(KINDS)} (or a preset)"
        )
    if kind not in KINDS:
        raise ParameterError(
            f"{where('top')}kind = {kind!r} is not allowed: use one of {', '.join(KINDS)}"
        )
    _check_fields(where("top"), top, TOP_FIELDS[kind], f"of a {kind} top")
    _check_fields(where("state"), state, STATE_FIELDS[kind], f"of a {kind} top's state")
    _check_fields(where("simulation"), sim, SIMULATION_FIELDS, "of the simulation")
    needed = required(kind, top)
    for name in needed:
        if name not in top:
            raise ParameterError(
                f"{where('top')}{name} is missing: a {kind} top needs "
                f"{', '.join(needed)} (g defaults to 9.81 m/s^2)"
                + (" or, instead of s and rho, shape" if kind == "play" else "")
            )
    if drive and kind == "play":
        raise ParameterError(
            f"{head}[{next(iter(drive))}] is not allowed for a play top: a moving or damped "
            "pivot belongs to a heavy or lagrange top (a play top's friction is in [top])"
        )
    _drive(drive, where)  # its messages name the [pivot] or [damping] table
    model = _model(kind, {**top, **drive}, where("top"))
    st = _state(kind, model, state, where("state"))
    settings = _settings(kind, model, sim, where("simulation"))
    tables_out = {"top": {"kind": kind, **top}, **drive, "state": state, "simulation": sim}
    return Problem(kind, model, st, settings, tables_out, chosen)


def _drive(drive: dict, where) -> dict:
    """The pivot and damping keyword arguments of a top from its [pivot], [damping] tables."""
    from .pivots import PivotDamping, pivot_from_dict

    out = {}
    if "pivot" in drive:
        try:
            out["pivot"] = pivot_from_dict(drive["pivot"])
        except ParameterError as e:
            raise ParameterError(f"{where('pivot')}{e}") from None
    if "damping" in drive:
        d = drive["damping"]
        _check_fields(where("damping"), d, DAMPING_FIELDS, "of the damping")
        try:
            out["damping"] = PivotDamping(**d)
        except ParameterError as e:
            raise ParameterError(f"{where('damping')}{e}") from None
    return out


def _model(kind: str, top: dict, where: str):
    from ._heavy import HeavyTop
    from ._lagrange import LagrangeTop
    from ._play import Coulomb, CoulombContensou, Frictionless, PlayTop, Viscous

    try:
        if kind in ("lagrange", "heavy"):
            # a sweep's tables carry [pivot] and [damping] inside [top]
            top = dict(top)
            drive = {t: top.pop(t) for t in DRIVE_TABLES if isinstance(top.get(t), dict)}
            top.update(_drive(drive, lambda t: f"[{t}] "))
            return LagrangeTop(**top) if kind == "lagrange" else HeavyTop(**top)
        p = dict(top)
        friction = p.pop("friction", "coulomb")
        mu = p.pop("mu", None)
        patch = p.pop("patch_radius", None)
        if patch is not None and friction != "coulomb_contensou":
            raise ParameterError(
                f"patch_radius = {patch!r} is not allowed with friction = {friction!r}: it is "
                "the contact patch of friction = 'coulomb_contensou'"
            )
        if "shape" in p:
            p["shape"] = _parts(p["shape"])
        if friction not in FRICTIONS:
            raise ParameterError(
                f"friction = {friction!r} is not allowed: use one of {', '.join(FRICTIONS)}"
            )
        if friction == "none":
            if mu is not None and mu != 0:
                raise ParameterError(f"mu = {mu!r} is not allowed with friction = 'none'")
            law: Frictionless | Viscous | Coulomb | CoulombContensou = Frictionless()
        elif friction == "viscous":
            law = Viscous(mu=1.0 if mu is None else mu)
        elif friction == "coulomb_contensou":
            law = CoulombContensou(0.3 if mu is None else mu, 5e-4 if patch is None else patch)
        else:
            law = Coulomb(mu=0.3 if mu is None else mu)
        return PlayTop(friction=law, **p)
    except ParameterError as e:
        raise ParameterError(f"{where}{e}") from None


def part_kinds() -> dict:
    """``{kind: (class, fields)}`` of the contact parts a ``shape`` holds: each kind's fields
    are its class's own (the name aside)."""
    import dataclasses

    from .shapes import Sphere, Spheroid, Torus

    return {
        cls.__name__.lower(): (
            cls,
            tuple(f.name for f in dataclasses.fields(cls) if f.name != "name"),
        )
        for cls in (Sphere, Spheroid, Torus)
    }


def _parts(shape) -> list:
    """The parts of a ``shape`` field: an array of tables, each a sphere ``{radius, z}``, a
    spheroid ``{kind = "spheroid", equatorial, axial, z}`` or a torus ``{kind = "torus", major,
    minor, z}``, with an optional ``name``."""
    kinds = part_kinds()
    if not isinstance(shape, list) or not shape:
        raise ParameterError(
            f"shape = {shape!r} is not allowed: it must be an array of parts, each a table "
            "{ radius = ..., z = ..., name = ... } (a sphere; or kind = 'spheroid' or 'torus')"
        )
    out = []
    for i, part in enumerate(shape):
        if not isinstance(part, dict):
            raise ParameterError(f"shape[{i}] must be a table {{ radius, z, name }}, not "
                                 f"{_kind_of(part)}")  # fmt: skip
        kind = part.get("kind", "sphere")
        if kind not in kinds:
            raise ParameterError(
                f"shape[{i}] kind = {kind!r} is not allowed: use 'sphere', 'spheroid' or 'torus'"
            )
        cls, fields = kinds[kind]
        extra = set(part) - {*fields, "name", "kind"}
        if extra or not set(fields) <= set(part):
            raise ParameterError(
                f"shape[{i}] = {part!r} is not allowed: a {kind} is a table with "
                f"{', '.join(fields)} (and optionally name)"
            )
        out.append(cls(**{f: part[f] for f in fields}, name=part.get("name")))
    return out


def _state(kind: str, model, state: dict, where: str):
    try:
        if kind == "heavy" and ("quaternion" in state or "omega" in state):
            mixed = [k for k in _EULER if k in state]
            if mixed:
                raise ParameterError(
                    f"{mixed[0]} is not allowed with quaternion and omega: give Euler angles "
                    "and rates, or a quaternion and omega, not both"
                )
            for k in ("quaternion", "omega"):
                if k not in state:
                    raise ParameterError(f"{k} is missing: quaternion and omega go together")
            return model.state_from_quaternion(state["quaternion"], state["omega"])
        if "theta" not in state:
            raise ParameterError(
                "theta is missing: the state needs theta (rad) and optionally "
                + ", ".join(k for k in STATE_FIELDS[kind] if k != "theta")
            )
        return model.state(**state)
    except ParameterError as e:
        raise ParameterError(f"{where}{e}") from None


def _settings(kind: str, model, sim: dict, where: str) -> Settings:
    from . import _core

    try:
        t_end = _real("", "t_end", sim.get("t_end", DEFAULT_T_END[kind]))
        exact = sim.get("exact", False)
        if not isinstance(exact, bool):
            raise ParameterError(f"exact = {exact!r} is not allowed: it must be true or false")
        method = sim.get("method")
        if exact and kind != "lagrange":
            raise ParameterError(
                "exact = true is not allowed: only a lagrange top has an exact solution"
            )
        driven = getattr(model, "driven", False)
        if exact and driven:
            raise ParameterError(
                "exact = true is not allowed: a top on a moving or damped pivot has no exact "
                "solution (it is simulated)"
            )
        if exact and method is not None:
            raise ParameterError(
                f"method = {method!r} is not allowed with exact = true: choose one of the two"
            )
        if kind == "lagrange" and method is None and not driven:
            exact = True
        if method is None:
            method = "dop853"
        if not isinstance(method, str):
            raise ParameterError(f"method = {method!r} is not allowed: give a method name")
        rtol = _real("", "rtol", sim.get("rtol", 1e-10))
        atol = _real("", "atol", sim.get("atol", 1e-12))
        dt = sim.get("dt")
        if dt is not None:
            dt = _real("", "dt", dt)
        if exact:
            if not (np.isfinite(t_end) and t_end >= 0):
                raise ParameterError(f"t_end = {t_end} is not allowed: it must be >= 0 s")
        else:
            # the rules of every simulation, the core's (as simulate would apply them)
            _core.check_settings(model._native_model(), t_end, method, rtol, atol, dt)
            if dt is not None and t_end / dt > MAX_RECORDED_STEPS:
                raise ParameterError(
                    f"dt = {dt} is not allowed: t_end / dt = {t_end / dt:.3g} steps, more "
                    f"than the {MAX_RECORDED_STEPS:.0e} a run of the command line records"
                )
        samples = sim.get("samples")
        if samples is None and exact:
            samples = 2001
        if samples is not None:
            if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
                raise ParameterError(f"samples = {samples!r} is not allowed: it must be an integer")
            if not 2 <= samples <= MAX_SAMPLES:
                raise ParameterError(
                    f"samples = {samples} is not allowed: it must lie in [2, {MAX_SAMPLES}]"
                )
            samples = int(samples)
    except ParameterError as e:
        raise ParameterError(f"{where}{e}") from None
    return Settings(t_end, exact, method, rtol, atol, dt, samples)


def to_toml(tables: dict, comments=()) -> str:
    """The TOML file of ``tables`` ([top], [state], [simulation]) that :func:`from_tables`
    reads back as they are, after a comment line for each of ``comments``. A list of tables
    (the parts of a ``shape``) is written as an array of tables, ``[[top.shape]]``."""

    def value(v):
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, (bool, np.bool_)):
            return "true" if v else "false"
        if isinstance(v, (int, np.integer)):
            return str(int(v))
        if isinstance(v, (float, np.floating)):
            x = float(v)
            if np.isnan(x):
                return "nan"
            return repr(x) if np.isfinite(x) else ("inf" if x > 0 else "-inf")
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        raise TypeError(f"{v!r} ({type(v).__name__}) has no TOML form")

    def is_tables(v):
        return isinstance(v, (list, tuple)) and bool(v) and all(isinstance(x, dict) for x in v)

    lines = [f"# {c}" for c in comments]
    if lines:
        lines.append("")
    for table in TABLES:
        if table in DRIVE_TABLES and not tables.get(table):
            continue
        fields = tables.get(table, {})
        lines.append(f"[{table}]")
        lines += [
            f"{k} = {value(v)}" for k, v in fields.items() if v is not None and not is_tables(v)
        ]
        lines.append("")
        for k, v in fields.items():
            if is_tables(v):
                for part in v:
                    lines.append(f"[[{table}.{k}]]")
                    lines += [f"{f} = {value(x)}" for f, x in part.items() if x is not None]
                    lines.append("")
    return "\n".join(lines)


def read_toml(path) -> dict:
    """The tables of a TOML file; a malformed file is a ParameterError with the line."""
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"{path} is not valid TOML: {e}") from None
    except RecursionError:
        raise ParameterError(
            f"{path}{_deepest(path)}: arrays or inline tables nested too deeply"
        ) from None

    except (OSError, UnicodeDecodeError) as e:
        raise ParameterError(f"{path} cannot be read: {e}") from None


def _deepest(path) -> str:
    """Where a TOML file nests deepest: ``", line N (field NAME)"``, or ``""``."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            lines = fh.readlines()
    except OSError:
        return ""
    depth = [(max(line.count("["), line.count("{")), i) for i, line in enumerate(lines)]
    if not depth:
        return ""
    _, i = max(depth)
    key = lines[i].split("=", 1)[0].strip() if "=" in lines[i] else ""
    return f", line {i + 1}" + (f" (field {key})" if key else "")
