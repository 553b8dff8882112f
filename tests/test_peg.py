"""Tops of several contact parts and Coulomb-Contensou friction (theory: several parts).

References are independent of the code under test: closed forms of the friction law
(theory: several parts), the rolling-ball closed form of a sliding sphere (v_T = 0 at t = 2 v0/(7
mu g),
then v = 5 v0/7: Newton's laws for a uniform ball, e.g. Routh, "Dynamics of a System of Rigid
Bodies" I, §243), the one-sphere play top's own equations (a second formulation), the
one-sphere stability theory (theory: play top: J_R(1)) applied to the peg, and conserved or
monotone quantities.
"""

from __future__ import annotations

import numpy as np
import pytest

import kreisel
from kreisel import Coulomb, CoulombContensou, ParameterError, PlayTop
from kreisel.shapes import Sphere

# Leine & Glocker's tippe top (theory: bodies of revolution).
M, A, C = 6e-3, 8e-7, 7e-7
BALL = Sphere(0.015, z=-0.003, name="ball")
PEG = Sphere(0.005, z=-0.016, name="peg")


def lg_top(radius=5e-4, **kw):
    return PlayTop(M, A, C, shape=[BALL, PEG], friction=CoulombContensou(0.3, radius), **kw)


def lg_start(top):
    return top.state(theta=np.pi - 0.1, psi_dot=180.0)


def same(a, b):
    for name in ("quaternion", "omega", "com", "com_velocity", "dissipated", "normal_force"):
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    np.testing.assert_array_equal(a.t, b.t)


def test_a_one_sphere_shape_is_the_classic_top_bit_for_bit():
    classic = PlayTop(0.015, 4e-6, 5e-6, s=0.003, rho=0.015)
    shaped = PlayTop(0.015, 4e-6, 5e-6, shape=[Sphere(0.015, z=-0.003)])
    st = classic.state(theta=0.1, psi_dot=150.0)
    a = kreisel.simulate(classic, st, 2.0)
    b = kreisel.simulate(shaped, shaped.state(theta=0.1, psi_dot=150.0), 2.0)
    same(a, b)
    assert shaped.part_names == ("part0",) and classic.part_names == ("tip",)


def test_coulomb_contensou_with_no_patch_is_coulomb_bit_for_bit():
    a_top = PlayTop(0.015, 4e-6, 5e-6, 0.003, 0.015, friction=Coulomb(0.3))
    b_top = PlayTop(0.015, 4e-6, 5e-6, 0.003, 0.015, friction=CoulombContensou(0.3, 0.0))
    st = a_top.state(theta=0.1, psi_dot=150.0)
    same(kreisel.simulate(a_top, st, 2.0), kreisel.simulate(b_top, st, 2.0))


def test_a_part_that_never_touches_changes_nothing():
    # a small sphere inside the ball can never be the lowest point
    inner = Sphere(0.002, z=0.0, name="inner")
    one = PlayTop(M, A, C, shape=[BALL], friction=CoulombContensou(0.3, 5e-4))
    two = PlayTop(M, A, C, shape=[BALL, inner], friction=CoulombContensou(0.3, 5e-4))
    a = kreisel.simulate(one, lg_start(one), 1.0)
    b = kreisel.simulate(two, lg_start(two), 1.0)
    same(a, b)
    assert not b.part_in_contact[:, 1].any()
    # and the same motion under Coulomb friction, to the tolerance (the parts' touchdowns
    # watched, the inner never found)
    classic = PlayTop(M, A, C, 0.003, 0.015, friction=Coulomb(0.3))
    shaped = PlayTop(M, A, C, shape=[BALL, inner], friction=Coulomb(0.3))
    te = np.linspace(0.0, 0.5, 11)
    c = kreisel.simulate(classic, lg_start(classic), 0.5, t_eval=te, rtol=1e-11, atol=1e-14)
    d = kreisel.simulate(shaped, lg_start(shaped), 0.5, t_eval=te, rtol=1e-11, atol=1e-14)
    np.testing.assert_allclose(d.u, c.u, atol=1e-7)
    np.testing.assert_allclose(d.omega, c.omega, rtol=1e-6, atol=1e-6)


