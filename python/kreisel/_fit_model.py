"""What a fit varies: the free names of a top and of its state, their coordinates, and the
model's prediction of each kind of observation."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ._errors import ParameterError
from ._heavy import HeavyTop, RigidState
from ._lagrange import LagrangeTop
from ._observations import Observations
from ._play import PlayState, PlayTop
from ._state import EulerState

# Quantities that are positive by nature: fitted in log coordinates (a step never crosses
# zero, and the data usually constrain their ratios).
POSITIVE = {"I1", "I2", "I3", "m", "g", "A", "C", "rho", "mu"}
EULER_FIELDS = ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")


@dataclass
class Param:
    """One scalar the fit varies: ``name`` as reported (``"com[2]"``), ``key`` the free name
    it belongs to (``"com"``), its component ``index`` (or None), its ``group`` (``"top"``,
    ``"state"`` or ``"sensor"``), its starting ``value`` (user units), whether it is fitted
    as its logarithm, and its name in the core's sensitivities (None: finite differences)."""

    name: str
    key: str
    index: int | None
    group: str
    value: float
    log: bool
    sens: str | None


@dataclass
class TopSpec:
    """A top's free names: key -> number of components (None: a scalar), its constructor
    arguments, a function that makes a top from them, and the keys the core's
    sensitivities know."""

    sizes: dict[str, int | None]
    kwargs: dict[str, Any]
    make: Callable[[dict[str, Any]], Any]
    sensitive: frozenset


def top_spec(top) -> TopSpec:
    """The free names of ``top`` (HeavyTop, LagrangeTop, PlayTop, with its damping)."""
    if isinstance(top, HeavyTop):
        kw: dict[str, Any] = dict(
            I1=top.I1, I2=top.I2, I3=top.I3, m=top.m, com=list(top.com), g=top.g
        )
        sizes: dict[str, int | None] = dict(I1=None, I2=None, I3=None, m=None, com=3, g=None)
        sens = frozenset(sizes)
        cls: Any = HeavyTop
    elif isinstance(top, LagrangeTop):
        kw = dict(I1=top.I1, I3=top.I3, m=top.m, l=top.l, g=top.g)
        sizes = dict.fromkeys(kw)
        sens = frozenset(sizes)
        cls = LagrangeTop
    elif isinstance(top, PlayTop):
        return _play_spec(top)
    else:
        raise ParameterError(
            f"top = {top!r} is not allowed: fit a HeavyTop, LagrangeTop or PlayTop"
        )

    def plain(p, cls=cls):
        return cls(**p)

    make: Callable[[dict[str, Any]], Any] = plain
    if top.driven:
        sens = frozenset()
        damping = top.damping
        base = cls
        if damping is not None:
            for k in ("viscous", "drag", "dry"):
                kw[k] = getattr(damping, k)
                sizes[k] = None

        def driven(p, base=base, damping=damping, pivot=top.pivot):
            p = dict(p)
            d = None
            if damping is not None:
                d = dataclasses.replace(
                    damping, **{k: p.pop(k) for k in ("viscous", "drag", "dry")}
                )
            return base(**p, pivot=pivot, damping=d)

        make = driven

    return TopSpec(sizes, kw, make, sens)


def _play_spec(top: PlayTop) -> TopSpec:
    p = dict(top._p)
    given_shape = top._given_shape
    friction = top.friction
    kw = {k: p[k] for k in ("m", "A", "C", "g", "restitution", "rolling_resistance",
                            "drilling_resistance", "air_drag")}  # fmt: skip
    if not given_shape:
        kw["s"], kw["rho"] = p["s"], p["rho"]
    if hasattr(friction, "mu"):
        kw["mu"] = friction.mu

    def make(q):
        q = dict(q)
        law = friction
        if "mu" in q:
            law = dataclasses.replace(friction, mu=q.pop("mu"))
        shape = list(top.shape) if given_shape else None
        return PlayTop(**q, friction=law, shape=shape)

    # the core's sensitivities know every one of these names (theory: sensitivities)
    return TopSpec(dict.fromkeys(kw), kw, make, frozenset(kw))


