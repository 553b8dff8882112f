"""Animations of a top in motion: GIF, MP4 (imageio and its ffmpeg plugin) and an interactive
HTML view (plotly).

The top is drawn as a body of revolution about its figure axis (body axis 3) with a dark
stripe, so that the spin shows, and its tip: on a pivot (a post below it) for a
:class:`~kreisel.LagrangeTop` or :class:`~kreisel.HeavyTop`, a sphere on a floor for a
:class:`~kreisel.PlayTop`. The trace of the upper end of the axis follows it, and for a
play top the track of the contact point on the floor. Sizes come from the model: the length
from the distance to the centre of mass, the radius from the axial moment (a disc's
``I3 = m R^2 / 2``). A top drawn on a pivot whose centre of mass is off its axis (the
Kovalevskaya top) is drawn as a cylinder about its axis through the centre of mass, with a rod
from the pivot.

Frames are taken at equal steps of time (the exact solution is evaluated there for an exact
Lagrange trajectory; a simulated one is interpolated, quaternions by slerp). A fast spin
sampled at a video's frame rate aliases, as under a stroboscope: animate a short time span
with many frames to see it turn smoothly.

Every function imports matplotlib, imageio or plotly only when called.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Union, cast

import numpy as np

from ._errors import ParameterError

if TYPE_CHECKING:
    from collections.abc import Callable
    from pathlib import Path

    import plotly.graph_objects as go

    from ._heavy import HeavyTop
    from ._lagrange import LagrangeTop
    from ._play import PlayTop
    from ._trajectory import Trajectory

    PathLike = Union[str, Path]

_BODY = np.array([0.80, 0.30, 0.22])  # lacquered red
_TIP = np.array([0.72, 0.74, 0.78])  # steel
_STRIPE = np.array([0.12, 0.12, 0.14])
_LIGHT = np.array([-0.4, -0.6, 0.7]) / np.linalg.norm([-0.4, -0.6, 0.7])


# -- geometry ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Shape:
    """A body of revolution in the body frame.

    Attributes
    ----------
    z, r : ndarray (n,)
        The profile: distance along the axis and radius (m), from one end to the other.
    centre : ndarray (3,)
        A point of the axis in the body frame (m); the axis is parallel to body axis 3.
    tip : ndarray (n,) of bool
        Which profile segments belong to the tip (drawn in steel).
    top : float
        The z of the upper end of the axis, whose trace is drawn (m).
    rod : bool
        Draw a rod from the body origin (the pivot) to ``centre`` (a top off its axis).
    """

    z: np.ndarray
    r: np.ndarray
    centre: np.ndarray
    tip: np.ndarray
    top: float
    rod: bool = False

    @property
    def size(self) -> float:
        """The largest distance of the body from the body origin (m)."""
        return float(np.max(np.hypot(self.z, self.r)) + np.linalg.norm(self.centre))


def _profile(points, tip_until=0):
    pts = np.asarray(points, dtype=float)
    tip: np.ndarray = np.zeros(len(pts) - 1, dtype=bool)
    tip[:tip_until] = True
    return pts[:, 0], pts[:, 1], tip


def _toy_profile(length, radius):
    """A toy top standing on its tip at 0 with its centre of mass at ``length`` (m)."""
    s = np.sign(length) if length != 0 else 1.0
    a = abs(length) if length != 0 else radius
    pts = [
        (0.0, 0.0),
        (0.18 * a, 0.06 * radius),
        (0.55 * a, 0.55 * radius),
        (0.85 * a, radius),
        (1.12 * a, radius),
        (1.25 * a, 0.55 * radius),
        (1.32 * a, 0.13 * radius),
        (1.85 * a, 0.13 * radius),
        (1.9 * a, 0.0),
    ]
    z, r, tip = _profile(pts, tip_until=1)
    return z * s, r, tip, 1.9 * a * s


def shape_of(model: HeavyTop | LagrangeTop | PlayTop) -> Shape:
    """The drawn shape of a LagrangeTop, HeavyTop or PlayTop."""
    from ._heavy import HeavyTop
    from ._lagrange import LagrangeTop
    from ._play import PlayTop

    zero = np.zeros(3)
    if isinstance(model, PlayTop) and model._given_shape:
        return _parts_shape(model)
    if isinstance(model, PlayTop):
        rho, s = model.rho, model.s
        if s < rho:
            # a tippe top: a ball, full on the side of the centre of mass, truncated on the
            # other, with a short stem that stays inside the ball's envelope (the model's only
            # contact is the sphere).
            ang = np.linspace(0.0, np.arccos(-0.5), 12)
            pts = [(rho * np.cos(a), rho * np.sin(a)) for a in ang]
            pts += [(-0.5 * rho, 0.16 * rho), (-0.93 * rho, 0.15 * rho), (-0.94 * rho, 0.0)]
            z, r, tip = _profile(pts)
            return Shape(z, r, zero, tip, -0.94 * rho)
        radius = float(np.clip(np.sqrt(2.0 * model.C / model.m), 0.25 * s, 1.2 * s))
        ang = np.linspace(np.pi, np.pi / 2, 7)
        pts = [(rho * np.cos(a), rho * np.sin(a)) for a in ang]
        body = [
            (max(0.55 * s, rho * 1.01), max(0.55 * radius, rho)),
            (0.85 * s, radius),
            (1.12 * s, radius),
            (1.25 * s, 0.55 * radius),
            (1.32 * s, 0.13 * radius),
            (1.85 * s, 0.13 * radius),
            (1.9 * s, 0.0),
        ]
        z, r, tip = _profile(pts + body, tip_until=len(pts) - 1)
        return Shape(z, r, zero, tip, 1.9 * s)
    if isinstance(model, LagrangeTop):
        com = np.array([0.0, 0.0, model.l])
        I3, m = model.I3, model.m
    elif isinstance(model, HeavyTop):
        com, I3, m = model.com, model.I3, model.m
    else:
        raise ParameterError(
            f"model = {model!r} is not allowed: draw a LagrangeTop, HeavyTop or PlayTop"
        )
    radius = np.sqrt(2.0 * I3 / m)
    if abs(com[0]) < 1e-15 and abs(com[1]) < 1e-15 and com[2] != 0.0:
        l = com[2]  # noqa: E741 (the physics name)
        radius = float(np.clip(radius, 0.2 * abs(l), 1.2 * abs(l)))
        z, r, tip, top = _toy_profile(l, radius)
        return Shape(z, r, zero, tip, top)
    # off its axis (or no torque at all): a cylinder about the axis through the centre of
    # mass, long as a Kovalevskaya body (I1 = 2 I3 for a cylinder of length 3 R).
    if np.linalg.norm(com) > 0:
        radius = float(np.clip(radius, 0.5 * np.linalg.norm(com), 5 * np.linalg.norm(com)))
    h = 1.5 * radius
    pts = [(-h, 0.0), (-h, 0.9 * radius), (-0.92 * h, radius), (0.92 * h, radius),
           (h, 0.9 * radius), (h, 0.0)]  # fmt: skip
    z, r, tip = _profile(pts)
    return Shape(z, r, np.array(com, dtype=float), tip, h, rod=bool(np.linalg.norm(com) > 0))


def _part_profile(part, s: float):
    """(centre, half-length along the axis, radius at z) of a part, from the body origin."""
    zc = part.z + s
    if part.kind == "sphere":
        rc = part.radius
        return zc, rc, lambda z: np.sqrt(np.clip(rc * rc - (z - zc) ** 2, 0.0, None))
    if part.kind == "spheroid":
        a, b = part.equatorial, part.axial
        return zc, b, lambda z: a * np.sqrt(np.clip(1.0 - ((z - zc) / b) ** 2, 0.0, None))
    big, small = part.major, part.minor
    half = max(small, 1e-3 * big)  # a sharp rim drawn as a thin ring
    return zc, half, lambda z: big + np.sqrt(np.clip(half * half - (z - zc) ** 2, 0.0, None))


def _parts_shape(model) -> Shape:
    """The drawn shape of a top given by its parts: their union along the axis (each part as
    it is, joined by a neck where two parts do not meet: thin between spheres, full between
    rims, as a disk's body), so that nothing drawn reaches below the lowest part: the floor
    is never crossed. Measured from the body origin the frames use (``com - s e3``); the
    parts other than the first in steel."""
    s = model.s
    profiles = [_part_profile(p, s) for p in model.shape]
    lo = min(zc - h for zc, h, _ in profiles)
    hi = max(zc + h for zc, h, _ in profiles)
    zs = np.unique(np.r_[np.linspace(lo, hi, 97), [zc for zc, _, _ in profiles]])
    r = np.zeros_like(zs)
    owner: np.ndarray = np.zeros(len(zs), dtype=int)
    for i, (zc, h, radius_at) in enumerate(profiles):
        inside = np.abs(zs - zc) <= h
        ri = np.where(inside, radius_at(zs), 0.0)
        better = inside & (ri > r)
        r[better], owner[better] = ri[better], i
    # necks between parts that do not meet; every neck lies in the parts' convex hull, which
    # is above the floor wherever the parts are
    order = sorted(range(len(profiles)), key=lambda i: profiles[i][0])
    for a, b in zip(order, order[1:]):
        pa, pb = model.shape[a], model.shape[b]
        (za, _, at_a), (zb, _, at_b) = profiles[a], profiles[b]
        ra, rb = float(at_a(za)), float(at_b(zb))
        between = (zs > za) & (zs < zb)
        if {pa.kind, pb.kind} == {"torus"}:
            neck = np.full(len(zs), min(pa.major, pb.major))
        elif "torus" in (pa.kind, pb.kind) and 0 in (a, b):
            # the tip and a rim: the cone between them (a toy top's body)
            neck = ra + (rb - ra) * (zs - za) / (zb - za)
        elif "torus" in (pa.kind, pb.kind):
            neck = np.full(len(zs), min(ra, rb))  # a handle on a rim's face
        else:
            neck = np.full(len(zs), 0.5 * min(ra, rb) if min(ra, rb) > 0
                           else 0.05 * max(ra, rb, 1e-3))  # fmt: skip
        thin = between & (r < neck)
        r[thin], owner[thin] = neck[thin], b
    r[0] = r[-1] = 0.0
    tip = owner[:-1] != 0
    first = profiles[0][0]
    far = hi if abs(hi - first) >= abs(lo - first) else lo
    return Shape(zs, r, np.zeros(3), tip, float(far))


def _mesh(shape: Shape, around: int):
    """Body-frame vertices (n_profile, around, 3) and face colours (n_profile-1, around, 3)."""
    ang = np.linspace(0.0, 2 * np.pi, around, endpoint=False)
    v = np.empty((len(shape.z), around, 3))
    v[..., 0] = shape.r[:, None] * np.cos(ang)[None, :] + shape.centre[0]
    v[..., 1] = shape.r[:, None] * np.sin(ang)[None, :] + shape.centre[1]
    v[..., 2] = shape.z[:, None] + shape.centre[2]
    colours = np.where(shape.tip[:, None, None], _TIP, _BODY) * np.ones((1, around, 1))
    stripe: np.ndarray = np.zeros(around, dtype=bool)
    # two stripes on opposite sides, so that one is always in sight
    stripe[: max(1, around // 9)] = True
    stripe[around // 2 : around // 2 + max(1, around // 9)] = True
    colours[:, stripe] = np.where(shape.tip[:, None, None], _TIP * 0.55, _STRIPE)
    return v, colours


def _rotation(q):
    """Rotation matrices (n, 3, 3) of unit quaternions (n, 4), (w, x, y, z): the core's."""
    from . import _core

    return _core.rotation_matrices(np.ascontiguousarray(q, dtype=float).reshape(-1, 4))


def _euler_quaternion(phi, theta, psi):
    """Quaternions (n, 4) of z-x-z Euler angles (the core's): q = qz(phi) qx(theta) qz(psi)."""
    from . import _core

    def a(x):
        return np.ascontiguousarray(np.atleast_1d(x), dtype=float)

    return _core.quaternions_from_euler(a(phi), a(theta), a(psi))


def _slerp(t, ts, qs):
    """Quaternions at times ``t`` by slerp between the samples ``qs`` at ``ts``."""
    i = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 2)
    span = ts[i + 1] - ts[i]
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(span > 0, (t - ts[i]) / span, 0.0)
    f = np.clip(f, 0.0, 1.0)[:, None]
    q0, q1 = qs[i], qs[i + 1].copy()
    d = np.sum(q0 * q1, axis=1)
    q1[d < 0] *= -1
    d = np.abs(d)[:, None]
    omega = np.arccos(np.clip(d, -1.0, 1.0))
    so = np.sin(omega)
    small = so < 1e-9
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(small, 1.0 - f, np.sin((1.0 - f) * omega) / so)
        b = np.where(small, f, np.sin(f * omega) / so)
    q = a * q0 + b * q1
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _interp(t, ts, cols):
    cols = np.asarray(cols, dtype=float)
    return np.stack([np.interp(t, ts, cols[:, j]) for j in range(cols.shape[1])], -1)


