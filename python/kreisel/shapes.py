"""The contact parts of a top of revolution: convex bodies centred on its figure axis.

A :class:`~kreisel.PlayTop` built with ``shape=[...]`` touches the floor with the union of
its parts (theory: bodies of revolution). Each part's position ``z`` is measured from the
centre of mass G along the figure axis e3 (the classic tip sphere is ``Sphere(rho, z=-s)``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union

from ._errors import ParameterError
from ._validate import real

__all__ = ["Sphere", "Spheroid", "Torus"]


def _label(kind: str, name: str | None) -> str:
    return f"{kind} {name!r}" if name is not None else kind


def _check_name(name) -> None:
    if name is not None and (not isinstance(name, str) or not name):
        raise ParameterError(
            f"name = {name!r} is not allowed: a part's name must be a non-empty string"
        )


def _length(label: str, what: str, value, zero: bool) -> float:
    x = real(f"{label}: {what}", value)
    if (zero and x == 0.0) or 1e-100 <= x <= 1e100:
        return x
    allowed = "0 (a sharp edge) or a length in" if zero else "a length in"
    raise ParameterError(f"{label}: {what} = {x!r} is not allowed: it must be {allowed} "
                         "[1e-100, 1e+100] m")  # fmt: skip


def _position(label: str, value) -> float:
    z = real(f"{label}: z", value)
    if not abs(z) <= 1e100:
        raise ParameterError(f"{label}: z = {z!r} is not allowed: |z| must be at most 1e+100 m")
    return z


@dataclass(frozen=True)
class Sphere:
    """A spherical contact part whose centre lies on the figure axis at ``z``.

    Parameters
    ----------
    radius : float
        Radius (m), >= 0 (0: a sharp point).
    z : float
        Position of the centre along e3 from the centre of mass (m); negative below G when
        the top stands upright (the tip sphere of ``PlayTop(s, rho)`` is ``Sphere(rho, -s)``).
    name : str, optional
        The part's name in trajectories and events (default ``"part0"``, ``"part1"``, ... by
        its position in the top's ``shape``).

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> from kreisel.shapes import Sphere
    >>> ball, peg = Sphere(0.015, z=-0.003, name="ball"), Sphere(0.005, z=-0.016, name="peg")
    >>> top = PlayTop(m=6e-3, A=8e-7, C=7e-7, shape=[ball, peg])
    >>> [p.name for p in top.shape], top.s, top.rho
    (['ball', 'peg'], 0.003, 0.015)
    >>> Sphere(0.01, z=0.0)
    Sphere(radius=0.01, z=0.0, name=None)
    """

    radius: float
    z: float
    name: str | None = None

    def __post_init__(self) -> None:
        _check_name(self.name)
        label = _label("Sphere", self.name)
        object.__setattr__(self, "radius", _length(label, "radius", self.radius, True))
        object.__setattr__(self, "z", _position(label, self.z))

    def _native(self) -> tuple[str, float, float, float]:
        return ("sphere", self.radius, 0.0, self.z)

    def _named(self, name: str) -> Sphere:
        return Sphere(self.radius, self.z, name)

    @property
    def kind(self) -> str:
        """The part's kind, ``"sphere"``."""
        return "sphere"


@dataclass(frozen=True)
class Spheroid:
    """An ellipsoid of revolution about the figure axis: semi-axes ``equatorial`` (across the
    axis) and ``axial`` (along it), centred at ``z`` on the axis (m). Its lowest point is the
    support point in the direction -ez (theory: bodies of revolution). A hard-boiled egg is one
    prolate
    spheroid (``axial > equatorial``); ``Spheroid(r, r, z)`` is ``Sphere(r, z)``.

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> from kreisel.shapes import Spheroid
    >>> egg = PlayTop(m=0.06, A=3.1e-5, C=1.9e-5, shape=[Spheroid(0.02, 0.03, z=0.0)])
    >>> egg.shape[0]
    Spheroid(equatorial=0.02, axial=0.03, z=0.0, name='part0')
    """

    equatorial: float
    axial: float
    z: float
    name: str | None = None

    def __post_init__(self) -> None:
        _check_name(self.name)
        label = _label("Spheroid", self.name)
        object.__setattr__(self, "equatorial", _length(label, "equatorial", self.equatorial, False))
        object.__setattr__(self, "axial", _length(label, "axial", self.axial, False))
        object.__setattr__(self, "z", _position(label, self.z))

    def _native(self) -> tuple[str, float, float, float]:
        return ("spheroid", self.equatorial, self.axial, self.z)

    def _named(self, name: str) -> Spheroid:
        return Spheroid(self.equatorial, self.axial, self.z, name)

    @property
    def kind(self) -> str:
        """The part's kind, ``"spheroid"``."""
        return "spheroid"


@dataclass(frozen=True)
class Torus:
    """A ring about the figure axis in the plane at ``z`` (m): ``major`` the radius of the
    tube's centre line, ``minor`` the tube's radius (0: a sharp circular edge, a coin's or a
    disk's rim, whose contact point moves along the rim). Lying flat (the axis vertical) the
    whole rim is lowest; a run of a top that settles flat needs the ``flat`` event.

    Examples
    --------
    >>> from kreisel import PlayTop
    >>> from kreisel.shapes import Torus
    >>> rim = Torus(0.0375, 0.0, z=0.0, name="rim")
    >>> PlayTop(m=0.1, A=3.5e-5, C=7e-5, shape=[rim]).part_names
    ('rim',)
    """

    major: float
    minor: float
    z: float
    name: str | None = None

    def __post_init__(self) -> None:
        _check_name(self.name)
        label = _label("Torus", self.name)
        object.__setattr__(self, "major", _length(label, "major", self.major, False))
        object.__setattr__(self, "minor", _length(label, "minor", self.minor, True))
        object.__setattr__(self, "z", _position(label, self.z))

    def _native(self) -> tuple[str, float, float, float]:
        return ("torus", self.major, self.minor, self.z)

    def _named(self, name: str) -> Torus:
        return Torus(self.major, self.minor, self.z, name)

    @property
    def kind(self) -> str:
        """The part's kind, ``"torus"``."""
        return "torus"


Part = Union[Sphere, Spheroid, Torus]
_PARTS = (Sphere, Spheroid, Torus)


def _named(parts: object) -> tuple[Part, ...]:
    """The parts of a ``shape`` argument, each named (``part{i}`` by default), checked: at
    least one, at most four, every one a part, no name twice."""
    if isinstance(parts, _PARTS) or not isinstance(parts, (list, tuple)):
        raise ParameterError(
            f"shape = {parts!r} is not allowed: it must be a list of parts, such as "
            "[kreisel.shapes.Sphere(radius, z)]"
        )
    if not 1 <= len(parts) <= 4:
        raise ParameterError(
            f"shape has {len(parts)} parts, which is not allowed: a top needs between 1 and 4 "
            "contact parts"
        )
    out = []
    for i, p in enumerate(parts):
        if not isinstance(p, _PARTS):
            raise ParameterError(
                f"shape[{i}] = {p!r} is not allowed: a part must be a kreisel.shapes.Sphere, "
                "Spheroid or Torus"
            )
        out.append(p if p.name is not None else p._named(f"part{i}"))
    seen: dict[str, int] = {}
    for i, p in enumerate(out):
        assert p.name is not None
        if p.name in seen:
            raise ParameterError(
                f"shape[{i}] is named {p.name!r} like shape[{seen[p.name]}]: every part needs a "
                "name of its own"
            )
        seen[p.name] = i
    return tuple(out)
