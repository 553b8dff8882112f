"""The play-top API: PlayTop, its states, simulate's trajectory and events, simulate_many.

Reference values: the state map and the invariants are recomputed here from the documented
conventions (z-x-z Euler angles, scalar-first quaternions, body-frame omega, theory: play
top) by ``_play_reference.py``, which does not use kreisel; the ball that stops
under rolling resistance is solved in closed form in its test.
"""

from __future__ import annotations

import math

import _play_reference as ref
import numpy as np
import pytest

import kreisel
from kreisel import ParameterError

T1 = ref.tippe_t1()
T1_START = {"theta": math.pi - 0.1, "psi_dot": 150.0}
BASE = {"m": 0.02, "A": 2.56e-6, "C": 3.2e-6, "s": 0.006, "rho": 0.02}

FLOAT_COLUMNS_1 = [
    "t", "theta", "phi", "psi", "u", "slip_speed", "normal_force", "jellett", "energy",
    "energy_translation", "energy_rotation", "energy_potential", "dissipated",
]  # fmt: skip
FLOAT_COLUMNS_3 = ["omega", "com", "com_velocity", "contact_point", "slip_velocity"]


def t1(friction=None, **kw) -> kreisel.PlayTop:
    return kreisel.PlayTop(**T1.kwargs(), friction=friction or kreisel.Viscous(mu=1.0), **kw)


@pytest.fixture(scope="module")
def t1_traj():
    pt = t1()
    return kreisel.simulate(pt, pt.state(**T1_START), 4.0)


@pytest.fixture(scope="module")
def hop_traj():
    """Slides, leaves the floor, lands, rolls (Coulomb): every mode appears."""
    top = ref.Top(m=0.1, A=2e-5, C=3e-5, s=0.01, rho=0.03)
    pt = kreisel.PlayTop(**top.kwargs(), friction=kreisel.Coulomb(mu=0.3), restitution=0.3)
    return top, kreisel.simulate(pt, pt.state(1.0, phi_dot=60.0, psi_dot=50.0), 0.3)


# --------------------------------------------------------------------------------------
# parameters and validation
# --------------------------------------------------------------------------------------


def test_properties_alpha_gamma_J_beta():
    pt = kreisel.PlayTop(m=0.03, A=4e-6, C=5e-6, s=0.004, rho=0.025, g=9.7)
    assert pt.alpha == pytest.approx(0.004 / 0.025, rel=1e-15)
    assert pt.gamma == pytest.approx(4e-6 / 5e-6, rel=1e-15)
    assert pt.J_beta == pytest.approx(0.025 * math.sqrt(5e-6 * 0.03 * 9.7 * 0.004), rel=1e-14)


def test_defaults_are_coulomb_0_3_and_earth_gravity():
    pt = kreisel.PlayTop(**BASE)
    st = pt.state(0.5, psi_dot=10.0)
    assert pt.energy(st) == pytest.approx(
        0.5 * BASE["C"] * 10.0**2 + BASE["m"] * 9.81 * (BASE["rho"] + BASE["s"] * math.cos(0.5)),
        rel=1e-14,
    )
    same = kreisel.PlayTop(**BASE, g=9.81, friction=kreisel.Coulomb(mu=0.3))
    a = kreisel.simulate(pt, st, 0.2)
    b = kreisel.simulate(same, same.state(0.5, psi_dot=10.0), 0.2)
    np.testing.assert_array_equal(a.u, b.u)


def test_parameter_error_is_a_value_error():
    assert issubclass(ParameterError, ValueError)


BAD = [
    ("m", 0.0), ("m", -1.0), ("A", 0.0), ("C", 0.0), ("C", -1e-6), ("rho", 0.0),
    ("rho", -0.01), ("s", -1e-3), ("g", -9.81),
    ("m", math.nan), ("A", math.inf), ("C", math.nan), ("s", math.inf), ("rho", math.nan),
    ("g", math.nan), ("g", math.inf),
    ("restitution", -0.1), ("restitution", 1.1), ("restitution", math.nan),
    ("rolling_resistance", -1e-4), ("drilling_resistance", -1e-4), ("air_drag", -1e-9),
    ("rolling_resistance", math.inf), ("drilling_resistance", math.nan), ("air_drag", math.nan),
]  # fmt: skip


