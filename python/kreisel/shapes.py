"""The contact parts of a top of revolution: convex bodies centred on its figure axis.

A :class:`~kreisel.PlayTop` built with ``shape=[...]`` touches the floor with the union of
its parts (PHYSICS notes, section 4.1). Each part's position ``z`` is measured from the
centre of mass G along the figure axis e3 (the classic tip sphere is ``Sphere(rho, z=-s)``).
"""

from __future__ import annotations

from dataclasses import dataclass

from ._errors import ParameterError
from ._validate import real

__all__ = ["Sphere"]


def _label(name: str | None) -> str:
    return f"Sphere {name!r}" if name is not None else "Sphere"


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
        label = _label(self.name)
        if self.name is not None and (not isinstance(self.name, str) or not self.name):
            raise ParameterError(
                f"name = {self.name!r} is not allowed: a part's name must be a non-empty string"
            )
        r = real(f"{label}: radius", self.radius)
        if not (r == 0.0 or 1e-100 <= r <= 1e100):
            raise ParameterError(
                f"{label}: radius = {r!r} is not allowed: it must be 0 (a sharp point) or a "
                "length in [1e-100, 1e+100] m"
            )
        z = real(f"{label}: z", self.z)
        if not abs(z) <= 1e100:
            raise ParameterError(f"{label}: z = {z!r} is not allowed: |z| must be at most 1e+100 m")
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "z", z)

    def _native(self) -> tuple[str, float, float]:
        return ("sphere", self.radius, self.z)

    @property
    def kind(self) -> str:
        """The part's kind, ``"sphere"``."""
        return "sphere"


def _named(parts: object) -> tuple[Sphere, ...]:
    """The parts of a ``shape`` argument, each named (``part{i}`` by default), checked: at
    least one, at most four, every one a part, no name twice."""
    if isinstance(parts, Sphere) or not isinstance(parts, (list, tuple)):
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
        if not isinstance(p, Sphere):
            raise ParameterError(
                f"shape[{i}] = {p!r} is not allowed: a part must be a kreisel.shapes.Sphere"
            )
        out.append(p if p.name is not None else Sphere(p.radius, p.z, f"part{i}"))
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