@dataclass(frozen=True)
class Frames:
    """The motion sampled at the animation's frames.

    Attributes
    ----------
    t : ndarray (n,)
        Times (s).
    rotation : ndarray (n, 3, 3)
        Body-to-space rotation matrices.
    origin : ndarray (n, 3)
        Where the body origin is (m): the pivot (0) or the centre of the tip sphere.
    contact : ndarray (n, 3) or None
        The contact point on the floor (play tops).
    modes : ndarray (n,) of str or None
        The contact mode (play tops).
    dense : Frames or None
        The same at several times per frame, for the traces.
    parts : tuple of str or None
        The names of the contact parts (play tops).
    part_modes : ndarray (n, parts) of str or None
        Each part's contact state (``Trajectory.part_modes``: flight, rolling, drilling,
        sliding, flat).
    """

    t: np.ndarray
    rotation: np.ndarray
    origin: np.ndarray
    contact: np.ndarray | None
    modes: np.ndarray | None
    dense: Frames | None = None
    parts: tuple[str, ...] | None = None
    part_modes: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t)


def _check_frames(frames):
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 2:
        raise ParameterError(f"frames = {frames!r} is not allowed: it must be an integer >= 2")
    return int(frames)


def _at(traj, model, t) -> Frames:
    from ._lagrange import LagrangeTop

    ts = np.asarray(traj.t, dtype=float)
    cols = set(traj.columns)
    if "quaternion" not in cols:
        if isinstance(model, LagrangeTop) and "psi_dot" in cols:
            ex = model.exact(traj.state, t)
            q = _euler_quaternion(ex.phi, ex.theta, ex.psi)
        else:
            order = np.argsort(ts)
            ang = [
                np.interp(t, ts[order], np.asarray(traj[k])[order]) for k in ("phi", "theta", "psi")
            ]
            q = _euler_quaternion(*ang)
    elif len(ts) == 1:
        q = np.repeat(np.asarray(traj.quaternion, dtype=float), len(t), axis=0)
    else:
        q = _slerp(t, ts, np.asarray(traj.quaternion, dtype=float))
    rot = _rotation(q)
    if "contact_point" not in cols:
        # a top on a pivot: the body's origin is the pivot, which may move
        moving = "pivot_position" in cols and len(ts) > 1
        origin = _interp(t, ts, traj.pivot_position) if moving else np.zeros((len(t), 3))
        return Frames(t, rot, origin, None, None)
    com = _interp(t, ts, traj.com)
    origin = com - model.s * rot[:, :, 2]
    contact = _interp(t, ts, traj.contact_point)
    contact[:, 2] = 0.0
    idx = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 1)
    states = traj.part_modes
    if not states:
        return Frames(t, rot, origin, contact, np.asarray(traj.mode)[idx])
    parts = tuple(states)
    per_part = np.stack([np.asarray(states[p])[idx] for p in parts], axis=1)
    return Frames(t, rot, origin, contact, np.asarray(traj.mode)[idx], None, parts, per_part)