@pytest.mark.parametrize("name, value", BAD, ids=[f"{n}={v}" for n, v in BAD])
def test_invalid_parameters_are_refused_naming_the_argument(name, value):
    with pytest.raises(ParameterError, match=name):
        kreisel.PlayTop(**{**BASE, name: value})


def test_C_above_2A_is_refused():
    with pytest.raises(ParameterError, match="C"):
        kreisel.PlayTop(**{**BASE, "C": 2.0 * BASE["A"] * (1 + 1e-9)})
    kreisel.PlayTop(**{**BASE, "C": 2.0 * BASE["A"]})  # a thin disc is allowed


def test_edge_values_are_allowed():
    kreisel.PlayTop(**{**BASE, "s": 0.0})
    kreisel.PlayTop(**{**BASE, "g": 0.0})
    kreisel.PlayTop(**BASE, restitution=0.0)
    kreisel.PlayTop(**BASE, restitution=1.0)
    kreisel.PlayTop(**BASE, friction=kreisel.Coulomb(mu=0.0))
    kreisel.PlayTop(**BASE, friction=kreisel.Viscous(mu=0.0))
    kreisel.PlayTop(**BASE, friction=kreisel.Frictionless())


@pytest.mark.parametrize("law", [kreisel.Coulomb, kreisel.Viscous])
@pytest.mark.parametrize("mu", [-0.1, math.nan, math.inf])
def test_invalid_friction_coefficient_is_refused(law, mu):
    with pytest.raises(ParameterError, match="mu"):
        kreisel.PlayTop(**BASE, friction=law(mu=mu))


def test_state_below_the_floor_is_refused():
    pt = kreisel.PlayTop(**BASE)
    with pytest.raises(ParameterError, match="floor"):
        pt.state(0.3, height=-1e-6)
    with pytest.raises(ParameterError, match="height"):
        pt.state(0.3, height=math.nan)
    pt.state(0.3, height=0.0)


@pytest.mark.parametrize("name", ["theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot"])
def test_non_finite_state_is_refused(name):
    pt = kreisel.PlayTop(**BASE)
    kw = {"theta": 0.3, name: math.nan} if name != "theta" else {"theta": math.nan}
    with pytest.raises(ParameterError, match=name):
        pt.state(**kw)


def test_only_dop853_is_accepted():
    pt = t1()
    st = pt.state(**T1_START)
    kreisel.simulate(pt, st, 0.01, method="dop853")
    for method in ["rk4", "splitting", "bogus"]:
        with pytest.raises(ParameterError, match="method"):
            kreisel.simulate(pt, st, 0.01, method=method)


# --------------------------------------------------------------------------------------
# states
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("theta", [0.0, 0.4, math.pi / 2, 2.9, math.pi])
def test_state_in_contact(theta):
    pt = t1()
    e = {"phi": 0.7, "psi": -1.1, "theta_dot": 0.3, "phi_dot": 2.0, "psi_dot": 50.0}
    st = pt.state(theta, **e, vx=0.05, vy=-0.02)
    assert isinstance(st, kreisel.PlayState)
    q = np.asarray(st.quaternion)
    assert q.shape == (4,) and np.asarray(st.omega).shape == (3,)
    q_ref = ref.euler_quat(e["phi"], theta, e["psi"])
    assert min(np.max(np.abs(q - q_ref)), np.max(np.abs(q + q_ref))) < 1e-15
    w_ref = ref.body_omega(theta, e["psi"], e["theta_dot"], e["phi_dot"], e["psi_dot"])
    np.testing.assert_allclose(st.omega, w_ref, rtol=0, atol=1e-13)
    # (the state is put on the floor by the tip's support function: rounding)
    np.testing.assert_allclose(st.com, [0, 0, T1.rho + T1.s * math.cos(theta)], atol=1e-17)
    vz = -T1.s * math.sin(theta) * 0.3
    np.testing.assert_allclose(st.com_velocity, [0.05, -0.02, vz], rtol=1e-13, atol=1e-17)
    # the invariants of the state, from the documented conventions
    j = ref.jellett(T1, q, st.omega)[0]
    e_tot = ref.energy(T1, q, st.omega, st.com_velocity, st.com[2])[0]
    assert pt.jellett(st) == pytest.approx(j, rel=1e-13)
    assert pt.energy(st) == pytest.approx(e_tot, rel=1e-14)


