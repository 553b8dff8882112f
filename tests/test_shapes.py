"""Contact parts other than spheres: spheroids and tori.

References: theory: bodies of revolution (support points) and 4.5 (a disk rolling with its centre at
rest: Omega^2 sin(alpha) = m g a / A, from the balance of the gravity torque with the turning
of L; for a thin uniform disk 4 g / a). The derivatives of each part's gap and slip velocity
are checked against finite differences in the core (shapes.rs); here, whole motions.
"""

from __future__ import annotations

import numpy as np
import pytest

import kreisel
from kreisel import Coulomb, CoulombContensou, ParameterError, PlayTop
from kreisel.shapes import Sphere, Spheroid, Torus


def same(a, b):
    for name in ("quaternion", "omega", "com", "com_velocity", "dissipated"):
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_a_round_spheroid_is_the_sphere():
    """Spheroid(r, r, z) equals Sphere(r, z) bit for bit on the several-part equations (a
    patch of friction sends both there), and to the tolerance against the one-sphere ones."""
    law = CoulombContensou(0.3, 5e-4)
    ball = PlayTop(6e-3, 8e-7, 7e-7, shape=[Sphere(0.015, -0.003)], friction=law)
    round_ = PlayTop(6e-3, 8e-7, 7e-7, shape=[Spheroid(0.015, 0.015, -0.003)], friction=law)
    st = ball.state(theta=np.pi - 0.1, psi_dot=180.0)
    same(kreisel.simulate(ball, st, 1.0), kreisel.simulate(round_, st, 1.0))
    classic = PlayTop(6e-3, 8e-7, 7e-7, 0.003, 0.015, friction=Coulomb(0.3))
    shaped = PlayTop(6e-3, 8e-7, 7e-7, shape=[Spheroid(0.015, 0.015, -0.003)],
                     friction=Coulomb(0.3))  # fmt: skip
    te = np.linspace(0.0, 0.5, 6)
    c = kreisel.simulate(classic, st, 0.5, t_eval=te, rtol=1e-11, atol=1e-14)
    d = kreisel.simulate(shaped, st, 0.5, t_eval=te, rtol=1e-11, atol=1e-14)
    np.testing.assert_allclose(d.u, c.u, atol=1e-7)


def test_a_torus_that_never_touches_changes_nothing():
    law = CoulombContensou(0.3, 5e-4)
    ball = PlayTop(6e-3, 8e-7, 7e-7, shape=[Sphere(0.015, -0.003)], friction=law)
    # a ring inside the ball: never its lowest point
    ringed = PlayTop(6e-3, 8e-7, 7e-7, shape=[Sphere(0.015, -0.003), Torus(0.005, 0.001, 0.0)],
                     friction=law)  # fmt: skip
    st = ball.state(theta=np.pi - 0.1, psi_dot=180.0)
    b = kreisel.simulate(ringed, st, 1.0)
    same(kreisel.simulate(ball, st, 1.0), b)
    assert not b.part_in_contact[:, 1].any()


@pytest.mark.parametrize("alpha", [0.3, 0.8, 1.2])
def test_a_disk_rolling_with_its_centre_at_rest_stays_so(alpha):
    """Euler's disk on its steady motion (theory: bodies of revolution): a thin uniform disk of
    radius a
    (A = m a^2/4, C = m a^2/2, its rim a sharp torus) inclined by alpha, precessing at
    Omega with Omega^2 sin(alpha) = 4 g / a and spinning at psi_dot = -Omega cos(alpha), rolls
    without slip with G at rest; it stays on that motion."""
    a, m, g = 0.0375, 0.1, 9.81
    disk = PlayTop(m, m * a * a / 4, m * a * a / 2, shape=[Torus(a, 0.0, 0.0, "rim")],
                   friction=Coulomb(0.5))  # fmt: skip
    omega = np.sqrt(4 * g / a / np.sin(alpha))
    st = disk.state(theta=alpha, phi_dot=omega, psi_dot=-omega * np.cos(alpha))
    te = np.linspace(0.0, 1.0, 2001)
    run = kreisel.simulate(disk, st, 1.0, t_eval=te)
    assert set(run.mode) == {"roll"} and run.events == []
    np.testing.assert_allclose(run.u, np.cos(alpha), atol=1e-12)
    assert np.abs(run.com_velocity).max() < 1e-12
    np.testing.assert_allclose(run.part_normal_force[:, 0], m * g, rtol=1e-12)
    # the axis turns about the vertical at Omega
    e3 = run.quaternion  # the precession angle from the unwrapped phi column
    rate = np.polyfit(te, np.unwrap(run.phi), 1)[0]
    assert rate == pytest.approx(omega, rel=1e-9), e3.shape


