"""The exact Lagrange-top solution against independent references.

References (see conftest.py): mpmath quadrature of the reduced problem u = cos(theta),
tight DOP853 integration of the Euler-Lagrange equations, rigid-body integration with
quaternions (regular through the vertical) and the closed-form free symmetric top.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from conftest import Params, Start
from numpy.testing import assert_allclose

import kreisel

SYM = Params(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0)
GYRO = Params(I1=2.0, I3=1.5, m=0.8, l=0.6, g=9.81)
HANG = Params(I1=1.2, I3=0.9, m=1.0, l=-0.4, g=9.81)  # centre of mass below the pivot
FREE = Params(I1=1.0, I3=1.6, m=2.0, l=0.0, g=9.81)  # l = 0: free symmetric top
WEIGHTLESS = Params(I1=1.0, I3=0.7, m=1.0, l=0.5, g=0.0)  # g = 0: also free
FLAT = Params(I1=0.5, I3=0.9, m=1.0, l=0.3, g=9.81)  # oblate, I3 > I1


def _separatrix_start(p: Params, theta0: float, omega3: float, sign: float, fac: float = 1.0):
    """Mz = M3 (axis can reach the vertical) and E = m g l + M3^2/(2 I3) for fac = 1."""
    m3 = p.I3 * omega3
    c = math.cos(theta0)
    phi_dot = m3 / (p.I1 * (1.0 + c))  # makes Mz = M3
    # E = upright energy  <=>  I1 thetadot^2 = (1 - c) (2 m g l - M3^2 / (I1 (1 + c)))
    one_minus_c = 2.0 * math.sin(theta0 / 2) ** 2
    rad = one_minus_c / p.I1 * (2 * p.mgl - m3 * m3 / (p.I1 * (1.0 + c)))
    assert rad > 0
    return Start(theta0, sign * fac * math.sqrt(rad), phi_dot, omega3 - phi_dot * c)


CASES = {
    # X1: between the turning points, moving down (theta increasing); loops
    "x1_down": (SYM, Start(1.0, 0.3, 0.7, 9.0, phi=0.2, psi=-0.4)),
    # same, moving up
    "x1_up": (SYM, Start(1.0, -0.3, 0.7, 9.0)),
    # released at rest: upper turning point, cusps
    "x1_cusps": (SYM, Start(1.0, 0.0, 0.0, 9.0)),
    # at the lower turning point (theta max), rising from there; waves
    "sym_lower_tp": (SYM, Start(1.2, 0.0, 3.0, 6.0, phi=-1.0, psi=2.0)),
    # at the upper turning point with some precession; waves
    "sym_upper_tp": (SYM, Start(0.7, 0.0, 0.1, 9.0)),
    # axis below the horizontal, moving up
    "sym_below_horizontal": (SYM, Start(2.0, -0.4, 1.0, 7.0)),
    # fast top: waves, loops, cusps
    "gyro_waves": (GYRO, Start(0.6, 0.0, 0.08, 20.0, phi=1.0)),
    "gyro_loops": (GYRO, Start(0.6, -0.4, -1.0, 20.0)),
    "gyro_cusps": (GYRO, Start(0.6, 0.0, 0.0, 20.0, psi=0.5)),
    # l < 0: hanging below the pivot
    "hang": (HANG, Start(0.5, 0.8, 1.5, 4.0)),
    # l = 0 and g = 0: free tops
    "free": (FREE, Start(0.8, 0.5, 1.2, 3.0, phi=0.3, psi=0.2)),
    "weightless": (WEIGHTLESS, Start(1.1, -0.7, 0.4, -2.0)),
    # oblate top
    "flat": (FLAT, Start(1.3, 1.0, -0.8, 15.0)),
    # just below the separatrix: long period, modulus close to 1
    "near_separatrix": (SYM, _separatrix_start(SYM, 0.5, 2.0, -1.0, fac=0.999)),
}


def build(p: Params, st: Start):
    top = kreisel.LagrangeTop(p.I1, p.I3, p.m, p.l, g=p.g)
    state = top.state(
        st.theta,
        phi=st.phi,
        psi=st.psi,
        theta_dot=st.theta_dot,
        phi_dot=st.phi_dot,
        psi_dot=st.psi_dot,
    )
    return top, state


@pytest.fixture(scope="module")
def motions(ref):
    """mpmath references, built once per case."""
    cache = {}

    def get(name):
        if name not in cache:
            p, st = CASES[name]
            cache[name] = ref.MpMotion(p, st)
        return cache[name]

    return get


# --------------------------------------------------------------------------------------
# 1. t(u) by quadrature
# --------------------------------------------------------------------------------------

T_OF_U_CASES = [
    "x1_down",
    "x1_up",
    "x1_cusps",
    "sym_lower_tp",
    "sym_below_horizontal",
    "gyro_loops",
    "hang",
    "free",
    "weightless",
    "flat",
    "near_separatrix",
]


@pytest.mark.parametrize("name", T_OF_U_CASES)
def test_time_to_reach_u_matches_quadrature(name, motions):
    p, st = CASES[name]
    mm = motions(name)
    top, state = build(p, st)
    # phases relative to the start: forwards and backwards, within the first half period
    # and several periods away.  u(s) = u1 + (u2 - u1) sin^2 s, and t(s) by quadrature.
    dss = [0.05, 0.37, 1.1, 2.9, 7.3, 20.2, -0.8, -4.1]
    times, us, udots = [], [], []
    with mpmath.workdps(30):
        for ds in dss:
            s = mm.s0 + ds
            times.append(float(mm.time(s)))
            u = mm.u_of_s(s)
            us.append(float(u))
            udots.append(float(mm.udot(s)))
    times = np.array(times)
    assert np.all(np.sign(times) == np.sign(dss))
    traj = top.exact(state, times)
    assert_allclose(np.cos(traj.theta), us, rtol=0, atol=1e-10)
    udot_k = -np.sin(traj.theta) * traj.theta_dot
    assert_allclose(udot_k, udots, rtol=0, atol=1e-9 * max(1.0, np.max(np.abs(udots))))


# --------------------------------------------------------------------------------------
# 2. period, precession and spin advance per nutation period
# --------------------------------------------------------------------------------------

PERIOD_CASES = [
    "x1_down",
    "x1_cusps",
    "sym_lower_tp",
    "sym_upper_tp",
    "sym_below_horizontal",
    "gyro_waves",
    "gyro_loops",
    "hang",
    "free",
    "flat",
    "near_separatrix",
]


@pytest.mark.parametrize("name", PERIOD_CASES)
def test_period_and_advances_match_quadrature(name, motions):
    p, st = CASES[name]
    mm = motions(name)
    period, dphi, dpsi = (float(x) for x in mm.period_advances())
    top, state = build(p, st)

    assert top.nutation_period(state) == pytest.approx(period, rel=1e-10, abs=0)
    mean_rate = dphi / period
    assert top.mean_precession_rate(state) == pytest.approx(
        mean_rate, rel=1e-10, abs=1e-10 * max(abs(float(mm.a)), 1.0)
    )

    k = np.array([0.0, 1.0, 2.0, 5.0, -3.0])
    traj = top.exact(state, k * period)
    assert_allclose(traj.theta, st.theta, rtol=0, atol=1e-10)
    assert_allclose(traj.theta_dot, st.theta_dot, rtol=0, atol=1e-9)
    tol_phi = 1e-10 * max(1.0, abs(dphi))
    tol_psi = 1e-10 * max(1.0, abs(dpsi))
    assert_allclose(traj.phi - st.phi, k * dphi, rtol=0, atol=5 * tol_phi)
    assert_allclose(traj.psi - st.psi, k * dpsi, rtol=0, atol=5 * tol_psi)


# --------------------------------------------------------------------------------------
# 3. against direct integration of the Euler-Lagrange equations, >= 20 periods
# --------------------------------------------------------------------------------------

INTEGRATION_CASES = [
    "x1_down",
    "x1_up",
    "sym_lower_tp",
    "sym_upper_tp",
    "sym_below_horizontal",
    "gyro_waves",
    "gyro_loops",
    "gyro_cusps",
    "hang",
    "free",
    "flat",
]


@pytest.mark.parametrize("name", INTEGRATION_CASES)
def test_matches_euler_lagrange_integration(name, ref, motions):
    p, st = CASES[name]
    period = float(motions(name).period())
    n_periods = 21
    num = ref.integrate_euler_lagrange(p, st, n_periods * period)
    top, state = build(p, st)
    traj = top.exact(state, num.t)
    assert_allclose(traj.t, num.t, rtol=0, atol=0)
    assert_allclose(traj.theta, num.theta, rtol=0, atol=1e-9)
    assert_allclose(traj.phi, num.phi, rtol=0, atol=1e-9)
    assert_allclose(traj.psi, num.psi, rtol=0, atol=1e-9)
    rate_tol = 1e-8 * max(1.0, np.max(np.abs(num.phi_dot)), np.max(np.abs(num.psi_dot)))
    assert_allclose(traj.theta_dot, num.theta_dot, rtol=0, atol=rate_tol)
    assert_allclose(traj.phi_dot, num.phi_dot, rtol=0, atol=rate_tol)
    assert_allclose(traj.psi_dot, num.psi_dot, rtol=0, atol=rate_tol)


# --------------------------------------------------------------------------------------
# 4. conservation along the exact solution
# --------------------------------------------------------------------------------------

CONSERVATION_CASES = [
    "x1_down",
    "sym_lower_tp",
    "gyro_loops",
    "gyro_cusps",
    "hang",
    "free",
    "flat",
    "near_separatrix",
]


@pytest.mark.parametrize("name", CONSERVATION_CASES)
def test_invariants_conserved(name, ref):
    p, st = CASES[name]
    top, state = build(p, st)
    e0, mz0, m30, _ = ref.invariants(p, st.theta, st.theta_dot, st.phi_dot, st.psi_dot)
    rng = np.random.default_rng(7)
    t = rng.uniform(-40.0, 60.0, 1000)
    traj = top.exact(state, t)
    e, mz, m3, e_scale = ref.invariants(p, traj.theta, traj.theta_dot, traj.phi_dot, traj.psi_dot)
    c = np.cos(traj.theta)
    s = np.sin(traj.theta)
    m_scale = np.max(
        np.abs(p.I1 * traj.phi_dot * s * s)
        + np.abs(m3 * c)
        + p.I3 * (np.abs(traj.psi_dot) + np.abs(traj.phi_dot))
    )
    assert np.max(np.abs(e - e0)) <= 1e-12 * np.max(e_scale)
    assert np.max(np.abs(mz - mz0)) <= 1e-12 * m_scale
    assert np.max(np.abs(m3 - m30)) <= 1e-12 * m_scale


# --------------------------------------------------------------------------------------
# 5. derivative consistency
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["x1_down", "sym_lower_tp", "gyro_loops", "hang", "free"])
def test_rates_are_derivatives_of_angles(name):
    p, st = CASES[name]
    top, state = build(p, st)
    t0 = np.linspace(-3.0, 7.0, 37)
    h = 1e-3
    offsets = np.array([-2.0, -1.0, 1.0, 2.0]) * h
    t = np.concatenate([t0, (t0[:, None] + offsets[None, :]).ravel()])
    traj = top.exact(state, t)
    n = t0.size

    def check(values, rates):
        centre = values[:n]
        v = values[n:].reshape(n, 4)
        # 4th-order central difference
        deriv = (v[:, 0] - 8 * v[:, 1] + 8 * v[:, 2] - v[:, 3]) / (12 * h)
        scale = max(1.0, np.max(np.abs(rates[:n])))
        assert_allclose(deriv, rates[:n], rtol=0, atol=2e-7 * scale)
        assert np.all(np.isfinite(centre))

    check(traj.theta, traj.theta_dot)
    check(traj.phi, traj.phi_dot)
    check(traj.psi, traj.psi_dot)


# --------------------------------------------------------------------------------------
# 6. degenerate and special motions
# --------------------------------------------------------------------------------------

REGULAR = [
    (SYM, 0.8, 9.0),
    (GYRO, 0.3, 20.0),
    (GYRO, 2.2, 20.0),  # below the horizontal: one retrograde rate
    (HANG, 0.5, 5.0),
    (FLAT, 1.0, -12.0),
]


@pytest.mark.parametrize("which", [0, 1])
@pytest.mark.parametrize(("p", "theta0", "omega3"), REGULAR)
def test_regular_precession_keeps_theta_constant(p, theta0, omega3, which, ref):
    rates = ref.steady_precession_rates(p, theta0, omega3)
    assert len(rates) == 2
    omega = rates[which]
    st = Start(theta0, 0.0, omega, omega3 - omega * math.cos(theta0), phi=0.1, psi=-0.2)
    top, state = build(p, st)
    t = np.linspace(-20.0, 50.0, 701)
    traj = top.exact(state, t)
    assert_allclose(traj.theta, theta0, rtol=0, atol=1e-12)
    assert_allclose(traj.theta_dot, 0.0, rtol=0, atol=1e-12 * max(1.0, abs(omega3)))
    span = np.max(np.abs(t))
    assert_allclose(traj.phi, st.phi + omega * t, rtol=0, atol=1e-11 * (1 + abs(omega) * span))
    assert_allclose(
        traj.psi, st.psi + st.psi_dot * t, rtol=0, atol=1e-11 * (1 + abs(st.psi_dot) * span)
    )
    assert_allclose(traj.phi_dot, omega, rtol=1e-12, atol=1e-14)

    # the period of the limiting small nutations: ds/dt = sqrt(g(u0)) / 2 with the
    # double root u0, g(u0) = -f''(u0) / 2 = a^2 + Omega^2 sin^2 - 2 beta u0.
    a = p.I3 * omega3 / p.I1
    beta = 2 * p.mgl / p.I1
    u0 = math.cos(theta0)
    omega_n = math.sqrt(a * a + omega**2 * (1 - u0 * u0) - 2 * beta * u0)
    assert top.nutation_period(state) == pytest.approx(2 * math.pi / omega_n, rel=1e-9)
    assert top.mean_precession_rate(state) == pytest.approx(omega, rel=1e-12)
    lo, hi = top.turning_points(state)
    assert lo == pytest.approx(theta0, abs=1e-12)
    assert hi == pytest.approx(theta0, abs=1e-12)


@pytest.mark.parametrize(
    ("p", "omega3"),
    [
        (SYM, 6.0),  # above the sleeping threshold sqrt(4 I1 m g l)/I3 = 4
        (SYM, 2.0),  # below: an unstable, but exact, equilibrium
        (GYRO, -15.0),
        (HANG, 3.0),  # l < 0: hanging straight down
    ],
)
def test_sleeping_top_stays_upright(p, omega3, ref):
    st = Start(0.0, 0.0, 0.0, omega3, phi=0.3, psi=0.1)
    top, state = build(p, st)
    t = np.linspace(-10.0, 10.0, 201)
    traj = top.exact(state, t)
    assert np.all(np.abs(traj.theta) <= 1e-12)
    assert np.all(np.abs(traj.theta_dot) <= 1e-12)
    # orientation: a pure rotation about the vertical at omega3
    r = ref.euler_matrix(traj.phi, traj.theta, traj.psi)
    expected = ref.euler_matrix(st.phi + st.psi + omega3 * t, np.zeros_like(t), np.zeros_like(t))
    assert np.max(np.abs(r - expected)) <= 1e-10


@pytest.mark.parametrize("omega3", [0.0, 4.0])
def test_hanging_top_stays_down(omega3, ref):
    p = GYRO
    st = Start(math.pi, 0.0, 0.0, omega3)
    top, state = build(p, st)
    t = np.linspace(-10.0, 10.0, 101)
    traj = top.exact(state, t)
    assert_allclose(traj.theta, math.pi, rtol=0, atol=1e-12)
    r = ref.euler_matrix(traj.phi, traj.theta, traj.psi)
    # spinning about the (downward) figure axis: R(t) = R0 Rz(omega3 t)
    expected = ref.euler_matrix(np.zeros_like(t), np.full_like(t, math.pi), omega3 * t)
    assert np.max(np.abs(r - expected)) <= 1e-10


@pytest.mark.parametrize("sign", [-1.0, 1.0])
def test_separatrix_asymptotic_to_vertical(sign, ref):
    p = SYM
    omega3 = 2.0  # below the sleeping threshold 4
    st = _separatrix_start(p, 0.5, omega3, sign)
    top, state = build(p, st)
    assert math.isinf(top.nutation_period(state))
    assert top.nutation_period(state) > 0

    # closed form: f(u) = beta (1 - u)^2 (u - u1), u1 = a^2/beta - 1, so with
    # w = sqrt(u - u1), k^2 = 1 - u1:  w(t) = k tanh(k sqrt(beta) t / 2 + C).
    a = p.I3 * omega3 / p.I1
    beta = 2 * p.mgl / p.I1
    u1 = a * a / beta - 1
    k = math.sqrt(1 - u1)
    w0 = math.sqrt(math.cos(st.theta) - u1)
    c0 = math.atanh(w0 / k)
    lam = k * math.sqrt(beta) / 2
    # moving up (sign < 0): w increases for ever; moving down: first through w = 0
    c0 = c0 if sign < 0 else -c0
    t_end = (math.atanh(math.sqrt(1 - 1e-8 / k**2)) - abs(c0)) / lam + (
        0 if sign < 0 else 2 * abs(c0) / lam
    )
    num = ref.integrate_euler_lagrange(p, st, t_end, max_step=0.05)
    traj = top.exact(state, num.t)
    w = k * np.tanh(lam * num.t + c0)
    u_closed = u1 + w * w
    assert_allclose(np.cos(num.theta), u_closed, rtol=0, atol=1e-11)  # the reference itself
    assert_allclose(np.cos(traj.theta), u_closed, rtol=0, atol=1e-11)
    assert_allclose(traj.theta, num.theta, rtol=0, atol=1e-8)
    assert_allclose(traj.phi, num.phi, rtol=0, atol=1e-8)
    assert_allclose(traj.psi, num.psi, rtol=0, atol=1e-8)
    # theta -> 0 monotonically at the end
    late = traj.theta[num.t > t_end / 2 + (0 if sign < 0 else abs(c0) / lam)]
    assert np.all(np.diff(late) <= 0)
    assert traj.theta[-1] < 1e-3
    # further on theta stays ~0 while phidot -> M3/(2 I1) and psidot -> M3/I3 - M3/(2 I1)
    # (corrections ~ int (1 - u) dt ~ 1e-8 after t_end)
    m3 = p.I3 * omega3
    far_t = np.array([2.0, 10.0, 40.0]) * t_end
    far = top.exact(state, far_t)
    assert np.all(far.theta < 1e-6)
    phi_far = num.phi[-1] + m3 / (2 * p.I1) * (far_t - t_end)
    psi_far = num.psi[-1] + (m3 / p.I3 - m3 / (2 * p.I1)) * (far_t - t_end)
    assert_allclose(far.phi, phi_far, rtol=0, atol=1e-6)
    assert_allclose(far.psi, psi_far, rtol=0, atol=1e-6)


@pytest.mark.parametrize(("p", "omega3"), [(SYM, 1.0), (SYM, 6.0), (GYRO, 10.0)])
def test_through_vertical_orientation(p, omega3, ref):
    st = Start(0.0, 0.5, 0.0, omega3)
    top, state = build(p, st)
    # the period in u between u1 and 1 (u = 1 is a simple root since Mz = M3 exactly)
    e, _, m3, _ = ref.invariants(p, st.theta, st.theta_dot, st.phi_dot, st.psi_dot)
    a = m3 / p.I1
    beta = 2 * p.mgl / p.I1
    alpha = 2 * (e - m3 * m3 / (2 * p.I3)) / p.I1
    # f(u) = (1 - u) [ -beta u^2 + (alpha - beta + a^2) u + (alpha - a^2) ]
    if beta == 0:
        u1 = -(alpha - a * a) / (alpha + a * a)
    else:
        qb, qc = alpha - beta + a * a, alpha - a * a
        u1 = (qb - math.sqrt(qb * qb + 4 * beta * qc)) / (2 * beta)
    lo, hi = top.turning_points(state)
    assert lo == pytest.approx(0.0, abs=1e-9)
    assert hi == pytest.approx(math.acos(u1), abs=1e-10)
    mm = ref.MpMotion(p, st)  # u oscillates in [u1, 1]: the quadrature still applies
    assert float(mm.u2) == pytest.approx(1.0, abs=1e-25)
    assert float(mm.u1) == pytest.approx(u1, abs=1e-12)
    assert top.nutation_period(state) == pytest.approx(float(mm.period()), rel=1e-10)

    t = np.linspace(0.0, 25.0, 400)[1:]
    traj = top.exact(state, t)
    r_kreisel = ref.euler_matrix(traj.phi, traj.theta, traj.psi)
    r_ref = ref.integrate_rigid_body(p, st, t)
    assert np.max(np.abs(r_kreisel - r_ref)) <= 1e-9
    # and backwards in time (time reversal: reverse all rates)
    back = top.exact(state, -t)
    rev = Start(0.0, -0.5, 0.0, -omega3)
    r_back = ref.euler_matrix(back.phi, back.theta, back.psi)
    assert np.max(np.abs(r_back - ref.integrate_rigid_body(p, rev, t))) <= 1e-9


@pytest.mark.parametrize("name", ["free", "weightless"])
def test_free_top_closed_form(name, ref):
    p, st = CASES[name]
    top, state = build(p, st)
    t = np.linspace(-30.0, 30.0, 601)
    traj = top.exact(state, t)
    r_kreisel = ref.euler_matrix(traj.phi, traj.theta, traj.psi)
    r_closed, l_space, l_norm = ref.free_top_matrices(p, st, t)
    assert np.max(np.abs(r_kreisel - r_closed)) <= 1e-10
    # the figure axis keeps a constant angle to L and precesses about it at |L|/I1
    axis = r_kreisel[:, :, 2]
    l_hat = l_space / l_norm
    assert_allclose(axis @ l_hat, axis[len(t) // 2] @ l_hat, rtol=0, atol=1e-12)
    perp = axis - np.outer(axis @ l_hat, l_hat)
    ref_vec = perp[len(t) // 2]
    ang = np.arctan2(np.cross(ref_vec, perp) @ l_hat, perp @ ref_vec)
    ang = np.unwrap(ang)
    rate = np.polyfit(t, ang, 1)[0]
    assert rate == pytest.approx(l_norm / p.I1, rel=1e-10)


# --------------------------------------------------------------------------------------
# 7. evaluation order, negative times, t = 0
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["x1_down", "gyro_cusps", "hang", "free", "sym_lower_tp"])
def test_order_independence_and_negative_times(name):
    p, st = CASES[name]
    top, state = build(p, st)
    t_sorted = np.linspace(-17.0, 23.0, 401)
    perm = np.random.default_rng(3).permutation(t_sorted.size)
    t_shuffled = t_sorted[perm]
    a = top.exact(state, t_sorted)
    b = top.exact(state, t_shuffled)
    assert_allclose(b.t, t_shuffled, rtol=0, atol=0)
    for field in ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot"):
        assert_allclose(getattr(b, field), getattr(a, field)[perm], rtol=0, atol=1e-12)
    # one time at a time gives the same
    for i in (0, 150, 200, 400):
        single = top.exact(state, t_sorted[i : i + 1])
        assert single.theta[0] == pytest.approx(a.theta[i], abs=1e-12)
        assert single.phi[0] == pytest.approx(a.phi[i], abs=1e-12)
    # continuity of the unwrapped angles across the sorted grid (dt = 0.1)
    assert np.max(np.abs(np.diff(a.phi))) < 0.1 * np.max(np.abs(a.phi_dot)) + 1e-9
    assert np.max(np.abs(np.diff(a.psi))) < 0.1 * np.max(np.abs(a.psi_dot)) + 1e-9

    # time reversal: the motion at -t is the motion at +t of the state with all rates reversed
    rev = Start(st.theta, -st.theta_dot, -st.phi_dot, -st.psi_dot, phi=st.phi, psi=st.psi)
    top_r, state_r = build(p, rev)
    t_pos = t_sorted[t_sorted > 0]
    fwd_rev = top_r.exact(state_r, t_pos)
    bwd = top.exact(state, -t_pos)
    assert_allclose(bwd.theta, fwd_rev.theta, rtol=0, atol=1e-10)
    assert_allclose(bwd.phi, fwd_rev.phi, rtol=0, atol=1e-9)
    assert_allclose(bwd.psi, fwd_rev.psi, rtol=0, atol=1e-9)
    assert_allclose(bwd.theta_dot, -fwd_rev.theta_dot, rtol=0, atol=1e-9)


@pytest.mark.parametrize("name", sorted(CASES))
def test_exact_at_zero_reproduces_state(name):
    p, st = CASES[name]
    top, state = build(p, st)
    traj = top.exact(state, np.array([0.0]))
    assert traj.theta[0] == pytest.approx(st.theta, abs=1e-12)
    assert traj.phi[0] == pytest.approx(st.phi, abs=1e-12)
    assert traj.psi[0] == pytest.approx(st.psi, abs=1e-12)
    scale = 1e-11 * max(1.0, abs(st.phi_dot), abs(st.psi_dot), abs(st.theta_dot))
    assert traj.theta_dot[0] == pytest.approx(st.theta_dot, abs=scale)
    assert traj.phi_dot[0] == pytest.approx(st.phi_dot, abs=scale)
    assert traj.psi_dot[0] == pytest.approx(st.psi_dot, abs=scale)
    # the state object itself is frozen and holds what was given
    assert state.theta == st.theta
    assert state.psi_dot == st.psi_dot
    with pytest.raises((AttributeError, TypeError)):
        state.theta = 0.3