def test_dropped_state():
    pt = t1()
    st = pt.state(0.4, psi_dot=30.0, theta_dot=2.0, vx=0.1, height=0.005)
    np.testing.assert_allclose(st.com, [0, 0, 0.005 + T1.rho + T1.s * math.cos(0.4)], atol=1e-17)
    np.testing.assert_array_equal(st.com_velocity, [0.1, 0.0, 0.0])
    traj = kreisel.simulate(pt, st, 0.1)
    assert traj.mode[0] == "flight"
    assert "touchdown" in [e.name for e in traj.events]


def test_state_is_frozen():
    st = t1().state(**T1_START)
    with pytest.raises(AttributeError):
        st.omega = np.zeros(3)
    with pytest.raises(AttributeError):
        st.com = np.zeros(3)


def test_jellett_and_energy_need_a_play_state():
    pt = t1()
    with pytest.raises((TypeError, ParameterError)):
        pt.jellett((1.0, 0.0, 0.0, 0.0))


# --------------------------------------------------------------------------------------
# trajectories
# --------------------------------------------------------------------------------------


def test_trajectory_columns_and_shapes(t1_traj):
    traj = t1_traj
    n = len(traj.t)
    assert n > 100
    for name in FLOAT_COLUMNS_1:
        col = np.asarray(getattr(traj, name))
        assert col.shape == (n,), name
        assert col.dtype == np.float64 and np.all(np.isfinite(col)), name
    for name in FLOAT_COLUMNS_3:
        col = np.asarray(getattr(traj, name))
        assert col.shape == (n, 3), name
        assert col.dtype == np.float64 and np.all(np.isfinite(col)), name
    assert np.asarray(traj.quaternion).shape == (n, 4)
    mode = np.asarray(traj.mode)
    assert mode.shape == (n,) and mode.dtype.kind == "U"
    assert traj.t[0] == 0.0 and traj.t[-1] == 4.0
    assert np.all(np.diff(traj.t) >= 0.0)


def test_columns_agree_with_the_state_columns(hop_traj):
    top, traj = hop_traj
    assert set(traj.mode) == {"slip", "roll", "flight"}
    q = traj.quaternion
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-14)
    r = ref.quat_matrices(q)
    np.testing.assert_allclose(traj.u, r[:, 2, 2], atol=1e-14)
    np.testing.assert_allclose(traj.u, np.cos(traj.theta), atol=1e-13)
    assert np.all((traj.theta >= 0) & (traj.theta <= math.pi))
    # Euler angles reproduce the attitude (away from the vertical, where phi, psi are free)
    k = np.sin(traj.theta) > 1e-3
    re = np.array(
        [
            ref.quat_matrix(ref.euler_quat(a, b, c))
            for a, b, c in zip(traj.phi[k], traj.theta[k], traj.psi[k])
        ]
    )
    np.testing.assert_allclose(re, r[k], atol=1e-12)
    # the lowest point of the sphere, the velocity of the sphere's material point there
    e3 = r[:, :, 2]
    cp = traj.com - top.s * e3 - np.array([0.0, 0.0, top.rho])
    np.testing.assert_allclose(traj.contact_point, cp, atol=1e-15)
    vt = ref.tip_velocity(top, q, traj.omega, traj.com_velocity)
    np.testing.assert_allclose(traj.slip_velocity, vt, atol=1e-12)
    contact = traj.mode != "flight"
    np.testing.assert_allclose(traj.contact_point[contact, 2], 0.0, atol=1e-12)
    assert np.all(traj.contact_point[~contact, 2] >= -1e-12)
    np.testing.assert_allclose(
        traj.slip_speed[contact], np.hypot(vt[contact, 0], vt[contact, 1]), atol=1e-12
    )
    roll = traj.mode == "roll"
    assert np.all(traj.slip_speed[roll] < 1e-12)
    np.testing.assert_array_equal(traj.normal_force[~contact], 0.0)
    assert np.all(traj.normal_force[contact] >= -1e-9)
    # energies
    w = traj.omega
    e_rot = 0.5 * (top.A * (w[:, 0] ** 2 + w[:, 1] ** 2) + top.C * w[:, 2] ** 2)
    np.testing.assert_allclose(traj.energy_rotation, e_rot, rtol=1e-13)
    v = traj.com_velocity
    np.testing.assert_allclose(traj.energy_translation, 0.5 * top.m * np.sum(v * v, 1), rtol=1e-13)
    np.testing.assert_allclose(traj.energy_potential, top.m * top.g * traj.com[:, 2], rtol=1e-13)
    np.testing.assert_allclose(traj.jellett, ref.jellett(top, q, traj.omega), rtol=1e-11, atol=0)