def test_a_spin_about_the_vertical_stops_at_the_drilling_time():
    """Upright spin with no slip: M = -mu N Rbar, so w(t) = w0 - mu m g Rbar t / C and the
    spin stops at t* = C w0 / (mu m g Rbar) (theory: several parts). The part rolls with its
    patch drilling (no tangential force: no slip) until the drilling ends (``drill_end``)."""
    mu, R, w0, m, c = 0.3, 1e-3, 50.0, 0.02, 3e-6
    # the sphere's centre 5 mm above G: a stable standing ball
    top = PlayTop(m, 2.5e-6, c, shape=[Sphere(0.02, z=0.005)], friction=CoulombContensou(mu, R))
    rbar = 3 * np.pi * R / 16
    t_star = c * w0 / (mu * m * 9.81 * rbar)
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, w0])
    te = np.linspace(0.0, 0.9 * t_star, 10)
    tr = kreisel.simulate(top, st, 1.2 * t_star, t_eval=te, rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(tr.omega[:, 2], w0 - mu * m * 9.81 * rbar * te / c, rtol=1e-8,
                               atol=1e-9 * w0)  # fmt: skip
    stops = [e.t for e in tr.events if e.name == "drill_end"]
    assert stops and abs(stops[0] - t_star) < 1e-6 * t_star, (stops, t_star)


@pytest.mark.parametrize("radius", [0.0, 5e-4])
def test_a_ball_sliding_without_spin_decelerates_as_under_coulomb(radius):
    """No drilling: the patch changes nothing; the uniform ball rolls from t = 2 v0/(7 mu g)
    on at 5/7 of its speed."""
    mu, r, m, v0 = 0.2, 0.01, 0.05, 1.0
    i = 0.4 * m * r * r
    top = PlayTop(m, i, i, shape=[Sphere(r, z=0.0)], friction=CoulombContensou(mu, radius))
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], vx=v0)
    t_roll = 2 * v0 / (7 * mu * 9.81)
    tr = kreisel.simulate(top, st, 2 * t_roll, t_eval=[0.5 * t_roll, 1.5 * t_roll],
                          rtol=1e-10, atol=1e-13)  # fmt: skip
    np.testing.assert_allclose(tr.com_velocity[0, 0], v0 - mu * 9.81 * 0.5 * t_roll, rtol=1e-8)
    np.testing.assert_allclose(tr.com_velocity[1, 0], 5 * v0 / 7, rtol=1e-8)
    rolls = [e.t for e in tr.events if e.name == "slip_to_roll"]
    assert rolls and abs(rolls[0] - t_roll) < 1e-6 * t_roll


def test_a_small_slip_under_drilling_meets_a_viscous_force():
    """|v| << Rbar |w_n|: F ~ -mu N v / (Rbar |w_n|) to first order (theory: several parts)."""
    mu, R, w0, m, c, v0 = 0.3, 1e-3, 100.0, 0.02, 3e-6, 1e-4
    top = PlayTop(m, 2.5e-6, c, shape=[Sphere(0.02, z=0.005)], friction=CoulombContensou(mu, R))
    rbar = 3 * np.pi * R / 16
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, w0], vx=v0)
    dt = 1e-4
    tr = kreisel.simulate(top, st, dt, t_eval=[0.0, dt], rtol=1e-12, atol=1e-16)
    accel = (tr.com_velocity[1, 0] - tr.com_velocity[0, 0]) / dt
    viscous = -mu * 9.81 * v0 / (rbar * w0)
    assert abs(accel / viscous - 1) < 1e-2, (accel, viscous)
    # Coulomb's would be mu g: hundreds of times larger
    assert abs(accel) < 0.01 * mu * 9.81


@pytest.fixture(scope="module")
def lg_run():
    top = lg_top()
    te = np.linspace(0.0, 8.0, 1601)
    return top, kreisel.simulate(top, lg_start(top), 8.0, t_eval=te,
                                 events=[kreisel.events.inversion(0.9)])  # fmt: skip


def _first(tr, name, part):
    return next(e.t for e in tr.events if e.name == name and e.part == part)


def test_leine_glockers_tippe_top_rises_onto_its_peg(lg_run):
    top, tr = lg_run
    t_peg = _first(tr, "touchdown", "peg")
    t_ball_off = _first(tr, "lift_off", "ball")
    assert 1.0 < t_peg < 2.0
    assert t_ball_off >= t_peg
    on_peg = (tr.t > t_ball_off + 0.2) & (tr.t < t_ball_off + 1.0)
    assert on_peg.any()
    assert tr.part_in_contact[on_peg, 1].all() and not tr.part_in_contact[on_peg, 0].any()
    assert (tr.u[on_peg] > 0.95).all()
    # the parts drawn are above the floor: every part's lowest point at height >= 0
    from scipy.spatial.transform import Rotation

    e3 = Rotation.from_quat(tr.quaternion[:, [1, 2, 3, 0]]).apply([0.0, 0.0, 1.0])
    for part in top.shape:
        low = tr.com[:, 2] + part.z * e3[:, 2] - part.radius
        assert (low > -1e-9).all(), part.name


