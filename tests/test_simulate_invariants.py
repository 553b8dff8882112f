"""Long-time behaviour of kreisel.simulate: integrals of the motion, agreement with the
exact Lagrange solution, and Lyapunov exponents.

Every integral is recomputed here from the trajectory's quaternion and body angular
velocity with the plain-numpy formulas of ``_sim_reference`` (and compared with kreisel's
own columns). The reference formulas themselves are checked first against two independent
scipy integrations.
"""

from __future__ import annotations

import math

import _sim_reference as ref
import numpy as np
import pytest
from numpy.testing import assert_allclose

import kreisel

# Lagrange top of the order tests: nutation period 2.41 s
LAG = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.3, "g": 1.0}
LAG_START = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 5.0}
LAG_BODY = ref.Body(LAG["I1"], LAG["I1"], LAG["I3"], LAG["m"], (0.0, 0.0, LAG["l"]), LAG["g"])

EULER_BODY = ref.Body(1.0, 1.6, 2.1, 1.0, (0.0, 0.0, 0.0), 9.81)
EULER_START = (ref.euler_to_quat(0.4, 0.7, -1.1), np.array([1.0, 0.5, 2.0]))

KOV_BODY = ref.Body(2.0, 2.0, 1.0, 1.0, (0.3, 0.0, 0.0), 9.81)
KOV_START = (ref.euler_to_quat(0.1, 0.9, 0.5), np.array([1.0, -2.0, 4.0]))

# a generic asymmetric heavy top in a chaotic motion (largest Lyapunov exponent ~0.46 /s
# from the scipy reference integration with the same renormalisation)
CHAOS_BODY = ref.Body(1.0, 0.75, 0.5, 1.0, (0.3, 0.2, 0.4), 9.81)
CHAOS_START = (ref.euler_to_quat(0.0, 1.2, 0.3), np.array([2.0, 1.0, 3.0]))


def heavy_top(body: ref.Body):
    return kreisel.HeavyTop(body.I1, body.I2, body.I3, body.m, body.com, body.g)


def integrals(body: ref.Body, traj):
    """(E, Mz, M3) recomputed from the trajectory's quaternion and omega."""
    gam = ref.gamma_of(traj.quaternion)
    w = traj.omega
    return ref.energy(body, w, gam), ref.vertical_momentum(body, w, gam), body.I3 * w[:, 2]


def tenth_max(err):
    """Largest |err| in the first and in the last tenth of the samples."""
    n = len(err) // 10
    return float(np.abs(err[:n]).max()), float(np.abs(err[-n:]).max())


# --------------------------------------------------------------------------------------
# the references agree with each other
# --------------------------------------------------------------------------------------


def test_reference_formulations_agree():
    """(q, omega) and Euler-Poisson (M, Gamma) integrations of the same general heavy top."""
    t = np.linspace(0.0, 10.0, 101)
    q0, w0 = CHAOS_START
    body = ref.Body(1.0, 0.8, 0.6, 1.0, (0.2, -0.1, 0.3), 9.81)
    q, w = ref.integrate_quaternion(body, q0, w0, t)
    big_m, gam = ref.integrate_poisson(body, body.inertia * w0, ref.gamma_of(q0), t)
    assert_allclose(body.inertia * w, big_m, rtol=0, atol=1e-9)
    assert_allclose(ref.gamma_of(q), gam, rtol=0, atol=1e-9)


def test_reference_kovalevskaya_integral():
    """The K of _sim_reference (nu = m g x0 / I3, Gamma upward) is conserved by a tight scipy
    integration; with the opposite sign of nu it is not."""
    t = np.linspace(0.0, 20.0, 401)
    q, w = ref.integrate_quaternion(KOV_BODY, *KOV_START, t)
    gam = ref.gamma_of(q)
    k = ref.kovalevskaya(KOV_BODY, w, gam)
    assert np.ptp(k) < 1e-10 * k[0]
    flipped = ref.Body(2.0, 2.0, 1.0, 1.0, (-0.3, 0.0, 0.0), 9.81)
    assert np.ptp(ref.kovalevskaya(flipped, w, gam)) > 0.1 * k[0]


