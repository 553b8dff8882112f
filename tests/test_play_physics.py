"""Physics of kreisel's play top (theory: play top) against independent references.

Every reference value comes from ``_play_reference.py``, which does not use kreisel: scipy
DOP853 integrations of the Newton-Euler equations with the contact force derived there
(sliding, rolling), closed-form free flight, and mpmath quadrature of the frictionless
reduced equation. The stationary-motion formulas of the theory page are themselves checked
against the rolling integration before they are used.
"""

from __future__ import annotations

import math
import subprocess
import sys

import _play_reference as ref
import mpmath
import numpy as np
import pytest
from scipy.integrate import cumulative_simpson
from scipy.optimize import brentq

import kreisel

# docs/benchmarks.md T1 (tippe top, area (c) of the vertical-axis diagram:
# 1 - alpha < gamma < 1 + alpha)
T1 = ref.tippe_t1()
T1_START = {"theta": math.pi - 0.1, "psi_dot": 150.0}

# A tippe top that turns over under Coulomb friction without leaving the floor (found by a
# scan, see test_coulomb_tippe_top_turns_over_and_ends_rolling_upright): C = 0.2 m rho^2,
# A = 0.9 C, mu = 0.02.
_C02 = 0.2 * 0.02 * 0.02**2
COULOMB_TIPPE = ref.Top(m=0.02, A=0.9 * _C02, C=_C02, s=0.006, rho=0.02)
COULOMB_TIPPE_START = {"theta": 2.8, "psi_dot": 150.0}
COULOMB_TIPPE_MU = 0.02

# The same kind of top laid on its side, Coulomb mu = 0.3: slips, then rolls after 0.16 s.
SIDE_TOP = ref.Top(m=0.02, A=0.8 * _C02, C=_C02, s=0.006, rho=0.02)
SIDE_START = {"theta": math.pi / 2, "psi_dot": 150.0}

# a blunt and a pointed tip on the same top (theory: the play top): friction
# raises the one and lowers the other
BLUNT = ref.Top(m=0.05, A=1.8e-5, C=2e-5, s=0.01, rho=0.04)  # alpha = 0.25
POINTED = ref.Top(m=0.05, A=1.8e-5, C=2e-5, s=0.01, rho=0.0005)  # alpha = 20

# A heavier, ordinary top (G well above the sphere centre) for the frictionless cases.
HEAVY = ref.Top(m=0.1, A=2e-5, C=3e-5, s=0.01, rho=0.03)


def play_top(top: ref.Top, friction, **kw) -> kreisel.PlayTop:
    return kreisel.PlayTop(**top.kwargs(), friction=friction, **kw)


def run(top: ref.Top, friction, start: dict, t_end: float, model_kw=None, **kw):
    pt = play_top(top, friction, **(model_kw or {}))
    return kreisel.simulate(pt, pt.state(**start), t_end, **kw)


def rel_drift(x) -> float:
    x = np.asarray(x)
    return float(np.max(np.abs(x - x[0])) / abs(x[0]))


def space_L(top: ref.Top, traj):
    _, _, _, ls = ref.space_quantities(top, traj.quaternion, traj.omega)
    return ls


def rows_at(traj, t):
    """Indices of the rows recorded at time t (two at a mode switch: before, after)."""
    return np.flatnonzero(traj.t == t)


# --------------------------------------------------------------------------------------
# shared runs
# --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def t1_viscous():
    return run(T1, kreisel.Viscous(mu=1.0), T1_START, 12.0)


@pytest.fixture(scope="module")
def coulomb_tippe():
    return run(COULOMB_TIPPE, kreisel.Coulomb(mu=COULOMB_TIPPE_MU), COULOMB_TIPPE_START, 10.0)


@pytest.fixture(scope="module")
def side_top():
    return run(SIDE_TOP, kreisel.Coulomb(mu=0.3), SIDE_START, 2.0)


@pytest.fixture(scope="module")
def t1_coulomb():
    return run(T1, kreisel.Coulomb(mu=0.3), T1_START, 5.0)


CASE_TOPS = {
    "t1_viscous": T1,
    "coulomb_tippe": COULOMB_TIPPE,
    "side_top": SIDE_TOP,
    "t1_coulomb": T1,
}
CASES = list(CASE_TOPS)