def test_energy_never_rises_and_is_accounted_for(lg_run):
    top, tr = lg_run
    assert np.diff(tr.energy).max() <= 1e-12 * tr.energy[0]
    total = tr.energy + tr.dissipated
    assert np.abs(total - total[0]).max() <= 1e-7 * total[0]


def test_the_top_leaves_its_peg_when_the_spin_falls_below_the_pegs_sleeping_threshold(lg_run):
    """On its peg the top is a one-sphere play top (s = 0.016, rho = 0.005): its upright spin
    is stable only while |J| > J_R(1) (theory: play top). The drilling torque wears J down; the top
    must stay on its peg while J is above the threshold and fall back onto its ball after."""
    top, tr = lg_run
    peg_top = PlayTop(M, A, C, s=0.016, rho=0.005)
    threshold = peg_top.J_R(1.0)
    t_off = _first(tr, "lift_off", "ball")
    back = [e.t for e in tr.events if e.name == "touchdown" and e.part == "ball" and e.t > t_off]
    assert back, "the top never came back onto its ball"
    # J about the peg's contact point, upright: L . (s e3 + rho ez)
    e3z = tr.u
    j_peg = C * tr.omega[:, 2] * (0.016 + 0.005 * e3z)
    on = (tr.t > t_off + 0.05) & (tr.t < back[0])
    assert (np.abs(j_peg[(tr.t > t_off + 0.05) & (tr.t < back[0] - 1.0)]) > 0.9 * threshold).all()
    crossing = tr.t[on][np.argmax(np.abs(j_peg[on]) < threshold)]
    assert crossing < back[0] < crossing + 1.5, (crossing, back[0])


def test_the_event_times_converge_as_the_tolerance_tightens():
    top = lg_top()
    times = []
    for rtol in (1e-6, 1e-8, 1e-10):
        tr = kreisel.simulate(top, lg_start(top), 2.0, rtol=rtol, atol=rtol * 1e-3)
        times.append(_first(tr, "touchdown", "peg"))
    assert abs(times[1] - times[2]) < 1e-5 and abs(times[0] - times[2]) < 1e-4, times


def test_under_point_contact_coulomb_the_tippe_top_locks_into_rolling_and_hangs():
    top = lg_top(radius=0.0)
    tr = kreisel.simulate(top, lg_start(top), 8.0, t_eval=np.linspace(0, 8, 81))
    rolls = [e.t for e in tr.events if e.name == "slip_to_roll"]
    assert rolls and rolls[0] < 0.1
    assert (tr.u < -0.99).all()
    assert not tr.part_in_contact[:, 1].any()


def test_bad_shapes_name_the_part():
    with pytest.raises(ParameterError, match=r"Sphere 'peg': radius = -1.0 is not allowed"):
        Sphere(-1.0, z=0.0, name="peg")
    with pytest.raises(ParameterError, match=r"z = inf is not allowed"):
        Sphere(0.01, z=float("inf"), name="peg")
    with pytest.raises(ParameterError, match=r"shape has 0 parts"):
        PlayTop(M, A, C, shape=[])
    with pytest.raises(ParameterError, match=r"shape\[1\] is named 'ball' like shape\[0\]"):
        PlayTop(M, A, C, shape=[BALL, Sphere(0.005, -0.016, "ball")])
    with pytest.raises(ParameterError, match=r"exactly one of the two"):
        PlayTop(M, A, C, 0.003, 0.015, shape=[BALL])
    with pytest.raises(ParameterError, match=r"radius = -0.001 is not allowed"):
        CoulombContensou(0.3, -1e-3)
    top = PlayTop(M, A, C, shape=[Sphere(0.01, z=0.004, name="cap"), PEG])
    with pytest.raises(ParameterError, match=r"shape\[0\] = .*'cap'.* atlas"):
        top.classify()


def test_simulate_many_and_summaries_report_the_parts():
    top = lg_top()
    b = kreisel.simulate_many(top, [lg_start(top)] * 2, 2.0)
    assert (b.final_parts_in_contact == 2).all()  # bit 1: the peg alone
    assert np.all((b.first_touchdown_time[:, 1] > 1.0) & (b.first_touchdown_time[:, 1] < 2.0))
    assert np.isnan(b.first_touchdown_time[:, 0]).all()