def sample(
    traj: Trajectory,
    frames: int = 60,
    *,
    model: HeavyTop | LagrangeTop | PlayTop | None = None,
    t_start: float | None = None,
    t_stop: float | None = None,
) -> Frames:
    """The trajectory at ``frames`` equally spaced times from ``t_start`` to ``t_stop`` (s;
    default: its whole span), with ``dense`` samples (up to 3000) for the traces."""
    frames = _check_frames(frames)
    model = _model_of(traj, model)
    ts = np.asarray(traj.t, dtype=float)
    if len(ts) < 1:
        raise ParameterError("traj is not allowed: it has no samples")
    a = ts.min() if t_start is None else float(t_start)
    b = ts.max() if t_stop is None else float(t_stop)
    if not (ts.min() <= a <= b <= ts.max()):
        raise ParameterError(
            f"t_start = {a}, t_stop = {b} are not allowed: they must lie in "
            f"[{ts.min():g}, {ts.max():g}] s with t_start <= t_stop"
        )
    t = np.linspace(a, b, frames)
    n_dense = min(3000, max(frames * 10, int(np.count_nonzero((ts >= a) & (ts <= b)))))
    dense = _at(traj, model, np.linspace(a, b, n_dense))
    f = _at(traj, model, t)
    return Frames(f.t, f.rotation, f.origin, f.contact, f.modes, dense, f.parts, f.part_modes)