@pytest.mark.parametrize("alpha", [0.3, 1.0])
def test_a_thick_disk_rolls_with_its_centre_at_rest_on_its_own_law(alpha):
    """A thick disk (kreisel.bodies.disk: two sharp rims at z = +-h/2) on its lower rim, k =
    h/(2a). Derived here: rolling with G at rest needs omega parallel to G -> T, T the lower
    rim's lowest point, GT = -(a/s) ez + (a c/s - a k) e3 (c, s = cos, sin alpha), so with
    omega = Omega ez + psi_dot e3, psi_dot = -Omega (c - k s); then omega . e3 = Omega k s,
    L = A Omega ez + Omega (C k s - A c) e3, and Omega ez x L = GT x m g ez gives
    Omega^2 s (A c - C k s) = m g a (c - k s) (theory: bodies of revolution at k = 0)."""
    from kreisel import bodies

    a, h, m, g = 0.0375, 0.0125, 0.434, 9.81
    disk = bodies.disk(a, h, m, friction=Coulomb(0.3))
    k, c, s = h / (2 * a), np.cos(alpha), np.sin(alpha)
    omega = np.sqrt(m * g * a * (c - k * s) / (s * (disk.A * c - disk.C * k * s)))
    st = disk.state(theta=alpha, phi_dot=omega, psi_dot=-omega * (c - k * s))
    run = kreisel.simulate(disk, st, 1.0, t_eval=np.linspace(0.0, 1.0, 501))
    assert set(run.mode) == {"roll"} and run.events == []
    np.testing.assert_allclose(run.u, c, atol=1e-11)
    assert np.abs(run.com_velocity).max() < 1e-10
    np.testing.assert_allclose(run.part_normal_force[:, 1], m * g, rtol=1e-9)
    # the thin-disk law would not hold it
    thin = np.sqrt(m * g * a / (disk.A * s))
    st = disk.state(theta=alpha, phi_dot=thin, psi_dot=-thin * c)
    off = kreisel.simulate(disk, st, 1.0, t_eval=np.linspace(0.0, 1.0, 501))
    assert np.abs(off.u - c).max() > 1e-4


def test_a_disk_started_off_its_steady_motion_does_not_stay():
    """The same disk with 10 % less precession: the closed form is what holds it."""
    a, m, g, alpha = 0.0375, 0.1, 9.81, 0.8
    disk = PlayTop(m, m * a * a / 4, m * a * a / 2, shape=[Torus(a, 0.0, 0.0)],
                   friction=Coulomb(0.5))  # fmt: skip
    omega = 0.9 * np.sqrt(4 * g / a / np.sin(alpha))
    st = disk.state(theta=alpha, phi_dot=omega, psi_dot=-omega * np.cos(alpha))
    run = kreisel.simulate(disk, st, 0.2, t_eval=np.linspace(0.0, 0.2, 201))
    assert np.abs(run.u - np.cos(alpha)).max() > 1e-3


def test_an_egg_spun_on_its_side_keeps_its_energy_account():
    """A prolate spheroid (a hard-boiled egg, uniform: A = m (a^2 + b^2)/5, C = 2 m a^2/5)
    spun on its side under Coulomb-Contensou friction: the energy never rises and E +
    dissipated holds."""
    a, b, m = 0.02, 0.03, 0.06
    egg = PlayTop(m, m * (a * a + b * b) / 5, 2 * m * a * a / 5, shape=[Spheroid(a, b, 0.0)],
                  friction=CoulombContensou(0.3, 5e-4))  # fmt: skip
    st = egg.state(theta=np.pi / 2 - 0.05, phi_dot=40.0)
    run = kreisel.simulate(egg, st, 1.0, t_eval=np.linspace(0.0, 1.0, 501))
    assert np.diff(run.energy).max() <= 1e-12
    total = run.energy + run.dissipated
    assert np.abs(total - total[0]).max() <= 1e-8 * total[0]
    # on the floor all along: G at the spheroid's support height
    phi = np.sqrt(a * a * (1 - run.u**2) + b * b * run.u**2)
    np.testing.assert_allclose(run.com[:, 2], phi, atol=1e-9)


