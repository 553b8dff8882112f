"""What the 3D view draws of a top: its parts, in the body frame, from one description.

Positions are along the figure axis e3 (body frame, m), measured from the point the
trajectory moves: the centre of mass G for a play top (its ``com`` column), the fixed pivot
for a Lagrange or heavy top. The page draws every part of the list and nothing else, so a
top with several contact parts (a tippe top's ball and peg) is drawn as it is computed.
"""

from __future__ import annotations

import math


def _contact_parts(top) -> list[dict]:
    """The parts that touch the floor: the top's ``shape`` where it has one, else its tip
    sphere (radius rho, centre z = -s). A sphere is drawn as a sphere; a spheroid or a torus
    as a lathe of its profile (the animation's, ``kreisel.animate._part_profile``), with the
    largest radius as its ``radius``."""
    shape = getattr(top, "shape", None)
    if not shape:
        return [{"kind": "sphere", "name": "tip", "radius": float(top.rho), "z": -float(top.s),
                 "role": "contact"}]  # fmt: skip
    out = []
    for i, p in enumerate(shape):
        name = p.name or f"part{i}"
        if p.kind == "sphere":
            out.append({"kind": "sphere", "name": name, "radius": float(p.radius),
                        "z": float(p.z), "role": "contact"})  # fmt: skip
            continue
        from ..animate import _part_profile

        zc, half, radius_at = _part_profile(p, 0.0)
        # evenly in the angle from the axis, not in z: the poles of a spheroid are round too
        zs = [zc - half * math.cos(math.pi * k / 40) for k in range(41)]
        rs = [float(radius_at(z)) for z in zs]
        rs[0] = rs[-1] = 0.0
        out.append({"kind": "lathe", "name": name, "radius": max(rs), "z": float(zc),
                    "profile": [[r, z] for r, z in zip(rs, zs)], "role": "contact"})  # fmt: skip
    return out


def _play_hull(top, contact: list[dict]) -> dict:
    """The body drawn around the contact parts, a surface of revolution about e3 (its
    profile as (r, z) points from bottom to top), sized by the axial moment: a disc of the
    same mass and C has radius sqrt(2 C / m)."""
    disc = math.sqrt(2.0 * top.C / top.m)
    big = max(contact, key=lambda p: p["radius"])
    r, zc = big["radius"], big["z"]
    if r >= 0.5 * disc:
        # a ball top (a tippe top): the ball is the body; the flat face where its stem stands
        # is on the side away from G (-e3). The stem itself is not drawn: the ball alone
        # touches the floor in this model, and a stem would go through it once inverted.
        face = zc - 0.88 * r
        profile = [
            (0.0, face - 0.04 * r),
            (0.5 * r, face - 0.04 * r),
            (0.5 * r, face + 0.1 * r),
            (0.0, face + 0.1 * r),
        ]
    else:
        # a toy top on a small tip: a cone from the tip up to a disc at G, and a stem
        low = min(p["z"] for p in contact)
        stem = 0.12 * disc
        profile = [
            (0.0, low),
            (max(0.9 * r, 1e-4 * disc), low),
            (disc, -0.12 * disc),
            (disc, 0.12 * disc),
            (stem, 0.2 * disc),
            (stem, 0.9 * disc),
            (0.0, 0.95 * disc),
        ]
    return {"kind": "lathe", "name": "body", "profile": [list(p) for p in profile], "role": "hull"}


def _pivot_lathe(length: float, radius: float) -> dict:
    """A symmetric top on a pivot: an axle from the pivot through G (at ``length`` along e3)
    and a disc of ``radius`` at G."""
    sign = 1.0 if length >= 0 else -1.0
    ax, h = 0.06 * radius, 0.12 * radius
    g = length
    profile = [
        (0.0, 0.0),
        (ax, sign * 0.1 * abs(g)),
        (ax, g - sign * h),
        (radius, g - sign * h),
        (radius, g + sign * h),
        (ax, g + sign * h),
        (ax, g + sign * 0.6 * radius),
        (0.0, g + sign * 0.65 * radius),
    ]
    if sign < 0:
        profile.reverse()
    return {"kind": "lathe", "name": "body", "profile": [list(p) for p in profile], "role": "hull"}