def _contact_label(f: Frames, i: int) -> str:
    """The contact of frame ``i`` for a title: the top's mode, then each part touching and
    its state (``"slip: ball sliding"``, ``"roll: peg drilling"``; ``"flight"`` when none
    touches)."""
    assert f.modes is not None
    mode = str(f.modes[i])
    if f.parts is None or f.part_modes is None:
        return mode
    touching = [f"{p} {s}" for p, s in zip(f.parts, f.part_modes[i]) if s != "flight"]
    return f"{mode}: {', '.join(touching)}" if touching else mode


# -- drawing with matplotlib -------------------------------------------------------------------


class _Scene:
    """A matplotlib 3D scene whose artists are updated frame by frame."""

    def __init__(self, model, frames: Frames, *, size_px=480, around=36, title=None, trail=None):
        from .plot import _pyplot

        plt = _pyplot()
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        self.shape = shape_of(model)
        self.frames = frames
        self.vert, self.colour = _mesh(self.shape, around)
        dpi = 80
        self.fig = plt.figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
        self.ax = self.fig.add_axes((0.01, 0.02, 0.9, 0.9), projection="3d")
        self.title = title
        self.text = self.fig.text(0.5, 0.965, "", ha="center", va="center", fontsize=10)
        ax = self.ax
        self.play = frames.contact is not None
        self.trail = (0.2 if self.play else 0.5) if trail is None else float(trail)
        # where the upper end of the axis is at every frame
        top_body = self.shape.centre + np.array([0.0, 0.0, self.shape.top])
        d = frames.dense if frames.dense is not None else frames
        self.dense_t = d.t
        self.trace = d.origin + d.rotation @ top_body
        self.dense_contact: Any = d.contact
        size = self.shape.size
        if self.play:
            travel = np.ptp(frames.origin[:, :2], axis=0).max()
            self.follow = travel > 1.5 * size
            self.half = 1.6 * size
            lo_z, hi_z = 0.0, 2.0 * self.half
        else:
            self.follow = False
            # a moving pivot: the view holds the body wherever the pivot takes it
            travel = np.ptp(frames.origin, axis=0)
            self.half = 1.1 * size + 0.5 * float(travel[:2].max())
            allz = frames.rotation[:, 2, :] @ (self.vert.reshape(-1, 3).T)
            oz = frames.origin[:, 2]
            lo_z = min(float(allz.min()), -0.35 * size) + float(oz.min()) - 0.05 * size
            hi_z = max(float(allz.max()), 0.2 * size) + float(oz.max()) + 0.05 * size
        self.zlim = (lo_z, hi_z)
        ax.set_zlim(*self.zlim)
        centre = self._centre(0)
        self._set_xy(centre)
        ax.set_box_aspect((1.0, 1.0, (hi_z - lo_z) / (2 * self.half)))
        ax.view_init(elev=20, azim=-60)
        unit, scale = ("mm", 1e3) if size < 0.5 else ("m", 1.0)
        self.scale = scale
        fmt = plt.FuncFormatter(lambda v, _pos: f"{v * scale:.0f}" if scale > 1 else f"{v:.2g}")
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            axis.set_major_formatter(fmt)
            axis.set_major_locator(plt.MaxNLocator(4))
        ax.tick_params(labelsize=7, pad=0)
        ax.set_xlabel(f"x ({unit})", fontsize=8, labelpad=-4)
        ax.set_ylabel(f"y ({unit})", fontsize=8, labelpad=-4)
        ax.set_zlabel(f"z ({unit})", fontsize=8, labelpad=-4)
        self.floor: Any = None
        if self.play:
            # the floor is always behind the top (the camera looks from above it)
            ax.computed_zorder = False
            self.floor = Poly3DCollection(
                [], facecolor=(0.88, 0.88, 0.84, 1.0), edgecolor="none", zorder=1
            )
            ax.add_collection3d(self.floor)
            (self.grid,) = ax.plot([], [], [], color="0.72", lw=0.5, zorder=2)
            (self.track,) = ax.plot([], [], [], color="#1f5fa8", lw=1.2, zorder=3)
        else:
            h = 0.35 * size
            ang = np.linspace(0, 2 * np.pi, 25)
            self.post_shape = np.array([
                [(0.0, 0.0, 0.0), (0.12 * h * np.cos(a), 0.12 * h * np.sin(a), -h),
                 (0.12 * h * np.cos(b), 0.12 * h * np.sin(b), -h)]
                for a, b in zip(ang[:-1], ang[1:])
            ])  # fmt: skip
            # the post carries the pivot, and moves with it where it moves
            self.post = Poly3DCollection(
                list(self.post_shape + frames.origin[0]), facecolor=(0.45, 0.45, 0.48),
                edgecolor="none",
            )  # fmt: skip
            ax.add_collection3d(self.post)
            (self.pivot_mark,) = ax.plot(*([x] for x in frames.origin[0]), marker="o",
                                         color="k", ms=3)  # fmt: skip
        self.body = Poly3DCollection([], edgecolor="none", linewidth=0, zorder=4)
        ax.add_collection3d(self.body)
        (self.axis_trace,) = ax.plot([], [], [], color="#6a3d9a", lw=1.0, zorder=3.5)
        (self.rod,) = ax.plot([], [], [], color="0.25", lw=2.0)

    def _centre(self, i):
        if self.follow:
            return self.frames.origin[i, :2]
        if self.play:
            return 0.5 * (self.frames.origin[:, :2].min(0) + self.frames.origin[:, :2].max(0))
        return np.zeros(2)

    def _set_xy(self, c):
        self.ax.set_xlim(c[0] - self.half, c[0] + self.half)
        self.ax.set_ylim(c[1] - self.half, c[1] + self.half)

    def _in_view(self, pts, c):
        inside = np.all(np.abs(pts[:, :2] - c) <= self.half, axis=1)
        out = pts.astype(float).copy()
        out[~inside] = np.nan
        return out

    def draw(self, i):
        f = self.frames
        rot, origin = f.rotation[i], f.origin[i]
        c = self._centre(i)
        if self.follow:
            self._set_xy(c)
        v = self.vert @ rot.T + origin
        quads = np.stack([v[:-1, :-1], v[1:, :-1], v[1:, 1:], v[:-1, 1:]], axis=2)
        wrap = np.stack([v[:-1, -1], v[1:, -1], v[1:, 0], v[:-1, 0]], axis=1)[:, None]
        quads = np.concatenate([quads, wrap], axis=1).reshape(-1, 4, 3)
        normal = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
        norm = np.linalg.norm(normal, axis=1, keepdims=True)
        normal = np.divide(normal, norm, out=np.zeros_like(normal), where=norm > 0)
        light = 0.45 + 0.55 * np.abs(normal @ _LIGHT)
        colours = np.clip(self.colour.reshape(-1, 3) * light[:, None], 0, 1)
        self.body.set_verts(list(quads))
        self.body.set_facecolor(colours)
        upto = int(np.searchsorted(self.dense_t, f.t[i], side="right"))
        # the trail covers the last part of the span only, or it hides the top
        first = int(np.searchsorted(self.dense_t, f.t[i] - self.trail * np.ptp(f.t)))
        tr = self.trace[first:upto]
        if self.play:
            h = self.half
            x0, x1, y0, y1 = c[0] - h, c[0] + h, c[1] - h, c[1] + h
            self.floor.set_verts([[(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)]])
            step = _nice_step(2 * h / 6)
            xs = np.arange(np.ceil(x0 / step), np.floor(x1 / step) + 1) * step
            ys = np.arange(np.ceil(y0 / step), np.floor(y1 / step) + 1) * step
            gx, gy = [], []
            for x in xs:
                gx += [x, x, np.nan]
                gy += [y0, y1, np.nan]
            for y in ys:
                gx += [x0, x1, np.nan]
                gy += [y, y, np.nan]
            self.grid.set_data_3d(np.array(gx), np.array(gy), np.zeros(len(gx)))
            track = self._in_view(self.dense_contact[:upto], c)
            self.track.set_data_3d(track[:, 0], track[:, 1], track[:, 2])
            tr = self._in_view(tr, c)
        self.axis_trace.set_data_3d(tr[:, 0], tr[:, 1], tr[:, 2])
        if not self.play:
            self.post.set_verts(list(self.post_shape + origin))
            self.pivot_mark.set_data_3d([origin[0]], [origin[1]], [origin[2]])
        if self.shape.rod:
            p = rot @ self.shape.centre + origin
            self.rod.set_data_3d(*(np.array([o, x]) for o, x in zip(origin, p)))
        label = f"t = {f.t[i]:.3f} s"
        if f.modes is not None:
            label += f"   ({_contact_label(f, i)})"
        self.text.set_text(f"{self.title}   {label}" if self.title else label)

    def rgb(self, i) -> np.ndarray:
        self.draw(i)
        self.fig.canvas.draw()
        return np.asarray(self.fig.canvas.buffer_rgba())[..., :3].copy()

    def close(self):
        from .plot import _pyplot

        _pyplot().close(self.fig)