def _slip_coefficient(top, st, mu):
    """The slip mode's denominator from Newton-Euler in the space frame (a second formulation
    of the core's): the contact height's acceleration per unit normal force,
    1/m + (a x ez) . I^-1 (a x (ez + f)), with f = -mu v_T/|v_T| and a = G -> T."""
    from scipy.spatial.transform import Rotation

    rot = Rotation.from_quat(np.r_[st.quaternion[1:], st.quaternion[:1]])
    e3 = rot.apply([0.0, 0.0, 1.0])
    ez = np.array([0.0, 0.0, 1.0])
    a = -top.s * e3 - top.rho * ez
    w = rot.apply(st.omega)
    vt = st.com_velocity + np.cross(w, a)
    f = ez - mu * np.r_[vt[:2], 0.0] / np.hypot(*vt[:2])
    inv_i = rot.as_matrix() @ np.diag([1 / top.A, 1 / top.A, 1 / top.C]) @ rot.as_matrix().T
    return 1 / top.m + np.cross(a, ez) @ inv_i @ np.cross(a, f)


@pytest.mark.parametrize("friction", [Coulomb(0.5), CoulombContensou(0.5, 1e-4)])
def test_the_painleve_case_is_resolved_by_a_tangential_impact(friction):
    """A tall top (s = 5 cm, radius of gyration 1 cm) sliding with mu = 0.5: at theta = 0.12
    sliding along +y has no consistent normal force (the slip mode's denominator is negative
    while gravity presses the tip down). The run takes a tangential impact that stops the slip
    (Painleve's paradox; Genot & Brogliato, Eur. J. Mech. A/Solids 18 (1999) 653), and the tip
    hops off the floor, as chalk pushed over a board does; it never passes through it."""
    from scipy.spatial.transform import Rotation

    top = PlayTop(0.1, 1e-5, 2e-6, 0.05, 0.002, friction=friction)
    st = top.state(theta=0.12, vy=2.0)
    assert _slip_coefficient(top, st, 0.5) < 0  # and the free acceleration of the tip is -g
    tr = kreisel.simulate(top, st, 0.05, t_eval=np.linspace(0.0, 0.05, 51))
    assert [e.name for e in tr.events][:1] == ["tangential_impact"] and tr.events[0].t == 0.0
    assert tr.slip_speed[0] < 1e-9  # the impact stopped the slip
    e3 = Rotation.from_quat(tr.quaternion[:, [1, 2, 3, 0]]).apply([0.0, 0.0, 1.0])
    tip = tr.com[:, 2] - top.s * e3[:, 2] - top.rho
    assert (tip > -1e-9).all()
    assert tr.energy[0] < top.energy(st)  # the impact took energy
    assert np.diff(tr.energy).max() <= 1e-12


def test_a_sweep_of_the_tippe_preset_over_the_patch_radius(tmp_path):
    """Sweeps take tops with parts: the spin and the patch radius swept over the preset (Leine
    and Glocker's top); a point contact (R = 0) never gets the peg down, the patch does."""
    spec = {
        "top": {"preset": "tippe"},
        "simulation": {"t_end": 2.0},
        "grid": {"psi_dot": [180.0], "patch_radius": [0.0, 5e-4]},
        "output": {
            "keep": ["final_parts_in_contact", "first_touchdown_time_1", "first_touchdown_time_peg"]
        },
    }
    ds = kreisel.sweep(spec, tmp_path / "s.zarr", progress=False)
    parts = ds["final_parts_in_contact"].values.ravel()
    touch = ds["first_touchdown_time_1"].values.ravel()
    assert parts.tolist() == [1, 2]  # ball alone (bit 0), peg alone (bit 1)
    assert np.isnan(touch[0]) and touch[1] == pytest.approx(1.371, abs=1e-3)
    # the peg by its name: the same numbers
    np.testing.assert_array_equal(ds["first_touchdown_time_peg"].values.ravel(), touch)
    assert "'peg'" in ds["first_touchdown_time_peg"].attrs["description"]
    with pytest.raises(ParameterError, match=r"first_touchdown_time_<part> .*ball, peg"):
        kreisel.sweep({**spec, "output": {"keep": ["first_touchdown_time_stem"]}}, None,
                      progress=False)  # fmt: skip
