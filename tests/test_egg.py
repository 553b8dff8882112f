"""The rising egg: a uniform solid prolate spheroid spun fast enough on its side
rises towards its end, one spun slower stays down, and the energy never rises.

References, each derived in docs/guide/play.md ("The rising egg") and again here where a test
needs it, independently of the code under test:

- gyroscopic balance (Moffatt & Shimomura, Nature 416 (2002) 385): C n = A Omega cos(theta),
  L = A Omega ez, Jellett's J = A Omega h kept, energy at fixed J
  E(x) = m g h + J^2 (C (1 - x) + A x) / (2 A C h^2), x = cos^2(theta), h^2 = a^2 + (b^2 - a^2) x;
  E falls at the lying egg (x = 0) iff Omega^2 > 2 m g a / A, and all the way to the end (x = 1)
  iff Omega > that (b/a)^(3/2): the formulas derived in kreisel from that assumption;
- steady no-slip motions (derived for kreisel): G at rest and omega parallel to GP, which the
  gravity torque keeps turning iff Omega^2 = m g a^2 (b^2 - a^2) / (h (C b^2 - A a^2)) = 5 g / h
  (uniform); they branch off the lying spin at Omega^2 = 5 g / a, which is (A/C) times the
  balance threshold: the egg near threshold spins too slowly for the fast-spin approximation.

The default egg (a = 22.5 mm, b = 30 mm): balance thresholds 39.62 and 61.00 rad/s; steady
ones 46.69 and 69.01 rad/s. The sweeps use Viscous(0.3) friction, under which Jellett's
integral drifts by about 1 % during a rise, so that the egg ends where the steady motion of
its J is.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import kreisel
from kreisel import ParameterError, Viscous, bodies

A_EQ, B_AX, M, G = 0.0225, 0.03, 0.06, 9.81
BIG_A, BIG_C = M * (A_EQ**2 + B_AX**2) / 5, 2 * M * A_EQ**2 / 5  # uniform solid spheroid
D = B_AX**2 - A_EQ**2
TILT = 0.05  # the start: the axis 0.05 rad above the horizontal, spun about the vertical


def _height(u):
    return np.sqrt(A_EQ**2 + D * u * u)


def _lying(egg, spin):
    return egg.state(theta=np.pi / 2 - TILT, phi_dot=spin)


def _balance_energy(x, big_j):
    h = _height(np.sqrt(x))
    return M * G * h + big_j**2 * (BIG_C * (1 - x) + BIG_A * x) / (2 * BIG_A * BIG_C * h * h)


def test_gyroscopic_balance_energy_and_its_thresholds():
    """The balance state's L, J and kinetic energy from vectors, then the thresholds as sign
    changes of finite differences of E(x) at fixed J (not from the closed forms)."""
    th = bodies.egg_rising_thresholds(A_EQ, B_AX, G)
    theta, big_omega = 0.7, 55.0
    ez, e3 = np.array([0.0, 0.0, 1.0]), np.array([np.sin(theta), 0.0, np.cos(theta)])
    n = BIG_A * big_omega * np.cos(theta) / BIG_C
    omega = big_omega * ez + (n - big_omega * np.cos(theta)) * e3
    big_l = BIG_A * omega + (BIG_C - BIG_A) * (omega @ e3) * e3
    np.testing.assert_allclose(big_l, BIG_A * big_omega * ez, atol=1e-18)
    q = A_EQ**2 * np.eye(3) + D * np.outer(e3, e3)
    g_minus_p = q @ ez / np.sqrt(ez @ q @ ez)  # the support point of the spheroid, from G
    h = _height(np.cos(theta))
    big_j = big_l @ g_minus_p
    assert big_j == pytest.approx(BIG_A * big_omega * h, rel=1e-14)
    kinetic = 0.5 * omega @ big_l
    x = np.cos(theta) ** 2
    assert kinetic + M * G * h == pytest.approx(_balance_energy(x, big_j), rel=1e-13)

    def slope(x0, spin):  # dE/dx at fixed J = A spin a (the lying egg's J), one-sided
        step = 1e-6 if x0 == 0 else -1e-6
        big_j = BIG_A * spin * A_EQ
        return (_balance_energy(x0 + step, big_j) - _balance_energy(x0, big_j)) / step

    rise = brentq(lambda w: slope(0.0, w), 20.0, 60.0, xtol=1e-10)
    assert rise == pytest.approx(th.balance_rise, rel=1e-5)
    stand = brentq(lambda w: slope(1.0, w), 40.0, 90.0, xtol=1e-10)
    assert stand == pytest.approx(th.balance_stand, rel=1e-5)
    # between them E has one interior minimum, at h = a (Omega / balance_rise)^(2/3)
    spin = 1.2 * th.balance_rise
    best = minimize_scalar(lambda x: _balance_energy(x, BIG_A * spin * A_EQ), bounds=(0, 1),
                           method="bounded", options={"xatol": 1e-12})  # fmt: skip
    assert _height(np.sqrt(best.x)) == pytest.approx(A_EQ * 1.2 ** (2 / 3), rel=1e-6)
    assert th.balance_rise**2 == pytest.approx(BIG_C / BIG_A * th.rise**2, rel=1e-12)


@pytest.mark.parametrize("u", [0.2, 0.5, 0.9, -0.6])
def test_the_steady_no_slip_motions_are_motions_of_the_egg(u):
    """Started on the family (Omega^2 = 5 g / h, psi_dot = Omega (b^2 - a^2) u / a^2 so that
    omega is parallel to GP, G at rest) the egg stays there: no slip, no loss, u fixed; its
    Jellett's integral is the one egg_settled_inclination inverts."""
    egg = bodies.egg(friction=Viscous(0.3))
    big_omega = np.sqrt(5 * G / _height(u))
    st = egg.state(theta=np.arccos(u), phi_dot=big_omega, psi_dot=big_omega * D * u / A_EQ**2)
    run = kreisel.simulate(egg, st, 1.0, t_eval=np.linspace(0.0, 1.0, 101))
    assert np.abs(run.u - u).max() < 1e-9
    assert run.slip_speed.max() < 1e-9 and run.dissipated[-1] < 1e-15
    spin = run.jellett[0] / (BIG_A * A_EQ)
    assert bodies.egg_settled_inclination(spin, A_EQ, B_AX, G) == pytest.approx(abs(u), abs=1e-9)