def _nice_step(x):
    e = 10.0 ** np.floor(np.log10(x))
    for m in (1, 2, 5, 10):
        if m * e >= x:
            return m * e
    return 10 * e  # pragma: no cover


def _model_of(traj, model):
    model = model if model is not None else getattr(traj, "model", None)
    if model is None:
        raise ParameterError(
            "model = None is not allowed: this trajectory does not carry its model; pass model="
        )
    return model


def render(
    traj: Trajectory,
    *,
    frames: int = 60,
    model: HeavyTop | LagrangeTop | PlayTop | None = None,
    size_px: int = 480,
    title: str | None = None,
    progress: Callable[[int], object] | None = None,
    t_start: float | None = None,
    t_stop: float | None = None,
    trail: float | None = None,
) -> list[np.ndarray]:
    """The animation's frames as RGB images, a list of ``frames`` arrays (size_px, size_px, 3)
    of uint8.

    Parameters
    ----------
    traj : Trajectory
        From :func:`kreisel.simulate` or :meth:`kreisel.LagrangeTop.exact`.
    frames : int
        Number of frames, >= 2, at equal steps of time.
    model : optional
        The top; default: the one the trajectory carries.
    size_px : int
        Width and height in pixels (a multiple of 16 suits every video codec).
    title : str, optional
        Shown above the time.
    progress : callable, optional
        Called with 1 after each frame (e.g. a progress bar's ``update``).
    t_start, t_stop : float, optional
        The animated span (s); default: the whole trajectory.
    trail : float, optional
        How far back the traces reach, as a fraction of the span (default 0.5 on a pivot,
        0.2 on the floor).
    """
    model = _model_of(traj, model)
    f = sample(traj, frames, model=model, t_start=t_start, t_stop=t_stop)
    scene = _Scene(model, f, size_px=int(size_px), title=title, trail=trail)
    try:
        images = []
        for i in range(len(f)):
            images.append(scene.rgb(i))
            if progress is not None:
                progress(1)
        return images
    finally:
        scene.close()