def test_bad_parts_name_the_part():
    with pytest.raises(ParameterError, match=r"Spheroid 'egg': axial = 0.0 is not allowed"):
        Spheroid(0.02, 0.0, 0.0, "egg")
    with pytest.raises(ParameterError, match=r"Torus 'rim': minor = -0.001 is not allowed"):
        Torus(0.03, -0.001, 0.0, "rim")
    with pytest.raises(ParameterError, match=r"Torus: major = 0.0 is not allowed"):
        Torus(0.0, 0.0, 0.0)
    with pytest.raises(ParameterError, match=r"atlas"):
        PlayTop(0.1, 3e-5, 6e-5, shape=[Torus(0.03, 0.0, 0.0)]).classify()


def test_parts_in_toml_tables():
    from kreisel._config import from_tables

    tables = {
        "top": {"kind": "play", "m": 0.1, "A": 3.5e-5, "C": 7e-5,
                "shape": [{"kind": "torus", "major": 0.0375, "minor": 0.0, "z": 0.0,
                           "name": "rim"}]},
        "state": {"theta": 0.5, "phi_dot": 30.0},
        "simulation": {"t_end": 0.1},
    }  # fmt: skip
    problem = from_tables(tables)
    assert problem.model.shape == (Torus(0.0375, 0.0, 0.0, "rim"),)
    bad = {**tables, "top": {**tables["top"], "shape": [{"kind": "cone", "z": 0.0}]}}
    with pytest.raises(ParameterError, match=r"shape\[0\] kind = 'cone' is not allowed"):
        from_tables(bad)


def test_a_dissipating_disk_precesses_faster_as_it_settles_and_lies_flat_in_finite_time():
    """Euler's disk with a rolling resistance (2 mm): started on its steady motion at 0.1
    rad, it settles; its precession rate follows the quasi-steady Omega = sqrt(4 g /(a sin
    alpha)), so log Omega against log alpha has the slope -1/2 (Moffatt, Nature 404 (2000)
    833); it lies flat (the event "flat") at a finite time, then spins down flat and stops
    (the rim's Coulomb torque mu m g a, with the sliding it stops with), the energy never
    rising."""
    from scipy.spatial.transform import Rotation

    a, m, g, alpha0 = 0.0375, 0.1, 9.81, 0.1
    disk = PlayTop(m, m * a * a / 4, m * a * a / 2, shape=[Torus(a, 0.0, 0.0, "rim")],
                   friction=Coulomb(0.5), rolling_resistance=2e-3)  # fmt: skip
    omega = np.sqrt(4 * g / a / np.sin(alpha0))
    st = disk.state(theta=alpha0, phi_dot=omega, psi_dot=-omega * np.cos(alpha0))
    te = np.linspace(0.0, 0.53, 20001)
    run = kreisel.simulate(disk, st, 5.0, t_eval=te, rtol=1e-8, atol=1e-11)
    flat = [e for e in run.events if e.name == "flat"]
    assert len(flat) == 1 and flat[0].part == "rim" and 0.3 < flat[0].t < 1.0
    # lying flat is a state: the disk spins down on its face and stops
    assert run.status == "completed" and run.events[-1].name == "slip_to_roll"
    assert flat[0].t < run.events[-1].t < 5.0
    assert np.diff(run.energy).max() <= 1e-12
    e3 = Rotation.from_quat(run.quaternion[:, [1, 2, 3, 0]]).apply([0.0, 0.0, 1.0])
    rate = np.abs(np.gradient(np.unwrap(np.arctan2(e3[:, 1], e3[:, 0])), run.t))
    alpha = np.arccos(np.clip(run.u, -1.0, 1.0))
    sel = (alpha < 0.05) & (alpha > 0.002)
    slope = np.polyfit(np.log(alpha[sel]), np.log(rate[sel]), 1)[0]
    assert abs(slope + 0.5) < 0.05, slope