def test_reference_matches_exact_lagrange():
    top = kreisel.LagrangeTop(**LAG)
    st = top.state(**LAG_START)
    t = np.linspace(0.0, 10.0, 201)
    q0 = ref.euler_to_quat(0.0, LAG_START["theta"], 0.0)
    w0 = ref.body_omega(LAG_START["theta"], 0.0, *list(LAG_START.values())[1:])
    q, _ = ref.integrate_quaternion(LAG_BODY, q0, w0, t)
    ex = top.exact(st, t)
    err = np.abs(ref.quat_to_matrix(q) - ref.euler_matrix(ex.phi, ex.theta, ex.psi)).max()
    assert err < 1e-10


# --------------------------------------------------------------------------------------
# 10^6 steps: symplectic splitting against rk4 and dop853
# --------------------------------------------------------------------------------------

DT = 1.0 / 1024  # exact in binary: the output times are grid points
N_STEPS = 10**6
T_LONG = N_STEPS * DT  # 976.5625 s, ~405 nutation periods
T_EVAL = np.arange(0, N_STEPS // 100 + 1) * (100 * DT)


@pytest.fixture(scope="module")
def long_runs():
    top = kreisel.LagrangeTop(**LAG)
    st = top.state(**LAG_START)
    e0, mz0, m30 = ref.lagrange_invariants(
        LAG["I1"], LAG["I3"], LAG["m"] * LAG["g"] * LAG["l"], *LAG_START.values()
    )
    out = {}
    for method, dt in (("splitting", DT), ("rk4", DT), ("dop853", None)):
        traj = kreisel.simulate(top, st, T_LONG, method=method, dt=dt, t_eval=T_EVAL)
        assert np.array_equal(traj.t, T_EVAL)
        e, mz, m3 = integrals(LAG_BODY, traj)
        # kreisel's columns say the same
        assert_allclose(traj.energy, e, rtol=0, atol=1e-13 * abs(e0))
        assert_allclose(traj.Mz, mz, rtol=0, atol=1e-13 * abs(mz0))
        assert_allclose(traj.M3, m3, rtol=0, atol=1e-14 * abs(m30))
        out[method] = {
            "energy": (e - e0) / abs(e0),
            "Mz": (mz - mz0) / abs(mz0),
            "M3": (m3 - m30) / abs(m30),
        }
    return out


def test_splitting_keeps_momenta(long_runs):
    err = long_runs["splitting"]
    assert np.abs(err["Mz"]).max() < 1e-13
    assert np.abs(err["M3"]).max() < 1e-13


def test_splitting_energy_bounded(long_runs):
    err = long_runs["splitting"]["energy"]
    first, last = tenth_max(err)
    assert 1e-12 < first < 1e-3  # a genuine O(dt^2) error, not round-off
    assert last < 1.5 * first, (first, last)
    # no linear trend: the mean error hardly moves
    n = len(err) // 10
    assert abs(err[-n:].mean() - err[:n].mean()) < 0.1 * first


@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_non_symplectic_methods_drift(long_runs, method):
    """For contrast: rk4 at the same step and dop853 at its default tolerance let Mz and the
    energy drift, and the drift grows with time."""
    err = long_runs[method]
    split = long_runs["splitting"]
    for name in ("Mz", "energy"):
        first, last = tenth_max(err[name])
        assert last > 3.0 * first, (method, name, first, last)
    assert np.abs(err["Mz"]).max() > 100 * max(np.abs(split["Mz"]).max(), 1e-16)
    e_first, e_last = tenth_max(err["energy"])
    s_first, s_last = tenth_max(split["energy"])
    # relative to its own start the drift is large, unlike the splitting's bounded error
    assert e_last / e_first > 3.0 * s_last / s_first


# --------------------------------------------------------------------------------------
# symplectic methods on asymmetric and Kovalevskaya tops
# --------------------------------------------------------------------------------------

TOPS = {
    "euler": (EULER_BODY, EULER_START),
    "kovalevskaya": (KOV_BODY, KOV_START),
    "chaotic": (CHAOS_BODY, CHAOS_START),
}


@pytest.mark.parametrize("method", ["splitting", "splitting4", "splitting6"])
@pytest.mark.parametrize("which", sorted(TOPS))
def test_splittings_keep_mz_of_every_top(which, method):
    """Free-body flows keep the space angular momentum, gravity kicks change M only
    perpendicular to the vertical: Mz is kept to round-off by every splitting, for any top
    (10^5 steps); for the Euler top the whole space vector R M is kept."""
    body, start = TOPS[which]
    top = heavy_top(body)
    dt = 1.0 / 256
    t = np.linspace(0.0, 10**5 * dt, 1001)
    st = top.state_from_quaternion(*start)
    traj = kreisel.simulate(top, st, t[-1], method=method, dt=dt, t_eval=t)
    scale = np.linalg.norm(body.inertia * start[1])
    _, mz, _ = integrals(body, traj)
    assert np.abs(mz - mz[0]).max() < 1e-13 * scale
    if which == "euler":
        big_l = ref.space_momentum(body, traj.quaternion, traj.omega)
        assert np.abs(big_l - big_l[0]).max() < 1e-12 * scale


@pytest.mark.parametrize("method", ["splitting", "splitting4", "splitting6", "midpoint", "gauss4"])
def test_symplectic_energy_bounded_kovalevskaya(method):
    """On the (integrable) Kovalevskaya top the energy error of every symplectic method stays
    bounded over 1562.5 s (4 10^5 steps): the second half is no worse than the first. (The
    error of midpoint and gauss4 is modulated with a period of ~600 s, hence halves.)
    splitting6 takes a longer step, so that its truncation error (not round-off, which drifts
    by ~2e-17 per step) is what is measured."""
    top = heavy_top(KOV_BODY)
    dt = 1.0 / 32 if method == "splitting6" else 1.0 / 256
    t = np.linspace(0.0, 1562.5, 4001)
    st = top.state_from_quaternion(*KOV_START)
    traj = kreisel.simulate(top, st, t[-1], method=method, dt=dt, t_eval=t)
    e, _, _ = integrals(KOV_BODY, traj)
    err = np.abs(e - e[0]) / abs(e[0])
    half = len(err) // 2
    first, second = err[:half].max(), err[half:].max()
    assert 1e-14 < first < 1e-2
    assert second < 1.5 * first, (first, second)


# --------------------------------------------------------------------------------------
# dop853 against the exact solution over 100 nutation periods
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("tolerances", "bound"),
    [
        # scipy's DOP853 on the same equations: at rtol 1e-10, atol 1e-12 the figure axis is
        # off by 2.5e-8, the rotation by 3.3e-8, psi by 5.9e-8 after 100 periods (so 1e-9 is
        # out of reach at the default tolerances); at 1e-12, 1e-14 axis and rotation by 2e-10
        ({}, 2e-7),
        ({"rtol": 1e-12, "atol": 1e-14}, 1e-9),
    ],
)
def test_dop853_matches_exact_over_100_periods(tolerances, bound):
    top = kreisel.LagrangeTop(**LAG)
    st = top.state(**LAG_START)
    period = top.nutation_period(st)
    t = np.linspace(0.0, 100 * period, 5001)
    traj = kreisel.simulate(top, st, t[-1], t_eval=t, **tolerances)
    ex = top.exact(st, t)
    e3 = ref.quat_to_matrix(traj.quaternion)[:, :, 2]
    axis_err = np.abs(e3 - ref.figure_axis(ex.theta, ex.phi)).max()
    psi_err = np.abs(traj.psi - ex.psi).max()
    assert axis_err < bound, axis_err
    assert psi_err < bound, psi_err
    assert np.abs(traj.theta - ex.theta).max() < bound
    assert np.abs(traj.phi - ex.phi).max() < bound