# --------------------------------------------------------------------------------------
# 1. Jellett's integral and the energy balance
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASES)
def test_jellett_integral_is_conserved_in_slip_and_roll(case, request):
    traj = request.getfixturevalue(case)
    modes = set(traj.mode)
    assert "slip" in modes
    if case != "t1_viscous":
        assert "roll" in modes  # Coulomb: the slip stops and the top rolls
    # kreisel's column against J = L.(s e3 + rho ez) from the state columns
    top = CASE_TOPS[case]
    mine = ref.jellett(top, traj.quaternion, traj.omega)
    np.testing.assert_allclose(traj.jellett, mine, rtol=1e-12, atol=0)
    assert rel_drift(traj.jellett) < 1e-9


@pytest.mark.parametrize("case", CASES)
def test_energy_never_increases(case, request):
    traj = request.getfixturevalue(case)
    e = np.asarray(traj.energy)
    rises = np.diff(e) / abs(e[0])
    worst = int(np.argmax(rises))
    # While rolling, E is constant in the model, so between samples it moves only by the
    # integration error (rtol 1e-10): 1e-10 bounds that; a systematic rise (as at a badly
    # made slip-to-roll switch, +4e-11 per switch) still shows up at the switches below.
    assert rises[worst] <= 1e-10, (
        f"E rises by {rises[worst]:.3g} E0 from t = {traj.t[worst]!r} ({traj.mode[worst]}) "
        f"to t = {traj.t[worst + 1]!r} ({traj.mode[worst + 1]})"
    )


@pytest.mark.parametrize("case", CASES)
def test_energy_plus_dissipated_is_the_initial_energy(case, request):
    traj = request.getfixturevalue(case)
    top = CASE_TOPS[case]
    mine = ref.energy(top, traj.quaternion, traj.omega, traj.com_velocity, traj.com[:, 2])
    np.testing.assert_allclose(traj.energy, mine, rtol=1e-12, atol=0)
    np.testing.assert_allclose(
        traj.energy, traj.energy_translation + traj.energy_rotation + traj.energy_potential,
        rtol=1e-13, atol=0,
    )  # fmt: skip
    d = np.asarray(traj.dissipated)
    assert d[0] == 0.0
    assert np.all(np.diff(d) >= 0.0)
    e0 = traj.energy[0]
    assert np.max(np.abs(traj.energy + d - e0)) <= 1e-9 * abs(e0)


def test_no_work_is_dissipated_while_rolling(coulomb_tippe):
    traj = coulomb_tippe
    roll = np.flatnonzero(traj.mode == "roll")
    assert len(roll) > 10
    # No friction work: the dissipated energy moves only by the projection's booking of the
    # integration's drift (the velocity put back on the rolling constraint), within the
    # tolerance (rtol 1e-10) of the energy.
    assert np.ptp(traj.dissipated[roll]) <= 1e-10 * traj.energy[0]
    assert np.max(traj.slip_speed[roll]) < 1e-12
    assert np.ptp(traj.energy[roll]) <= 1e-12 * traj.energy[0]


def jellett_rate_of_torque(top: ref.Top, traj, torque):
    """dJ/dt = M . (s e3 + rho ez) for an extra torque M about G (the contact force at T
    drops out of dJ/dt, theory: play top)."""
    _, e3, _, _ = ref.space_quantities(top, traj.quaternion, traj.omega)
    lever = top.s * e3
    lever[:, 2] += top.rho
    return np.einsum("ni,ni->n", torque, lever)


RESISTANCE_CASES = [
    ("hanging-tippe", T1, T1_START, {"drilling_resistance": 2e-4}),
    ("hanging-tippe", T1, T1_START, {"air_drag": 1e-7}),
    ("upright-blunt", BLUNT, {"theta": 0.3, "psi_dot": 50.0}, {"drilling_resistance": 2e-4}),
    ("upright-blunt", BLUNT, {"theta": 0.3, "psi_dot": 50.0}, {"air_drag": 1e-7}),
    ("upright-blunt", BLUNT, {"theta": 0.3, "psi_dot": 50.0}, {"rolling_resistance": 2e-5}),
]


