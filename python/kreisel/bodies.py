"""Bodies people spin on a table, as play tops of uniform density: an egg, a disk (Euler's
disk, a coin) and a toy top. Each helper computes the mass distribution from the geometry
(the formulas are in each docstring) and returns a :class:`~kreisel.PlayTop` whose contact
parts (:mod:`kreisel.shapes`) are the body's own surfaces.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple, Union

from ._errors import ParameterError
from ._play import Coulomb, CoulombContensou, Frictionless, PlayState, PlayTop, Viscous
from ._validate import real
from .shapes import Part, Sphere, Spheroid, Torus

__all__ = [
    "EggThresholds",
    "disk",
    "disk_rolling_rates",
    "disk_rolling_state",
    "egg",
    "egg_rising_thresholds",
    "egg_settled_inclination",
    "toy_top",
]

Law = Union[Coulomb, Viscous, Frictionless, CoulombContensou]
# the largest rate (rad/s) a state may have (PlayTop.state checks it)
MAX_RATE = 1e100
# the longest egg the rising thresholds are computed for (axial / equatorial)
MAX_EGG_RATIO = 1e6


def _positive(name: str, value: object) -> float:
    x = real(name, value)
    if not 1e-100 <= x <= 1e100:
        raise ParameterError(f"{name} = {x!r} is not allowed: it must be a length or mass in "
                             "[1e-100, 1e+100]")  # fmt: skip
    return x


def _moments(m: float, a: float, c: float, **geometry: float) -> tuple[float, float]:
    """``(A, C)`` if a top may have them (as :class:`~kreisel.PlayTop` checks them), else a
    ParameterError naming the ``geometry`` that gave them."""
    for name, x in (("A", a), ("C", c)):
        if not 1e-100 <= x <= 1e100:
            given = ", ".join(f"{k} = {v!r}" for k, v in geometry.items())
            raise ParameterError(
                f"{given} are not allowed together: they give {name} = {x!r} kg m^2, and a "
                "top's moments of inertia must lie in [1e-100, 1e+100]"
            )
    return a, c


def egg(
    equatorial: float = 0.0225,
    axial: float = 0.03,
    mass: float = 0.06,
    friction: Law | None = None,
    **kwargs: Any,
) -> PlayTop:
    """A hard-boiled egg as a uniform solid prolate spheroid (semi-axes ``equatorial`` across
    the axis and ``axial`` along it, m; ``mass`` kg): ``C = 2 m a^2 / 5`` about the axis and
    ``A = m (a^2 + b^2) / 5`` across it, its one part ``Spheroid(a, b, 0, "shell")`` centred at
    the centre of mass. Friction defaults to Coulomb-Contensou (mu 0.3 over a 0.5 mm patch);
    other keywords go to :class:`~kreisel.PlayTop`. Spun on its side it rises above the spin
    :func:`egg_rising_thresholds` gives.

    Examples
    --------
    >>> from kreisel import bodies
    >>> e = bodies.egg()
    >>> round(e.C, 12), round(e.A, 12), e.part_names
    (1.215e-05, 1.6875e-05, ('shell',))
    """
    a, b, m = (
        _positive("equatorial", equatorial),
        _positive("axial", axial),
        _positive("mass", mass),
    )
    friction = CoulombContensou(0.3, 5e-4) if friction is None else friction
    big_a, big_c = _moments(m, m * (a * a + b * b) / 5, 2 * m * a * a / 5,
                            equatorial=a, axial=b, mass=m)  # fmt: skip
    return PlayTop(m, big_a, big_c, shape=[Spheroid(a, b, 0.0, "shell")], friction=friction,
                   **kwargs)  # fmt: skip


def disk(
    radius: float, thickness: float, mass: float, friction: Law | None = None, **kwargs: Any
) -> PlayTop:
    """A uniform solid disk (a cylinder of ``radius`` and ``thickness``, m; ``mass`` kg):
    ``C = m a^2 / 2`` about its axis and ``A = m (3 a^2 + h^2) / 12`` across it; its contact
    parts are its two sharp rims, ``Torus(a, 0, +h/2, "upper_rim")`` and ``Torus(a, 0, -h/2,
    "lower_rim")``. Euler's disk is ``disk(0.0375, 0.0125, 0.434)`` (steel); a coin is one too.
    Friction defaults to Coulomb-Contensou (mu 0.3 over a 0.2 mm patch: a rim's contact is a
    small patch with a drilling torque, Leine, Arch. Appl. Mech. 79 (2009) 1063). What each
    law does, measured on Euler's disk rolling with its centre at rest from 0.3 rad
    (:func:`disk_rolling_state`, rtol 1e-8):

    - point Coulomb friction alone dissipates nothing on this rolling: the disk keeps rolling
      at 0.3 rad;
    - Coulomb-Contensou alone (this default, no rolling resistance): its drilling torque is
      the only loss, and a slow one: 0.3 rad -> 0.22 rad in 20 s, flat after 243 s;
    - with ``rolling_resistance=2e-3`` (the preset ``euler-disk``) rolling resistance does it:
      flat at 0.963 s with Coulomb-Contensou and at 0.965 s with point Coulomb friction;
      drilling takes at most 0.52 % of the energy dissipated (its bound (2/3) mu N r_patch
      abs(omega_z) integrated over the run).

    Examples
    --------
    >>> from kreisel import bodies
    >>> d = bodies.disk(radius=0.0375, thickness=0.0125, mass=0.4)
    >>> round(d.C, 9), round(d.A, 9), d.part_names
    (0.00028125, 0.000145833, ('upper_rim', 'lower_rim'))
    """
    a, h = _positive("radius", radius), _positive("thickness", thickness)
    m = _positive("mass", mass)
    friction = CoulombContensou(0.3, 2e-4) if friction is None else friction
    big_a, big_c = _moments(m, m * (3 * a * a + h * h) / 12, m * a * a / 2,
                            radius=a, thickness=h, mass=m)  # fmt: skip
    return PlayTop(m, big_a, big_c,
                   shape=[Torus(a, 0.0, h / 2, "upper_rim"), Torus(a, 0.0, -h / 2, "lower_rim")],
                   friction=friction, **kwargs)  # fmt: skip


def disk_rolling_rates(top: PlayTop, alpha: float) -> tuple[float, float]:
    """``(Omega, psi_dot)`` (rad/s) of a disk (a top whose lowest part is a sharp rim
    ``Torus(a, 0, z)``, such as :func:`disk`'s lower rim) rolling on that rim with its centre
    of mass at rest, its axis at ``alpha`` rad from the vertical: Euler's disk's steady
    motion, the precession rate Omega (``phi_dot``) and the spin ``psi_dot``. Rolling with G
    at rest needs omega along G -> T (T the rim's lowest point), ``psi_dot = -Omega
    (cos(alpha) - k sin(alpha))`` with ``k = -z / a``, and the gravity torque turns L when

        Omega^2 sin(alpha) (A cos(alpha) - C k sin(alpha)) = m g a (cos(alpha) - k sin(alpha))

    (theory: bodies of revolution, ``Omega^2 sin(alpha) = m g a / A``, at k = 0; derived in
    ``tests/test_shapes.py``, which checks that a disk started on it stays there).
    :func:`disk_rolling_state` is the state.

    Examples
    --------
    >>> from kreisel import bodies
    >>> d = bodies.disk(0.0375, 0.0125, 0.434)
    >>> [round(w, 3) for w in bodies.disk_rolling_rates(d, 0.3)]
    [59.966, -54.334]
    """
    rims = [p for p in top.shape if isinstance(p, Torus) and p.minor == 0.0]
    if not rims:
        raise ParameterError(
            f"top = {top!r} is not allowed: its steady rolling is that of a disk on a sharp "
            "rim, and it has no Torus part of minor = 0"
        )
    rim = min(rims, key=lambda p: p.z)
    a, k = rim.major, -rim.z / rim.major
    x = real("alpha", alpha)
    c, s = math.cos(x), math.sin(x)
    if not (0.0 < x < math.pi / 2 and c - k * s > 0.0 and top.A * c - top.C * k * s > 0.0):
        raise ParameterError(
            f"alpha = {x!r} is not allowed: the disk rolls on its rim for 0 < alpha < pi/2 "
            f"with cos(alpha) > k sin(alpha) and A cos(alpha) > C k sin(alpha) (k = {k:.6g})"
        )
    omega = math.sqrt(top.m * top.g * a * (c - k * s) / (s * (top.A * c - top.C * k * s)))
    if not omega <= MAX_RATE:
        raise ParameterError(
            f"alpha = {x!r} is not allowed: the disk rolls there at Omega = {omega:.3g} rad/s, "
            f"faster than the {MAX_RATE:.0e} rad/s a top's state may turn; take a larger alpha "
            "(Omega grows as 1 / sqrt(alpha) near 0)"
        )
    return omega, -omega * (c - k * s)


def disk_rolling_state(top: PlayTop, alpha: float) -> PlayState:
    """The state of :func:`disk_rolling_rates`' steady rolling at ``alpha``: on the floor,
    G at rest.

    Examples
    --------
    >>> from kreisel import bodies
    >>> d = bodies.disk(0.0375, 0.0125, 0.434)
    >>> st = bodies.disk_rolling_state(d, 0.3)
    >>> [round(float(w), 4) for w in st.omega]  # body frame: n = Omega k sin(alpha) on e3
    [0.0, 17.7212, 2.9535]
    """
    omega, psi_dot = disk_rolling_rates(top, alpha)
    return top.state(theta=float(alpha), phi_dot=omega, psi_dot=psi_dot)


def toy_top(
    mass: float = 0.05,
    radius: float = 0.025,
    height: float = 0.03,
    handle_radius: float = 0.003,
    handle_length: float = 0.02,
    tip_radius: float = 0.001,
    shoulder: float = 0.002,
    friction: Law | None = None,
    **kwargs: Any,
) -> PlayTop:
    """A classic toy top: a uniform solid cone standing on its apex (base ``radius``,
    ``height``) with a cylindrical handle on its base (``handle_radius``, ``handle_length``),
    of one density and total ``mass``. Cone: volume ``pi R^2 H / 3``, centre of mass ``3 H /
    4`` above the apex, ``C = 3 m R^2 / 10``, ``A = 3 m R^2 / 20 + 3 m H^2 / 80`` about its
    centre of mass; handle: ``C = m r^2 / 2``, ``A = m (3 r^2 + L^2) / 12``; the two combined
    about the common centre of mass (parallel axes). Contact parts: the rounded ``tip``
    (a sphere of ``tip_radius`` at the apex), the ``shoulder`` (the base's rim, a torus of tube
    radius ``shoulder``) and the ``handle`` end (a sphere of the handle's radius). Friction
    defaults to Coulomb-Contensou (mu 0.3, patch 0.2 mm).

    The default top's sleeping threshold about its tip (Routh, a Lagrange top about the tip's
    centre: ``C^2 w^2 = 4 A_tip m g l``) is 126.5 rad/s, but the default friction holds it up
    only well above that: measured from 0.02, 0.05 or 0.1 rad off the vertical (rtol 1e-9,
    no rolling resistance), its mean tilt grows over 2 s below about 201 rad/s (by 1.5 % at
    180 rad/s, 0.06 % at 200 rad/s) and shrinks above (by 0.15 % at 205 rad/s, 0.6 % at
    220 rad/s), while the tip's drilling friction takes about 2 rad/s of spin per second.

    Examples
    --------
    >>> from kreisel import bodies
    >>> t = bodies.toy_top()
    >>> t.part_names, round(t.m, 6)
    (('tip', 'shoulder', 'handle'), 0.05)
    """
    m = _positive("mass", mass)
    big_r, big_h = _positive("radius", radius), _positive("height", height)
    r_h, l_h = _positive("handle_radius", handle_radius), _positive("handle_length", handle_length)
    r_t, r_s = _positive("tip_radius", tip_radius), _positive("shoulder", shoulder)
    if r_h >= big_r or r_t >= big_h / 2 or r_s >= big_r / 2:
        raise ParameterError(
            f"handle_radius = {r_h!r}, tip_radius = {r_t!r}, shoulder = {r_s!r} are not allowed "
            f"with radius = {big_r!r}, height = {big_h!r}: the handle must be narrower than the "
            "body, the tip smaller than half the height and the shoulder than half the radius"
        )
    v_cone = math.pi * big_r**2 * big_h / 3
    v_handle = math.pi * r_h**2 * l_h
    m_c, m_h = m * v_cone / (v_cone + v_handle), m * v_handle / (v_cone + v_handle)
    z_c, z_h = 0.75 * big_h, big_h + l_h / 2  # from the apex
    z_g = (m_c * z_c + m_h * z_h) / m
    c = 0.3 * m_c * big_r**2 + 0.5 * m_h * r_h**2
    a = (0.15 * m_c * big_r**2 + 3 * m_c * big_h**2 / 80 + m_c * (z_c - z_g) ** 2
         + m_h * (3 * r_h**2 + l_h**2) / 12 + m_h * (z_h - z_g) ** 2)  # fmt: skip
    friction = CoulombContensou(0.3, 2e-4) if friction is None else friction
    parts: list[Part] = [
        Sphere(r_t, r_t - z_g, "tip"),
        Torus(big_r - r_s, r_s, big_h - r_s - z_g, "shoulder"),
        Sphere(r_h, big_h + l_h - r_h - z_g, "handle"),
    ]
    a, c = _moments(m, a, c, mass=m, radius=big_r, height=big_h, handle_radius=r_h,
                    handle_length=l_h)  # fmt: skip
    return PlayTop(m, a, c, shape=parts, friction=friction, **kwargs)


class EggThresholds(NamedTuple):
    """The spin rates (rad/s, about the vertical, of an egg lying on its side) at which a
    uniform solid prolate spheroid starts to rise and rises all the way onto its end: by the
    steady no-slip motions (``rise``, ``stand``; derived in the guide's section on the egg)
    and by Moffatt and Shimomura's gyroscopic balance (``balance_rise``, ``balance_stand``, a
    fast-spin approximation that lies about 15 % low for an egg-shaped 3 : 4 spheroid).

    Examples
    --------
    >>> from kreisel import bodies
    >>> bodies.egg_rising_thresholds()._fields
    ('rise', 'stand', 'balance_rise', 'balance_stand')
    """

    rise: float
    stand: float
    balance_rise: float
    balance_stand: float


def _prolate(equatorial: object, axial: object, g: object) -> tuple[float, float, float]:
    a, b = _positive("equatorial", equatorial), _positive("axial", axial)
    if not b > a:
        raise ParameterError(
            f"axial = {b!r} is not allowed with equatorial = {a!r}: a rising egg is a prolate "
            "spheroid, axial > equatorial"
        )
    if not b / a <= MAX_EGG_RATIO:
        raise ParameterError(
            f"axial = {b!r} is not allowed with equatorial = {a!r}: the thresholds are computed "
            f"for an egg, axial / equatorial <= {MAX_EGG_RATIO:.0e} (here {b / a:.3g})"
        )
    gg = real("g", g)
    if not 1e-100 <= gg <= 1e100:
        raise ParameterError(f"g = {gg!r} is not allowed: it must lie in [1e-100, 1e+100] m/s^2")
    return a, b, gg


def _steady_spin(a: float, b: float, g: float, u: float) -> float:
    """J / (A a) of the steady no-slip motion of a uniform prolate spheroid at u = cos(theta)
    (G at rest, omega parallel to GP): the spin about the vertical of the lying egg with the
    same Jellett's integral. Omega^2 = 5 g / h; J from L = A omega + (C - A) n e3. Computed
    in units of the equatorial radius a (r = b / a, h = a H), so that no power of a length
    leaves the range of a float: sqrt(g / a) times a function of r and u."""
    r = b / a
    d = r * r - 1.0
    big_h = math.sqrt(1.0 + d * u * u)
    c_over_a = 2.0 / (1.0 + r * r)
    # |a^2 ez + d u e3|^2 from A omega . (G - P), and (C - A) n b^2 u from the spin part
    square = 1.0 + 2.0 * d * u * u + d * d * u * u
    spin = math.sqrt(5.0 / big_h) * (square + (c_over_a - 1.0) * r**4 * u * u) / big_h
    return math.sqrt(g / a) * spin


def egg_rising_thresholds(
    equatorial: float = 0.0225, axial: float = 0.03, g: float = 9.81
) -> EggThresholds:
    """The spin rates (rad/s) at which a uniform solid prolate spheroid (semi-axes
    ``equatorial`` a < ``axial`` b, m; the body of :func:`egg`; ``g`` m/s^2) spun about the
    vertical while lying on its side, G at rest, rises part way and all the way onto its end.
    The mass drops out. With the friction at the contact keeping Jellett's integral (a viscous
    law nearly does; Coulomb-Contensou's drilling torque wears it away, and the egg falls
    back), the egg ends on the steady motion of its Jellett's integral J = A Omega a:

    - steady no-slip motions (derived in the guide, checked in ``tests/test_egg.py``): G at
      rest, omega parallel to GP, precession ``Omega^2 = m g a^2 (b^2 - a^2) / (h (C b^2 - A
      a^2))`` (``= 5 g / h`` uniform) at any inclination, h the height of G. They branch off
      the lying spin at ``rise^2 = m g a (b^2 - a^2) / (C b^2 - A a^2) = 5 g / a`` and reach
      the end at ``stand = 2 b^3 sqrt(5 g / b) / (a (a^2 + b^2))`` (J of the standing egg
      ``C b w`` with ``w = (b/a)^2 sqrt(5 g / b)``, over ``A a``);
    - gyroscopic balance (Moffatt & Shimomura, Nature 416 (2002) 385: ``C n = A Omega
      cos(theta)``, L vertical, J = A Omega h kept; the energy at fixed J, ``E = m g h + J^2 (C
      sin^2 + A cos^2) / (2 A C h^2)``, falls towards the end): ``balance_rise^2 = m g a C (b^2 -
      a^2) / (A (C b^2 - A a^2)) = 2 m g a / A`` (uniform), which is ``(C/A) rise^2``, and
      ``balance_stand = balance_rise (b/a)^(3/2)`` (the minimum of E at ``h = a
      (Omega/balance_rise)^(2/3)`` reaches the end). These formulas are derived here from
      their assumptions; the fast-spin approximation misses the threshold by ``sqrt(A/C)``
      (1.18 for the default egg), which the simulations confirm.

    Examples
    --------
    >>> from kreisel import bodies
    >>> [round(w, 2) for w in bodies.egg_rising_thresholds()]
    [46.69, 69.01, 39.62, 61.0]
    >>> bodies.egg_rising_thresholds(0.03, 0.03)
    Traceback (most recent call last):
    ...
    kreisel._errors.ParameterError: axial = 0.03 is not allowed with equatorial = 0.03: ...
    """
    a, b, gg = _prolate(equatorial, axial, g)
    balance = math.sqrt(gg / a) * math.sqrt(10.0 / (1.0 + (b / a) ** 2))
    return EggThresholds(
        rise=_steady_spin(a, b, gg, 0.0),
        stand=_steady_spin(a, b, gg, 1.0),
        balance_rise=balance,
        balance_stand=balance * (b / a) ** 1.5,
    )


def egg_settled_inclination(
    spin: float, equatorial: float = 0.0225, axial: float = 0.03, g: float = 9.81
) -> float:
    """``|u| = |cos(theta)|`` of the steady no-slip motion an egg (a uniform solid prolate
    spheroid, as in :func:`egg_rising_thresholds`) spun at ``spin`` rad/s about the vertical
    on its side settles on, if Jellett's integral J = A spin a is kept: 0 below
    ``rise``, 1 above ``stand``, between them the root of J(u) = J (J(u) rises with u).
    For a run whose J drifted, give ``spin = J / (A a)``.

    Examples
    --------
    >>> from kreisel import bodies
    >>> round(bodies.egg_settled_inclination(52.0), 4), bodies.egg_settled_inclination(40.0)
    (0.4227, 0.0)
    """
    w = abs(real("spin", spin))
    a, b, gg = _prolate(equatorial, axial, g)
    if w <= _steady_spin(a, b, gg, 0.0):
        return 0.0
    if w >= _steady_spin(a, b, gg, 1.0):
        return 1.0
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _steady_spin(a, b, gg, mid) < w else (lo, mid)
    return 0.5 * (lo + hi)