def test_the_steady_thresholds_are_the_ends_of_the_family():
    """rise: the family at u = 0, Omega^2 = 5 g / a with J = A Omega a; stand: at u = 1,
    Omega^2 = 5 g / b, spin w = Omega + psi_dot = Omega b^2 / a^2 about ez = e3, J = C w b."""
    th = bodies.egg_rising_thresholds(A_EQ, B_AX, G)
    assert th.rise == pytest.approx(np.sqrt(5 * G / A_EQ), rel=1e-14)
    w = np.sqrt(5 * G / B_AX) * B_AX**2 / A_EQ**2
    assert th.stand == pytest.approx(BIG_C * w * B_AX / (BIG_A * A_EQ), rel=1e-14)
    assert [round(x, 2) for x in th] == [46.69, 69.01, 39.62, 61.0]


def test_bad_eggs_are_refused_by_name():
    with pytest.raises(ParameterError, match=r"axial = 0.02 is not allowed .* prolate"):
        bodies.egg_rising_thresholds(0.03, 0.02)
    with pytest.raises(ParameterError, match=r"g = -9.81 is not allowed"):
        bodies.egg_rising_thresholds(g=-9.81)
    with pytest.raises(ParameterError, match=r"spin = 'fast' is not allowed"):
        bodies.egg_settled_inclination("fast")
    with pytest.raises(ParameterError, match=r"equatorial = 0.0 is not allowed"):
        bodies.egg_settled_inclination(50.0, 0.0)


def test_an_egg_spun_fast_rises_and_a_slow_one_stays_down():
    """Final |u| after 60 s: 0.7 and 1.1 times the balance threshold stay down (the second
    one above Moffatt-Shimomura's criterion, below the steady one); 1.3 times it rises part
    way; 0.7 times the steady threshold stays down, 1.3 times it rises further, 1.8 times
    the balance threshold (above both stand thresholds) stands on its end."""
    th = bodies.egg_rising_thresholds()
    egg = bodies.egg(friction=Viscous(0.3))
    spins = [0.7 * th.balance_rise, 1.1 * th.balance_rise, 1.3 * th.balance_rise,
             0.7 * th.rise, 1.3 * th.rise, 1.8 * th.balance_rise]  # fmt: skip
    out = kreisel.simulate_many(egg, [_lying(egg, w) for w in spins], 60.0, rtol=1e-8)
    assert out.errors == (None,) * 6
    down, short, part, down2, further, end = np.abs(out.final_u)
    assert max(down, short, down2) < 0.01  # started at 0.05
    assert 0.3 < part < 0.6 and 0.6 < further < 0.9 and end > 0.999