def test_repeated_times_only_at_switches(hop_traj):
    _, traj = hop_traj
    same = np.flatnonzero(np.diff(traj.t) == 0.0)
    switch_times = {e.t for e in traj.events}
    assert len(same) >= 3
    for i in same:
        assert traj.t[i] in switch_times
    for e in traj.events:
        assert len(np.flatnonzero(traj.t == e.t)) == 2, e
    names = {e.name for e in traj.events}
    assert {"lift_off", "touchdown"} <= names
    assert names <= {"slip_to_roll", "roll_to_slip", "lift_off", "touchdown", "inversion", "rest"}
    for e in traj.events:
        assert isinstance(e, kreisel.EventRecord)
        assert isinstance(e.name, str) and isinstance(e.t, float) and isinstance(e.index, int)


def test_mode_switch_events_match_the_modes(hop_traj):
    _, traj = hop_traj
    pairs = {
        "slip_to_roll": ("slip", "roll"),
        "roll_to_slip": ("roll", "slip"),
        "lift_off": (None, "flight"),
        "touchdown": ("flight", None),
    }
    for e in traj.events:
        i, j = np.flatnonzero(traj.t == e.t)
        before, after = pairs[e.name]
        if before:
            assert traj.mode[i] == before, e
        if after:
            assert traj.mode[j] == after, e


def test_t_eval_is_returned_exactly():
    pt = t1()
    st = pt.state(**T1_START)
    t_eval = np.sort(np.concatenate([[0.0, 1e-7, 2.0], np.random.default_rng(1).random(50) * 2]))
    traj = kreisel.simulate(pt, st, 2.0, t_eval=t_eval)
    assert np.array_equal(traj.t, t_eval)
    assert traj.quaternion.shape == (len(t_eval), 4)
    assert len(traj.mode) == len(t_eval)
    # dense output at the accepted steps of a plain run gives the same states
    plain = kreisel.simulate(pt, st, 2.0)
    pick = plain.t[::37]
    again = kreisel.simulate(pt, st, 2.0, t_eval=pick)
    np.testing.assert_allclose(again.u, plain.u[::37], rtol=0, atol=1e-12)
    np.testing.assert_allclose(again.jellett, plain.jellett[::37], rtol=1e-12)


def test_t_eval_across_mode_switches(hop_traj):
    top, plain = hop_traj
    t_eval = np.linspace(0.0, 0.3, 601)
    pt = kreisel.PlayTop(**top.kwargs(), friction=kreisel.Coulomb(mu=0.3), restitution=0.3)
    traj = kreisel.simulate(pt, pt.state(1.0, phi_dot=60.0, psi_dot=50.0), 0.3, t_eval=t_eval)
    assert np.array_equal(traj.t, t_eval)
    assert set(traj.mode) == {"slip", "roll", "flight"}
    assert [e.name for e in traj.events] == [e.name for e in plain.events]
    np.testing.assert_allclose([e.t for e in traj.events], [e.t for e in plain.events], rtol=1e-12)


def test_bad_t_eval_is_refused():
    pt = t1()
    st = pt.state(**T1_START)
    for bad in ([0.0, 2.0, 1.0], [-0.1, 0.5], [0.0, 1.5]):
        with pytest.raises(ParameterError):
            kreisel.simulate(pt, st, 1.0, t_eval=bad)


