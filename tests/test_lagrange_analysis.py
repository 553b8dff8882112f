"""Steady precession, small nutations, the sleeping top, the effective potential, the
classification of the motion and parameter validation of kreisel.LagrangeTop, each
against an independent computation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import Params, Start
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

import kreisel

SYM = Params(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0)
GYRO = Params(I1=2.0, I3=1.5, m=0.8, l=0.6, g=9.81)
HANG = Params(I1=1.2, I3=0.9, m=1.0, l=-0.4, g=9.81)
FREE = Params(I1=1.0, I3=1.6, m=2.0, l=0.0, g=9.81)
WEIGHTLESS = Params(I1=1.0, I3=0.7, m=1.0, l=0.5, g=0.0)
FLAT = Params(I1=0.5, I3=0.9, m=1.0, l=0.3, g=9.81)


def make_top(p: Params):
    return kreisel.LagrangeTop(p.I1, p.I3, p.m, p.l, g=p.g)


def make_state(top, st: Start):
    return top.state(
        st.theta,
        phi=st.phi,
        psi=st.psi,
        theta_dot=st.theta_dot,
        phi_dot=st.phi_dot,
        psi_dot=st.psi_dot,
    )


# --------------------------------------------------------------------------------------
# 1. steady precession
# --------------------------------------------------------------------------------------

STEADY = [
    (SYM, 0.8, 9.0),
    (SYM, 0.2, 4.5),
    (GYRO, 0.3, 20.0),
    (GYRO, 2.2, 20.0),  # below the horizontal: one retrograde, one prograde rate
    (GYRO, 1.2, -8.0),  # negative spin: both rates negative
    (HANG, 0.5, 5.0),  # l < 0
    (FLAT, 1.0, -12.0),
    (SYM, 2.5, 0.0),  # below the horizontal even without spin
]


@pytest.mark.parametrize(("p", "theta0", "omega3"), STEADY)
def test_steady_precession_rates(p, theta0, omega3, ref):
    # m g l = W (I3 omega3 - I1 W cos theta0)  <=>  I1 cos W^2 - I3 omega3 W + m g l = 0
    qa, qb, qc = p.I1 * math.cos(theta0), -p.I3 * omega3, p.mgl
    disc = qb * qb - 4 * qa * qc
    assert disc > 0
    expected = sorted([(-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa)])
    assert_allclose(ref.steady_precession_rates(p, theta0, omega3), expected, rtol=1e-12)

    rates = make_top(p).steady_precession(theta0, omega3)
    assert isinstance(rates, tuple)
    assert len(rates) == 2
    slow, fast = rates
    assert slow < fast
    scale = max(abs(x) for x in expected)
    assert_allclose(rates, expected, rtol=1e-12, atol=1e-13 * scale)
    for w in rates:
        residual = p.mgl - w * (p.I3 * omega3 - p.I1 * w * math.cos(theta0))
        assert abs(residual) <= 1e-12 * (abs(p.mgl) + abs(w * p.I3 * omega3) + p.I1 * w * w)


@pytest.mark.parametrize(("p", "theta0", "omega3"), [(SYM, 0.8, 1.0), (GYRO, 0.3, 2.0)])
def test_steady_precession_none_when_discriminant_negative(p, theta0, omega3):
    assert (p.I3 * omega3) ** 2 - 4 * p.I1 * math.cos(theta0) * p.mgl < 0
    assert make_top(p).steady_precession(theta0, omega3) == ()


@pytest.mark.parametrize(("p", "theta0", "omega3"), [(SYM, 0.8, 9.0), (GYRO, 2.2, 20.0)])
def test_steady_precession_state_is_steady(p, theta0, omega3):
    top = make_top(p)
    for w in top.steady_precession(theta0, omega3):
        st = Start(theta0, 0.0, w, omega3 - w * math.cos(theta0))
        state = make_state(top, st)
        assert top.motion_kind(state) == "regular_precession"
        traj = top.exact(state, np.linspace(0.0, 30.0, 61))
        assert_allclose(traj.theta, theta0, rtol=0, atol=1e-12)


# --------------------------------------------------------------------------------------
# 2. small nutations about the steady precession
# --------------------------------------------------------------------------------------


def measured_nutation_frequency(p: Params, theta0, omega3, rate, eps=1e-5, periods=30):
    """Perturb the steady precession by thetadot = eps (same Mz, M3) and time the nutation
    with our own integration of the Euler-Lagrange equations.  Instead of the zero crossings
    of theta - mean we time the successive maxima of theta (downward zeros of p_theta,
    located by the event finder): same period, no need to estimate the mean first."""
    m3 = p.I3 * omega3
    mz = p.I1 * rate * math.sin(theta0) ** 2 + m3 * math.cos(theta0)

    def rhs(_t, y):
        s, c = math.sin(y[0]), math.cos(y[0])
        phd = (mz - m3 * c) / (p.I1 * s * s)
        return [y[1] / p.I1, p.I1 * phd * phd * s * c - m3 * phd * s + p.mgl * s]

    def maximum(_t, y):
        return y[1]

    maximum.direction = -1
    # a crude upper bound on the period, only to choose the integration span
    guess = 2 * math.pi / max(abs(m3) / p.I1, 1e-3)
    t_span = (0.0, 4 * periods * guess)
    sol = solve_ivp(
        rhs,
        t_span,
        [theta0, p.I1 * eps],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        events=maximum,
    )
    te = sol.t_events[0]
    assert te.size >= 10
    # also confirm it was a small oscillation about theta0
    assert np.max(np.abs(sol.y[0] - theta0)) < 1e-3
    return 2 * math.pi * (te.size - 1) / (te[-1] - te[0])


@pytest.mark.parametrize(
    ("p", "theta0", "omega3"),
    [(SYM, 0.8, 9.0), (GYRO, 0.3, 20.0), (GYRO, 2.2, 20.0), (HANG, 0.5, 5.0), (SYM, 2.5, 3.0)],
)
def test_nutation_frequency(p, theta0, omega3, ref):
    top = make_top(p)
    rates = ref.steady_precession_rates(p, theta0, omega3)
    assert len(rates) == 2
    for w in rates:
        measured = measured_nutation_frequency(p, theta0, omega3, w)
        got = top.nutation_frequency(theta0, omega3, w)
        assert got == pytest.approx(measured, rel=1e-3)
        # closed form from the double root u0 of f: omega_n^2 = -f''(u0)/2
        a, beta, u0 = p.I3 * omega3 / p.I1, 2 * p.mgl / p.I1, math.cos(theta0)
        closed = math.sqrt(a * a + w * w * (1 - u0 * u0) - 2 * beta * u0)
        assert measured == pytest.approx(closed, rel=1e-6)
        assert got == pytest.approx(closed, rel=1e-9)


# --------------------------------------------------------------------------------------
# 3. sleeping top
# --------------------------------------------------------------------------------------


def curvature_at_vertical(values, h):
    """V(theta) = A + B theta^2 + C theta^4 through theta = h, 2h, 3h; returns V''(0) = 2 B."""
    mat = np.array([[1.0, (k * h) ** 2, (k * h) ** 4] for k in (1, 2, 3)])
    return 2 * np.linalg.solve(mat, values)[1]


@pytest.mark.parametrize("p", [SYM, GYRO, FLAT])
def test_sleeping_threshold(p, ref):
    top = make_top(p)
    threshold = math.sqrt(4 * p.I1 * p.mgl) / p.I3
    assert top.sleeping_threshold() == pytest.approx(threshold, rel=1e-12)
    h = 0.02
    thetas = np.array([h, 2 * h, 3 * h])
    for fac, sign in ((1.01, 1.0), (0.99, -1.0)):
        m3 = p.I3 * fac * threshold
        v = top.effective_potential(thetas, m3, m3)
        curv = curvature_at_vertical(np.asarray(v, dtype=float), h)
        curv_own = curvature_at_vertical(ref.veff(p, thetas, m3, m3), h)
        analytic = -p.mgl + m3 * m3 / (4 * p.I1)
        assert np.sign(curv) == sign
        assert np.sign(curv_own) == sign
        assert curv == pytest.approx(analytic, rel=1e-3)

    # dynamically: nudge the upright top; it stays close to the vertical only above the
    # threshold.  theta_max from f(u) = (1 - u) [-beta u^2 + (alpha - beta + a^2) u + alpha
    # - a^2] with alpha - beta = thetadot^2.
    for fac, small in ((1.05, True), (0.95, False)):
        omega3 = fac * threshold
        thetadot = 1e-3
        a, beta = p.I3 * omega3 / p.I1, 2 * p.mgl / p.I1
        alpha = beta + thetadot**2
        qb, qc = alpha - beta + a * a, alpha - a * a
        u1 = (qb - math.sqrt(qb * qb + 4 * beta * qc)) / (2 * beta)
        theta_max = math.acos(u1)
        state = make_state(top, Start(0.0, thetadot, 0.0, omega3))
        lo, hi = top.turning_points(state)
        assert lo == pytest.approx(0.0, abs=1e-9)
        assert hi == pytest.approx(theta_max, rel=1e-8)
        assert (hi < 0.05) == small


@pytest.mark.parametrize("p", [HANG, FREE, WEIGHTLESS])
def test_sleeping_threshold_zero_without_upright_torque(p):
    assert make_top(p).sleeping_threshold() == 0.0


# --------------------------------------------------------------------------------------
# 4. effective potential, invariants and turning points
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("p", [SYM, GYRO, HANG, FREE, FLAT])
def test_effective_potential_energy_and_turning_points(p, ref):
    top = make_top(p)
    rng = np.random.default_rng(11)
    for _ in range(6):
        st = Start(
            theta=float(rng.uniform(0.15, math.pi - 0.15)),
            theta_dot=float(rng.uniform(-2, 2)),
            phi_dot=float(rng.uniform(-3, 3)),
            psi_dot=float(rng.uniform(-15, 15)),
            phi=float(rng.uniform(-3, 3)),
            psi=float(rng.uniform(-3, 3)),
        )
        state = make_state(top, st)
        e, mz, m3, scale = ref.invariants(p, st.theta, st.theta_dot, st.phi_dot, st.psi_dot)
        inv = top.invariants(state)
        assert inv.E == pytest.approx(e, rel=1e-13, abs=1e-14 * scale)
        assert inv.Mz == pytest.approx(mz, rel=1e-13, abs=1e-14 * abs(m3))
        assert inv.M3 == pytest.approx(m3, rel=1e-13)

        v0 = top.effective_potential(st.theta, mz, m3)
        assert isinstance(v0, float)
        assert 0.5 * p.I1 * st.theta_dot**2 + v0 == pytest.approx(e, rel=1e-12, abs=1e-13 * scale)

        grid = np.linspace(0.05, math.pi - 0.05, 57)
        vg = top.effective_potential(grid, mz, m3)
        assert isinstance(vg, np.ndarray)
        assert vg.shape == grid.shape
        assert_allclose(vg, ref.veff(p, grid, mz, m3), rtol=1e-13)

        # the turning points: where Veff = E; compare with the roots of f (mpmath)
        lo, hi = top.turning_points(state)
        mm = ref.MpMotion(p, st)
        lo_ref, hi_ref = mm.theta_range()
        assert lo == pytest.approx(lo_ref, abs=1e-10)
        assert hi == pytest.approx(hi_ref, abs=1e-10)
        assert lo <= st.theta <= hi
        v_tp = top.effective_potential(np.array([lo, hi]), mz, m3)
        assert_allclose(v_tp, e, rtol=0, atol=1e-9 * scale)
        # and Veff < E strictly inside
        inside = np.linspace(lo, hi, 9)[1:-1]
        assert np.all(top.effective_potential(inside, mz, m3) < e)


def test_turning_points_at_rest_release():
    """A top released at rest (thetadot = phidot = 0) starts at its highest point."""
    top = make_top(SYM)
    state = make_state(top, Start(1.0, 0.0, 0.0, 9.0))
    lo, hi = top.turning_points(state)
    assert lo == pytest.approx(1.0, abs=1e-13)
    assert hi > 1.0


# --------------------------------------------------------------------------------------
# 5. motion kinds
# --------------------------------------------------------------------------------------


def _separatrix(p: Params, theta0, omega3, sign):
    m3 = p.I3 * omega3
    c = math.cos(theta0)
    phi_dot = m3 / (p.I1 * (1.0 + c))
    rad = 2 * math.sin(theta0 / 2) ** 2 / p.I1 * (2 * p.mgl - m3 * m3 / (p.I1 * (1.0 + c)))
    return Start(theta0, sign * math.sqrt(rad), phi_dot, omega3 - phi_dot * c)


def _steady(p: Params, theta0, omega3, which):
    coeffs = [p.I1 * math.cos(theta0), -p.I3 * omega3, p.mgl]
    w = float(np.sort(np.roots(coeffs).real)[which])
    return Start(theta0, 0.0, w, omega3 - w * math.cos(theta0))


KINDS = [
    ("waves", SYM, Start(0.7, 0.0, 0.1, 9.0)),
    ("waves", SYM, Start(1.2, 0.0, 3.0, 6.0)),
    ("waves", GYRO, Start(0.6, 0.0, 0.08, 20.0)),
    ("waves", GYRO, Start(0.6, 0.05, 0.15, 20.0)),
    ("loops", SYM, Start(1.0, 0.3, 0.7, 9.0)),
    ("loops", GYRO, Start(0.6, 0.0, -0.1, 20.0)),
    ("loops", GYRO, Start(0.6, -0.4, -1.0, 20.0)),
    ("cusps", SYM, Start(1.0, 0.0, 0.0, 9.0)),
    ("cusps", GYRO, Start(0.6, 0.0, 0.0, 20.0)),
    ("cusps", GYRO, Start(2.0, 0.0, 0.0, 5.0)),
    ("regular_precession", SYM, _steady(SYM, 0.8, 9.0, 0)),
    ("regular_precession", SYM, _steady(SYM, 0.8, 9.0, 1)),
    ("regular_precession", HANG, _steady(HANG, 0.5, 5.0, 0)),
    ("sleeping", SYM, Start(0.0, 0.0, 0.0, 6.0)),
    ("sleeping", GYRO, Start(0.0, 0.0, 1.0, 14.0)),
    ("through_vertical", SYM, Start(0.0, 0.5, 0.0, 1.0)),
    ("through_vertical", GYRO, Start(0.0, 0.5, 0.0, 10.0)),
    ("hanging", GYRO, Start(math.pi, 0.0, 0.0, 0.0)),
    ("hanging", SYM, Start(math.pi, 0.0, 0.0, 3.0)),
    ("asymptotic", SYM, _separatrix(SYM, 0.5, 2.0, -1.0)),
    ("asymptotic", SYM, _separatrix(SYM, 0.5, 2.0, 1.0)),
]


@pytest.mark.parametrize(("kind", "p", "st"), KINDS)
def test_motion_kind(kind, p, st, ref):
    if kind in ("waves", "loops"):
        # our own classification: phidot = (b - a u)/(1 - u^2) is linear in u in the
        # numerator, so it keeps its sign iff b - a u has the same sign at both roots.
        mm = ref.MpMotion(p, st)
        at1, at2 = float(mm.b - mm.a * mm.u1), float(mm.b - mm.a * mm.u2)
        margin = 1e-3 * max(abs(at1), abs(at2))
        if kind == "waves":
            assert at1 > margin and at2 > margin
        else:
            assert at1 * at2 < -(margin**2)
    if kind == "sleeping":
        assert abs(st.phi_dot + st.psi_dot) > math.sqrt(4 * p.I1 * p.mgl) / p.I3
    top = make_top(p)
    assert top.motion_kind(make_state(top, st)) == kind


# --------------------------------------------------------------------------------------
# 6. validation
# --------------------------------------------------------------------------------------

GOOD = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.5, "g": 9.81}
NAN, INF = math.nan, math.inf


def test_error_hierarchy():
    assert issubclass(kreisel.ParameterError, kreisel.KreiselError)
    assert issubclass(kreisel.ParameterError, ValueError)
    assert issubclass(kreisel.KreiselError, Exception)


def _value_text(value):
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf"
    return f"{value:g}"


@pytest.mark.parametrize(
    ("name", "value"),
    [(name, value) for name in ("I1", "I3", "m", "l", "g") for value in (NAN, INF, -INF)]
    + [
        ("I1", 0.0),
        ("I1", -1.0),
        ("I3", 0.0),
        ("I3", -0.5),
        ("m", 0.0),
        ("m", -2.0),
        ("g", -9.81),
    ],
)
def test_bad_parameter(name, value):
    kwargs = dict(GOOD)
    kwargs[name] = value
    with pytest.raises(kreisel.ParameterError) as info:
        kreisel.LagrangeTop(**kwargs)
    assert isinstance(info.value, ValueError)
    assert isinstance(info.value, kreisel.KreiselError)
    msg = str(info.value)
    assert name in msg
    assert _value_text(value) in msg.lower()


def test_triangle_inequality():
    with pytest.raises(ValueError) as info:
        kreisel.LagrangeTop(I1=1.0, I3=2.5, m=1.0, l=0.5, g=9.81)
    assert isinstance(info.value, kreisel.ParameterError)
    msg = str(info.value)
    assert "I3" in msg and "I1" in msg
    assert "2.5" in msg


def test_parallel_axis_theorem():
    with pytest.raises(kreisel.ParameterError) as info:
        kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.5, g=9.81)
    assert "I1" in str(info.value)
    with pytest.raises(kreisel.ParameterError):
        kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=-1.5, g=9.81)


def test_boundary_values_accepted():
    kreisel.LagrangeTop(I1=1.0, I3=2.0, m=1.0, l=0.5)  # I3 = 2 I1
    kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=1.0, g=1.0)  # I1 = m l^2
    kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=-1.0, g=1.0)
    kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=0.0)
    kreisel.LagrangeTop(I1=1.0, I3=0.5, m=1.0, l=0.5, g=0.0)
    top = kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.5)  # g defaults to 9.81
    assert top.sleeping_threshold() == pytest.approx(math.sqrt(4 * 0.5 * 9.81) / 0.5, rel=1e-12)
    top.state(0.0)
    top.state(math.pi)


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("theta", -1e-3),
        ("theta", math.pi + 1e-3),
        ("theta", NAN),
        ("theta", INF),
        ("phi", NAN),
        ("phi", INF),
        ("psi", -INF),
        ("theta_dot", NAN),
        ("phi_dot", INF),
        ("psi_dot", NAN),
    ],
)
def test_bad_state(name, value):
    top = kreisel.LagrangeTop(**GOOD)
    kwargs = {"phi": 0.1, "psi": 0.2, "theta_dot": 0.3, "phi_dot": 0.4, "psi_dot": 5.0}
    theta = 0.7
    if name == "theta":
        theta = value
    else:
        kwargs[name] = value
    with pytest.raises(kreisel.ParameterError) as info:
        top.state(theta, **kwargs)
    assert isinstance(info.value, ValueError)
    msg = str(info.value)
    assert name in msg
    if not math.isfinite(value):
        assert _value_text(value) in msg.lower()


@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_bad_times(bad):
    top = kreisel.LagrangeTop(**GOOD)
    state = top.state(0.7, theta_dot=0.3, phi_dot=0.4, psi_dot=5.0)
    with pytest.raises(kreisel.ParameterError) as info:
        top.exact(state, np.array([0.0, 1.0, bad, 2.0]))
    assert isinstance(info.value, ValueError)
    assert "t" in str(info.value)