@pytest.mark.parametrize(
    "top, start, resistance",
    [c[1:] for c in RESISTANCE_CASES],
    ids=[f"{c[0]}-{next(iter(c[3]))}" for c in RESISTANCE_CASES],
)
def test_resistances_consume_jellett_and_are_counted_as_dissipation(top, start, resistance):
    traj = run(top, kreisel.Viscous(mu=1.0), start, 2.0, model_kw=resistance)
    free = run(top, kreisel.Viscous(mu=1.0), start, 2.0)
    j = np.abs(traj.jellett)
    assert j[-1] < (1 - 1e-4) * j[0]
    assert np.abs(free.jellett[-1]) == pytest.approx(j[0], rel=1e-9)
    e0 = traj.energy[0]
    assert np.max(np.diff(traj.energy)) <= 1e-12 * e0
    assert np.max(np.abs(traj.energy + traj.dissipated - e0)) <= 1e-9 * e0


def test_air_drag_changes_jellett_by_its_torque():
    """J(t) - J(0) = integral of (-c omega) . (s e3 + rho ez) dt, by Simpson on a fine grid."""
    c = 1e-7
    t_eval = np.linspace(0.0, 1.0, 20001)
    traj = run(T1, kreisel.Viscous(mu=1.0), T1_START, 1.0, model_kw={"air_drag": c}, t_eval=t_eval)
    _, _, om, _ = ref.space_quantities(T1, traj.quaternion, traj.omega)
    rate = jellett_rate_of_torque(T1, traj, -c * om)
    expected = traj.jellett[0] + cumulative_simpson(rate, x=t_eval, initial=0.0)
    assert np.max(np.abs(traj.jellett - expected)) < 1e-7 * abs(traj.jellett[0])
    assert abs(traj.jellett[-1] - traj.jellett[0]) > 1e-3 * abs(traj.jellett[0])


def test_rolling_resistance_on_a_hanging_top_does_not_stall():
    """T1 with rolling_resistance = 2e-4 m: the resistance stops the horizontal rotation of
    the hanging top after about 1.8 s. A simulation of 2.5 s must end in seconds (it is a
    few thousand steps of work); run in a subprocess so that a stall cannot hang the suite."""
    code = (
        "import math, kreisel;"
        f"pt = kreisel.PlayTop(**{T1.kwargs()!r}, friction=kreisel.Viscous(mu=1.0),"
        " rolling_resistance=2e-4);"
        "tr = kreisel.simulate(pt, pt.state(math.pi - 0.1, psi_dot=150.0), 2.5);"
        "print(len(tr.t))"
    )
    try:
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=15
        )
    except subprocess.TimeoutExpired:
        pytest.fail("kreisel.simulate with rolling_resistance did not finish 2.5 s in 15 s")
    assert out.returncode == 0, out.stderr[-2000:]
    assert int(out.stdout.split()[-1]) < 100_000


# --------------------------------------------------------------------------------------
# 2. regular precession (rolling, G at rest)
# --------------------------------------------------------------------------------------

GYRO = ref.Top(m=0.1, A=3e-5, C=2e-5, s=0.01, rho=0.03)  # gamma = 1.5 > 1 + alpha: area (a)


def precession_start(top: ref.Top, u: float, sign: float = 1.0) -> dict:
    om, _, psidot = top.precession(u)
    return {"theta": math.acos(u), "phi_dot": sign * om, "psi_dot": sign * psidot}


def test_regular_precession_formulas_give_a_rolling_equilibrium():
    """The theory page's Omega, omega3, psidot and J_R(u), checked against the reference's own
    rolling integration: u stays, G stays at rest, the contact force is m g ez."""
    for top, u in [(T1, -0.6), (T1, 0.5), (GYRO, 0.3)]:
        start = precession_start(top, u)
        roll = ref.integrate_roll(top, start, 0.5)
        assert np.max(np.abs(roll.u - u)) < 1e-10
        assert np.max(np.abs(roll.com_velocity)) < 1e-10
        np.testing.assert_allclose(roll.force, [[0, 0, top.m * top.g]] * len(roll.t), atol=1e-10)
        om, w3, _ = top.precession(u)
        q, w, _, _ = ref.initial(top, **start)
        assert w[2] == pytest.approx(w3, rel=1e-14)
        assert abs(ref.jellett(top, q, w)[0]) == pytest.approx(top.J_R(u), rel=1e-13)
        # a wrong rate is not an equilibrium
        off = ref.integrate_roll(top, dict(start, phi_dot=1.01 * start["phi_dot"]), 0.5)
        assert np.max(np.abs(off.u - u)) > 1e-4