def state_spec(top, state) -> tuple[dict[str, int | None], dict[str, Any], Callable, frozenset]:
    """The free names of ``state``: sizes, values, a function making a state from values and
    the trial top, and the keys the core's sensitivities know."""
    if isinstance(state, EulerState):
        vals: dict[str, Any] = {f: getattr(state, f) for f in EULER_FIELDS}

        def make(v, trial):
            s = EulerState(**v)
            # on a floor the state's height follows the trial top's geometry (s, rho)
            return trial.state(*s.as_tuple()) if isinstance(trial, PlayTop) else s

        # a play top's sensitivities move these fields of trial.state(...) as make does
        return dict.fromkeys(EULER_FIELDS), vals, make, frozenset(EULER_FIELDS)
    if isinstance(state, RigidState):
        q0 = np.asarray(state.quaternion, dtype=float)

        def make_rigid(v, trial):
            return RigidState(quat_mul(q0, quat_exp(np.asarray(v["orientation"]))),
                              np.asarray(v["omega"], dtype=float))  # fmt: skip

        vals = {"orientation": [0.0, 0.0, 0.0], "omega": list(state.omega)}
        return dict(orientation=3, omega=3), vals, make_rigid, frozenset(vals)
    if isinstance(state, PlayState):

        def make_play(v, trial):
            return dataclasses.replace(state, omega=np.asarray(v["omega"], dtype=float))

        return dict(omega=3), {"omega": list(state.omega)}, make_play, frozenset()
    raise ParameterError(
        f"state = {state!r} is not allowed: give an EulerState, RigidState or PlayState"
    )


def quat_exp(delta: np.ndarray) -> np.ndarray:
    """exp(delta / 2) as a unit quaternion (w, x, y, z): a rotation by the vector delta."""
    a = float(np.linalg.norm(delta))
    if a < 1e-300:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[math.cos(a / 2)], math.sin(a / 2) * np.asarray(delta) / a])


def quat_mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The Hamilton product p q."""
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])  # fmt: skip


def rotation_matrix(r: np.ndarray) -> np.ndarray:
    """The rotation matrix of the rotation vector r (Rodrigues)."""
    a = float(np.linalg.norm(r))
    k = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    if a < 1e-12:
        return np.eye(3) + k + 0.5 * k @ k
    return np.eye(3) + math.sin(a) / a * k + (1 - math.cos(a)) / a**2 * k @ k


def predict(cols: dict[str, np.ndarray], obs: Observations, idx: np.ndarray, rot, play: bool):
    """The model's values of ``obs`` (shape (n, k)) from the run's columns at rows ``idx``;
    ``rot`` is the sensor rotation vector (body rates in the sensor frame)."""
    if obs.kind == "body_rates":
        w = cols["omega"][idx]
        return w @ rotation_matrix(rot) if obs.frame == "sensor" else w
    if obs.kind == "euler_angles":
        return np.stack([cols[c][idx] for c in obs.columns], axis=1)
    th, ph = cols["theta"][idx], cols["phi"][idx]
    d = float(obs.axis_point)  # type: ignore[arg-type]
    xy = d * np.stack([np.sin(th) * np.sin(ph), -np.sin(th) * np.cos(ph)], axis=1)
    if play:
        xy = xy + cols["com"][idx, :2] - cols["com"][0, :2]
    return xy


def predict_derivative(
    sens: dict[str, np.ndarray], cols, obs, idx, rot, play: bool = False
) -> np.ndarray:
    """d(prediction)/dp, shape (n, k), from the core's sensitivities of one parameter p
    (a heavy or Lagrange top on a fixed pivot, or a top on a floor when ``play``)."""
    if obs.kind == "body_rates":
        dw = np.asarray(sens["omega"])[idx]
        return dw @ rotation_matrix(rot) if obs.frame == "sensor" else dw
    if obs.kind == "euler_angles":
        return np.stack([np.asarray(sens[c])[idx] for c in obs.columns], axis=1)
    th, ph = cols["theta"][idx], cols["phi"][idx]
    dth, dph = np.asarray(sens["theta"])[idx], np.asarray(sens["phi"])[idx]
    d = float(obs.axis_point)
    dx = d * (np.cos(th) * np.sin(ph) * dth + np.sin(th) * np.cos(ph) * dph)
    dy = d * (-np.cos(th) * np.cos(ph) * dth + np.sin(th) * np.sin(ph) * dph)
    out = np.stack([dx, dy], axis=1)
    if play:
        dcom = np.asarray(sens["com"])
        out = out + dcom[idx, :2] - dcom[0, :2]
    return out


def difference(pred: np.ndarray, obs: Observations) -> np.ndarray:
    """model - data (n, k); phi and psi taken modulo 2 pi into (-pi, pi]."""
    r = pred - obs.values
    if obs.kind == "euler_angles":
        for j, c in enumerate(obs.columns):
            if c in ("phi", "psi"):
                r[:, j] -= 2 * np.pi * np.round(r[:, j] / (2 * np.pi))
    return r