def _check_fps(fps):
    if isinstance(fps, bool) or not isinstance(fps, (int, float, np.integer, np.floating)):
        raise ParameterError(f"fps = {fps!r} is not allowed: it must be a number > 0")
    if not 0 < fps <= 120:
        raise ParameterError(f"fps = {fps!r} is not allowed: it must lie in (0, 120]")
    return float(fps)


def to_gif(
    traj: Trajectory, path: PathLike, *, frames: int = 60, fps: float = 15, **kwargs: Any
) -> PathLike:
    """Writes the animation to a looping GIF at ``path`` (``fps`` frames per second); the
    keywords of :func:`render` apply. Returns the path."""
    import imageio.v3 as iio

    fps = _check_fps(fps)
    images = render(traj, frames=frames, **kwargs)
    iio.imwrite(path, np.stack(images), extension=".gif", duration=1000.0 / fps, loop=0)
    return path


def to_mp4(
    traj: Trajectory, path: PathLike, *, frames: int = 60, fps: float = 15, **kwargs: Any
) -> PathLike:
    """Writes the animation to an H.264 MP4 at ``path`` with the ffmpeg that the
    ``imageio-ffmpeg`` package ships (no system install); keywords as :func:`render`.
    Returns the path."""
    import imageio.v2 as iio2

    fps = _check_fps(fps)
    images = render(traj, frames=frames, **kwargs)
    writer = iio2.get_writer(
        str(path), format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=7,
        pixelformat="yuv420p", macro_block_size=16, ffmpeg_log_level="error",
    )  # fmt: skip
    try:
        for im in images:
            writer.append_data(im)
    finally:
        writer.close()
    return path