def _solid_of_revolution(radius, z0, z1, mass, kinks=()):
    """(C, A about G, z of G) of a uniform solid of revolution of radius profile radius(z) on
    [z0, z1] and the given mass, by slices (scipy quadrature): a slice of radius r at z has
    the axial moment pi r^4 / 2 and the transverse pi r^2 (r^2 / 4 + (z - z_G)^2) per unit
    density and length."""
    from scipy import integrate

    def quad(f):
        return integrate.quad(f, z0, z1, points=list(kinks) or None)[0]

    vol = quad(lambda z: np.pi * radius(z) ** 2)
    rho = mass / vol
    zg = quad(lambda z: z * np.pi * radius(z) ** 2) / vol
    c = rho * quad(lambda z: np.pi * radius(z) ** 4 / 2)
    a = rho * quad(lambda z: np.pi * radius(z) ** 2 * (radius(z) ** 2 / 4 + (z - zg) ** 2))
    return c, a, zg


def test_the_bodies_have_their_uniform_density_inertia():
    """Independent closed forms: a solid spheroid's moments (2/5 m a^2 about its axis,
    m (a^2 + b^2)/5 across), a solid cylinder's (m a^2/2, m (3 a^2 + h^2)/12); and every body
    by numerical integration over its solid of revolution (scipy)."""
    from kreisel import bodies

    e = bodies.egg(0.02, 0.03, 0.05)
    assert (e.C, e.A) == pytest.approx((0.4 * 0.05 * 0.02**2, 0.05 * (0.02**2 + 0.03**2) / 5))
    c, a, zg = _solid_of_revolution(lambda z: 0.02 * np.sqrt(max(1 - (z / 0.03) ** 2, 0.0)),
                                    -0.03, 0.03, 0.05)  # fmt: skip
    assert (e.C, e.A, e.shape[0].z) == pytest.approx((c, a, zg), rel=1e-8, abs=1e-15)
    d = bodies.disk(0.0375, 0.0125, 0.434)
    assert (d.C, d.A) == pytest.approx(
        (0.434 * 0.0375**2 / 2, 0.434 * (3 * 0.0375**2 + 0.0125**2) / 12)
    )
    c, a, zg = _solid_of_revolution(lambda z: 0.0375, -0.00625, 0.00625, 0.434)
    assert (d.C, d.A) == pytest.approx((c, a), rel=1e-9) and zg == pytest.approx(0.0, abs=1e-15)
    assert [p.z for p in d.shape] == [0.00625, -0.00625]
    # toy top: radius profile r(z) from the apex (cone, then handle), density from the mass
    m, big_r, big_h, r_h, l_h = 0.05, 0.025, 0.03, 0.003, 0.02
    t = bodies.toy_top(m, big_r, big_h, r_h, l_h)
    c, a, zg = _solid_of_revolution(lambda z: big_r * z / big_h if z <= big_h else r_h,
                                    0.0, big_h + l_h, m, kinks=[big_h])  # fmt: skip
    assert (t.C, t.A) == pytest.approx((c, a), rel=1e-9)
    assert t.shape[0].z == pytest.approx(0.001 - zg)  # the tip's centre, 1 mm above the apex


@pytest.mark.parametrize("name", ["egg", "euler-disk", "coin", "toy-top"])
def test_the_body_presets_are_the_bodies(name):
    from kreisel import bodies
    from kreisel._config import from_tables, preset

    model = from_tables(preset(name)).model
    made = {
        "egg": lambda: bodies.egg(),
        "euler-disk": lambda: bodies.disk(0.0375, 0.0125, 0.434),
        "coin": lambda: bodies.disk(0.01213, 0.00175, 0.00567),
        "toy-top": lambda: bodies.toy_top(),
    }[name]()
    assert (model.m, model.A, model.C) == pytest.approx((made.m, made.A, made.C), rel=1e-12)
    assert model.shape == made.shape