# --------------------------------------------------------------------------------------
# Euler and Kovalevskaya tops
# --------------------------------------------------------------------------------------


def test_euler_top_keeps_space_momentum_and_energy():
    top = heavy_top(EULER_BODY)
    assert top.kind == "euler"
    st = top.state_from_quaternion(*EULER_START)
    traj = kreisel.simulate(top, st, 100.0, t_eval=np.linspace(0.0, 100.0, 2001))
    big_l = ref.space_momentum(EULER_BODY, traj.quaternion, traj.omega)
    l0 = np.linalg.norm(big_l[0])
    assert np.abs(big_l - big_l[0]).max() < 1e-9 * l0
    body_norm = np.linalg.norm(EULER_BODY.inertia * traj.omega, axis=1)
    assert np.abs(body_norm - l0).max() < 1e-9 * l0
    e, mz, _ = integrals(EULER_BODY, traj)
    assert np.abs(e - e[0]).max() < 1e-9 * abs(e[0])
    assert_allclose(traj.energy, e, rtol=1e-13)
    # the motion is not trivial: omega moves a lot in the body
    assert np.ptp(traj.omega[:, 0]) > 1.0


def test_kovalevskaya_integral_is_kept():
    top = heavy_top(KOV_BODY)
    assert top.kind == "kovalevskaya"
    st = top.state_from_quaternion(*KOV_START)
    traj = kreisel.simulate(top, st, 100.0, t_eval=np.linspace(0.0, 100.0, 2001))
    gam = ref.gamma_of(traj.quaternion)
    k = ref.kovalevskaya(KOV_BODY, traj.omega, gam)
    assert np.abs(k - k[0]).max() < 1e-8 * k[0]
    assert_allclose(traj.kovalevskaya, k, rtol=1e-12)
    e, mz, _ = integrals(KOV_BODY, traj)
    assert np.abs(e - e[0]).max() < 1e-8 * abs(e[0])
    assert np.abs(mz - mz[0]).max() < 1e-8 * np.abs(KOV_BODY.inertia * traj.omega).max()


