"""kreisel.simulate and kreisel.HeavyTop: the interface, checked against independent physics.

References: the exact Lagrange solution (``LagrangeTop.exact``, tested on its own against
mpmath), and the plain-numpy rigid-body formulas of ``_sim_reference`` (rotation matrices
from Euler angles and quaternions, body angular velocity from Euler rates, the integrals).
"""

from __future__ import annotations

import dataclasses
import math

import _sim_reference as ref
import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.optimize import brentq

import kreisel

# the top of the order tests: nutation period 2.41 s, theta in [0.590, 1.038], loops
LAG = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.3, "g": 1.0}
LAG_START = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 5.0}
GENERAL = {"I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0, "com": (0.3, 0.2, 0.4), "g": 9.81}
KOVALEVSKAYA = {"I1": 2.0, "I2": 2.0, "I3": 1.0, "m": 1.0, "com": (0.3, 0.0, 0.0), "g": 9.81}

FIXED_STEP = ("rk4", "splitting", "splitting4", "splitting6", "verlet", "midpoint", "gauss4")


def lagrange():
    top = kreisel.LagrangeTop(**LAG)
    return top, top.state(**LAG_START)


def heavy_lagrange():
    top = kreisel.HeavyTop(
        LAG["I1"], LAG["I1"], LAG["I3"], LAG["m"], (0.0, 0.0, LAG["l"]), LAG["g"]
    )
    return top, top.state(**LAG_START)


def body_of(params: dict) -> ref.Body:
    return ref.Body(**params)


LAG_BODY = ref.Body(LAG["I1"], LAG["I1"], LAG["I3"], LAG["m"], (0.0, 0.0, LAG["l"]), LAG["g"])


def general_start(top):
    return top.state_from_quaternion(ref.euler_to_quat(0.0, 1.2, 0.3), [2.0, 1.0, 3.0])


def rotation_error(traj, phi, theta, psi):
    """Largest entry of R(traj.quaternion) - Rz(phi) Rx(theta) Rz(psi)."""
    return float(
        np.abs(ref.quat_to_matrix(traj.quaternion) - ref.euler_matrix(phi, theta, psi)).max()
    )


def exact_roots(fn, t_end, n=4001):
    """All simple roots of a smooth function on (0, t_end]: sign changes of ``fn(grid)`` (fn is
    vectorised over times), refined with brentq. Returns (root, sign of the slope) pairs."""
    grid = np.linspace(0.0, t_end, n)
    vals = fn(grid)

    def scalar(t):
        return float(fn(np.array([t]))[0])

    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fb < 0:
            roots.append((brentq(scalar, a, b, xtol=1e-15, rtol=1e-15, maxiter=200), np.sign(fb)))
        elif fb == 0.0:
            raise AssertionError("a root on the grid: move the grid")
    return roots


# --------------------------------------------------------------------------------------
# methods and model kinds
# --------------------------------------------------------------------------------------

EXPECTED_METHODS = {
    # name: (order, adaptive, symplectic, events)
    "dop853": (8, True, False, True),
    "rk4": (4, False, False, False),
    "splitting": (2, False, True, False),
    "splitting4": (4, False, True, False),
    "splitting6": (6, False, True, False),
    "verlet": (2, False, True, False),
    "midpoint": (2, False, True, False),
    "gauss4": (4, False, True, False),
}


def test_methods_content():
    infos = kreisel.methods()
    assert isinstance(infos, tuple)
    assert all(isinstance(info, kreisel.MethodInfo) for info in infos)
    names = [info.name for info in infos]
    assert len(names) == len(set(names))
    assert set(names) == set(EXPECTED_METHODS)
    for info in infos:
        got = (info.order, info.adaptive, info.symplectic, info.events)
        assert got == EXPECTED_METHODS[info.name], info


@pytest.mark.parametrize(
    ("args", "kind"),
    [
        ((1.0, 1.3, 1.5, 1.0, (0.0, 0.0, 0.0)), "euler"),
        ((1.0, 1.0, 0.5, 1.0, (0.0, 0.0, 0.0)), "euler"),  # free symmetric top
        ((1.0, 1.3, 1.5, 1.0, (0.1, 0.2, 0.3), 0.0), "euler"),  # g = 0
        ((1.0, 1.0, 0.5, 1.0, (0.0, 0.0, 0.3)), "lagrange"),
        ((1.0, 1.0, 0.5, 1.0, (0.0, 0.0, -0.3)), "lagrange"),  # hanging below the pivot
        ((2.0, 2.0, 1.0, 1.0, (0.0, 0.0, 0.3)), "lagrange"),  # Kovalevskaya moments, on axis
        ((2.0, 2.0, 1.0, 1.0, (0.3, 0.0, 0.0)), "kovalevskaya"),
        ((2.0, 2.0, 1.0, 1.0, (0.1, -0.2, 0.0)), "kovalevskaya"),
        ((2.0, 2.0, 1.0, 1.0, (0.1, 0.0, 0.05)), "general"),
        ((1.0, 1.0, 0.5, 1.0, (0.1, 0.0, 0.3)), "general"),  # symmetric, off-axis
        ((1.0, 0.75, 0.5, 1.0, (0.0, 0.0, 0.3)), "general"),  # asymmetric, on axis
        ((1.0, 0.75, 0.5, 1.0, (0.3, 0.2, 0.4)), "general"),
    ],
)
def test_kind(args, kind):
    assert kreisel.HeavyTop(*args).kind == kind


# --------------------------------------------------------------------------------------
# states and invariants
# --------------------------------------------------------------------------------------


def test_euler_state_conventions():
    """top.state(...) is the orientation Rz(phi) Rx(theta) Rz(psi) with the body angular
    velocity of the z-x-z rates; the trajectory starts there."""
    top = kreisel.HeavyTop(**GENERAL)
    ang = {"theta": 0.8, "phi": 0.4, "psi": -1.1}
    rates = {"theta_dot": 0.6, "phi_dot": -0.9, "psi_dot": 2.5}
    st = top.state(**ang, **rates)
    assert isinstance(st, kreisel.EulerState)
    traj = kreisel.simulate(top, st, 0.05)
    r0 = ref.euler_matrix(ang["phi"], ang["theta"], ang["psi"])
    assert_allclose(ref.quat_to_matrix(traj.quaternion[0]), r0, rtol=0, atol=1e-14)
    w0 = ref.body_omega(ang["theta"], ang["psi"], *rates.values())
    assert_allclose(traj.omega[0], w0, rtol=0, atol=1e-14)
    assert_allclose(
        [traj.theta[0], traj.phi[0], traj.psi[0]],
        [ang["theta"], ang["phi"], ang["psi"]],
        rtol=0,
        atol=1e-14,
    )
    assert traj.t[0] == 0.0


def test_state_from_quaternion_normalises_and_is_frozen():
    top = kreisel.HeavyTop(**GENERAL)
    q = np.array([1.0, 2.0, -0.5, 0.25])
    st = top.state_from_quaternion(3.0 * q, [0.1, -0.2, 0.3])
    assert isinstance(st, kreisel.RigidState)
    assert isinstance(st.quaternion, np.ndarray) and st.quaternion.shape == (4,)
    assert isinstance(st.omega, np.ndarray) and st.omega.shape == (3,)
    assert_allclose(st.quaternion, q / np.linalg.norm(q), rtol=0, atol=1e-15)
    assert_allclose(st.omega, [0.1, -0.2, 0.3], rtol=0, atol=0)
    with pytest.raises((dataclasses.FrozenInstanceError, AttributeError)):
        st.omega = np.zeros(3)
    # the trajectory starts at the normalised state
    traj = kreisel.simulate(top, st, 0.01)
    assert_allclose(traj.quaternion[0], q / np.linalg.norm(q), rtol=0, atol=1e-15)


def test_invariants_dict():
    top, st = heavy_lagrange()
    inv = top.invariants(st)
    e, mz, m3 = ref.lagrange_invariants(
        LAG["I1"], LAG["I3"], LAG["m"] * LAG["g"] * LAG["l"], *LAG_START.values()
    )
    assert {"energy", "Mz", "M3"} <= set(inv) and "kovalevskaya" not in inv
    assert_allclose([inv["energy"], inv["Mz"], inv["M3"]], [e, mz, m3], rtol=1e-14)

    kov = kreisel.HeavyTop(**KOVALEVSKAYA)
    q, w = ref.euler_to_quat(0.1, 0.9, 0.5), np.array([1.0, -2.0, 4.0])
    inv = kov.invariants(kov.state_from_quaternion(q, w))
    body = body_of(KOVALEVSKAYA)
    gam = ref.gamma_of(q)
    assert {"energy", "Mz", "kovalevskaya"} <= set(inv) and "M3" not in inv
    assert_allclose(inv["energy"], ref.energy(body, w, gam), rtol=1e-14)
    assert_allclose(inv["Mz"], ref.vertical_momentum(body, w, gam), rtol=1e-14)
    assert_allclose(inv["kovalevskaya"], ref.kovalevskaya(body, w, gam), rtol=1e-13)

    gen = kreisel.HeavyTop(**GENERAL)
    st = general_start(gen)
    inv = gen.invariants(st)
    assert set(inv) == {"energy", "Mz"}
    body = body_of(GENERAL)
    gam = ref.gamma_of(st.quaternion)
    assert_allclose(inv["energy"], ref.energy(body, st.omega, gam), rtol=1e-14)
    assert_allclose(inv["Mz"], ref.vertical_momentum(body, st.omega, gam), rtol=1e-14)


# --------------------------------------------------------------------------------------
# trajectories: columns, shapes, t_eval
# --------------------------------------------------------------------------------------

COMMON = ("t", "quaternion", "omega", "theta", "phi", "psi", "energy", "Mz")


@pytest.mark.parametrize("which", ["lagrange", "kovalevskaya", "general"])
def test_columns_and_shapes(which):
    if which == "lagrange":
        top, st = heavy_lagrange()
        body, extra, absent = LAG_BODY, "M3", "kovalevskaya"
    elif which == "kovalevskaya":
        top = kreisel.HeavyTop(**KOVALEVSKAYA)
        st = top.state_from_quaternion(ref.euler_to_quat(0.1, 0.9, 0.5), [1.0, -2.0, 4.0])
        body, extra, absent = body_of(KOVALEVSKAYA), "kovalevskaya", "M3"
    else:
        top = kreisel.HeavyTop(**GENERAL)
        st = general_start(top)
        body, extra, absent = body_of(GENERAL), None, "M3"
    traj = kreisel.simulate(top, st, 3.0)
    n = len(traj)
    assert n == traj.stats["steps"] + 1 > 10
    for name in COMMON:
        assert name in traj.columns
    assert traj.t.shape == (n,) and traj.quaternion.shape == (n, 4) and traj.omega.shape == (n, 3)
    for name in ("theta", "phi", "psi", "energy", "Mz"):
        assert getattr(traj, name).shape == (n,), name
    if extra is not None:
        assert extra in traj.columns and traj[extra].shape == (n,)
    assert absent not in traj.columns
    if extra is None:
        assert "kovalevskaya" not in traj.columns
    with pytest.raises(AttributeError):
        getattr(traj, absent)
    # times
    assert traj.t[0] == 0.0 and traj.t[-1] == 3.0
    assert np.all(np.diff(traj.t) > 0)
    # stats
    assert set(traj.stats) >= {"steps", "rejected", "rhs_evals"}
    assert all(isinstance(traj.stats[k], int) for k in ("steps", "rejected", "rhs_evals"))
    assert traj.stats["rhs_evals"] >= traj.stats["steps"] >= 1 and traj.stats["rejected"] >= 0
    assert traj.events == []
    # the columns are what they claim to be
    q, w = traj.quaternion, traj.omega
    gam = ref.gamma_of(q)
    e = ref.energy(body, w, gam)
    assert_allclose(traj.energy, e, rtol=1e-13, atol=1e-13 * np.abs(e).max())
    mz = ref.vertical_momentum(body, w, gam)
    assert_allclose(traj.Mz, mz, rtol=0, atol=1e-13 * np.abs(body.inertia * w).max())
    if extra == "M3":
        assert_allclose(traj.M3, body.I3 * w[:, 2], rtol=1e-14)
    if extra == "kovalevskaya":
        assert_allclose(traj.kovalevskaya, ref.kovalevskaya(body, w, gam), rtol=1e-12)
    # Euler angles describe the same orientation, and are unwrapped
    assert rotation_error(traj, traj.phi, traj.theta, traj.psi) < 1e-12
    assert np.all((traj.theta >= 0) & (traj.theta <= math.pi))
    assert np.abs(np.diff(traj.phi)).max() < 2.0 and np.abs(np.diff(traj.psi)).max() < 2.0


@pytest.mark.parametrize("method", FIXED_STEP)
def test_fixed_step_rows(method):
    top, st = lagrange()
    dt = 1.0 / 64
    traj = kreisel.simulate(top, st, 1.0, method=method, dt=dt)
    assert len(traj) == 65
    assert_allclose(traj.t, np.arange(65) * dt, rtol=0, atol=1e-15)
    assert traj.t[-1] == 1.0
    assert traj.stats["steps"] == 64 and traj.stats["rejected"] == 0


def test_t_eval_dop853_is_dense_and_exact_times():
    top, st = lagrange()
    rng = np.random.default_rng(7)
    t_eval = np.concatenate([[0.0], np.sort(rng.uniform(0.0, 10.0, 57)), [10.0]])
    traj = kreisel.simulate(top, st, 10.0, t_eval=t_eval)
    assert_array_equal(traj.t, t_eval)
    assert len(traj) == len(t_eval) and traj.quaternion.shape == (len(t_eval), 4)
    ex = top.exact(st, t_eval)
    assert rotation_error(traj, ex.phi, ex.theta, ex.psi) < 1e-8
    # the dense output agrees with the step-by-step trajectory where they meet
    full = kreisel.simulate(top, st, 10.0)
    assert_allclose(traj.quaternion[-1], full.quaternion[-1], rtol=0, atol=1e-13)
    # a t_eval not reaching t_end ends there
    part = kreisel.simulate(top, st, 10.0, t_eval=t_eval[:20])
    assert_array_equal(part.t, t_eval[:20])
    assert_allclose(part.quaternion, traj.quaternion[:20], rtol=0, atol=1e-13)


@pytest.mark.parametrize("method", FIXED_STEP)
def test_t_eval_fixed_step_partial_steps(method):
    """Fixed-step methods: an off-grid output time is a partial step from the last grid point,
    i.e. exactly what a run ending at that time computes (its last step is shortened to land
    there); grid times are the grid run's rows, and the main run is undisturbed."""
    top, st = lagrange()
    dt = 1.0 / 32
    grid = kreisel.simulate(top, st, 2.0, method=method, dt=dt)
    t_eval = np.array([0.0, 0.3, 10 * dt, 1.0 + 0.4 * dt, 1.5, 2.0 - 0.25 * dt, 2.0])
    traj = kreisel.simulate(top, st, 2.0, method=method, dt=dt, t_eval=t_eval)
    assert_array_equal(traj.t, t_eval)
    for t, q, w in zip(t_eval, traj.quaternion, traj.omega):
        k = round(t / dt)
        if abs(t - k * dt) < 1e-12:  # on the grid: the grid run's row
            assert_allclose(q, grid.quaternion[k], rtol=0, atol=1e-15, err_msg=f"t = {t}")
            assert_allclose(w, grid.omega[k], rtol=0, atol=1e-15, err_msg=f"t = {t}")
        else:  # grid steps, then one partial step: a run that ends at t
            short = kreisel.simulate(top, st, t, method=method, dt=dt)
            assert len(short) == math.ceil(t / dt) + 1
            assert_allclose(q, short.quaternion[-1], rtol=0, atol=1e-15, err_msg=f"t = {t}")
            assert_allclose(w, short.omega[-1], rtol=0, atol=1e-15, err_msg=f"t = {t}")
    assert_allclose(traj.quaternion[-1], grid.quaternion[-1], rtol=0, atol=1e-15)


def test_lagrange_top_and_heavy_top_same_trajectory():
    lag, st = lagrange()
    heavy, st_h = heavy_lagrange()
    assert heavy.kind == "lagrange"
    for method, dt in (("dop853", None), ("splitting", 0.01), ("rk4", 0.01)):
        a = kreisel.simulate(lag, st, 20.0, method=method, dt=dt)
        b = kreisel.simulate(heavy, st_h, 20.0, method=method, dt=dt)
        assert len(a) == len(b), method
        assert_allclose(a.t, b.t, rtol=0, atol=1e-12)
        assert_allclose(a.quaternion, b.quaternion, rtol=0, atol=1e-12, err_msg=method)
        assert_allclose(a.omega, b.omega, rtol=0, atol=1e-12, err_msg=method)
        assert_allclose(a.M3, b.M3, rtol=1e-12, err_msg=method)


def test_reduced_matches_full():
    """The reduced route (theta, p_theta; phi, psi from the conserved momenta) and the full
    rigid-body integration describe the same motion. At rtol 1e-12 each is within ~2e-11 of
    the exact solution over 30 s, so they must agree to 1e-9; at the default tolerances each
    is within 1e-8 of the exact motion (the full route's own error there is ~3e-9)."""
    top, st = lagrange()
    t_eval = np.linspace(0.0, 30.0, 301)
    tight = {"rtol": 1e-12, "atol": 1e-14}
    full = kreisel.simulate(top, st, 30.0, t_eval=t_eval, **tight)
    red = kreisel.simulate(top, st, 30.0, t_eval=t_eval, reduced=True, **tight)
    assert_array_equal(red.t, t_eval)
    for name in ("theta", "phi", "psi"):
        assert_allclose(red[name], full[name], rtol=0, atol=1e-9, err_msg=name)
    assert rotation_error(red, full.phi, full.theta, full.psi) < 1e-9
    assert_allclose(red.omega, full.omega, rtol=0, atol=1e-9)
    assert_allclose(red.M3, full.M3, rtol=1e-12)
    ex = top.exact(st, t_eval)
    for tol in ({}, tight):
        red = kreisel.simulate(top, st, 30.0, t_eval=t_eval, reduced=True, **tol)
        assert rotation_error(red, ex.phi, ex.theta, ex.psi) < (1e-8 if tol == {} else 1e-10)
        assert np.abs(red.theta - ex.theta).max() < (1e-8 if tol == {} else 1e-10)
    # and without t_eval: one row per accepted step
    every = kreisel.simulate(top, st, 30.0, reduced=True)
    assert len(every) == every.stats["steps"] + 1 and every.t[-1] == 30.0


def test_reduced_needs_a_lagrange_top():
    top = kreisel.HeavyTop(**GENERAL)
    with pytest.raises(kreisel.KreiselError):
        kreisel.simulate(top, general_start(top), 1.0, reduced=True)


@pytest.mark.parametrize("method", ["dop853", *FIXED_STEP])
def test_quaternion_stays_unit(method):
    top, st = lagrange()
    dt = None if method == "dop853" else 2e-3
    traj = kreisel.simulate(top, st, 20.0, method=method, dt=dt)
    assert len(traj) > (200 if method == "dop853" else 10_000)
    assert np.abs(np.linalg.norm(traj.quaternion, axis=1) - 1.0).max() < 1e-12


def test_quaternion_stays_unit_general_top():
    top = kreisel.HeavyTop(**GENERAL)
    for method, dt in (("dop853", None), ("rk4", 1e-3), ("splitting", 1e-3)):
        traj = kreisel.simulate(top, general_start(top), 20.0, method=method, dt=dt)
        assert np.abs(np.linalg.norm(traj.quaternion, axis=1) - 1.0).max() < 1e-12, method


# --------------------------------------------------------------------------------------
# events
# --------------------------------------------------------------------------------------


def _exact(top, st, name, offset=0.0):
    """The exact column ``name`` minus ``offset`` as a vectorised function of time."""
    return lambda t: top.exact(st, t)[name] - offset


def test_turning_points_event():
    top, st = lagrange()
    period = top.nutation_period(st)
    t_end = 4.3 * period
    theta_min, theta_max = top.turning_points(st)
    expected = [t for t, _ in exact_roots(_exact(top, st, "theta_dot"), t_end)]
    assert len(expected) >= 8

    traj = kreisel.simulate(top, st, t_end, events=[kreisel.events.turning_points()])
    assert traj.t[-1] == t_end  # not terminal
    got = [ev.t for ev in traj.events]
    assert all(isinstance(ev, kreisel.EventRecord) for ev in traj.events)
    assert all(ev.index == 0 for ev in traj.events)
    assert len(got) == len(expected)
    assert_allclose(got, expected, rtol=0, atol=2e-9)
    # and the turning points are the exact ones, alternately theta_max and theta_min
    at = kreisel.simulate(top, st, t_end, t_eval=got)
    turning = np.where(np.arange(len(got)) % 2 == 0, theta_max, theta_min)
    assert st.theta_dot > 0  # first turning point is theta_max
    assert_allclose(at.theta, turning, rtol=0, atol=1e-9)


@pytest.mark.parametrize("direction", [0, 1, -1])
def test_theta_crossing_event(direction):
    top, st = lagrange()
    t_end = 3.2 * top.nutation_period(st)
    value = 0.8
    roots = exact_roots(_exact(top, st, "theta", value), t_end)
    expected = [t for t, slope in roots if direction == 0 or np.sign(slope) == direction]
    assert len(expected) >= 3
    ev = kreisel.events.theta_crossing(value, direction=direction)
    traj = kreisel.simulate(top, st, t_end, events=[ev])
    assert_allclose([e.t for e in traj.events], expected, rtol=0, atol=2e-9)


def test_terminal_theta_crossing_stops_the_run():
    top, st = lagrange()
    value = 0.7
    roots = exact_roots(_exact(top, st, "theta", value), 10.0)
    first_up = next(t for t, slope in roots if slope > 0)
    assert first_up > roots[0][0]  # a downward crossing comes first and must not stop it
    ev = kreisel.events.theta_crossing(value, direction=1, terminal=True)
    traj = kreisel.simulate(top, st, 10.0, events=[ev])
    assert len(traj.events) == 1
    assert abs(traj.events[0].t - first_up) < 2e-9
    assert traj.t[-1] == traj.events[0].t
    assert abs(traj.theta[-1] - value) < 1e-9
    assert np.all(traj.t[:-1] < traj.t[-1])
    # with t_eval: times after the stop are not reported
    t_eval = np.linspace(0.0, 10.0, 101)
    cut = kreisel.simulate(top, st, 10.0, events=[ev], t_eval=t_eval)
    assert_array_equal(cut.t[cut.t < first_up - 1e-6], t_eval[t_eval < first_up - 1e-6])
    assert cut.t[-1] <= first_up + 1e-8


def test_user_events_and_indices():
    top, st = lagrange()
    t_end = 2.5 * top.nutation_period(st)
    seen_types = set()
    value = 0.8

    def height(t, s):
        seen_types.add(type(s))
        return ref.quat_to_matrix(s.quaternion)[2, 2] - math.cos(value)  # cos(theta) - cos(0.8)

    events = [
        kreisel.Event(lambda t, s: t - 1.2345, name="clock"),
        kreisel.Event(height, name="height", direction=-1),  # cos decreasing: theta rising
        kreisel.events.theta_crossing(value, direction=1),
    ]
    traj = kreisel.simulate(top, st, t_end, events=events)
    assert seen_types == {kreisel.RigidState}
    times = [e.t for e in traj.events]
    assert times == sorted(times)
    by_index = {i: [e for e in traj.events if e.index == i] for i in range(3)}
    assert [e.name for e in by_index[0]] == ["clock"]
    assert abs(by_index[0][0].t - 1.2345) < 1e-10
    assert all(e.name == "height" for e in by_index[1])
    assert len(by_index[1]) == len(by_index[2]) >= 2
    assert_allclose([e.t for e in by_index[1]], [e.t for e in by_index[2]], rtol=0, atol=1e-9)


def test_terminal_user_event_general_top():
    top = kreisel.HeavyTop(**GENERAL)
    st = general_start(top)
    body = body_of(GENERAL)
    level = 0.2  # height of the centre of mass above the pivot (m)

    def com_height(t, s):
        return float(ref.gamma_of(s.quaternion) @ np.asarray(body.com)) - level

    traj = kreisel.simulate(top, st, 20.0, events=[kreisel.Event(com_height, terminal=True)])
    assert len(traj.events) == 1
    t_stop = traj.events[0].t
    assert traj.t[-1] == t_stop < 20.0
    assert abs(float(ref.gamma_of(traj.quaternion[-1]) @ np.asarray(body.com)) - level) < 1e-10
    # the same instant from a tight scipy integration of the reference equations
    q, _ = ref.integrate_quaternion(body, st.quaternion, st.omega, [0.0, t_stop])
    assert abs(float(ref.gamma_of(q[-1]) @ np.asarray(body.com)) - level) < 1e-8


# --------------------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------------------

OK_BODY = {"I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0, "com": (0.3, 0.2, 0.4), "g": 9.81}


@pytest.mark.parametrize(
    ("change", "name"),
    [
        ({"I1": 0.0}, "I1"),
        ({"I1": -1.0}, "I1"),
        ({"I2": -0.5}, "I2"),
        ({"I3": 0.0}, "I3"),
        ({"I1": math.nan}, "I1"),
        ({"I2": math.inf}, "I2"),
        ({"I3": 2.0}, "I[123]"),  # triangle inequality: I3 > I1 + I2
        ({"I1": 1.0, "I2": 3.0, "I3": 1.5}, "I[123]"),  # I2 > I1 + I3
        ({"m": 0.0}, r"\bm\b"),
        ({"m": -1.0}, r"\bm\b"),
        ({"m": math.nan}, r"\bm\b"),
        ({"g": -9.81}, r"\bg\b"),
        ({"g": math.inf}, r"\bg\b"),
        ({"com": (math.nan, 0.0, 0.0)}, "com"),
        ({"com": (0.0, math.inf, 0.0)}, "com"),
    ],
)
def test_heavy_top_validation(change, name):
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.HeavyTop(**{**OK_BODY, **change})


def test_parameter_error_is_a_value_error():
    assert issubclass(kreisel.ParameterError, ValueError)
    assert issubclass(kreisel.ParameterError, kreisel.KreiselError)
    assert issubclass(kreisel.NumericalError, kreisel.KreiselError)


def test_triangle_equality_is_allowed():
    kreisel.HeavyTop(1.0, 1.0, 2.0, 1.0, (0.0, 0.0, 0.1))  # flat disc: I3 = I1 + I2


def test_zero_quaternion():
    top = kreisel.HeavyTop(**OK_BODY)
    with pytest.raises(kreisel.ParameterError, match=r"\bq\b|quaternion"):
        top.state_from_quaternion([0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0])


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"t_end": -1.0}, "t_end"),
        ({"t_end": math.nan}, "t_end"),
        ({"rtol": 0.0}, "rtol"),
        ({"rtol": 1e-16}, "rtol"),
        ({"rtol": 1.0}, "rtol"),
        ({"rtol": -1e-8}, "rtol"),
        ({"rtol": math.nan}, "rtol"),
        ({"atol": 0.0}, "atol"),
        ({"atol": -1e-12}, "atol"),
        ({"atol": math.nan}, "atol"),
        ({"method": "euler"}, "method"),
        ({"method": "DOP853x"}, "method"),
        ({"method": "rk4"}, "dt"),
        ({"method": "splitting"}, "dt"),
        ({"method": "rk4", "dt": 0.0}, "dt"),
        ({"method": "gauss4", "dt": -0.01}, "dt"),
        ({"method": "rk4", "dt": 0.01, "events": "turning_points"}, "events"),
        ({"method": "splitting", "dt": 0.01, "events": "turning_points"}, "events"),
        ({"method": "gauss4", "dt": 0.01, "events": "user"}, "events"),
        ({"t_eval": [0.0, 2.0]}, "t_eval"),  # beyond t_end
        ({"t_eval": [0.5, 0.2]}, "t_eval"),  # not sorted
        ({"t_eval": [-0.1, 0.5]}, "t_eval"),
    ],
)
def test_simulate_validation(kwargs, name):
    top, st = lagrange()
    args = {"t_end": 1.0, **kwargs}
    t_end = args.pop("t_end")
    if args.get("events") == "turning_points":
        args["events"] = [kreisel.events.turning_points()]
    elif args.get("events") == "user":
        args["events"] = [kreisel.Event(lambda t, s: t - 0.5)]
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.simulate(top, st, t_end, **args)


def test_tolerance_bounds_are_inclusive():
    top, st = lagrange()
    kreisel.simulate(top, st, 0.1, rtol=1e-15, atol=1e-16)
    kreisel.simulate(top, st, 0.1, rtol=0.5, atol=1.0)


def test_verlet_needs_a_symmetric_lagrange_top():
    top = kreisel.HeavyTop(**GENERAL)
    with pytest.raises(kreisel.KreiselError):
        kreisel.simulate(top, general_start(top), 1.0, method="verlet", dt=0.01)


def test_verlet_through_the_vertical_raises():
    """A planar swing (M3 = Mz = 0) through theta = 0: Euler angles are singular there."""
    top = kreisel.LagrangeTop(**LAG)
    st = top.state(0.3, theta_dot=-1.0)
    with pytest.raises(kreisel.NumericalError):
        kreisel.simulate(top, st, 2.0, method="verlet", dt=1e-3)
    # the quaternion methods go through
    traj = kreisel.simulate(top, st, 2.0, method="splitting", dt=1e-3)
    assert traj.theta.min() < 1e-2