def test_inversion_event():
    pt = t1()
    st = pt.state(**T1_START)
    traj = kreisel.simulate(pt, st, 6.0, events=[kreisel.events.inversion(level=0.9)])
    inv = [e for e in traj.events if e.name == "inversion"]
    assert len(inv) == 1
    t_inv = inv[0].t
    assert 2.0 < t_inv < 4.0
    at = kreisel.simulate(pt, st, t_inv, t_eval=[t_inv])
    assert at.u[-1] == pytest.approx(0.9, abs=1e-9)
    assert np.all(traj.u[traj.t < t_inv] < 0.9)
    assert traj.t[-1] == 6.0
    stop = kreisel.simulate(pt, st, 6.0, events=[kreisel.events.inversion(0.9, terminal=True)])
    assert stop.t[-1] == pytest.approx(t_inv, abs=1e-12)
    assert stop.u[-1] == pytest.approx(0.9, abs=1e-9)
    low = kreisel.simulate(pt, st, 6.0, events=[kreisel.events.inversion(level=0.0)])
    t0 = [e.t for e in low.events if e.name == "inversion"][0]
    assert t0 < t_inv


def test_rest_event_of_a_ball_stopped_by_rolling_resistance():
    """A homogeneous ball (s = 0, A = C = 0.4 m rho^2) pushed at v0 with no spin: Coulomb
    slip until v = rho omega at t1 = v0 / (mu g + m g rho (mu rho - d) / I), then rolling
    decelerated by the resistance torque d N: omega' = -a, a = d m g / (I + m rho^2), which
    would stop it at t_stop = t1 + omega1 / a.

    kreisel's torque is the sharp law down to omega = reg and linear in omega below (docs:
    theory, "Contact thresholds": a sharp switch is stiff), reg = max(1e-6 sqrt(g / rho),
    d m g tau / I) with tau = 1e-4 sqrt(rho / g) (the ball's reach is rho), here the second.
    So the slip starts with omega = w_inf (1 - exp(-t / tau)), w_inf = mu rho reg / d, until
    omega = reg at t_a = -tau ln(1 - d / (mu rho)), then grows at alpha = (mu rho - d) m g / I
    until v0 - mu g t = rho omega at t1. Rolling, omega decays from omega1 as
    reg exp(-a (t - t_reg) / reg) from t_reg = t1 + (omega1 - reg) / a, and the rest event
    (kinetic energy 1/2 (I + m rho^2) omega^2 below 1e-12 of 1/2 m v0^2, at omega_e) comes at
    t_reg + (reg / a) ln(reg / omega_e)."""
    m, rho, mu, d, g, v0 = 0.05, 0.02, 0.3, 1e-3, 9.81, 0.1
    inertia = 0.4 * m * rho**2
    pt = kreisel.PlayTop(
        m=m, A=inertia, C=inertia, s=0.0, rho=rho, g=g, friction=kreisel.Coulomb(mu=mu),
        rolling_resistance=d,
    )  # fmt: skip
    tau = 1e-4 * math.sqrt(rho / g)
    reg = max(1e-6 * math.sqrt(g / rho), d * m * g * tau / inertia)
    assert reg > 1e-6 * math.sqrt(g / rho)
    t_a = -tau * math.log(1.0 - d / (mu * rho))
    alpha = (mu * rho - d) * m * g / inertia
    t1_ = (v0 - rho * reg + rho * alpha * t_a) / (mu * g + rho * alpha)
    w1 = (v0 - mu * g * t1_) / rho
    a = d * m * g / (inertia + m * rho**2)
    w_end = v0 * math.sqrt(1e-12 * m / (inertia + m * rho**2))
    t_rest = t1_ + (w1 - reg) / a + reg / a * math.log(reg / w_end)
    # the sharp law's stop
    t1_sharp = v0 / (mu * g + rho * alpha)
    t_stop = t1_sharp + (mu * rho - d) * m * g * t1_sharp / inertia / a
    traj = kreisel.simulate(pt, pt.state(0.0, vx=v0), 10.0, events=[kreisel.events.rest()])
    names = [e.name for e in traj.events]
    assert names == ["slip_to_roll", "rest"]
    assert traj.events[0].t == pytest.approx(t1_, abs=2e-9)
    assert traj.events[1].t == pytest.approx(t_rest, abs=1e-7)
    # and the sharp law's stop: the linear law's tail moves it by (reg / a) (ln(reg / w_end)
    # - 1) = 5e-5 s of its 0.3 s, no more
    assert traj.events[1].t == pytest.approx(t_stop, abs=6e-5)
    assert traj.t[-1] == traj.events[1].t
    ke = traj.energy_translation + traj.energy_rotation
    assert ke[-1] <= 1.01e-12 * ke[0]