# --------------------------------------------------------------------------------------
# Lyapunov exponents
# --------------------------------------------------------------------------------------

TAU = 1.0  # renormalisation interval (s)
D0 = 1e-9  # initial separation


def kreisel_stepper(top):
    def step(q, w, tau):
        traj = kreisel.simulate(top, top.state_from_quaternion(q, w), tau, t_eval=[tau])
        return traj.quaternion[-1], traj.omega[-1]

    return step


DIRECTIONS = ([1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.3, -1.0, 0.5])


def test_early_separation_is_exponential():
    """Two starts 1e-9 apart: log(distance) grows linearly at first."""
    top = heavy_top(CHAOS_BODY)
    q0, w0 = CHAOS_START
    qp, wp = ref.perturb(q0, w0, D0 * np.array(DIRECTIONS[1]) / np.linalg.norm(DIRECTIONS[1]))
    t = np.linspace(0.0, 40.0, 401)
    a = kreisel.simulate(top, top.state_from_quaternion(q0, w0), t[-1], t_eval=t)
    b = kreisel.simulate(top, top.state_from_quaternion(qp, wp), t[-1], t_eval=t)
    dist = np.linalg.norm(ref.difference(a.quaternion, a.omega, b.quaternion, b.omega), axis=1)
    assert dist[0] == pytest.approx(D0, rel=1e-3)
    # grows by more than five decades within 40 s
    assert dist[-1] > 1e-4
    window = (t >= 5.0) & (dist < 1e-4)
    slope = np.polyfit(t[window], np.log(dist[window]), 1)[0]
    assert 0.2 < slope < 1.0, slope


def test_lyapunov_exponent_chaotic_top():
    top = heavy_top(CHAOS_BODY)
    assert top.kind == "general"
    step = kreisel_stepper(top)
    lam = [ref.lyapunov_renormalised(step, *CHAOS_START, d, D0, TAU, 300)[-1] for d in DIRECTIONS]
    assert min(lam) > 0.2, lam  # clearly positive (scipy reference: ~0.46 /s)
    assert abs(lam[0] - lam[1]) < 0.3 * 0.5 * (lam[0] + lam[1]), lam


def test_lyapunov_exponent_lagrange_top_vanishes():
    top = kreisel.LagrangeTop(**LAG)
    q0 = ref.euler_to_quat(0.0, LAG_START["theta"], 0.0)
    w0 = ref.body_omega(LAG_START["theta"], 0.0, *list(LAG_START.values())[1:])
    step = kreisel_stepper(top)
    for d in DIRECTIONS:
        est = ref.lyapunov_renormalised(step, q0, w0, d, D0, TAU, 300)
        # integrable: the separation grows only linearly, so the estimate decays ~ log(t)/t
        assert est[-1] < 0.04, est[-1]
        assert est[-1] < 0.7 * est[99], (est[99], est[-1])
        assert math.isfinite(est[-1])