def figure(
    traj: Trajectory,
    *,
    frames: int = 60,
    model: HeavyTop | LagrangeTop | PlayTop | None = None,
    around: int = 24,
    t_start: float | None = None,
    t_stop: float | None = None,
    title: str | None = None,
) -> go.Figure:
    """An interactive plotly figure: the top as a 3D mesh, with a play button and a time
    slider over ``frames`` frames, and the trace of its axis (and the contact track of a play
    top). Rotate and zoom it with the mouse."""
    import plotly.graph_objects as go

    model = _model_of(traj, model)
    f = sample(traj, frames, model=model, t_start=t_start, t_stop=t_stop)
    shape = shape_of(model)
    vert, colour = _mesh(shape, around)
    n_p = vert.shape[0]
    idx = np.arange(n_p * around).reshape(n_p, around)
    a, b = idx[:-1], idx[1:]
    a1, b1 = np.roll(a, -1, axis=1), np.roll(b, -1, axis=1)
    tri_i = np.concatenate([a.ravel(), a.ravel()])
    tri_j = np.concatenate([b.ravel(), b1.ravel()])
    tri_k = np.concatenate([b1.ravel(), a1.ravel()])
    fc = (np.concatenate([colour.reshape(-1, 3)] * 2) * 255).astype(int)
    facecolor = [f"rgb({r},{g},{bb})" for r, g, bb in fc]
    flat = vert.reshape(-1, 3)
    top_body = shape.centre + np.array([0.0, 0.0, shape.top])
    # the traces at up to 600 times: the file stays small, the curves smooth
    d = cast(Frames, f.dense)
    keep = np.unique(np.linspace(0, len(d.t) - 1, min(600, len(d.t))).astype(int))
    dt_, trace = d.t[keep], np.round((d.origin + d.rotation @ top_body)[keep], 6)
    dcontact: Any = d.contact[keep] if d.contact is not None else None
    play = f.contact is not None

    def body(i, full=True):
        v = np.round(flat @ f.rotation[i].T + f.origin[i], 6)
        if not full:  # a frame changes only the vertices
            return go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2])
        return go.Mesh3d(
            x=v[:, 0], y=v[:, 1], z=v[:, 2], i=tri_i, j=tri_j, k=tri_k, facecolor=facecolor,
            flatshading=True, lighting=dict(ambient=0.5, diffuse=0.7, specular=0.2),
            hoverinfo="skip", name="top",
        )  # fmt: skip

    def lines(i):
        n = int(np.searchsorted(dt_, f.t[i], side="right"))
        out = [go.Scatter3d(x=trace[:n, 0], y=trace[:n, 1], z=trace[:n, 2],
                            mode="lines", line=dict(color="#6a3d9a", width=3),
                            name="trace of the axis")]  # fmt: skip
        if play:
            c = dcontact[:n]
            out.append(go.Scatter3d(x=c[:, 0], y=c[:, 1], z=c[:, 2], mode="lines",
                                    line=dict(color="#1f5fa8", width=3),
                                    name="contact track"))  # fmt: skip
        return out

    size = shape.size
    allv = np.concatenate([flat @ r.T + o for r, o in zip(f.rotation, f.origin)])
    lo, hi = allv.min(axis=0), allv.max(axis=0)
    centre = 0.5 * (lo + hi)
    half = 0.5 * max(np.max(hi - lo), size) * 1.1
    static = []
    if play:
        x0, x1 = centre[0] - half, centre[0] + half
        y0, y1 = centre[1] - half, centre[1] + half
        static.append(go.Mesh3d(x=[x0, x1, x1, x0], y=[y0, y0, y1, y1], z=[0, 0, 0, 0],
                                i=[0, 0], j=[1, 2], k=[2, 3], color="rgb(225,225,214)",
                                hoverinfo="skip", name="floor"))  # fmt: skip
        # the floor is wide where the top travels; z spans only the top's height
        zr = [0.0, max(float(hi[2]) * 1.15, 0.1 * half)]
    else:
        static.append(go.Scatter3d(x=[0], y=[0], z=[0], mode="markers",
                                   marker=dict(size=4, color="black"), name="pivot"))  # fmt: skip
        zr = [centre[2] - half, centre[2] + half]
    data = [body(0), *lines(0), *static]
    n_dyn = 2 + (1 if play else 0)
    head = title or f"{type(model).__name__}: drag to rotate, scroll to zoom"

    def frame_layout(i):
        # a play top's frame names its contact: the top's mode, each touching part's state
        if f.modes is None:
            return None
        return dict(title=dict(text=f"{head}   t = {f.t[i]:.3f} s ({_contact_label(f, i)})"))

    fr = [
        go.Frame(data=[body(i, full=False), *lines(i)], traces=list(range(n_dyn)), name=f"{i}",
                 layout=frame_layout(i))
        for i in range(len(f))
    ]  # fmt: skip
    duration = 80
    steps = [
        dict(method="animate", label=f"{f.t[i]:.2f}" if i % max(1, len(f) // 6) == 0 else "",
             args=[[f"{i}"], dict(mode="immediate", frame=dict(duration=0, redraw=True))])
        for i in range(len(f))
    ]  # fmt: skip
    fig = go.Figure(data=data, frames=fr)
    km = 1e3 if size < 0.5 else 1.0
    unit = "mm" if km > 1 else "m"

    def ax(name, rng, n=5):
        ticks = np.linspace(rng[0], rng[1], n)
        text = [f"{round(v * km):d}" if km > 1 else f"{v + 0.0:.2f}" for v in ticks]
        return dict(title=f"{name} ({unit})", range=list(rng), tickvals=list(ticks), ticktext=text)

    fig.update_layout(
        title=head if f.modes is None else f"{head}   t = {f.t[0]:.3f} s ({_contact_label(f, 0)})",
        scene=dict(
            xaxis=ax("x", (centre[0] - half, centre[0] + half)),
            yaxis=ax("y", (centre[1] - half, centre[1] + half)),
            zaxis=ax("z", tuple(zr), 3 if play else 5),
            aspectmode="manual",
            aspectratio=dict(x=1, y=1, z=max((zr[1] - zr[0]) / (2 * half), 0.15)),
        ),
        updatemenus=[
            dict(
                type="buttons",
                showactive=False,
                x=0.05,
                y=0.05,
                buttons=[
                    dict(
                        label="play",
                        method="animate",
                        args=[
                            None,
                            dict(frame=dict(duration=duration, redraw=True), fromcurrent=True),
                        ],
                    ),
                    dict(
                        label="pause",
                        method="animate",
                        args=[[None], dict(mode="immediate", frame=dict(duration=0, redraw=False))],
                    ),
                ],
            )
        ],  # fmt: skip
        sliders=[dict(steps=steps, currentvalue=dict(prefix="t (s) = "), x=0.15, len=0.8)],
        margin=dict(l=0, r=0, t=40, b=0),
    )
    return fig


def to_html(traj: Trajectory, path: PathLike, *, frames: int = 60, **kwargs: Any) -> PathLike:
    """Writes the interactive view of :func:`figure` to a self-contained HTML file (plotly.js
    included: it opens offline). Returns the path."""
    fig = figure(traj, frames=frames, **kwargs)
    fig.write_html(str(path), include_plotlyjs=True, full_html=True, auto_play=False)
    return path