def body_parts(top) -> list[dict]:
    """The parts of ``top`` to draw, in its body frame (m).

    Each part is a dict with ``kind``, ``name`` and ``role`` (``"contact"``: it touches the
    floor, ``"hull"``: the drawn body, ``"pivot"``) and its size: a ``"sphere"`` has
    ``radius`` and ``z`` (its centre on the figure axis); a ``"lathe"`` is a surface of
    revolution about e3 with ``profile``, (r, z) points from bottom to top; an
    ``"ellipsoid"`` has ``center`` (x, y, z) and ``radii``; a ``"rod"`` joins ``start`` and
    ``end`` with ``radius``.

    A play top is drawn about its centre of mass: its contact parts (its ``shape``, or the tip
    sphere of radius rho at z = -s) and a body around them. A Lagrange top is an axle and a
    disc of the same axial moment on its pivot; a heavy top is the ellipsoid of its inertia
    (the uniform ellipsoid with the same mass and moments) about its centre of mass, joined
    to the pivot by a rod.

    Examples
    --------
    >>> from kreisel import LagrangeTop, PlayTop
    >>> from kreisel.explore._geometry import body_parts
    >>> tippe = PlayTop(m=0.02, A=2.56e-6, C=3.2e-6, s=0.006, rho=0.02)
    >>> [(p["kind"], p["role"]) for p in body_parts(tippe)]
    [('sphere', 'contact'), ('lathe', 'hull')]
    >>> body_parts(tippe)[0]["z"], body_parts(tippe)[0]["radius"]
    (-0.006, 0.02)
    >>> [p["kind"] for p in body_parts(LagrangeTop(I1=1.75e-4, I3=2e-5, m=0.1, l=0.04))]
    ['lathe', 'sphere']
    """
    from .._lagrange import LagrangeTop
    from .._play import PlayTop

    if isinstance(top, PlayTop):
        contact = _contact_parts(top)
        if any(p["kind"] != "sphere" for p in contact):
            # a body of spheroids and rings: drawn as the union of its parts joined by necks
            # (the animation's profile, measured there from com - s e3)
            from ..animate import _parts_shape

            drawn = _parts_shape(top)
            profile = [[float(r), float(z) - float(top.s)] for r, z in zip(drawn.r, drawn.z)]
            hull = {"kind": "lathe", "name": "body", "profile": profile, "role": "hull"}
            return [*contact, hull]
        return [*contact, _play_hull(top, contact)]
    pivot = {"kind": "sphere", "name": "pivot", "radius": 0.0, "z": 0.0, "role": "pivot"}
    if isinstance(top, LagrangeTop):
        radius = math.sqrt(2.0 * top.I3 / top.m)
        pivot["radius"] = 0.05 * radius
        return [_pivot_lathe(float(top.l), radius), pivot]
    # a heavy top: semi-axes a_i^2 = 5 (I_j + I_k - I_i) / (2 m) of the uniform ellipsoid
    moments = (float(top.I1), float(top.I2), float(top.I3))
    total = sum(moments)
    radii = [math.sqrt(max(5.0 * (total - 2.0 * i) / (2.0 * top.m), 0.0)) for i in moments]
    com = [float(c) for c in top.com]
    pivot["radius"] = 0.04 * max(radii)
    rod = {
        "kind": "rod",
        "name": "arm",
        "start": [0.0, 0.0, 0.0],
        "end": com,
        "radius": 0.02 * max(radii),
        "role": "hull",
    }
    body = {"kind": "ellipsoid", "name": "body", "center": com, "radii": radii, "role": "hull"}
    return [body, rod, pivot]


def axis_tip(parts: list[dict]) -> float:
    """Where the figure axis is drawn to along e3 (m): just past the farthest part, the
    point whose path the view traces. A ball top (a tippe top, whose drawn body lies on the
    ball's side away from G) has it on that side, at -e3, where its stem would be.

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> from kreisel.explore._geometry import axis_tip, body_parts
    >>> round(axis_tip(body_parts(PlayTop(m=0.02, A=2.56e-6, C=3.2e-6, s=0.006, rho=0.02))), 4)
    -0.033
    >>> round(axis_tip(body_parts(PlayTop(m=0.1, A=1.6e-5, C=2e-5, s=0.03, rho=0.0005))), 4)
    0.0209
    """
    hull = [p for p in parts if p["role"] == "hull"]
    if len(hull) == 1 and hull[0]["kind"] == "lathe":
        zs = [z for _, z in hull[0]["profile"]]
        contact = [p for p in parts if p["role"] == "contact"]
        if contact and max(zs) < min(p["z"] for p in contact):
            big = max(contact, key=lambda p: p["radius"])
            return big["z"] - 1.35 * big["radius"]
    reach = 0.0
    for p in parts:
        if p["kind"] == "sphere":
            reach = max(reach, p["z"] + p["radius"])
        elif p["kind"] == "lathe":  # a hull, or a spheroid's or a ring's profile
            reach = max(reach, max(z for _, z in p["profile"]))
        elif p["kind"] == "ellipsoid":
            reach = max(reach, p["center"][2] + p["radii"][2])
        elif p["kind"] == "rod":
            reach = max(reach, p["start"][2], p["end"][2])
    return 1.1 * reach