@pytest.mark.parametrize(
    "top, u, sign",
    [(T1, -0.6, 1.0), (T1, 0.0, 1.0), (T1, 0.7, 1.0), (T1, 0.4, -1.0), (GYRO, 0.3, 1.0)],
    ids=["T1-u-0.6", "T1-u0", "T1-u0.7", "T1-u0.4-reversed", "gamma1.5-u0.3"],
)
def test_regular_precession_keeps_its_inclination_and_rolls(top, u, sign):
    pt = play_top(top, kreisel.Coulomb(mu=0.3))
    st = pt.state(**precession_start(top, u, sign))
    assert pt.jellett(st) == pytest.approx(sign * top.J_R(u), rel=1e-12)
    traj = kreisel.simulate(pt, st, 3.0)
    assert np.max(np.abs(traj.u - u)) < 1e-6
    assert set(traj.mode) == {"roll"}
    assert traj.events == []
    assert np.max(np.abs(traj.com_velocity)) < 1e-8
    np.testing.assert_allclose(traj.normal_force, top.m * top.g, rtol=1e-8)


# --------------------------------------------------------------------------------------
# 3. turning over, standing up, sinking
# --------------------------------------------------------------------------------------


def test_tippe_top_turns_over_with_viscous_friction(t1_viscous):
    traj = t1_viscous
    assert traj.u[0] == pytest.approx(-math.cos(0.1), rel=1e-15)
    assert traj.u[-1] > 0.99
    assert np.min(traj.u[traj.t > 6.0]) > 0.99
    # docs/benchmarks.md T1: it turns over at 2.5268 s; the reference crosses u = 0 at 2.527 s
    t_cross = traj.t[np.argmax(traj.u > 0.0)]
    assert 2.0 < t_cross < 3.5
    assert "flight" not in set(traj.mode)


def test_tippe_top_under_coulomb_friction_from_rest_rolls_and_stays_hanging(t1_coulomb):
    """The T1 start under Coulomb friction (mu = 0.3): the friction accelerates G until the
    tip stops slipping (after 0.038 s, per the reference); a top that rolls without slip
    keeps its energy and Jellett's integral and cannot rise, so it stays near hanging."""
    t_roll, cols, _ = ref.slide_until(T1, "coulomb", 0.3, T1_START, 1.0, stop="roll")
    assert t_roll is not None and 0.03 < t_roll < 0.05
    switches = [e for e in t1_coulomb.events if e.name == "slip_to_roll"]
    assert switches, t1_coulomb.events
    assert switches[0].t == pytest.approx(t_roll, abs=1e-6)
    assert [e.name for e in t1_coulomb.events] == ["slip_to_roll"]
    after = t1_coulomb.t > switches[0].t
    assert set(t1_coulomb.mode[after]) == {"roll"}
    assert np.max(t1_coulomb.u) < -0.99