def test_the_sweeps_find_the_steady_thresholds():
    """Final |u| against the spin: the egg rises where |u| ends above 0.01 (it starts at 0.05
    and decays to 0 below threshold; just above, it settles on a small u); it stands where |u|
    ends above 0.999. The rise threshold agrees with the steady one to 1 % (0.25 rad/s
    steps); the stand threshold lies 1-3 % below the steady one, because Jellett's integral
    grows by that much while the egg rises (measured below)."""
    th = bodies.egg_rising_thresholds()
    egg = bodies.egg(friction=Viscous(0.3))
    spins = np.arange(44.0, 50.01, 0.25)
    out = kreisel.simulate_many(egg, [_lying(egg, w) for w in spins], 120.0, rtol=1e-8)
    up = np.abs(out.final_u) > 0.01
    first = int(np.argmax(up))
    assert 0 < first and up[first:].all()  # one threshold inside the sweep
    measured = 0.5 * (spins[first - 1] + spins[first])
    assert measured == pytest.approx(th.rise, rel=0.01)
    assert measured / th.balance_rise > 1.15  # the balance criterion is 15 % low
    spins = np.arange(62.0, 72.01, 0.5)
    out = kreisel.simulate_many(egg, [_lying(egg, w) for w in spins], 60.0, rtol=1e-8)
    stands = np.abs(out.final_u) > 0.999
    first = int(np.argmax(stands))
    assert 0 < first and stands[first:].all()
    measured = 0.5 * (spins[first - 1] + spins[first])
    assert 0.97 * th.stand < measured < th.stand
    run = kreisel.simulate(egg, _lying(egg, spins[first]), 60.0, rtol=1e-8,
                           t_eval=np.linspace(0.0, 60.0, 61))  # fmt: skip
    grown = run.jellett[-1] / run.jellett[0]
    assert 1.005 < grown < 1.04
    assert measured == pytest.approx(th.stand / grown, rel=0.01)


def test_a_partial_rise_settles_on_the_steady_motion_of_its_jellett_integral():
    """At 52 rad/s (between rise and stand) the egg settles within 30 s on a steady no-slip
    motion: |u| as egg_settled_inclination gives for its J (to 0.001; 0.04 for the J it
    started with), precession Omega^2 = 5 g / h; the balance theory's settling point
    h = a (Omega/balance_rise)^(2/3) (|u| = 0.75) is far off."""
    egg = bodies.egg(friction=Viscous(0.3))
    te = np.linspace(0.0, 60.0, 6001)
    run = kreisel.simulate(egg, _lying(egg, 52.0), 60.0, rtol=1e-8, t_eval=te)
    late = te >= 40.0
    u = np.abs(run.u[late]).mean()
    assert np.abs(run.u[late]).std() < 1e-3 and run.slip_speed[late].max() < 1e-4
    spin_now = run.jellett[late].mean() / (BIG_A * A_EQ)
    assert u == pytest.approx(bodies.egg_settled_inclination(spin_now), abs=1e-3)
    assert u == pytest.approx(bodies.egg_settled_inclination(52.0), abs=0.04)
    precession = np.gradient(np.unwrap(run.phi), te)[late].mean()
    assert precession == pytest.approx(np.sqrt(5 * G / _height(u)), rel=0.01)
    h_balance = A_EQ * (52.0 / bodies.egg_rising_thresholds().balance_rise) ** (2 / 3)
    assert np.sqrt((h_balance**2 - A_EQ**2) / D) - u > 0.25


@pytest.mark.parametrize(
    ("friction", "spin", "t_end"), [(Viscous(0.3), 52.0, 60.0), (None, 90.0, 20.0)]
)
def test_the_energy_never_rises_and_its_budget_closes(friction, spin, t_end):
    """Between samples E never rises by more than 1e-12 of E0, and E + dissipated stays E0
    to 1e-10 (rtol 1e-10; under rolling, where nothing dissipates, E holds to the
    integrator's tolerance, so a coarser rtol lets it wander up by rtol-sized steps)."""
    egg = bodies.egg(friction=friction)
    run = kreisel.simulate(egg, _lying(egg, spin), t_end, t_eval=np.linspace(0, t_end, 2001))
    e0 = run.energy[0]
    assert np.diff(run.energy).max() <= 1e-12 * e0
    total = run.energy + run.dissipated
    assert np.abs(total - e0).max() <= 1e-10 * e0
    assert run.dissipated[-1] > 1e-3 * e0  # it did dissipate


def test_drilling_friction_wears_jellett_away_and_the_egg_falls_back():
    """Coulomb-Contensou (the default egg: mu 0.3, 0.5 mm patch): its drilling torque
    changes J (dJ/dt = M ez . GP, theory: several parts), so at 90 rad/s the egg rises onto its end
    within 3 s, then J drains and it sinks back towards its side."""
    egg = bodies.egg()
    te = np.linspace(0.0, 20.0, 201)
    run = kreisel.simulate(egg, _lying(egg, 90.0), 20.0, rtol=1e-8, t_eval=te)
    au = np.abs(run.u)
    assert au[te <= 3.0].max() > 0.95
    assert run.jellett[-1] < 0.3 * run.jellett[0]
    assert au[-1] < 0.5