# --------------------------------------------------------------------------------------
# simulate_many
# --------------------------------------------------------------------------------------


def single_summary(pt, st, t_end, level=0.9):
    traj = kreisel.simulate(pt, st, t_end)
    ev = kreisel.simulate(pt, st, t_end, events=[kreisel.events.inversion(level)])
    inv = [e.t for e in ev.events if e.name == "inversion"]
    j = traj.jellett
    e = traj.energy + traj.dissipated
    return {
        "final_u": traj.u[-1],
        "final_mode": traj.mode[-1],
        "inversion_time": inv[0] if inv else math.nan,
        "jellett_drift": np.max(np.abs(j - j[0])) / abs(j[0]),
        "energy_drift": np.max(np.abs(e - e[0])) / abs(e[0]),
    }


def assert_summary_equal(res, i, expected):
    assert res.final_u[i] == pytest.approx(expected["final_u"], abs=1e-14)
    assert res.final_mode[i] == expected["final_mode"]
    if math.isnan(expected["inversion_time"]):
        assert math.isnan(res.inversion_time[i])
    else:
        assert res.inversion_time[i] == pytest.approx(expected["inversion_time"], abs=1e-14)
    for key in ("jellett_drift", "energy_drift"):
        assert getattr(res, key)[i] == pytest.approx(expected[key], rel=1e-12, abs=0), key


def test_simulate_many_one_model_many_states_equals_single_runs():
    pt = t1()
    states = [pt.state(math.pi - 0.1, psi_dot=w) for w in (20.0, 150.0, 180.0)]
    states.append(pt.state(0.3, psi_dot=150.0))
    res = kreisel.simulate_many(pt, states, 4.0)
    assert isinstance(res, kreisel.BatchSummary)
    for name in ("final_u", "final_mode", "inversion_time", "jellett_drift", "energy_drift"):
        assert len(getattr(res, name)) == len(states), name
    assert res.final_mode.dtype.kind == "U"
    for i, st in enumerate(states):
        assert_summary_equal(res, i, single_summary(pt, st, 4.0))
    assert math.isnan(res.inversion_time[0])  # slow spin: stays hanging
    assert 2.0 < res.inversion_time[1] < 4.0
    assert np.all(res.jellett_drift < 1e-9)


def test_simulate_many_many_models_one_state_and_pairs():
    models = [
        t1(),
        t1(kreisel.Coulomb(mu=0.3)),
        t1(kreisel.Frictionless()),
        kreisel.PlayTop(**{**T1.kwargs(), "s": 0.004}, friction=kreisel.Viscous(mu=1.0)),
    ]
    st = models[0].state(**T1_START)
    res = kreisel.simulate_many(models, st, 1.0, inversion_level=-0.5)
    for i, pt in enumerate(models):
        assert_summary_equal(res, i, single_summary(pt, st, 1.0, level=-0.5))
    states = [pt.state(math.pi - 0.2, psi_dot=100.0 + 10 * i) for i, pt in enumerate(models)]
    res2 = kreisel.simulate_many(models, states, 1.0)
    for i, (pt, s) in enumerate(zip(models, states)):
        assert_summary_equal(res2, i, single_summary(pt, s, 1.0))


def test_simulate_many_is_deterministic_and_checks_lengths():
    pt = t1()
    states = [pt.state(math.pi - 0.05 * (k + 1), psi_dot=150.0) for k in range(6)]
    a = kreisel.simulate_many(pt, states, 1.0)
    b = kreisel.simulate_many([pt] * 6, states, 1.0)
    np.testing.assert_array_equal(a.final_u, b.final_u)
    np.testing.assert_array_equal(a.jellett_drift, b.jellett_drift)
    with pytest.raises(ParameterError):
        kreisel.simulate_many([pt, pt], states[:3], 1.0)