def test_coulomb_tippe_top_turns_over_and_ends_rolling_upright(coulomb_tippe):
    """Under Coulomb friction a tippe top must turn over while it still slips: once it rolls
    it keeps its energy. A scan over (C/(m rho^2), gamma, theta0, mu, spin) found that small
    mu and C = 0.2 m rho^2 do it from theta0 = 2.8 without leaving the floor; the slip stops
    only at 8.57 s, when the top is already upright."""
    traj = coulomb_tippe
    t_roll, cols, _ = ref.slide_until(
        COULOMB_TIPPE, "coulomb", COULOMB_TIPPE_MU, COULOMB_TIPPE_START, 10.0, stop="roll"
    )
    assert t_roll is not None
    events = [e.name for e in traj.events]
    assert events == ["slip_to_roll"]
    assert traj.events[0].t == pytest.approx(t_roll, abs=1e-5)
    # the sliding phase against the reference
    t_eval = np.linspace(0.0, t_roll - 1e-3, 200)
    mine = ref.integrate_slide(
        COULOMB_TIPPE, "coulomb", COULOMB_TIPPE_MU, COULOMB_TIPPE_START, t_eval[-1], t_eval=t_eval
    )
    kt = run(
        COULOMB_TIPPE, kreisel.Coulomb(mu=COULOMB_TIPPE_MU), COULOMB_TIPPE_START, t_eval[-1],
        t_eval=t_eval,
    )  # fmt: skip
    assert set(kt.mode) == {"slip"}
    assert np.max(np.abs(kt.u - mine.u)) < 1e-6
    i = rows_at(traj, traj.events[0].t)[-1]
    assert traj.u[i] == pytest.approx(cols.u[-1], abs=1e-6)
    assert traj.u[-1] > 0.99
    after = traj.t > traj.events[0].t
    assert np.min(traj.u[after]) > 0.99
    assert set(traj.mode[after]) == {"roll"}


def test_slip_to_roll_is_located_without_chattering_at_loose_tolerance():
    """The slip stops at the same instant whatever the tolerance (reference: 0.15635 s)."""
    t_roll, _, _ = ref.slide_until(SIDE_TOP, "coulomb", 0.3, SIDE_START, 1.0, stop="roll")
    for rtol, atol in [(1e-10, 1e-12), (1e-8, 1e-11)]:
        traj = run(SIDE_TOP, kreisel.Coulomb(mu=0.3), SIDE_START, 0.5, rtol=rtol, atol=atol)
        switch = [e.t for e in traj.events if e.name == "slip_to_roll"]
        assert switch and switch[0] == pytest.approx(t_roll, abs=1e-5), (rtol, switch, t_roll)
        assert len(traj.t) < 5000, (rtol, len(traj.t))


def upright_J_ratio(top: ref.Top, start: dict) -> float:
    """|J| / J_R(1) of a start (the theory page: upright spin stable iff gamma < 1 + alpha and
    |J| > J_R(1), J_R(1) = J_beta (1 + alpha)^2 / sqrt(1 + alpha - gamma))."""
    q, w, _, _ = ref.initial(top, **start)
    j = abs(ref.jellett(top, q, w)[0])
    return j / (top.J_beta * (1 + top.alpha) ** 2 / math.sqrt(1 + top.alpha - top.gamma))


TILTED = {"theta": 0.3, "psi_dot": 50.0}


def test_blunt_tip_stands_up():
    assert BLUNT.gamma < 1 + BLUNT.alpha and upright_J_ratio(BLUNT, TILTED) > 1.2
    traj = run(BLUNT, kreisel.Viscous(mu=0.5), TILTED, 10.0)
    assert traj.u[-1] > 0.999
    assert np.min(traj.u[traj.t > 9.0]) > 0.999


def test_pointed_tip_sinks():
    assert POINTED.gamma < 1 + POINTED.alpha and upright_J_ratio(POINTED, TILTED) < 0.8
    traj = run(POINTED, kreisel.Viscous(mu=0.5), TILTED, 10.0)
    assert np.max(traj.u[traj.t > 9.0]) < traj.u[0] - 0.05


def test_area_a_top_leaves_the_upright_and_settles_in_its_regular_precession():
    """gamma >= 1 + alpha: the upright spin is unstable however fast. The top ends in the
    stable regular precession with J_R(u) = |J| (J is kept by the sliding friction)."""
    top = ref.Top(m=0.05, A=3e-5, C=2e-5, s=0.01, rho=0.04)  # alpha 0.25, gamma 1.5
    start = {"theta": 0.3, "psi_dot": 200.0}
    traj = run(top, kreisel.Viscous(mu=0.5), start, 30.0)
    j = abs(traj.jellett[0])
    u_top = top.alpha / (top.gamma - 1)  # D(u) > 0 only below this
    u_star = brentq(lambda u: top.J_R(u) - j, -1.0, u_top - 1e-12, xtol=1e-15)
    assert u_star < 0.5
    assert traj.u[-1] == pytest.approx(u_star, abs=1e-6)