def test_an_egg_spun_fast_on_its_side_rises_and_a_slow_one_does_not():
    """The rising egg (Moffatt & Shimomura, Nature 416 (2002) 385): spun on its side, a
    prolate spheroid under sliding friction lifts its axis towards the vertical above a
    threshold spin and stays on its side below it (here 80 against 20 rad/s, 3 s)."""
    from kreisel import bodies

    egg = bodies.egg()
    fast = kreisel.simulate(egg, egg.state(theta=np.pi / 2 - 0.1, phi_dot=80.0), 3.0, rtol=1e-8)
    slow = kreisel.simulate(egg, egg.state(theta=np.pi / 2 - 0.1, phi_dot=20.0), 3.0, rtol=1e-8)
    assert fast.u[-1] > 0.8 and abs(slow.u[-1]) < 0.2
    for run in (fast, slow):
        assert np.diff(run.energy).max() <= 1e-12


@pytest.mark.parametrize(("alpha", "rho"), [(1.2, -0.1), (1.0, -0.05), (0.6, -0.03), (1.3, 3e-4)])
def test_a_coin_rolls_on_a_circle_of_the_radius_of_its_closed_form(alpha, rho):
    """Steady rolling of a thin disk on a circle, derived here from Newton-Euler about G
    (independent of the code): axis at alpha from the vertical precessing at Omega, spin
    w3 = omega . e3; rolling gives G the velocity -a w3 (perpendicular to the vertical plane
    of the axis), so G moves on a circle of signed radius rho = a w3 / Omega; the horizontal
    force m Omega^2 rho, the normal force m g and dL/dt = (C w3 - A Omega cos(alpha)) Omega
    sin(alpha) (along that perpendicular) give

        w3 (C + m a^2) Omega sin(alpha) = cos(alpha) (A Omega^2 sin(alpha) - m g a),

    which at rho = 0 is Euler's disk (theory: bodies of revolution). For a given circle: Omega^2 =
    m g a
    cos(alpha) / (A sin(alpha) cos(alpha) - rho (C + m a^2) sin(alpha) / a)."""
    a, m, g = 0.0121, 0.00567, 9.81
    big_a, big_c = m * a * a / 4, m * a * a / 2
    # friction enough to hold the rolling: |m Omega^2 rho| <= mu m g (checked below)
    coin = PlayTop(m, big_a, big_c, shape=[Torus(a, 0.0, 0.0, "rim")], friction=Coulomb(2.0))
    omega = np.sqrt(m * g * a * np.cos(alpha)
                    / (big_a * np.sin(alpha) * np.cos(alpha)
                       - rho * (big_c + m * a * a) * np.sin(alpha) / a))  # fmt: skip
    w3 = rho * omega / a
    assert omega**2 * abs(rho) < 2.0 * g
    # phi = pi/2: the axis leans towards +x; G's velocity -a w3 along y
    st = coin.state(theta=alpha, phi=np.pi / 2, phi_dot=omega, psi_dot=w3 - omega * np.cos(alpha),
                    vy=-a * w3)  # fmt: skip
    centre = st.com[:2] + np.array([rho, 0.0])
    te = np.linspace(0.0, 2 * np.pi / omega * 3, 601)  # three turns
    run = kreisel.simulate(coin, st, te[-1], t_eval=te)
    assert set(run.mode) == {"roll"} and run.events == []
    np.testing.assert_allclose(run.u, np.cos(alpha), atol=1e-10)
    np.testing.assert_allclose(np.hypot(*(run.com[:, :2] - centre).T), abs(rho), rtol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(run.com_velocity, axis=1), abs(rho) * omega,
                               rtol=1e-8)  # fmt: skip
    np.testing.assert_allclose(run.part_normal_force[:, 0], m * g, rtol=1e-8)


def test_disk_rolling_rates_refuse_what_does_not_roll_on_a_rim():
    from kreisel import bodies

    disk = bodies.disk(0.0375, 0.0125, 0.434)
    for alpha in (0.0, 1.6, float("nan")):
        with pytest.raises(ParameterError, match="alpha = .* is not allowed"):
            bodies.disk_rolling_rates(disk, alpha)
    ball = PlayTop(6e-3, 8e-7, 7e-7, shape=[Sphere(0.015, -0.003)])
    with pytest.raises(ParameterError, match="no Torus part of minor = 0"):
        bodies.disk_rolling_state(ball, 0.3)