def test_slowly_spinning_tippe_top_stays_hanging():
    """|J| < J_R(-1) = J_beta (1 - alpha)^2 / sqrt(alpha + gamma - 1): the hanging spin is
    stable; the tilted tippe top returns to it."""
    start = {"theta": math.pi - 0.1, "psi_dot": 20.0}
    q, w, _, _ = ref.initial(T1, **start)
    j = abs(ref.jellett(T1, q, w)[0])
    assert j < T1.J_beta * (1 - T1.alpha) ** 2 / math.sqrt(T1.alpha + T1.gamma - 1)
    traj = run(T1, kreisel.Viscous(mu=1.0), start, 10.0)
    assert traj.u[-1] < traj.u[0]
    assert traj.u[-1] < -0.999


# --------------------------------------------------------------------------------------
# 4. against the reference integration (viscous, T1)
# --------------------------------------------------------------------------------------


def test_viscous_tippe_top_matches_reference_integration():
    t_eval = np.linspace(0.0, 3.0, 301)
    mine = ref.integrate_slide(T1, "viscous", 1.0, T1_START, 3.0, t_eval=t_eval)
    traj = run(T1, kreisel.Viscous(mu=1.0), T1_START, 3.0, t_eval=t_eval)
    assert np.array_equal(traj.t, t_eval)
    assert np.max(np.abs(traj.u - mine.u)) < 1e-7
    assert np.max(np.abs(traj.jellett - mine.jellett)) < 1e-7 * abs(mine.jellett[0])
    assert np.max(np.abs(traj.com - mine.com)) < 1e-8  # m
    np.testing.assert_allclose(traj.dissipated, mine.dissipated, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(traj.normal_force, mine.normal_force, rtol=1e-6)
    np.testing.assert_allclose(traj.slip_speed, mine.slip_speed, rtol=1e-5, atol=1e-9)


# --------------------------------------------------------------------------------------
# 5. frictionless contact
# --------------------------------------------------------------------------------------

FREE_START = {"theta": 1.2, "psi_dot": 60.0, "vx": 0.1, "vy": -0.05}


def test_frictionless_top_keeps_Lz_L3_E_and_its_horizontal_velocity():
    traj = run(HEAVY, kreisel.Frictionless(), FREE_START, 1.0)
    assert set(traj.mode) == {"slip"}
    ls = space_L(HEAVY, traj)
    assert rel_drift(ls[:, 2]) < 1e-9
    assert rel_drift(HEAVY.C * traj.omega[:, 2]) < 1e-9
    assert rel_drift(traj.energy) < 1e-9
    assert np.max(np.abs(traj.dissipated)) < 1e-12 * traj.energy[0]
    np.testing.assert_allclose(traj.com_velocity[:, 0], 0.1, rtol=1e-12)
    np.testing.assert_allclose(traj.com_velocity[:, 1], -0.05, rtol=1e-12)
    np.testing.assert_allclose(traj.com[:, 0], 0.1 * traj.t, atol=1e-12)
    np.testing.assert_allclose(traj.com[:, 1], -0.05 * traj.t, atol=1e-12)


def test_frictionless_nutation_matches_the_reduced_equation_by_quadrature():
    """udot^2 = F(u) / (1 + (m s^2/A)(1 - u^2)): turning points and the times to reach
    phases between them, by mpmath quadrature (30 digits)."""
    motion = ref.FrictionlessMotion(HEAVY, FREE_START)
    s0 = motion.sigma0  # the start is the upper turning point (theta_dot = 0, falling)
    assert float(motion.u_of(s0)) == pytest.approx(math.cos(1.2), abs=1e-14)
    sigmas = [s0 + k * mpmath.pi / 8 for k in range(1, 25)]  # three half-periods
    times = np.array([float(motion.time(x)) for x in sigmas])
    u_exp = np.array([float(motion.u_of(x)) for x in sigmas])
    traj = run(HEAVY, kreisel.Frictionless(), FREE_START, times[-1], t_eval=times)
    np.testing.assert_allclose(traj.u, u_exp, rtol=0, atol=1e-8)
    # the lower turning point and the half period
    half = float(motion.time(s0 + mpmath.pi / 2))
    assert traj.u[3] == pytest.approx(float(motion.u1), abs=1e-8)
    fine = np.linspace(half - 2e-3, half + 2e-3, 2001)
    t2 = run(HEAVY, kreisel.Frictionless(), FREE_START, fine[-1], t_eval=fine)
    j = int(np.argmin(t2.u))
    assert t2.u[j] == pytest.approx(float(motion.u1), abs=1e-10)
    assert abs(fine[j] - half) <= 4e-6  # grid spacing 2e-6 s; u is flat at the turn


# --------------------------------------------------------------------------------------
# 6. lift-off, flight and touchdown
# --------------------------------------------------------------------------------------

HOP_START = {"theta": 1.0, "phi_dot": 30.0, "psi_dot": 50.0}  # N < 0 after 0.031 s


def hop(restitution: float):
    return run(HEAVY, kreisel.Frictionless(), HOP_START, 0.2, model_kw={"restitution": restitution})


def event(traj, name, k=0):
    found = [e for e in traj.events if e.name == name]
    assert len(found) > k, (name, traj.events)
    return found[k]


def test_lift_off_when_the_normal_force_vanishes():
    t_lift, cols, _ = ref.slide_until(HEAVY, "frictionless", 0.0, HOP_START, 1.0, "lift_off")
    assert t_lift is not None and 0.02 < t_lift < 0.04
    traj = hop(0.0)
    lift = event(traj, "lift_off")
    assert lift.t == pytest.approx(t_lift, abs=1e-8)
    i0, i1 = rows_at(traj, lift.t)
    assert traj.mode[i0] != "flight" and traj.mode[i1] == "flight"
    assert traj.normal_force[i1] == 0.0
    assert abs(traj.normal_force[i0]) < 1e-8 * HEAVY.m * HEAVY.g
    assert np.all(traj.normal_force[:i0] > 0.0)


def test_flight_is_ballistic_and_touchdown_is_where_the_sphere_meets_the_floor():
    traj = hop(0.0)
    lift, down = event(traj, "lift_off"), event(traj, "touchdown")
    i = rows_at(traj, lift.t)[-1]
    j = rows_at(traj, down.t)[0]
    fl = np.arange(i, j + 1)
    assert set(traj.mode[fl]) == {"flight"} and len(fl) > 3
    np.testing.assert_array_equal(traj.normal_force[fl], 0.0)
    args = (traj.quaternion[i], traj.omega[i], traj.com[i], traj.com_velocity[i])
    dt = traj.t[fl] - traj.t[i]
    rot, pos, ls = ref.free_flight(HEAVY, *args, dt)
    np.testing.assert_allclose(traj.com[fl], pos, rtol=0, atol=1e-12)
    acc = np.diff(traj.com_velocity[fl], axis=0) / np.diff(traj.t[fl])[:, None]
    np.testing.assert_allclose(acc, [[0.0, 0.0, -HEAVY.g]] * len(acc), atol=1e-9)
    l_k = space_L(HEAVY, traj)[fl]
    assert np.max(np.abs(l_k - ls)) < 1e-11 * np.linalg.norm(ls)
    np.testing.assert_allclose(ref.quat_matrices(traj.quaternion[fl]), rot, atol=1e-9)
    # the gap z_G - s u - rho of the closed form closes at the touchdown
    grid = np.linspace(1e-6, 0.2, 20001)
    gap = ref.flight_gap(HEAVY, *args, grid)
    k = int(np.argmax(gap < 0.0))
    t_down = brentq(lambda x: ref.flight_gap(HEAVY, *args, x)[0], grid[k - 1], grid[k], xtol=1e-15)
    assert down.t == pytest.approx(traj.t[i] + t_down, abs=1e-9)


def impact_rows(traj, name="touchdown", k=0):
    ev = event(traj, name, k)
    rows = rows_at(traj, ev.t)
    assert len(rows) == 2, rows
    return ev, rows[0], rows[1]


def check_impact(top: ref.Top, traj, restitution: float, frictionless: bool):
    ev, b, a = impact_rows(traj)
    vt_b = ref.tip_velocity(top, traj.quaternion[b], traj.omega[b], traj.com_velocity[b])[0]
    vt_a = ref.tip_velocity(top, traj.quaternion[a], traj.omega[a], traj.com_velocity[a])[0]
    assert vt_b[2] < 0.0
    assert vt_a[2] == pytest.approx(-restitution * vt_b[2], abs=1e-9 * abs(vt_b[2]))
    np.testing.assert_allclose(traj.quaternion[a], traj.quaternion[b], rtol=0, atol=1e-14)
    # the touchdown is located a hair below the floor (1e-12 of the reach, so that the event
    # is seen however short the flight) and the impact puts G back on the floor
    np.testing.assert_allclose(traj.com[a], traj.com[b], rtol=0, atol=1.5e-12 * (top.s + top.rho))
    # one impulse P at the contact point: m dv = P, dL = a x P
    imp = top.m * (traj.com_velocity[a] - traj.com_velocity[b])
    e3 = ref.quat_matrix(traj.quaternion[b])[:, 2]
    arm = -top.s * e3 - np.array([0.0, 0.0, top.rho])
    dl = space_L(top, traj)[a] - space_L(top, traj)[b]
    np.testing.assert_allclose(
        dl, np.cross(arm, imp), atol=1e-10 * np.linalg.norm(space_L(top, traj)[b])
    )
    assert imp[2] > 0.0
    if frictionless:
        assert np.max(np.abs(imp[:2])) < 1e-14
    # Jellett's integral is kept by any force at T, an impulse too; the energy never rises
    assert traj.jellett[a] == pytest.approx(traj.jellett[b], rel=1e-12)
    assert traj.energy[a] <= traj.energy[b] * (1 + 1e-12)
    if frictionless and restitution == 1.0:
        assert traj.energy[a] == pytest.approx(traj.energy[b], rel=1e-12)
    if restitution == 0.0:
        assert traj.mode[a] != "flight"
        assert not [e for e in traj.events if e.name == "lift_off" and e.t == ev.t]
    else:
        assert traj.mode[a] == "flight"
    return vt_b


@pytest.mark.parametrize("restitution", [0.0, 0.5, 1.0])
def test_touchdown_after_lift_off_reverses_the_normal_tip_velocity_times_e(restitution):
    check_impact(HEAVY, hop(restitution), restitution, frictionless=True)


@pytest.mark.parametrize("restitution", [0.0, 0.5, 0.9])
@pytest.mark.parametrize(
    "friction", [kreisel.Frictionless(), kreisel.Coulomb(mu=0.3), kreisel.Viscous(mu=0.5)],
    ids=["frictionless", "coulomb", "viscous"],
)  # fmt: skip
def test_dropped_top_impact(friction, restitution):
    pt = play_top(HEAVY, friction, restitution=restitution)
    st = pt.state(1.0, phi_dot=30.0, psi_dot=50.0, height=0.002)
    traj = kreisel.simulate(pt, st, 0.05)
    assert traj.mode[0] == "flight"
    check_impact(HEAVY, traj, restitution, isinstance(friction, kreisel.Frictionless))
    # E + dissipated stays the initial energy through the impact
    e0 = traj.energy[0]
    assert np.max(np.abs(traj.energy + traj.dissipated - e0)) <= 1e-9 * e0


def test_hopping_tippe_top_leaves_the_floor_after_plastic_touchdowns_and_goes_on():
    # A fast, strongly off-centre tippe top hops while it turns over: a plastic touchdown
    # (restitution 0) can leave it where sliding would need the floor to pull, so it flies
    # again with no normal speed. That flight's length is not known in advance (it used to
    # be taken as zero and the run stopped with "step size too small" at t = 2.07 s).
    top = kreisel.PlayTop(0.02, 2.56e-6, 3.2e-6, 0.008, 0.02, friction=kreisel.Viscous(1.0))
    traj = kreisel.simulate(top, top.state(3.0416, psi_dot=250.0), 4.0, rtol=1e-8)
    names = [e.name for e in traj.events]
    assert names.count("lift_off") >= 10 and names.count("touchdown") >= 10
    assert rel_drift(traj.jellett) < 1e-8
    e0 = traj.energy[0]
    assert np.max(np.abs(traj.energy + traj.dissipated - e0)) <= 1e-8 * abs(e0)
    assert traj.u[-1] > 0.99  # it still turns over and ends spinning upright
