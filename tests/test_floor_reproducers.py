"""Tops on a floor never go through it: the reproducers of runs that went through it, each with an
independent check.

- The height of each part's lowest point is computed here from G's height and u = cos(theta)
  alone: ``z_G + z u - phi(u)``, ``phi`` a sphere's radius, a torus's ``R sqrt(1 - u^2) + r``
  (the support function of the part, docs: theory, "Bodies of revolution").
- A ring lying flat touches along its whole rim with the normal force m g spread evenly:
  under viscous friction (F = -mu N v per point) its spin decays as
  ``w(t) = w0 exp(-mu m g R^2 t / C)``; under Coulomb friction a pure spin stops at
  ``t = C w0 / (mu m g R)``; under Coulomb-Contensou friction (a patch of effective radius
  rbar at every rim point) at ``t = C w0 / (mu m g sqrt(R^2 + rbar^2))``: the moment per point
  is ``mu (R^2 w + rbar^2 w) / sqrt(R^2 w^2 + rbar^2 w^2)`` times the load.
- A sharp rim lying flat that slides and spins under Coulomb friction: the means over the rim of
  the slip's direction and of its moment, by ``scipy.integrate.quad`` at every right-hand side
  of a ``solve_ivp`` run of ``dV/dt = -mu g <s_x>``, ``C dw/dt = -mu m g R <r x s>``.
- A flat ring bouncing on its whole rim: each flight is e times the one before (the vertical
  velocity is reversed times e, and the flight time of a ballistic hop is 2 v / g).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import kreisel
from kreisel import Coulomb, CoulombContensou, PlayState, PlayTop, Viscous
from kreisel.shapes import Sphere, Spheroid, Torus

G = 9.81


def _phi(part, u):
    if isinstance(part, Sphere):
        return part.radius + 0.0 * u
    if isinstance(part, Spheroid):  # the support function of the ellipsoid along the vertical
        return np.sqrt(part.equatorial**2 * (1.0 - u * u) + part.axial**2 * u * u)
    return part.major * np.sqrt(np.clip(1.0 - u * u, 0.0, None)) + part.minor


def part_gaps(parts, traj):
    """Each part's lowest point's height above the floor, row by row (n_parts x n_rows)."""
    u, zg = traj.u, traj.com[:, 2]
    return np.array([zg + p.z * u - _phi(p, u) for p in parts])


def test_a_bouncing_top_comes_to_rest_on_the_floor_after_its_bounces():
    t = PlayTop(0.053, 1.85e-6, 1.83e-6, s=0.0103, rho=0.00438, friction=Viscous(1.0),
                restitution=0.5)  # fmt: skip
    st = t.state(0.0, theta_dot=-5, phi_dot=-15.7, psi_dot=34.8, height=0.0043)
    tr = kreisel.simulate(t, st, 0.5)
    gaps = part_gaps([Sphere(0.00438, z=-0.0103)], tr)
    assert gaps.min() > -1e-9
    downs = [e.t for e in tr.events if e.name == "touchdown"]
    # the bounces end (a Zeno sequence cut off), then the top stays on the floor
    assert 5 < len(downs) < 60
    after = tr.t > downs[-1]
    assert set(tr.mode[after]) <= {"slip", "roll"} and np.abs(gaps[0, after]).max() < 1e-9
    total = tr.energy + tr.dissipated
    assert np.diff(total).max() <= 1e-10 * total[0]  # the integration's tolerance


@pytest.mark.parametrize("minor", [0.005, 0.0])
def test_a_ring_flat_upside_down_spins_down_as_the_closed_form(minor):
    m, c, r, mu = 0.113, 6e-5, 0.02, 1.0
    t = PlayTop(m, 4.35e-5, c, shape=[Torus(r, minor, 0.0)], friction=Viscous(mu),
                restitution=0.5)  # fmt: skip
    tr = kreisel.simulate(t, t.state(math.pi, psi_dot=10.0), 1.0)
    assert tr.stats["steps"] < 1000 and tr.status == "completed"
    np.testing.assert_allclose(tr.u, -1.0, rtol=0, atol=1e-15)
    assert np.all(tr.mode == "slip")
    np.testing.assert_allclose(tr.com[:, 2], minor, rtol=0, atol=1e-15)
    w = np.abs(tr.omega[:, 2])
    np.testing.assert_allclose(w, 10.0 * np.exp(-mu * m * G * r * r * tr.t / c), rtol=1e-8)


def test_a_flat_ring_with_a_tilting_rate_stays_on_the_floor():
    m, c, r, rr, mu = 0.0585, 3.977e-06, 0.01119, 0.001119, 0.448
    t = PlayTop(m, 2.265e-06, c, shape=[Torus(r, rr, 0.0, name="rim")], friction=Viscous(mu),
                restitution=0.9)  # fmt: skip
    st = PlayState(quaternion=[1, 0, 0, 0], omega=[-0.2737, 0, 79.62], com=[0, 0, rr],
                   com_velocity=[0, 0, 0])  # fmt: skip
    tr = kreisel.simulate(t, st, 1.0)
    assert tr.status == "completed" and tr.stats["steps"] < 1000
    np.testing.assert_allclose(tr.com[:, 2], rr, rtol=0, atol=1e-15)
    # the tilting rate is taken by the face's plastic impact; the spin decays as the closed form
    w = tr.omega[:, 2]
    np.testing.assert_allclose(w, 79.62 * np.exp(-mu * m * G * r * r * tr.t / c), rtol=1e-8)
    ke_tilt = 0.5 * 2.265e-06 * 0.2737**2
    assert tr.dissipated[0] == pytest.approx(ke_tilt, rel=1e-9)


def test_a_touchdown_on_the_peg_while_the_ball_rests_is_found():
    parts = [Sphere(0.01255, z=-0.00251, name="ball"), Sphere(0.003765, z=-0.01461, name="peg")]
    t = PlayTop(0.0034, 3.02e-07, 1.70e-07, shape=parts,
                friction=CoulombContensou(0.2425, 2.51e-4), restitution=0.9)  # fmt: skip
    st = PlayState(quaternion=[1, 0, 0, 0], omega=[-2.687, 0, -10.83], com=[0, 0, 0.04927],
                   com_velocity=[0, 0, 0])  # fmt: skip
    tr = kreisel.simulate(t, st, 1.0)
    gaps = part_gaps(parts, tr)
    assert gaps.min() > -1e-9
    # every part that comes down through the floor's level does so at a touchdown event
    for i, name in enumerate(("ball", "peg")):
        downs = {e.t for e in tr.events if e.name == "touchdown" and e.part == name}
        arrive = np.flatnonzero((gaps[i, :-1] > 1e-9) & (gaps[i, 1:] < 0.0))
        assert all(tr.t[k + 1] in downs for k in arrive), name
    total = tr.energy + tr.dissipated
    assert np.diff(total).max() <= 1e-10 * total[0]  # the integration's tolerance


def test_a_thin_ring_dropped_flat_bounces_on_its_whole_rim_and_rests():
    m, c, r, rr, e = 0.00835, 2.10e-8, 0.00441, 0.000441, 0.6
    t = PlayTop(m, 5.93e-8, c, shape=[Torus(r, rr, 0.0)], friction=CoulombContensou(0.637, 8.8e-5),
                restitution=e)  # fmt: skip
    tr = kreisel.simulate(t, t.state(math.pi, psi_dot=96.0, height=0.004), 2.0)
    assert tr.status == "completed" and tr.stats["steps"] < 10_000
    assert part_gaps([Torus(r, rr, 0.0)], tr).min() > -1e-9
    downs = np.array([ev.t for ev in tr.events if ev.name == "touchdown"])
    flights = np.diff(downs)
    np.testing.assert_allclose(flights[1:6] / flights[:5], e, rtol=1e-6)
    # the first fall: from 4 mm, t = sqrt(2 h / g)
    assert downs[0] == pytest.approx(math.sqrt(2 * 0.004 / G), rel=1e-9)
    assert tr.events[-1].name == "slip_to_roll"
    np.testing.assert_array_equal(tr.omega[-1], 0.0)
    total = tr.energy + tr.dissipated
    assert np.diff(total).max() <= 1e-10 * total[0]  # the integration's tolerance


@pytest.mark.parametrize("face", [0.0, math.pi])
def test_a_disk_started_flat_does_not_sink_and_stops_spinning_as_the_closed_form(face):
    from kreisel import bodies

    a, h, m = 0.0375, 0.0125, 0.434
    disk = bodies.disk(a, h, m)
    tr = kreisel.simulate(disk, disk.state(face, psi_dot=10.0), 5.0)
    np.testing.assert_allclose(tr.com[:, 2], h / 2, rtol=0, atol=1e-15)
    fr = disk.friction
    rbar = 3 * math.pi * fr.radius / 16
    t_stop = disk.C * 10.0 / (fr.mu * m * G * math.hypot(a, rbar))
    stop = [ev.t for ev in tr.events if ev.name == "slip_to_roll"]
    assert len(stop) == 1 and stop[0] == pytest.approx(t_stop, rel=1e-6)
    before = tr.t < stop[0]
    np.testing.assert_allclose(np.abs(tr.omega[before, 2]), 10.0 * (1 - tr.t[before] / t_stop),
                               rtol=0, atol=1e-5)  # fmt: skip


def test_a_sharp_rim_spinning_flat_under_coulomb_friction_stops_at_the_closed_form_time():
    m, c, r, mu = 0.00835, 2.10e-8, 0.00441, 0.3
    t = PlayTop(m, 5.93e-8, c, shape=[Torus(r, 0.0, 0.0)], friction=Coulomb(mu))
    tr = kreisel.simulate(t, t.state(0.0, psi_dot=50.0), 2.0)
    stop = [ev.t for ev in tr.events if ev.name == "slip_to_roll"]
    assert stop == [pytest.approx(c * 50.0 / (mu * m * G * r), rel=1e-8)]


def test_a_sharp_rim_sliding_and_spinning_flat_follows_the_mean_over_its_rim():
    """While the rim's centre slides slower than its rim turns (|v| < R |w|), one point of the
    rim slips backwards and one forwards; the mean over the rim was a 64-point sum, not smooth
    in |v| / R|w|, and such a slide took steps in proportion to 1/rtol (a random floor run: 5e5
    steps in 15 s). The closed form follows the quadrature below to 1e-9 and the slide ends in
    a few hundred steps, |v| and R|w| vanishing together."""
    from scipy.integrate import quad, solve_ivp

    m, r, mu = 0.00835, 0.00441, 0.3
    c = m * r * r
    t = PlayTop(m, c / 2, c, shape=[Torus(r, 0.0, 0.0)], friction=Coulomb(mu))
    st = t.state(0.0, psi_dot=30.0, vx=0.05)
    tr = kreisel.simulate(t, st, 1.0)
    stop = [ev.t for ev in tr.events if ev.name == "slip_to_roll"]
    assert len(stop) == 1 and tr.stats["steps"] < 1000, tr.stats
    np.testing.assert_array_equal(tr.com_velocity[-1], 0.0)

    def mean(f):
        return quad(f, 0, 2 * math.pi, points=[math.pi / 2], epsabs=1e-14, epsrel=1e-13,
                    limit=200)[0] / (2 * math.pi)  # fmt: skip

    def rhs(_, y):
        v, a = y[0], r * y[1]
        s = lambda p: math.sqrt(v * v + a * a - 2 * v * a * math.sin(p))  # noqa: E731
        gx = mean(lambda p: (v - a * math.sin(p)) / s(p))
        gm = mean(lambda p: (a - v * math.sin(p)) / s(p))
        return [-mu * G * gx, -mu * m * G * r * gm / c, v]

    ts = np.linspace(0, 0.95 * stop[0], 6)
    ref = solve_ivp(rhs, (0, ts[-1]), [0.05, 30.0, 0.0], t_eval=ts, rtol=1e-11, atol=1e-14,
                    method="DOP853").y  # fmt: skip
    got = kreisel.simulate(t, st, 1.0, t_eval=ts)
    np.testing.assert_allclose(got.com_velocity[:, 0], ref[0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(got.omega[:, 2], ref[1], rtol=0, atol=1e-8)
    np.testing.assert_allclose(got.com[:, 0], ref[2], rtol=0, atol=1e-12)
    # Near the end |v| = R |w| (the ratio 0.38 at the start): both stop together.
    late = got.com_velocity[-1, 0] / (r * got.omega[-1, 2])
    assert 0.9 < late < 1.1, late


def test_a_contact_with_no_consistent_force_never_pulls_energy_in():
    """The Painleve case after a landing (floor campaign, seed 1, case 3694): no set of
    contact modes is consistent even after the plastic impact. Sliding with the pulling normal
    force that no set allowed fed energy in through the friction (E + dissipated rose by 2 %
    of the energy); the contact now sticks (a sticking contact does no work, even where its
    normal force pulls), and E + dissipated never rises beyond rounding."""
    import kreisel
    from kreisel.shapes import Spheroid, Torus

    top = kreisel.PlayTop(
        0.22063414001252402, 3.22240268722107e-05, 3.320561966376072e-05,
        shape=[Torus(0.026044932357395786, 0.0, z=0.0011939141996768765),
               Spheroid(0.034912411557015306, 0.03281434106306832, z=-0.016572561110347626)],
        friction=kreisel.CoulombContensou(0.5873942998382576, 7.752367984944429e-05),
        restitution=0.95, rolling_resistance=0.0010544524094724867,
    )  # fmt: skip
    st = kreisel.PlayState(
        quaternion=np.array([0.9478325640534756, 0.3187686159580551, 0.0, 0.0]),
        omega=np.array([0.0, 0.4385744912100808, 0.43153134251765446]),
        com=np.array([0.08287886857027044, 0.0, 0.04728666423219676]),
        com_velocity=np.array([-0.002914145290041297, 0.0, 0.19373931947278386]),
    )
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    # the property suite's bound on rounding (tests/floor_properties.py: 1e-9 of the energy)
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    assert np.diff(np.asarray(tr.dissipated)).min() >= -1e-9 * total[0]


def test_a_normal_force_that_dips_through_zero_within_one_step_lifts_the_part_off():
    """Floor campaign, seed 1, case 8429: a top spinning at 300 rad/s upside down on a spheroid
    had its normal force fall from 0.11 N to -0.13 N and back to 0.02 N within one step of
    0.85 ms (the step follows the state, not the force); the lift-off between the two step
    ends was missed and the floor pulled, the viscous friction feeding in 2e-5 J. Sampled
    densely here (t_eval at 25 µs, a grid independent of the steps), the part touching never
    pulls, and the dissipated energy never falls."""
    top = kreisel.PlayTop(
        0.6233489471697647, 5.854525421215523e-05, 0.00011709050842431046,
        shape=[Sphere(0.0, z=-0.014646131905759124),
               Sphere(0.013824315291404134, z=-0.00490016967280864),
               Torus(0.01867967838038807, 0.005996791088673943, z=0.007712183903854784),
               kreisel.shapes.Spheroid(0.0077430633549378505, 0.01871585639354498,
                                       z=0.01009936959314018)],
        friction=Viscous(0.014380910222660373), restitution=0.3420884330788049,
        drilling_resistance=0.001214723493827688,
    )  # fmt: skip
    st = top.state(theta=3.1415423582808604, phi=0.47087928417326513,
                   theta_dot=-20.27910501238808, phi_dot=-0.15575269486581464,
                   psi_dot=299.9575495714782, vx=-0.024361759025167733,
                   vy=-0.018245305728391295)  # fmt: skip
    grid = np.arange(0.0, 0.1, 25e-6)
    tr = kreisel.simulate(top, st, 0.1, t_eval=grid)
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    full = kreisel.simulate(top, st, 0.1)
    total = np.asarray(full.energy) + np.asarray(full.dissipated)
    assert np.diff(np.asarray(full.dissipated)).min() >= -1e-9 * total[0]


def test_a_normal_force_that_dips_through_zero_just_after_a_step_end_lifts_the_part_off():
    """Floor campaign, seed 1, case 497: a sharp rim sliding under point Coulomb friction had
    its normal force at 4.5e-6 N at one step end (t = 0.2029 s) and 5.3e-5 N at the next, and
    turned to a pull in between, near the first end, where neither of the step's two interior
    test points looked; the floor pulled and the friction fed in 4.7e-10 J (the dissipated
    energy fell). Sampled densely here (t_eval at 20 µs), the part touching never pulls, and
    the dissipated energy never falls."""
    top = kreisel.PlayTop(
        0.0019184481065155376, 9.818547949312572e-09, 1.9637095898625145e-08,
        shape=[Torus(0.002110186769985083, 3.460834413669683e-05, z=-0.0034106724342431415),
               Torus(0.005932673149855536, 0.0, z=0.0021238078258440287),
               Sphere(0.0, z=-0.008983209717112377)],
        friction=kreisel.Coulomb(0.0667544294346033),
        drilling_resistance=8.505335946254026e-05,
    )  # fmt: skip
    st = kreisel.PlayState(
        quaternion=np.array([0.1363137392303317, 0.9906657178367712, 0.0, 0.0]),
        omega=np.array([0.0, 2.541878998551492, 227.51187809298105]),
        com=np.array([0.0, 0.0, 0.009494139071307254]),
        com_velocity=np.array([0.0, 0.0010731680048207271, -0.004438263591245263]),
    )
    full = kreisel.simulate(top, st, 0.21)
    assert any(e.name == "lift_off" and 0.2029 < e.t < 0.2031 for e in full.events)
    d = np.asarray(full.dissipated)
    assert np.diff(d).min() >= -1e-12 * (full.energy[0] + d[0])
    tr = kreisel.simulate(top, st, 0.21, t_eval=np.arange(0.19, 0.21, 20e-6))
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G


def test_a_creep_that_starts_with_its_slip_turned_away_ends_when_the_slip_grows():
    """Floor campaign, seed 1, case 4311: a spheroid-and-ring top on its ball failed to stick
    at 0.1147 s and crept, its round-off slip (2e-9 m/s) pointing against the creep's
    direction; the creep's test of a slip turned away started on its far side, so it never saw
    the slip grow past the creep's range (about 1e-4 m/s): the creep went on to a slip of
    0.23 m/s for 57 ms, holding the needed force, and fed in 5.9e-8 J. Now the creep ends
    within a millisecond and the dissipated energy never falls."""
    top = kreisel.PlayTop(
        0.024218707600552634, 2.5677927600460885e-06, 3.846201657968647e-07,
        shape=[Sphere(0.006000592635596068, z=-0.005132277837348853),
               Torus(0.00913205499903357, 0.0, z=0.03744489998740207)],
        friction=CoulombContensou(0.1902084440374015, 3.351580792786797e-05),
        restitution=0.8398052432808857, drilling_resistance=0.0002826841293877516,
    )  # fmt: skip
    st = top.state(theta=2.1790141715375135, phi=0.17983790146124692, psi=1.6635254735690737)
    # The story is sensitive to the integration (at rtol 1e-8 and 1e-10 both parts stick at
    # once, at 0.0797 s and 0.0724 s; whether the ball's failed stick at 0.1147 s happens
    # turns on the rounding of the steps before it): at each of these tolerances where the
    # creep of the campaign comes (at least one), it ends within a millisecond.
    seen = 0
    for kw in ({"rtol": 1e-12, "atol": 1e-14}, {"rtol": 2e-12, "atol": 1e-15}, {"rtol": 1e-6}):
        tr = kreisel.simulate(top, st, 0.2, **kw)
        creeps = [e.t for e in tr.events if e.name == "creep"]
        ends = [e.t for e in tr.events if e.name == "creep_end"]
        assert all(any(0 <= t1 - t0 < 1e-3 for t1 in ends) for t0 in creeps), kw
        seen += any(0.114 < t0 < 0.115 for t0 in creeps)
        d = np.asarray(tr.dissipated)
        assert np.diff(d).min() >= -1e-12 * (tr.energy[0] + d[0]), kw
    assert seen


def test_a_creep_without_a_consistent_friction_lifts_the_part_off():
    """Floor campaign, seed 1, case 6739: a spheroid spinning at 122 rad/s on its side stops
    sticking (the force sticking needs leaves the cone by 3e-4 of it) where no creep is
    consistent: as the friction shrinks from the needed force, the normal force falls faster,
    and without friction it would pull. The full friction along the needed force instead made
    the slip grow along the friction (feeding energy in); the creep was turned back 180 000
    times in 1.5 ms until the chattering guard refused the run. Lifting off is the consistent
    motion: the part's lowest point rises from the floor at once after it (its gap, from G's
    height and the attitude here), and E + dissipated never rises."""
    from kreisel.shapes import Spheroid

    parts = [
        Sphere(0.03173443291805962, z=-0.013552218440100908),
        Spheroid(0.01317529302314435, 0.01121800758656355, z=-0.05352884436912399),
    ]
    top = PlayTop(1.1739962390452696, 0.00022333770911936711, 0.00044667541823873423,
                  shape=parts, friction=Coulomb(0.9818219225958733))  # fmt: skip
    st = top.state(theta=1.2882301749673237, phi=0.5040813837284948, theta_dot=0.079350684792521,
                   phi_dot=0.6002363516387018, psi_dot=195.70862413247636, height=0.0)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3)
    assert tr.status == "completed" and tr.stats["steps"] < 5000, tr.stats
    lifts = [e.t for e in tr.events if e.name == "lift_off" and 0.2408 < e.t < 0.2409]
    assert len(lifts) == 1
    after = tr.t > lifts[0]
    z = tr.com[after, 2]
    # The spheroid's lowest point: G's height + z u - sqrt(a^2 sin^2 + c^2 u^2) (its support
    # function along the vertical, its equatorial and axial semi-axes).
    sp = parts[1]
    u = tr.u[after]
    low = z + sp.z * u - np.sqrt(sp.equatorial**2 * (1 - u * u) + sp.axial**2 * u * u)
    assert low[0] > 0 and np.all(np.diff(low[:3]) > 0), low[:3]
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def _rocking_cone():
    """Floor campaign, seed 1, case 5982: a four-part cone on its side, Coulomb-Contensou
    friction over a 15 µm patch."""
    from kreisel.shapes import Torus as T

    top = PlayTop(
        0.14920254663051025, 3.0130982019201018e-05, 3.414961374389355e-05,
        shape=[T(0.02238247425631983, 0.00699440315928502, z=-0.010340298361307058),
               Sphere(0.0, z=-0.012460240229162301),
               T(0.016990722931073083, 0.00023020947921903947, z=0.031884139315153284),
               Sphere(0.02473528882592799, z=0.013932419902089384)],
        friction=CoulombContensou(0.5774939808833554, 1.5432917724812607e-05),
        restitution=0.03472306431064093, rolling_resistance=1.8870069454141105e-05,
    )  # fmt: skip
    st = top.state(theta=1.5707963267948966, phi=0.9579852348076031, psi=1.594043876643549,
                   phi_dot=-0.16057114027969183, psi_dot=0.3659106836810419,
                   vx=-0.0021590810002916627, height=0.0025489899126537414)  # fmt: skip
    return top, st


def test_a_drilling_limited_slide_under_coulomb_contensou_friction_takes_few_steps():
    """The cone's ring rolls on its side while its friction cannot hold it without drilling:
    it slides at a slip of rbar w_n |x| / (mu N) ~ 3e-7 m/s, which relaxes at mu N |W| /
    (rbar w_n) (rbar 9 µm, w_n ~ 0.1 rad/s). DOP853 alone took steps of 0.24 µs there, 113 775
    of them to t = 0.05 s; with the stiffness test such a slide goes on by Radau IIA. The
    result agrees with a run at rtol 1e-12 (the integration's own convergence), and E +
    dissipated never rises."""
    top, st = _rocking_cone()
    tr = kreisel.simulate(top, st, 0.05)
    assert tr.stats["steps"] < 3000, tr.stats
    fine = kreisel.simulate(top, st, 0.05, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(tr.omega[-1], fine.omega[-1], rtol=0, atol=1e-6)
    np.testing.assert_allclose(tr.com[-1], fine.com[-1], rtol=0, atol=1e-9)
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slide_that_radau_cannot_follow_goes_on_by_dop853():
    """Floor campaign, seed 1, case 793: a ring with a ball rolling upright on its ball under
    Coulomb-Contensou friction and a drilling resistance; its slide tripped the stiffness
    test, and Radau IIA's steps fell to 1e-16 s where the friction's direction turns at a slip
    of rounding size (the run was refused). DOP853 goes on from Radau's last step: the run
    completes, no part below the floor, E + dissipated never rising."""
    top = PlayTop(
        0.0087488581087846, 2.497273783612416e-07, 3.9180805877168874e-07,
        shape=[Torus(0.00624978457773422, 0.0007957487597488167, z=-0.007092944852913632),
               Sphere(0.005454745507617157, z=-0.0026779039890281863)],
        friction=CoulombContensou(0.5779952308851292, 4.511194913924136e-05),
        drilling_resistance=0.00032928754811943135,
    )  # fmt: skip
    st = PlayState(
        quaternion=np.array([0.9953564674832421, 1.914950331759935e-09, 2.817601490812666e-11,
                             -0.09625748095229628]),
        omega=np.array([0.0, 0.0, -1.040402152061392]),
        com=np.array([0.0, 0.0, 0.01405812371269426]),
        com_velocity=np.array([-0.0010943406744135698, 0.0, -0.09674749090833266]),
    )  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status in ("completed", "event")
    assert part_gaps(top.shape, tr).min() > -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_rocking_between_two_parts_ends_with_both_on_the_floor():
    """The cone rocks from its ring onto its ball and back, the intervals between touchdowns
    shrinking geometrically (2.3 ms, 1.0, 0.44, 0.19, ...; restitution 0.035) towards an
    accumulation point. Each part slid on after the impacts at a slip of ~1e-6 m/s in
    whatever direction they left, with the full friction: those moments tipped it back, and
    the contacts alternated every few nanoseconds until 200 000 switches refused the run. The
    rocking ends where the two parts can be on the floor together, sticking: before the
    accumulation point of the geometric series of its last intervals, and from then on both
    parts touch and push, and E + dissipated never rises."""
    top, st = _rocking_cone()
    tr = kreisel.simulate(top, st, 0.3)
    assert tr.status == "completed"
    downs = np.array([e.t for e in tr.events if e.name == "touchdown"])
    gaps = np.diff(downs)
    ratio = gaps[-2] / gaps[-3]
    assert 0.2 < ratio < 0.7 and 0.2 < gaps[-1] / gaps[-2] < 0.7, gaps
    # The accumulation point the rocking was heading for, from the intervals before the last
    # touchdown (the geometric series' sum): the settling touchdown comes before it.
    accumulation = downs[-2] + gaps[-2] * ratio / (1 - ratio)
    settled = downs[-1]
    assert settled < accumulation, (settled, accumulation)
    after = tr.t > settled
    gap = part_gaps(top.shape, tr)[:, after]
    assert np.abs(gap[[0, 3]]).max() < 1e-9, np.abs(gap[[0, 3]]).max()
    n = np.asarray(tr.part_normal_force)[after]
    assert n[:, 0].min() > 0 and n[:, 3].min() > 0
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_frictionless_impact_that_turns_the_slip_is_taken():
    """Floor campaign, seed 1, case 279: a four-part top spinning at ~100 rad/s strikes with
    its ring at 2.2 m/s. No Coulomb impulse was consistent, and the fallback, the frictionless
    plastic impact, was refused by the check that a sliding impulse does not reverse the slip
    (without friction the normal impulse may turn the slip any way): the impact was not
    taken, and the touchdown was found again 2e-14 s later, 195 000 times, until the run was
    refused as stalled. It is taken now: the run completes, no part is ever below the floor
    (the ring's lowest point from G's height and the attitude), and E + dissipated never
    rises."""
    from kreisel.shapes import Spheroid

    parts = [
        Sphere(0.012989180824959921, z=-0.014149592947659415),
        Spheroid(0.00603433768226529, 0.016170230803048705, z=-0.0040287106335066),
        Sphere(0.010237209626430111, z=-0.011609185596388837),
        Torus(0.013398910080883269, 0.0023500980807018078, z=-0.024216625265517246),
    ]
    top = PlayTop(
        0.017060533087756985, 1.11737078943525e-06, 7.310664068724777e-07, shape=parts,
        friction=Coulomb(0.09350102683303452), restitution=0.8443389416494798,
        drilling_resistance=4.432082503991082e-05,
    )  # fmt: skip
    st = PlayState(
        quaternion=np.array([-0.7832887983622038, -0.0001091255778652705,
                             -0.0003256216624139849, 0.6216578966139141]),
        omega=np.array([0.0, -86.38935969406874, -53.8237659194027]),
        com=np.array([-0.0954449274205542, 0.0, 0.03494937424478574]),
        com_velocity=np.array([0.0, 0.0, -0.024688889841476044]),
    )  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3)
    assert tr.status == "completed" and tr.stats["steps"] < 5000, tr.stats
    assert any(e.name == "touchdown" and e.part == "part3" for e in tr.events)
    assert part_gaps([parts[0], parts[2], parts[3]], tr).min() > -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slide_that_stops_while_its_patch_drills_rolls_on_drilling():
    """Floor campaign, seed 1, case 8645: a light disk on a ball (lever 40 mm against A =
    2.4e-7 kg m^2) slides at 0.3 m/s and stops slipping within 1.1 ms, while its patch still
    drills at w_n = 1.5e-4 rad/s (rbar w_n = 6e-9 m/s, above the stick speed). Under
    Coulomb-Contensou friction the slip that carries the rolling's tangential force is then
    rbar |w_n| x / sqrt(1 - x^2) ~ 2e-11 m/s (x = |F| / (mu N) = 3e-3), relaxing at ~4e10 /s:
    the steps fell to 1e-10 s and the run was refused as stalled. Now the part rolls on with
    its patch drilling (the slip held at zero, the drilling torque the law's on its ellipse)
    until the drilling stops (``drill_end``), in few steps.

    Reference: the same top integrated by scipy's Radau through the law itself (slip
    included) from the state where the drilling starts (``_play_reference``, which does not
    use kreisel); the angular velocity and G's velocity agree to 1e-9 of their size over the
    drilling, and the drilling's end is where the reference's ``rbar |w_n|`` has fallen to the
    stick speed."""
    import _play_reference as ref

    mu, radius = 0.6196054903320489, 4.205991025432986e-05
    m, big_a, big_c = 0.006886063548669754, 2.4174925518601564e-07, 4.834985103720313e-07
    s, rho = 0.016662910876893477, 0.022864911441109897
    top = PlayTop(m, big_a, big_c, s=s, rho=rho, friction=CoulombContensou(mu, radius),
                  restitution=0.95)  # fmt: skip
    st = top.state(theta=0.0, psi=5.786330165078696, theta_dot=-0.05350772220188471,
                   vx=-0.29616957570217267)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.01)
    assert tr.status == "completed"
    assert tr.stats["steps"] < 1000, tr.stats
    names = [e.name for e in tr.events]
    assert names[:2] == ["slip_to_roll", "drill_end"], names
    t0, t1 = tr.events[0].t, tr.events[1].t
    assert 1e-5 < t1 - t0 < 2e-4
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    # The drilling sampled at 20 times, from its start (the row after the switch).
    grid = np.concatenate([[t0], np.linspace(t0, t1, 22)[1:-1]])
    dr = kreisel.simulate(top, st, t1 - 1e-7, t_eval=grid)
    j0 = np.nonzero(np.asarray(dr.t) == t0)[0][-1]
    rbar = 3 * math.pi * radius / 16
    rtop = ref.Top(m, big_a, big_c, s, rho)
    full = ref.slide_rhs(rtop, "contensou", mu, rbar)

    def rhs(t, z):  # (vx, vy, q, omega): the positions and D do not act on them
        return full(t, [0.0, 0.0, *z, 0.0])[2:-1]

    z0 = [*dr.com_velocity[j0][:2], *dr.quaternion[j0], *dr.omega[j0]]
    sol = ref.solve_ivp(rhs, (t0, t1), z0, method="Radau", rtol=1e-11, atol=1e-15,
                        dense_output=True)  # fmt: skip
    assert sol.success, sol.message
    w_size = np.linalg.norm(dr.omega[j0])
    v_size = np.linalg.norm(dr.com_velocity[j0])
    for j in range(j0 + 1, len(dr.t)):
        zr = sol.sol(dr.t[j])
        np.testing.assert_allclose(dr.omega[j], zr[6:9], rtol=0, atol=1e-9 * w_size)
        np.testing.assert_allclose(dr.com_velocity[j][:2], zr[:2], rtol=0, atol=1e-9 * v_size)
    # The drilling ends where the reference's rbar |w_n| has fallen to the stick speed, 1e-9
    # of the speed scale reach |omega| + |v| + sqrt(g reach) (kreisel's documented default).
    wn_end = ref.slide_forces(rtop, "contensou", mu, [0, 0, *sol.sol(t1), 0], rbar).omega[2]
    reach = s + rho
    eps = 1e-9 * (reach * w_size + v_size + math.sqrt(9.81 * reach))
    assert rbar * abs(wn_end) == pytest.approx(eps, rel=0.05)


def test_a_normal_force_that_jumps_through_zero_as_another_part_stops_keeps_the_part_down():
    """Floor campaign, seed 1, case 901: a top of three parts under Coulomb-Contensou
    friction, part 0 creeping and part 1 sliding at 4e-8 m/s. At 0.2137535 s part 0's creep
    force changes branch and part 1's normal force jumps from 0.025 N to -0.038 N: the
    lift-off is located at the jump, not at a crossing. It is no lift-off: with the modes
    resolved afresh both parts stick, pressing. The first builds lifted part 1 off there (its
    row showed the floor pulling by 0.038 N) and put it back down 1.25e-7 s later."""
    top = kreisel.PlayTop(
        0.006203787659746695, 1.1125925574390887e-07, 1.0571943337645271e-07,
        shape=[Torus(0.007956012474312558, 0.0, z=-0.0038795906547545098),
               Sphere(0.003812798309494164, z=-0.005046574610978495),
               kreisel.shapes.Spheroid(0.00895128891991164, 0.006268601400653112,
                                       z=0.0074456786534386876)],
        friction=CoulombContensou(0.6452374052333834, 0.0001465083396016857),
        restitution=0.95,
    )  # fmt: skip
    st = top.state(theta=2.5871220206904344e-09, phi=3.170785122060433,
                   theta_dot=-7.866907603929195, phi_dot=-0.706331079864157,
                   psi_dot=52.52033691630489, vy=0.035039846516847696)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    # the floor only pushes, in every row
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    near = [(e.name, e.part) for e in tr.events if abs(e.t - 0.2137535) < 1e-6]
    assert ("lift_off", "part1") not in near
    assert ("touchdown", "part1") not in near
    assert ("slip_to_roll", "part1") in near
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_patch_whose_slip_and_drilling_stop_together_sticks_instead_of_stalling():
    """Floor campaign, seed 1, case 3983: a top of three parts under Coulomb-Contensou friction
    (patch radius 0.9 mm) slides on its sphere from the start. At 0.0514 s its slip (2e-9 m/s)
    and its drilling (rbar |w_n| about 8e-9 m/s) have both fallen to a few stick speeds: the
    law's direction turns at about 1e9 /s there, and Radau IIA's finite-difference Jacobian
    steps across that turn. The first builds crawled (2.6e5 rejected steps of 1e-14 s) until
    the run was refused as stalled; the implicit steps now hand over where their pace would
    exceed the run's step limit: to the stick tried as at the part's slip_to_roll, its
    measure being within the creep's exit range (a few stick speeds), and the patch sticks,
    drilling no more (the first fix, DOP853 going on, stopped it by the drilling's torque
    within a microsecond, recording `drill_end` after it), and the run completes."""
    from kreisel.shapes import Spheroid

    top = PlayTop(
        0.17463270829692018, 2.615920082098775e-05, 1.6863013606033497e-05,
        shape=[Sphere(0.013781934744400764, z=0.02055661022115802),
               Torus(0.009479038513059007, 0.0008480805159186018, z=0.02298815072075769),
               Spheroid(0.015767594235631715, 0.02266623849219384, z=0.011058921248681085)],
        friction=CoulombContensou(0.9222744266805292, 0.0008993629965658286),
    )  # fmt: skip
    st = top.state(theta=3.1415926499324147, phi_dot=-1.4726657828312435,
                   vx=-0.42739651028877257, vy=0.002618458958552802)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.1, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert tr.stats["steps"] < 20000
    assert (tr.events[0].name, tr.events[0].part) == ("slip_to_roll", "part0")
    assert 0.05140 < tr.events[0].t < 0.05141
    # it sticks there: rolling (no slip, no drilling) until the next switch
    nxt = tr.events[1].t if len(tr.events) > 1 else tr.t[-1]
    on = (tr.t > tr.events[0].t + 1e-6) & (tr.t < nxt)
    assert on.sum() >= 2 and set(tr.mode[on]) == {"roll"}
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_phase_never_starts_with_the_floor_pulling():
    """Floor campaign, seed 1, case 632: a top whose sphere and sharp rim touch the floor at
    one point (their slips are equal), under Coulomb-Contensou friction, so the split of the
    normal force between them is not unique. At 0.2178274 s a creep's slip is turned back
    onto its direction and the phase after it started with the rim pulled by 0.026 N (the
    split on its other branch); the lift-off event, which starts below zero, could not see it,
    and 8 rows pulled (up to 0.10 N) until the phase ended. The modes are resolved afresh where
    a phase would start so: the rim leaves, the sphere stays (sticking, or creeping at the
    edge of its cone: the drilling resistance's linear law, 1e-4 of the top's time, tips it
    from one to the other at this split), and no row pulls."""
    top = PlayTop(
        0.02058858666589197, 3.508195021542103e-07, 4.2207267796355587e-07,
        shape=[Sphere(0.006916317415095848, z=-0.0009723037927996734),
               Torus(0.008782695439624387, 0.0, z=0.0018150446059144974),
               Sphere(0.0, z=-0.009017877542506568)],
        friction=CoulombContensou(0.4335324640396776, 0.00012690642841453633),
        drilling_resistance=2.108076763234713e-05,
    )  # fmt: skip
    st = PlayState(quaternion=np.array([-0.12713118703215343, 0.12101826562553963,
                                        0.9661624580331242, -0.18900355910980457]),
                   omega=np.array([0.8776758722115844, 0.0, 0.0]),
                   com=np.array([0.0, 0.0, 0.05547159881889811]),
                   com_velocity=np.array([0.0011297050810010214, 0.0, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    near = [(e.name, e.part) for e in tr.events if abs(e.t - 0.2178274) < 1e-6]
    assert ("lift_off", "part1") in near
    assert ("slip_to_roll", "part0") in near or ("creep", "part0") in near
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slip_stopped_by_another_parts_stick_sticks_too():
    """Floor campaign, seed 1, case 5415: a top upside down on its sharp rim and its point
    (Coulomb friction, rolling and drilling resistance) slides to rest on both, their slips
    nearly equal (the top hardly turns). The impulse that sticks the point at 0.2187580 s
    stops the rim's slip too, below the stick speed: the rim's `slip_to_roll` event, located
    on its slip falling to that speed, could not be seen from below it, and the rim went on
    sliding at slips of 1e-13 m/s, its law's direction chattering through 4 million steps in
    2e-8 s until the run was refused. A part whose slip a switch has already stopped is now
    stopped as at that event: both parts stick at that instant and the top comes to rest."""
    top = PlayTop(
        0.01577049178894355, 2.937431676683099e-06, 2.773655095283138e-06,
        shape=[Torus(0.022571488843499413, 0.0, z=-0.011448423826313517),
               Sphere(0.0, z=0.03995524887748883)],
        friction=Coulomb(0.3106948427994063), rolling_resistance=0.00172776848363518,
        drilling_resistance=0.0015667440771423144,
    )  # fmt: skip
    st = top.state(theta=2.876114105984642, phi=1.3269168809399297, psi=2.7496675524645324,
                   theta_dot=-0.049566783941722446, phi_dot=5.718264996804398,
                   psi_dot=-12.630315409067833)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "event"  # the rest
    assert tr.stats["steps"] < 5000
    sticks = {e.part: e.t for e in tr.events if e.name == "slip_to_roll" and e.t > 0.2}
    assert set(sticks) == {"part0", "part1"}
    assert 0.21875 < sticks["part0"] < 0.21876
    assert sticks["part1"] == pytest.approx(sticks["part0"], abs=1e-9)
    assert tr.events[-1].name == "rest"
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_part_off_the_floor_at_a_bounce_does_not_limit_the_flights_steps():
    """Floor campaign, seed 1, case 2559: a disk upside down, its ball below and its sharp rim
    2.3 cm up and level, bounces on the ball (restitution 0.95). The step limit of a flight
    after a bounce (a quarter of the bouncing part's expected flight, so that its touchdown is
    not stepped over) was taken over every part off the floor, the rim included: its gap's
    rate (4e-5 m/s, from the impact's spin) over its lowest point's free acceleration (5e9
    m/s^2 on a level sharp rim, where that point turns at any rate) gave steps of 8e-7 s
    through a flight of 0.18 s, 230 000 rows. Only parts at the floor at the impact bounce."""
    top = PlayTop(
        0.014482963135581542, 5.245193936069084e-07, 1.0490387872138168e-06,
        shape=[Sphere(0.018093040892314557, z=-0.004475202203307892),
               Torus(0.008545895913429111, 0.0, z=-0.009544506704941547)],
        friction=CoulombContensou(0.16152205264460184, 0.0), restitution=0.95,
    )  # fmt: skip
    st = top.state(theta=math.pi, psi=6.179849979255903, phi_dot=1.774519147934952,
                   vy=0.012117170883445208, height=0.0440107667833457)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3)
    assert tr.status == "completed"
    assert tr.stats["steps"] < 1000
    downs = [e.t for e in tr.events if e.name == "touchdown" and e.part == "part0"]
    assert len(downs) == 2
    # The flight between them: the centre of mass leaves at vz and the ball's lowest point
    # stays below G by the same height (the top hardly tilts), so it lasts 2 vz / g.
    t = np.asarray(tr["t"])
    r = int(np.searchsorted(t, downs[0], side="right")) - 1  # the row after the impact
    assert t[r] == downs[0]
    vz = np.asarray(tr.com_velocity)[r, 2]
    assert downs[1] - downs[0] == pytest.approx(2.0 * vz / G, rel=1e-3)
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-12 * total[0]


def test_a_dynamic_jam_whose_sticking_impulse_leaves_the_cone_is_an_impact():
    """Floor campaign, seed 1, case 2387: a top under Coulomb-Contensou friction (mu 0.95)
    slides on its ring with sliding's own coefficient heading for zero (the Painleve dynamic
    jam), its normal force growing as the coefficient's inverse. The tangential impact that
    should end it stopped the contact point only where that impulse lay in the cone; here it
    did not, nothing was done, the jam event (which started past its level) never fired
    again, and the normal force grew past 300 weights until the steps fell below 1e-16 s and
    the run was refused. The impact now goes on at the law's friction until the slip stops or
    has turned the coefficient clear of zero, and the jam is watched afresh from where each
    phase starts."""
    from kreisel.shapes import Spheroid

    top = PlayTop(
        0.031038597578746743, 1.0469786983045076e-06, 1.0353096722592859e-06,
        shape=[Torus(0.00467042388412155, 0.0009356582119759214, z=-0.01578014028821223),
               Torus(0.009845507402240529, 0.003353227073438942, z=0.0028594601106977213),
               Spheroid(0.006640919632618385, 0.002292425597315563, z=9.406324894992244e-05)],
        friction=CoulombContensou(0.9474347037112664, 5.9627904151504836e-05),
        rolling_resistance=0.000427808577224141,
    )  # fmt: skip
    st = top.state(theta=2.3768808624358426, phi=0.9917849198421828, psi=3.3540934647729554,
                   theta_dot=12.390314924575033, psi_dot=-7.9377714084716855)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert tr.stats["steps"] < 20000
    jams = [e.t for e in tr.events if e.name == "tangential_impact"]
    assert jams and 0.000455 < jams[0] < 0.000457
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_landing_never_takes_the_sliding_branch_of_a_painleve_contact():
    """Floor campaign, seed 1, case 7116: a cone (one sphere) under Coulomb-Contensou
    friction (mu 0.65) lands on its ball. Where sliding's own coefficient is negative, sliding
    with a pushing normal force is consistent, and so is flight: the landing took sliding (at
    -245 /kg), whose normal force grows without bound (0.19 N to 3900 N in 1.3 ms, 170 000
    weights) until the steps fell below 1e-16 s. The modes of a contact no longer take a
    sliding part whose coefficient is not positive: the top bounces and slides on with its
    normal force bounded."""
    top = PlayTop(
        0.0023691980229201617, 1.3828015040264449e-08, 1.3185743135361687e-08,
        s=0.005106741999366141, rho=0.007325804375420137,
        friction=CoulombContensou(0.652516768471943, 0.00016709258903575028),
        restitution=0.95, rolling_resistance=0.00039999673832978794,
    )  # fmt: skip
    st = top.state(theta=1.2299919344783508, theta_dot=10.581594155289139,
                   phi_dot=40.52035128909267, height=0.04424741072242146)  # fmt: skip
    _completes_with_bounded_pushing_forces(top, st)


def test_viscous_friction_may_jam():
    """Floor campaign, seed 1, case 500: a top of three parts under viscous friction
    (2.06 s/m: a force of mu |v| per unit normal force, 1.3 at its slip of 0.65 m/s) slides on
    its rim. Viscous friction was taken never to jam; the normal force grew past 280 N on a
    37 g top until the steps fell below 1e-16 s. Its force per unit normal force has no bound,
    so it is watched for the jam like the laws that can stick."""
    from kreisel.shapes import Spheroid

    top = PlayTop(
        0.03716866967458169, 3.964633402584378e-06, 2.683322663573635e-06,
        shape=[Spheroid(0.006194410970256744, 0.01890066772390389, z=-0.01241995817270403),
               Sphere(0.01614761543588894, z=-0.023732915868213487),
               Torus(0.017682065487616118, 0.0004160659804440846, z=-0.04800389173407224)],
        friction=Viscous(2.060421336462543), rolling_resistance=1.1499421213072118e-05,
        drilling_resistance=2.154110713075515e-05,
    )  # fmt: skip
    st = top.state(theta=0.8206119610960622, phi=4.985552752410004, phi_dot=0.319993578724153,
                   psi_dot=0.5412396208005358, height=0.04132309715289833)  # fmt: skip
    _completes_with_bounded_pushing_forces(top, st)


def _completes_with_bounded_pushing_forces(top, st):
    """A run to 0.3 s (or rest) completes, every part's normal force pushes (to 1e-9 of the
    weight) and stays below a hundred weights, and E + dissipated never rises."""
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    n = np.asarray(tr.part_normal_force)
    assert n.max() < 100 * top.m * G
    assert n.min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_sharp_rim_slapping_down_level_lands_flat():
    """Floor campaign, seed 1, case 7829: a top rolling on a sharp rim (radius 9.7 mm) comes
    down nearly level while G still falls at 0.22 m/s. The contact point must run round the
    rim ever faster and the normal force that keeps the rim rolling grows without bound before
    the tilt reaches the flat level (sin = 1e-4): at a tilt of 1.8e-4 it was 250 N on a 40 g
    top and rising, the steps 1e-13 s, and the run was refused as stalled. A ring lands flat
    where its tilt's sine is 1e-4 max(1, N / (100 m g)) (docs: theory, "Lying flat"): here
    the plastic impact of its face, then it slides and spins on its face to rest."""
    top = PlayTop(
        0.040504900112877315, 3.2086083840958274e-06, 2.9568237240109664e-06,
        shape=[Torus(0.009913721944166136, 0.0044379093825816455, z=0.0026897699049424208),
               Torus(0.009661868987465743, 0.0, z=-0.006885488816703225),
               Torus(0.011800161063137674, 0.0009460775600228377, z=-0.001657290649413978),
               kreisel.shapes.Spheroid(0.002838304893845779, 0.0018067635407805539,
                                       z=0.014737268413665551)],
        friction=CoulombContensou(0.9334088593124539, 0.00044931112330581536),
        restitution=0.9268874019088301, rolling_resistance=0.0002875812703695107,
    )  # fmt: skip
    st = PlayState(quaternion=np.array([-0.042368357203422746, 0.50463064627263,
                                        -0.49532606517572597, -0.7058363282715641]),
                   omega=np.array([-0.5338999213604145, 0.0, 0.0]),
                   com=np.array([0.0, 0.0, 0.01442592078089299]),
                   com_velocity=np.array([0.0, 0.0, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "event" and tr.events[-1].name == "rest"
    flat = [e for e in tr.events if e.name == "flat"]
    assert len(flat) == 1 and flat[0].part == "part1"
    # at the event: the row just before it, the tilt within the level its force sets
    k = np.searchsorted(tr.t, flat[0].t) - 1
    weights = tr.part_normal_force[k, 1] / (top.m * G)
    assert weights > 100  # the force's rule, not the plain level, landed it
    sin_tilt = math.sqrt(max(0.0, 1.0 - tr.u[k] ** 2))
    assert sin_tilt == pytest.approx(1e-4 * weights / 100, rel=0.05)
    # lying flat after it: the rim on the floor, G at the rim's height above it
    after = tr.t > flat[0].t
    assert np.all(tr.u[after] == pytest.approx(1.0, abs=1e-12))
    assert np.abs(part_gaps([top.shape[1]], tr)[0, after]).max() < 1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G


def test_a_top_sticking_on_two_parts_keeps_a_bounded_split_and_no_false_slip():
    """Floor campaign, seed 1, case 3369: a 3 g top rolling on its sphere and sharp rim, both
    sticking, the friction forces along the line between them statically indeterminate. Where
    the needed friction turned through an axis (0.2071 s) the elimination's rounding left the
    redundant pivot at 9e-14 of the matrix, above the rank test's 1e-13: the system was taken
    as full rank, the split came out at +-2835 N, and a roll_to_slip was located on that
    false margin; the rim then slid at a stopped slip beside the sphere's creep and its law's
    direction chattered for 460 000 steps in 4.4e-5 s (a hang). The needed friction, the same
    at both parts (the least-norm split), stays inside both cones by a third throughout
    (|F| / mu N <= 0.7, computed here from the rows): both parts roll to the end."""
    top = PlayTop(0.0031806774262363503, 2.8421667606604916e-08, 2.768015348396597e-08,
                  shape=[Sphere(0.005463066509591871, z=0.0019563638786888006),
                         Torus(0.0068555546008916566, 0.0, z=-0.002029940799566041)],
                  friction=Coulomb(0.20822491145211564), restitution=0.95)  # fmt: skip
    st = top.state(theta=1.7723098942330682, psi=0.4888611334855169, vx=0.20970651866922851)
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and len(tr.t) < 1000
    on = tr.t > 0.03
    assert np.all(tr.part_mode[on] == "rolling")
    f = np.linalg.norm(tr.part_friction_force[on], axis=2)
    use = f / (0.20822491145211564 * tr.part_normal_force[on])
    assert use.max() < 0.7
    assert [e.name for e in tr.events if e.t > 0.03] == []
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_viscous_friction_with_no_consistent_mode_locks_the_slip_before_sliding():
    """Floor campaign, seed 1, case 8627: a disk-like top under strong viscous friction
    (2.59 s/m, restitution 0) lands its spheroid at a slip of 0.3 m/s. No mode was consistent
    even after the viscous jam's impact, and the part was left sliding with the floor pulling
    (9 N on a 39 g top), its friction feeding the slip from 0.3 to 18 m/s in 2.4 ms until the
    steps fell below 1e-16 s. Where no mode is consistent the slip is now stopped by the
    plastic impulse (as for the laws that stick); viscous friction is zero at zero slip, and
    the part slides on from there, pressed."""
    from kreisel.shapes import Spheroid

    top = PlayTop(
        0.038574632419502486, 2.826291856837722e-07, 5.652583713675444e-07,
        shape=[Sphere(0.0, z=0.020452898074259755),
               Spheroid(0.00594571945786027, 0.010702192998921407, z=0.00040876497737765347)],
        friction=Viscous(2.59019592094108), rolling_resistance=0.0010473606549556234,
    )  # fmt: skip
    st = top.state(theta=2.3635918302365813, phi=1.0520647220601578, psi=4.720071697351148,
                   psi_dot=0.5923582714056181, vx=-0.11568138449506772,
                   vy=-0.02074559736660988, height=0.0)  # fmt: skip
    _completes_with_bounded_pushing_forces(top, st)
    tr = kreisel.simulate(top, st, 0.3)
    down = [e.t for e in tr.events if e.name == "touchdown" and e.part == "part1"]
    assert len(down) == 1
    k = np.searchsorted(tr.t, down[0], side="right") - 1  # the row after the touchdown
    slip = np.hypot(*tr.part_slip_velocity[k, 1].T)
    assert tr.part_mode[k, 1] == "sliding" and slip < 1e-12
    # the slip never runs away: the viscous force only takes energy
    assert np.hypot(tr.part_slip_velocity[:, 1, 0], tr.part_slip_velocity[:, 1, 1]).max() < 0.2


def test_a_part_stopped_by_its_landing_that_cannot_stick_creeps_pressed():
    """Floor campaign, seed 2, case 1707: a 48 g top spinning at 269 rad/s lands on a sharp
    rim; the impact stops the rim's slip and it cannot stick. Whether it was set creeping
    turned on the stick tried at the impact pushing or not, at rounding level; where not, the
    rim slid along the direction it had slid in before, the floor pulling it with 2.71 N for
    the row after the touchdown (the next row, 4e-11 s later, pushed). A phase that would
    start pulling, with no set of modes pressing, now lets the parts whose slips are stopped
    creep (the consistent sliding direction): the rim presses with 0.055 N from the start."""
    top = PlayTop(
        0.047555448439458116, 2.250690491625745e-06, 3.6186758901838957e-06,
        shape=[Sphere(0.0, z=-0.0004474403982521989),
               Sphere(0.008917967140134962, z=-0.006588773762155707),
               Torus(0.017880468004991237, 0.0, z=-0.015279304586754356),
               Torus(0.013282315485098924, 0.0, z=-0.01610508006261467)],
        friction=Coulomb(0.6520400210047206),
    )  # fmt: skip
    st = top.state(theta=1.3947129288236877, psi_dot=-269.35584203133567, height=0.0)
    tr = kreisel.simulate(top, st, 0.3)
    assert tr.status == "completed"
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    down = [e.t for e in tr.events if e.name == "touchdown" and e.part == "part2"]
    assert down
    after = [np.searchsorted(tr.t, t, side="right") - 1 for t in down]  # rows after them
    on = [k for k in after if tr.part_mode[k, 2] != "flight"]
    assert any(abs(tr.t[k] - 0.2325971) < 1e-6 for k in on)
    assert all(tr.part_normal_force[k, 2] > 0.0 for k in on)


def test_a_slide_held_at_a_few_stick_speeds_is_tried_sticking():
    """Floor campaign, seed 2, case 4129: a 1.2 g oblate spheroid under Coulomb-Contensou
    friction (patch 16 um) slides from the start; at 0.0836 s its slip and drilling settle at
    about 3.6 stick speeds (the law's own equilibrium at the edge of its ellipse), just above
    the speed its slip_to_roll is located at, so neither the stick nor the creep was ever
    tried; the law's direction turns at about 1e10 /s there, Radau IIA crawled and DOP853
    went on at steps of 1e-9 s until the run was refused as stalled. Where the implicit steps
    hand over so and a sliding part's measure is within the creep's exit range, the phase
    ends as at that part's slip_to_roll: here it cannot stick, and creeps."""
    from kreisel.shapes import Spheroid

    top = PlayTop(0.0011879096464077043, 4.608041420286269e-09, 8.62544341277981e-09,
                  shape=[Spheroid(0.004455182177235138, 0.0016687307022146373,
                                  z=0.0001357680588608915)],
                  friction=CoulombContensou(0.4384207497043944, 1.5884609745171846e-05),
                  restitution=0.95, drilling_resistance=0.0006192143975870365)  # fmt: skip
    st = top.state(theta=2.5040831882059154, psi=6.035611762016422,
                   theta_dot=-2.2263478136127555, psi_dot=-45.166060564543905,
                   vx=-0.46801504212769635, vy=0.005666026352477603)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 100_000
    first = [(e.name, round(e.t, 4)) for e in tr.events[:3]]
    assert first == [("slip_to_roll", 0.0836), ("roll_to_slip", 0.0836), ("creep", 0.0836)]
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slide_held_at_a_few_stick_speeds_under_crawling_steps_is_tried_sticking():
    """Floor campaign, seed 2, case 1314: a 0.34 kg top on a spheroid and a torus under
    Coulomb-Contensou friction (patch 20 um). From 0.090 s the torus creeps and the
    spheroid slides at about 1.2 stick speeds (its slip 2.2e-9 m/s: the law's own equilibrium
    beside the creep, just above the speed its slip_to_roll is located at); the law's
    direction turned so fast there that Radau IIA went on at steps of about 1e-7 s, 507 696
    accepted and a million rejected, without crawling by the run's step budget: 510 000
    rows and 33 s for 0.3 s. Where the mean of 512 steps falls below 1e-4 of the top's time
    sqrt(reach / g) while a sliding part is held within the creep's exit range, the phase
    ends as at that part's slip_to_roll, explicit or implicit. The motion's outcome is the
    same: the brute-force run dissipated 0.1088469829 J by 0.3 s (the slow build, stop 40),
    and E + dissipated never rises."""
    from kreisel.shapes import Spheroid

    top = PlayTop(0.3418217203875621, 0.0002042552997302861, 0.00027592134793013353,
                  shape=[Spheroid(0.008122775322416861, 0.032874302919825585,
                                  z=0.007223264804116355),
                         Torus(0.03538893734968474, 0.011230728642101943,
                               z=-0.011573790769976614)],
                  friction=CoulombContensou(0.8292878344621943, 1.953298366498696e-05),
                  restitution=0.7457778177304223,
                  rolling_resistance=0.0006384446895329508)  # fmt: skip
    st = top.state(theta=2.0015044176432424, phi=2.9821768750137614,
                   theta_dot=-0.9883968167492508, psi_dot=-28.858940609963835,
                   vx=0.03601083495890606, height=1.1290673587565826e-06)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 20_000
    creeps = {e.part for e in tr.events if e.name == "creep"}
    assert creeps == {"part0", "part1"}
    assert abs(tr.dissipated[-1] - 0.1088469829) < 1e-6 * tr.dissipated[-1]
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G
    assert np.nanmin(np.asarray(tr.part_contact_point)[..., 2]) >= -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_creep_turned_back_past_its_range_hands_over_to_the_law():
    """Floor campaign, seed 3, case 6045: a torus under Coulomb-Contensou friction lands on
    its side and creeps; at 0.111 s its slip (5e-5 m/s) turns away from the creep's
    direction. Putting it back on the direction by the dissipative impulse, in the contact's
    own metric where the patch's drilling is stiff, stretched it to 1.9e-3 m/s, ten times the
    creep's range (1e-3 mu g / Omega): the creep's end could no longer be located, the slip
    grew to 0.23 m/s under the creep's friction, and that friction fed in 2.1e-5 J (0.86 % of
    the energy) by 0.18 s. Now the law takes over there. While the part creeps, its slip
    stays within the range (bounded here by 1e-3 mu g / |omega|), and E + dissipated never
    rises."""
    mu = 0.5799624531242383
    top = PlayTop(0.006719868428720892, 9.522824591559342e-08, 1.8130440737096498e-07,
                  shape=[Torus(0.008094910149666982, 0.002407247043309947,
                               z=-0.0009492515565157336)],
                  friction=CoulombContensou(mu, 5.985784748686977e-05),
                  drilling_resistance=4.7493418525089335e-05)  # fmt: skip
    st = top.state(theta=1.5707963267948966, theta_dot=2.0992616137506777,
                   psi_dot=0.9232773796208527, vx=-0.061396369842941376,
                   height=0.02617116199605264)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    t = np.asarray(tr.t)
    slip = np.linalg.norm(np.asarray(tr.part_slip_velocity)[:, 0, :], axis=1)
    omega = np.linalg.norm(np.asarray(tr.omega), axis=1)
    starts = [e.t for e in tr.events if e.name == "creep"]
    ends = [e.t for e in tr.events if e.name == "creep_end"]
    assert starts and len(ends) == len(starts)
    assert any(abs(t1 - 0.11108) < 1e-4 for t1 in ends)
    for t0, t1 in zip(starts, ends):
        inside = (t > t0) & (t < t1)
        assert np.all(slip[inside] <= 1.001e-3 * mu * G / omega[inside]), (t0, t1)
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    assert np.diff(np.asarray(tr.dissipated)).min() >= -1e-12 * total[0]


@pytest.mark.parametrize("case", ["two rings, frictionless", "four parts, viscous"])
def test_bounces_beside_a_touching_part_end_in_contact(case):
    """Floor campaign, seed 3, cases 1120 and 6383: a top lying on its side bounces on one
    part while another touches. Whether a bounce is below the cut-off (its rise
    vn^2 / 2a under the gap's deceleration a) was judged in free flight, where the part
    seemed to lift off of itself (a <= 0): the bounce was always kept, the contact beside it
    brought the part back at once, and its rise settled at the touchdown offsets: a
    touchdown every 2.2e-7 s until the run was refused for chattering (200 000 switches).
    Judged beside the other parts' contacts, the bounces shrink geometrically to the cut-off
    (ln(h0 / cut-off) / ln(1 / e^2), a few dozen) and the part stays: no part below the floor
    by more than 1e-9 m, E + dissipated never rises."""
    if case == "two rings, frictionless":
        parts = [
            Torus(0.025792644415929666, 0.003800874272033871, z=-0.004152483829296356),
            Torus(0.01707278350521039, 0.0011695161782196463, z=0.024097371377880414),
        ]
        top = PlayTop(
            0.03050055005133018,
            3.1121549638272346e-06,
            5.191248387126655e-06,
            shape=parts,
            friction=kreisel.Frictionless(),
            restitution=0.45192565299922416,
        )
        st = top.state(
            theta=1.5707963267948966,
            phi=5.08999062883632,
            psi=3.0533094072033333,
            psi_dot=25.58280437762101,
        )
    else:
        parts = [
            Torus(0.02910745510503855, 0.0065581029451215, z=0.014941779124794325),
            Sphere(0.017995092293979692, z=0.028443042088285977),
            Torus(0.02176144298528489, 0.0, z=-0.01272498517638213),
            Sphere(0.022782211970470655, z=0.009294022773824753),
        ]
        top = PlayTop(
            0.09158038025249172,
            1.2191394788886993e-05,
            1.4300793830365415e-05,
            shape=parts,
            friction=Viscous(0.38457296455328716),
            restitution=0.36056504774828635,
            rolling_resistance=0.00016107398874983542,
        )
        st = top.state(theta=1.5707963267948966, phi=5.475668842669865,
                       phi_dot=-16.425286392203425, psi_dot=158.52011785039355)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    touchdowns = [e for e in tr.events if e.name == "touchdown"]
    assert 0 < len(touchdowns) < 100
    in_contact = [name for name, m in tr.part_modes.items() if m[-1] != "flight"]
    assert len(in_contact) >= 2
    assert part_gaps(parts, tr).min() >= -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_creep_whose_steps_crawl_hands_the_part_to_its_law():
    """Floor campaign, seed 3, case 3877: a 2.2 g top upside down on a spheroid (sliding)
    and a sphere (creeping) under point Coulomb friction. The creep's friction comes from
    the consistency of the contact, which beside the sliding part had two roots, 35 degrees
    apart; the solve jumped between them at every step, the steps fell to 4e-11 s and the run
    was refused as stalled at 0.2358 s (1.4e9 steps to go). Where the mean of 512 steps falls
    below 1e-4 of the top's time sqrt(reach / g) while a part creeps, the creep ends and the
    part slides under its law: a few such hand-overs within 30 us, then the sphere slides on,
    its slip growing (to about 0.08 m/s by 0.3 s), with every property of the floor held."""
    from kreisel.shapes import Spheroid

    parts = [Torus(0.007777386965337658, 0.0019637084342658253, z=0.004214973613641105),
             Spheroid(0.00835939411536529, 0.004352513360407701, z=0.005584110856694667),
             Sphere(0.004102335695271579, z=0.008048820708908432),
             Sphere(0.0055987715253564465, z=0.0032483333757368123)]  # fmt: skip
    top = PlayTop(0.0022088105376754374, 3.766759234898705e-08, 6.252698307116479e-08,
                  shape=parts, friction=Coulomb(0.31767463885626546),
                  restitution=0.2990899367892805)  # fmt: skip
    st = PlayState(quaternion=np.array([0.09455247663326843, 0.9435435226770065,
                                        0.3119873205498936, 0.058731267591279446]),
                   omega=np.array([2.9587479267981798, 0.0, 80.34673532007892]),
                   com=np.array([0.0, 0.0, 0.011951714150562082]),
                   com_velocity=np.array([0.0, 0.0, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 50_000
    late = [e for e in tr.events if e.t > 0.2358]
    assert 0 < len(late) < 100
    assert late[-1].name == "creep_end"
    assert tr.part_modes["part2"][-1] == "sliding"
    assert part_gaps([p for p in parts if isinstance(p, Sphere)], tr).min() >= -1e-9
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slide_held_just_above_the_stick_speed_while_its_patch_drills_rolls_on_drilling():
    """Floor campaign, seed 5, case 1858: a 13 g top upside down lands on a sphere under
    Coulomb-Contensou friction (patch 27 um) and slides; its slip falls to 1.6e-9 m/s, the
    law's own equilibrium with the patch drilling at about 5e-8 m/s, just above the stick
    speed at which slip_to_roll (here: rolling on drilling) is located, and the slip the
    drilling's friction needs was just above the stick speed too, so the drilling was never
    taken. The law's relaxation there held the steps at 2e-9 s until the run was refused as
    stalled at 2.4 ms. Where steps crawl so with the slip within the drilling's exit range,
    the part drills where the slip its friction needs is within that range (ten stick
    speeds; the range the drilling leaves at), then sticks when the drilling ends."""
    from kreisel.shapes import Spheroid

    top = PlayTop(0.013259887266497756, 6.001595021484339e-07, 1.2003190042968678e-06,
                  shape=[Spheroid(0.00982124214743506, 0.013425797940471286,
                                  z=-0.001110223134330554),
                         Sphere(0.01844846199045571, z=0.03761222376870198),
                         Torus(0.017253492258302652, 0.0, z=0.017615547175399798)],
                  friction=CoulombContensou(0.9886536895139083,
                                            2.7433367152035696e-05))  # fmt: skip
    st = PlayState(quaternion=np.array([0.11570755860733511, 0.9932833235694286, 0.0, 0.0]),
                   omega=np.array([2.533218631502596, 0.0, 0.0]),
                   com=np.array([0.0, 0.0, 0.05505356286794203]),
                   com_velocity=np.array([0.0010085751777352467, 0.028668570565415247,
                                          0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 20_000
    first = [(e.name, e.part) for e in tr.events[:3]]
    assert first == [("touchdown", "part1"), ("slip_to_roll", "part1"), ("drill_end", "part1")]
    assert 0.0020 < tr.events[1].t < 0.0023
    assert np.asarray(tr.part_normal_force).min() >= -1e-9 * top.m * G
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_normal_force_heading_for_zero_dips_through_it_between_two_clear_step_ends():
    """Floor campaign, seed 1, case 2130 at rtol 1e-8: a 6.4 g spheroid sliding under viscous
    friction; its normal force fell to 1.6 mN at one step's end, turned to a pull of about
    0.8 mN inside the 2 ms step and was 1.3 mN again at its end. Both ends were too far from
    zero for the locator's interior check, so the lift-off was missed and the pull's friction
    did negative work: the dissipated energy fell by 2.5e-9 J. The last step's slope carried on
    through the step flags it; the lift-off is located where the runs at rtol 1e-9 to 1e-11
    locate it (a convergence reference: the first event after 0.15 s at rtol 1e-11)."""
    from kreisel.shapes import Spheroid

    top = PlayTop(0.006432152918302915, 7.319951687187416e-08, 1.4639903374374832e-07,
                  shape=[Spheroid(0.007485443766454548, 0.004719971131630052,
                                  z=0.00023035507757343272)],
                  friction=Viscous(4.245387648865457),
                  restitution=0.7230236618669625)  # fmt: skip
    st = top.state(theta=0.036413602915726186, psi=5.544190937014065,
                   theta_dot=-0.12929887319345712, psi_dot=161.39894746310526,
                   vx=-0.21095033722920528)  # fmt: skip

    def first_after(tr, t0):
        return next((e.name, e.t) for e in tr.events if e.t > t0)

    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-8)
    fine = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-11)
    name, t_lift = first_after(tr, 0.15)
    assert name == "lift_off" and first_after(fine, 0.15)[0] == "lift_off"
    assert abs(t_lift - first_after(fine, 0.15)[1]) < 1e-6
    d = np.asarray(tr.dissipated)
    assert np.diff(d).min() >= -1e-12 * d[-1]
    total = np.asarray(tr.energy) + d
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_contact_ended_by_an_event_is_recorded_on_the_floor():
    """Floor campaign, seed 1, case 611 at rtol 1e-8: a frictionless 23 g top touches down on
    its tip and lifts off within one 5.4 ms step. Every step's end is put back on the
    contact's constraints, but the state at a located event comes from the step's dense
    output; the tip's gap there had drifted to -1.2e-9 m, below the floor in the row at the
    lift-off. No row may have a part more than 1e-9 m below the floor (gaps from G's height
    and the tilt alone)."""
    top = PlayTop(0.022995226465457493, 8.11581484604081e-06, 9.420146095321336e-06,
                  s=0.008202522939250365, rho=0.024332937722586184,
                  friction=kreisel.Frictionless())  # fmt: skip
    st = PlayState(quaternion=np.array([-0.3717657798847339, 0.6850693789605299,
                                        0.17515691824941987, -0.6014899873702767]),
                   omega=np.array([86.37460406399285, 3.5747496824623637,
                                   -12.835097569603862]),
                   com=np.array([0.0, 0.0, 0.0384667692859734]),
                   com_velocity=np.array([0.0, 0.0, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-8)
    names = [e.name for e in tr.events]
    assert "touchdown" in names and "lift_off" in names
    gaps = part_gaps([Sphere(0.024332937722586184, z=-0.008202522939250365)], tr)
    assert gaps.min() >= -1e-9


def test_a_slide_whose_friction_needs_just_above_the_stick_speed_starts_drilling_once():
    """Floor campaign, seed 2, case 2236 at rtol 1e-8: a 1.3 g ball (G 11 um off its centre)
    rolling under Coulomb-Contensou friction, its patch drilling at 4e-5 m/s. The slide's
    slip relaxes to the slip its friction needs, which was just above the stick speed: the
    slip hovered at it, the switch to drilling was located and refused (the need was above
    the one stick speed it allowed) 2727 times in 0.2 ms, the first step after the last
    refusal grew the slip to 1.4e-3 m/s and fed in 2.5e-9 J (2e-5 of E). Drilling now starts
    where the need is within DRILL_ENTRY = 2 stick speeds. The dissipated energy and the
    final spin agree with the run at rtol 1e-11, which slides throughout (its stick speed is
    a thousandth as large) and takes 916 steps (a convergence reference)."""
    top = PlayTop(0.0012989352126263653, 2.044250130051121e-08, 4.088500260102242e-08,
                  shape=[Sphere(0.009245464621020345, z=1.0760251534354393e-05)],
                  friction=CoulombContensou(0.8877305714357469,
                                            2.0915391416289326e-05))  # fmt: skip
    st = top.state(theta=1.700392440626833, phi=3.9269938607448207, psi=2.718409367223459,
                   theta_dot=-0.07010542750573555, psi_dot=15.819553581770815)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-8)
    fine = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-11)
    assert tr.stats["steps"] < 1000 and len(tr.events) <= 3
    assert [e.name for e in tr.events][:1] == ["slip_to_roll"]
    np.testing.assert_allclose(tr.dissipated[-1], fine.dissipated[-1], rtol=1e-6)
    np.testing.assert_allclose(tr.omega[-1], fine.omega[-1], rtol=0, atol=1e-4)
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def _spheroid_phi(a, b, u):
    # the lowest point of a spheroid (equatorial a, axial b) below its centre at tilt u
    return np.sqrt(a * a * (1.0 - u * u) + b * b * u * u)


@pytest.mark.parametrize("case", ["8342", "8859"])
def test_a_part_touching_down_beside_a_drifted_contact_is_on_the_floor(case):
    """Floor campaign, seed 4, cases 8342 and 8859 at rtol 1e-8: frictionless tops on one part
    when another touches down, after steps of 17 and 19 ms. The touching part's gap in the
    step's dense output had drifted by 1.26e-9 and 3.0e-9 m: putting G on it sank the part
    touching down as far below the floor. The drift is shared half each way up to 1e-9 m,
    and beyond it the top is turned onto the tilt where both parts are level. Every part of
    every row is within 1e-9 m of the floor or above it, a touching one within 1e-9 m of it
    (gaps from G's height and the tilt alone), and E + dissipated never rises beyond the
    integration's error."""
    from kreisel.shapes import Spheroid

    if case == "8342":
        parts = [Torus(0.011492665184210075, 0.005440394813602326, z=-0.0370446720660874),
                 Spheroid(0.029073708022891786, 0.029073708022891786,
                          z=0.015157115480023364)]  # fmt: skip
        top = PlayTop(1.263642401236845, 0.00047119128306708847, 0.00020208066114780988,
                      shape=parts, friction=kreisel.Frictionless())  # fmt: skip
        st = PlayState(quaternion=np.array([0.8127658505147036, 0.22501365764125883,
                                            -0.06550370528973203, -0.5333758437587222]),
                       omega=np.array([0.0, 42.688337960359895, -4.474371941341944]),
                       com=np.array([0.0, 0.0, 0.043657014948943106]),
                       com_velocity=np.array([0.0, 0.0, 0.0]))  # fmt: skip
    else:
        parts = [Sphere(0.007031457564485429, z=0.0020318962877598316),
                 Spheroid(0.01979759235144255, 0.005964026137229931, z=0.029052116191053603),
                 Torus(0.028488261479053104, 0.005520152029684048,
                       z=0.03340274751228893)]  # fmt: skip
        top = PlayTop(0.11597379462092049, 5.162423243050806e-05, 8.869071691342575e-05,
                      shape=parts, friction=kreisel.Frictionless())  # fmt: skip
        st = top.state(theta=1.6871359076732528, psi=5.287723052805289,
                       theta_dot=-5.216541248209005, phi_dot=2.150855441893812,
                       psi_dot=-6.01520999157347, height=0.002431126521181228)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-8)
    u, zg = tr.u, tr.com[:, 2]
    gaps = np.array([zg + p.z * u - (_spheroid_phi(p.equatorial, p.axial, u)
                                     if isinstance(p, Spheroid) else _phi(p, u))
                     for p in parts])  # fmt: skip
    assert gaps.min() >= -1e-9
    touching = np.asarray(tr.part_in_contact).reshape(len(tr.t), -1).T.astype(bool)
    assert np.abs(gaps[touching]).max() <= 1e-9
    assert sum(e.name == "touchdown" for e in tr.events) >= 2
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    # DOP853's own energy error at rtol 1e-8 (the campaign's allowance: 1e-9 + 50 rtol)
    assert np.diff(total).max() <= (1e-9 + 50 * 1e-8) * total[0]


@pytest.mark.parametrize("case", ["286", "2045", "13/8633"])
def test_a_ring_slapping_down_level_upside_down_lands_flat(case):
    """Floor campaign, seed 5, cases 286 and 2045: tops upside down on a ring (a torus of
    2 mm tube; a sharp rim) under Coulomb-Contensou friction, coming down nearly level with
    their horizontal spin kept. The contact point races round the rim, the normal force grew
    to 140 and 560 weights at tilts of 2.8e-3 and 7.7e-4 while the tilt still fell slowly, the
    steps fell to 1.5e-10 s, and both runs were refused as stalled. Seed 13, case 8633: a
    175 g top rolling down onto a sharp rim of 12.8 mm, pressed by 63 weights at a tilt of
    1.4e-4, its steps at 2e-11 s (refused as stalled while the rule asked for 100 weights).
    A ring pressed by more than 10 weights within a tilt of 1e-2 whose steps crawl lands
    flat, then spins down flat to rest. Checked: the landing's tilt and force (from the
    rows), every part above the floor (gaps from G's height and the tilt alone),
    E + dissipated never rising."""
    if case == "13/8633":
        parts = [Torus(0.012804873241906035, 0.0, z=-0.03413670371479238),
                 Sphere(0.0, z=-0.014424391784342894),
                 Sphere(0.020992621941900373, z=0.0016881461338681542)]  # fmt: skip
        top = PlayTop(0.17484368895279306, 9.578479038708864e-06, 1.915695807741773e-05,
                      shape=parts,
                      friction=CoulombContensou(0.7737288403361463, 1.0798217343468859e-05),
                      restitution=0.95, rolling_resistance=0.001490254226135496)  # fmt: skip
        st = PlayState(quaternion=np.array([-0.7038622566902575, 0.0, 0.0,
                                            -0.7103364861858767]),
                       omega=np.array([0.0, -32.875300410709556, -3.039259410321482]),
                       com=np.array([0.0, 0.0, 0.03559415309924067]),
                       com_velocity=np.array([0.008908443801065036, 0.0,
                                              -0.07306640334765907]))  # fmt: skip
    elif case == "286":
        parts = [Torus(0.010629096258617974, 0.002084099350943285, z=0.003127487152603966),
                 Sphere(0.003443695648331083, z=-0.008428942714102529),
                 Torus(0.020408920470193537, 0.0026229274010381993,
                       z=-0.010586654871893083)]  # fmt: skip
        top = PlayTop(0.006845035241257144, 4.775466807247413e-07, 8.798208492775761e-07,
                      shape=parts,
                      friction=CoulombContensou(0.9640800658154284, 1.095853652962518e-05),
                      restitution=0.41834796483247655)  # fmt: skip
        st = PlayState(quaternion=np.array([-0.364771315087626, -0.6369155291040288,
                                            -0.6791357176239006, 0.007427888182270109]),
                       omega=np.array([0.2895921574421741, -0.6988808258804283,
                                       -0.8603042507309894]),
                       com=np.array([0.0, 0.0, 0.01996821653282325]),
                       com_velocity=np.array([0.0, -0.017442619977831687, 0.0]))  # fmt: skip
    else:
        parts = [Torus(0.018628421602034758, 0.0, z=0.0029323498673258057),
                 Torus(0.028313634700795728, 0.0, z=-0.0006595644322424758),
                 Sphere(0.0, z=-0.01948852432851452)]  # fmt: skip
        top = PlayTop(0.01968363773661979, 4.214882819806423e-06, 7.807077273113426e-06,
                      shape=parts,
                      friction=CoulombContensou(0.8559992309311065, 0.00016751362834000277),
                      restitution=0.0667539664445605)  # fmt: skip
        st = top.state(theta=2.7168748475062974, phi=0.8023506752394803,
                       phi_dot=-0.247338434347339)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "event" and tr.stats["steps"] < 20_000
    flat = [e for e in tr.events if e.name == "flat"]
    assert len(flat) == 1 and flat[0].part == "part0"
    assert tr.events[-1].name == "rest"
    before = np.searchsorted(tr.t, flat[0].t) - 1
    assert 0.0 < math.sqrt(1.0 - tr.u[before] ** 2) <= 1e-2
    assert np.asarray(tr.part_normal_force)[before, 0] >= 10 * top.m * G
    assert part_gaps(parts, tr).min() >= -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_ring_does_not_land_flat_where_another_part_would_be_below_the_floor():
    """Floor campaign, seed 2, case 7371: a top of four rings upside down under
    Coulomb-Contensou friction comes down on a sharp rim pressed by more than 100 weights
    with its steps crawling. Landing that rim flat (the stalled-slap rule) turned the top by
    up to 1e-2 rad and put another ring 3.2e-5 m below the floor. A ring lands so only where
    every other part is then above the floor; every row's parts are within 1e-9 m of it or
    above (gaps from G's height and the tilt alone)."""
    parts = [Torus(0.01530768066996215, 0.000828691817408655, z=0.008268736597899543),
             Torus(0.02977948547898167, 0.0, z=0.009065965120122773),
             Torus(0.033365318365152385, 0.008193086479728242, z=-0.020298172995770268),
             Torus(0.012047839217479848, 0.004401659946799979,
                   z=-0.010194086243967846)]  # fmt: skip
    top = PlayTop(0.04226413776757685, 1.0804117480638135e-05, 1.7681209833509074e-05,
                  shape=parts, friction=CoulombContensou(0.992942126425399, 3.99382888572948e-05),
                  restitution=0.95)  # fmt: skip
    st = top.state(theta=3.1415925665926094, phi=2.2554490701490195,
                   theta_dot=-6.841340228809995, phi_dot=2.496988845866432,
                   height=0.024892025642657068)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status in ("completed", "event")
    assert part_gaps(parts, tr).min() >= -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_creep_turned_onto_its_direction_books_the_energy_it_takes_once():
    """Floor campaign, seed 1, case 1528 at rtol 1e-6: a 7.7 g top on two tori and a
    spheroid under Coulomb-Contensou friction; a failed stick leaves a part creeping, and
    its slip is turned onto the creep's direction and the state put back on the contacts.
    The projection books the kinetic energy it removes as dissipated itself; the turn's
    balance, taken on the kinetic energy around it, booked it a second time: E + dissipated
    rose by 2.5e-7 J (1.7e-4 of E). E + dissipated is conserved by the equations of motion
    and only falls at a switch; it may rise by no more than the integration error."""
    top = PlayTop(0.00767101376318667, 1.1693602310097496e-07, 2.338720462019499e-07,
                  shape=[Torus(0.008700454098737714, 0.004067507043000459,
                               z=-0.00611912867767779),
                         Spheroid(0.0015492514716274153, 0.0013490162684690126,
                                  z=0.004554976230971484),
                         Torus(0.008814982605975592, 0.0, z=0.0022696310720272906)],
                  friction=kreisel.CoulombContensou(0.27308512713153127,
                                                    1.1423651269991513e-05),
                  restitution=0.6725450800645119,
                  drilling_resistance=4.8901694146981084e-05)  # fmt: skip
    st = PlayState(quaternion=np.array([-0.06511037493331998, 0.11715823118636977,
                                        0.6973334560060065, 0.7041027191227446]),
                   omega=np.array([-95.22294678657384, 0.5047781626759728,
                                   -0.30436550666134016]),
                   com=np.array([0.09585821443996165, 0.0, 0.012767961141738175]),
                   com_velocity=np.array([-0.005067890515470974, 0.0, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-6)
    assert "creep" in [e.name for e in tr.events]
    total = tr["energy"] + tr["dissipated"]
    # the integration's own share: 50 rtol of the start's energy (as the campaign allows)
    assert (total - total[0]).max() <= 50 * 1e-6 * total[0]


def _ledger_kept(tr, rtol):
    """The dissipated energy never falls and E + dissipated never rises beyond the
    integration's own share, 50 rtol of the start's, as the floor campaign allows."""
    total = tr["energy"] + tr["dissipated"]
    allowed = 50 * rtol * total[0]
    assert np.diff(tr["dissipated"]).min() >= -allowed
    assert (total - total[0]).max() <= allowed


def test_an_events_state_keeps_the_phases_energy_and_dissipation():
    """Floor campaign, seed 2, case 7140 at rtol 1e-6: a 3.2 g top on four sharp rims under
    point Coulomb friction, upside down, slaps down flat on a rim. The state at the located
    `flat` event is the step's dense output, of order 3 where Radau IIA took the step: it
    had lost 4.6e-6 J of E + dissipated, and the dissipated energy there was 1.5e-6 J below
    the row before. E + dissipated is conserved along a phase, so the event's state takes
    the phase's; the dissipated energy never falls."""
    top = PlayTop(0.003194320050651308, 8.648762234411373e-08, 1.7297524468822746e-07,
                  shape=[Torus(0.01055245550896689, 0.0, z=-0.006556511503031623),
                         Torus(0.004443421381787808, 0.0, z=-0.011102683555898649),
                         Torus(0.002743100402951447, 0.0, z=0.002584989358115911),
                         Torus(0.0027575900773219157, 0.0, z=-0.0005198440578533278)],
                  friction=Coulomb(0.9016377648779472),
                  drilling_resistance=5.170907641491641e-05)  # fmt: skip
    st = top.state(theta=3.050828431178938, phi=4.523041024857772, height=0.04280563128111149)
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-6)
    assert "flat" in [e.name for e in tr.events]
    _ledger_kept(tr, 1e-6)


def test_a_phase_that_no_set_of_modes_keeps_pressing_lets_the_pulled_part_leave():
    """Floor campaign, seed 3, case 3546 at rtol 1e-8: a 0.26 kg top on a sphere and two tori
    under Coulomb-Contensou friction, the sphere sliding with its measure at the creep speed,
    where its law's friction changes branch; the torus's normal force jumps through zero
    there. The lift-off located on the jump was refused (no set of modes kept both parts
    pressing) and the next phases started with the floor pulling the torus by 0.165 N. The
    floor cannot pull: the torus leaves, and no touching part is pulled in any row."""
    top = PlayTop(0.26471049332604113, 1.7816304653604563e-05, 3.5632609307209126e-05,
                  shape=[Sphere(0.008383177400775469, z=0.002392562091685759),
                         Torus(0.01961208298452989, 0.004770593780830629,
                               z=0.014348266592672344),
                         Torus(0.021879813465010278, 0.0042019033425823174,
                               z=0.01899049131164044)],
                  friction=CoulombContensou(0.7793722015893687, 2.0660881111516433e-05),
                  restitution=0.95, drilling_resistance=9.431577991104377e-05)  # fmt: skip
    st = top.state(theta=math.pi / 2, vx=0.4567833075851608, vy=-0.002615166710072804,
                   height=0.025969003825544297)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-8)
    lifts = [e for e in tr.events if e.name == "lift_off" and 0.1815 < e.t < 0.1816]
    assert lifts and lifts[0].part == "part1"
    touching = tr["part_mode"] != "flight"
    assert tr["part_normal_force"][touching].min() >= -1e-9 * 0.26471049332604113 * 9.81


def test_a_normal_force_dipping_through_zero_in_a_phases_first_step_is_seen():
    """Floor campaign, seed 8, case 5023 at rtol 1e-6: a 30 g top on two tori under
    Coulomb-Contensou friction touches down on its fat torus and slides. The phase's first
    step was 12 ms long; inside it the torus's normal force fell from 0.028 N to a pull of
    0.024 N and rose to 0.020 N. The locator looks inside a step where the last step's
    slope heads for zero, and a phase's first step has none: the lift-off was missed, and
    the pulled friction fed 2e-5 J in (the dissipated energy fell by that in one step).
    The dissipated energy never falls, and E + dissipated never rises."""
    top = PlayTop(0.03029470579903082, 4.276162515597574e-06, 6.4122569859757715e-06,
                  shape=[Torus(0.01757235101127964, 0.0, z=-0.013777175377675858),
                         Torus(0.021909091006755203, 0.0030005434200889598,
                               z=0.011921123688940277)],
                  friction=CoulombContensou(0.3393514287922496, 1.1507233352200898e-05),
                  drilling_resistance=0.00011394476982613519)  # fmt: skip
    st = top.state(theta=2.493567302501573, psi=1.487692692602032,
                   phi_dot=-50.76859278742804, psi_dot=1.130353554153181,
                   vx=-0.002077417941010598, height=0.03446367770074431)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-6)
    lifts = [e.t for e in tr.events if e.name == "lift_off" and 0.1785 < e.t < 0.1906]
    assert lifts
    _ledger_kept(tr, 1e-6)


def test_a_ring_coming_down_flat_beside_a_pole_below_its_plane_rests_on_the_pole():
    """Floor campaign, seed 7, case 9484 (every rtol): a 1.8 g top upside down on a sharp
    rim, its spheroid's pole reaching 1.28e-7 m past the rim's plane (the pole at body
    z = -0.0028095 + 0.0056113, the rim at 0.0028017). Its tilt fell below the flat level
    with the pole still above the floor, and laying the rim flat put the pole 1.28e-7 m into
    the floor. The top now lies flat on the pole, the rim 1.28e-7 m above the floor (the
    state of a top on its pole and rim at a tilt of 2.4e-5 rad, below the flat level), and
    no part is ever below it. On the pole it spins down under the patch's drilling torque
    mu N rbar, rbar = 3 pi R / 16 (the Coulomb-Contensou law at zero slip, theory: "Friction
    laws"): the spin falls at mu m g rbar / C."""
    m, a, c = 0.0017783797297072444, 5.0560085739213835e-09, 1.0112017147842767e-08
    mu, radius = 0.7260612465753467, 0.0005068571047192349
    rim = Torus(0.00535056764655552, 0.0, z=0.002801653434752315)
    pole = Spheroid(0.0026477236855045228, 0.005611265424306459, z=-0.0028094839002067457)
    top = PlayTop(m, a, c, shape=[rim, pole], friction=CoulombContensou(mu, radius))
    st = top.state(theta=3.14049504940001, phi=3.291249852214779,
                   psi_dot=-3.4581208989067274)  # fmt: skip
    for rtol in (None, 1e-8, 1e-6):
        tol = {} if rtol is None else {"rtol": rtol}
        tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], **tol)
        assert part_gaps([rim, pole], tr).min() >= -1e-9
        names = [e.name for e in tr.events]
        assert names[0] == "flat" and names[-1] == "rest", names
        t = np.asarray(tr.t)
        i = int(np.searchsorted(t, tr.events[0].t, side="right"))
        # Flat on the pole: the pole touches at the floor, the rim is above it by the pole's
        # reach past its plane (upside down, G is as high as the pole reaches above it).
        assert np.asarray(tr.part_in_contact)[i:, 1].all()
        assert not np.asarray(tr.part_in_contact)[i:, 0].any()
        reach = pole.z + pole.axial - rim.z
        assert 1.2e-7 < reach < 1.3e-7
        z = np.asarray(tr.com)[i:, 2]
        np.testing.assert_allclose(z, pole.z + pole.axial, rtol=0, atol=1e-12)
        np.testing.assert_allclose(z - rim.z, reach, rtol=1e-6)  # the rim's height
        # The spin falls linearly, at mu m g rbar / C, while it lasts (the last rows stop at
        # the stick speed).
        w = np.abs(np.asarray(tr.omega)[i:, 2])
        on = w > 0.2 * w[0]
        slope = np.polyfit(t[i:][on], w[on], 1)[0]
        assert on.sum() >= 5
        assert -slope == pytest.approx(mu * m * 9.81 * (3 * math.pi * radius / 16) / c, rel=2e-3)
        total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
        assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_slide_whose_steps_a_missed_stiffness_holds_goes_on_implicitly():
    """Floor campaign, seed 10, case 2831: a 3.8 g top upside down on a sharp rim under
    Coulomb-Contensou friction with a drilling resistance. Coming down towards level, its
    spin about the figure axis relaxes under the rim's patch at about 1e10 /s (C = 3.1e-8
    kg m^2): DOP853 was stable at steps of 2.6e-10 s and not at 3.7e-10 s, but its
    stiffness test (along the last stages' difference) never tripped, and the run was
    refused as stalled at 0.0443 s. A slide whose explicit steps fall below the held pace
    with no switch to end it on goes on by Radau IIA: the rim sticks at 0.047 s. (The same
    run then stalled at 0.164 s, where Radau IIA's Newton iteration failed at steps above
    1e-8 s; it now slides again, lands flat at 0.074 s and rests at 0.085 s.)"""
    parts = [Spheroid(0.006925046267248409, 0.009958749318736809, z=-0.016186554598119948),
             Torus(0.006274931338621115, 0.0, z=0.0030480885484631508)]  # fmt: skip
    top = PlayTop(0.0037926319955674864, 1.5567157213201374e-07, 3.060310441251321e-08,
                  shape=parts, friction=CoulombContensou(0.380783051481319, 3.511484908747904e-05),
                  restitution=0.95, drilling_resistance=0.0006862728851255611)  # fmt: skip
    st = top.state(theta=3.0665337302707316, phi=0.40401387234015623, psi=4.36424608070319,
                   psi_dot=-44.10118353836169)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "event" and tr.events[-1].name == "rest"
    stuck = [e.t for e in tr.events if e.name == "slip_to_roll" and e.part == "part1"]
    assert stuck and 0.044 < stuck[0] < 0.05
    assert "flat" in [e.name for e in tr.events]
    assert part_gaps(parts, tr).min() >= -1e-9
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]


def test_a_drilling_resistance_stopping_a_spin_keeps_the_ledger_across_its_kink():
    """Floor campaign, seed 16, case 5955: a 2.6 g frictionless ball top upside down on its
    tip, its drilling resistance (1.8 mm) stopping the spin about the vertical at 0.065 s.
    The law is sharp down to a rate and linear below it (docs: theory, "Rolling and drilling
    resistance"); DOP853 took one step of four of the linear law's relaxation times across
    that kink, its error estimate blind to it, and E + dissipated rose by 7.2e-9 of the
    energy at the default rtol (the campaign allows 50 rtol). A phase restarts at the kink,
    nothing recorded there."""
    top = PlayTop(0.0026224797476976504, 2.6380682697913575e-08, 3.2322315811535664e-08,
                  s=0.0021287792441263952, rho=0.0038850804583236338,
                  friction=kreisel.Frictionless(),
                  rolling_resistance=1.4103590243887775e-05,
                  drilling_resistance=0.0017771196562104408)  # fmt: skip
    st = top.state(theta=2.8006294949539012, psi_dot=99.7318991787842,
                   height=5.453062606027911e-06)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    _ledger_kept(tr, 1e-10)
    # only the touchdown is an event, and only its time has two rows (before and after)
    assert [e.name for e in tr.events] == ["touchdown"]
    assert (np.diff(tr.t) == 0).sum() == 1
    # the spin about the vertical has stopped: within the linear law's band (4.3e-3 rad/s)
    q = tr["quaternion"][-1]
    w, x, y, z = q / np.linalg.norm(q)
    up = np.array([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])
    assert abs(up @ tr["omega"][-1]) < 1e-5 * st.omega[2]


def test_a_slide_whose_drilling_is_refused_slips_on_through_the_stick_speed():
    """Floor campaign, seed 16, case 8547 at rtol 1e-6: a 55 g torus (19.4 mm, tube 6.9 mm)
    dropped upside down, nearly flat, under Coulomb-Contensou friction. Its slip fell
    through the stick speed while its patch still drilled; drilling there needed 2.8 stick
    speeds of slip, above the 2 at which a part starts to drill, so the switch was refused
    and the part slid on, its slip still falling: the switch was located and refused again
    every 1e-11 s until the run was refused as stalled at 0.237 s. A refused switch to
    drilling is not watched again until another switch: the slide goes on under its law and
    the ring comes down flat and rests."""
    parts = [Torus(0.01939035965800984, 0.0068814230506669665, z=-5.8833620805567866e-05)]
    top = PlayTop(0.054971649033823504, 5.665991391903069e-06, 1.0809336376755391e-05,
                  shape=parts,
                  friction=CoulombContensou(0.5026035246538226, 0.0009068103393499746),
                  restitution=0.7369503551198388,
                  rolling_resistance=0.001220530728872401)  # fmt: skip
    st = PlayState(quaternion=np.array([-3.6803539827955813e-09, 0.24019745395783199,
                                        -0.9707240509599909, -9.650803196487464e-10]),
                   omega=np.array([0.0, 1.559405139830225, 0.0]),
                   com=np.array([0.0, 0.0, 0.01175043172084214]),
                   com_velocity=np.array([0.0, -0.3350062158329749, 0.0]))  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-6)
    assert tr.status == "event" and tr.stats["steps"] < 5_000
    assert [e.name for e in tr.events][-2:] == ["slip_to_roll", "rest"]
    assert "flat" in [e.name for e in tr.events]
    assert part_gaps(parts, tr).min() >= -1e-9
    _ledger_kept(tr, 1e-6)


def test_a_creep_whose_slip_turns_away_at_once_is_handed_to_its_law():
    """Floor campaign, seed 17, case 8713: a 2.7 g top upside down landing on a torus under
    Coulomb-Contensou friction with rolling and drilling resistance. The torus creeps (sliding
    at the cone's edge, its slip about 1e-8 m/s), and its slip turned away from the creep's
    direction within 1.3e-8 s of every realignment: 200000 switches at t = 0.0728 s, the run
    refused as chattering. After 64 realignments in a row the creep ends and the law slides
    the part on. Checked: the run completes, the torus's creep ends where it began,
    every part above the floor, E + dissipated never rising."""
    parts = [Spheroid(0.012858395037801217, 0.003547830566375233, z=0.0007701227891740523),
             Sphere(0.004584012779939692, z=0.01968121410221079),
             Torus(0.004104696005420472, 0.0016255170195731599, z=0.02136484046577394)]  # fmt: skip
    top = PlayTop(0.002653400033164178, 9.519773565275275e-08, 6.922324670282971e-08,
                  shape=parts,
                  friction=CoulombContensou(0.805729936220889, 5.514628445209432e-05),
                  restitution=0.95, rolling_resistance=0.0002047594990262123,
                  drilling_resistance=0.001151703086039161)  # fmt: skip
    st = top.state(theta=math.pi, phi=2.287961712855421, theta_dot=-0.7180628770337949,
                   psi_dot=-4.959364227931975, vx=0.3908325270348724,
                   vy=-0.002461952989500025, height=0.0017688455664605853)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.1, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 5_000
    creeps = [(e.name, e.t) for e in tr.events if e.part == "part2" and "creep" in e.name]
    assert [n for n, _ in creeps] == ["creep", "creep_end"]
    assert creeps[1][1] - creeps[0][1] < 1e-6
    assert part_gaps(parts, tr).min() >= -1e-9
    _ledger_kept(tr, 1e-10)


def test_a_slip_that_stops_within_a_phases_first_step_is_not_stepped_through():
    """Floor campaign, seed 19, case 4290 at rtol 1e-6: a 0.3 kg top of four parts dropped
    upside down, spinning, under Coulomb-Contensou friction. After a run of bounces its ring
    came to slide at 9e-4 m/s, a slip that stops within about 6e-5 s; the starting-step
    heuristic (two evaluations of the motion) chose 1.4e-4 s, DOP853's error estimate
    passed the step through the stop, and E + dissipated rose by 5.2e-5 of the energy.
    A phase's first step is at most a quarter of the time a decelerating slip takes to stop.
    Checked: E + dissipated never rises by more than rtol of the start's (it rose by 5e-9),
    every part above the floor."""
    parts = [Torus(0.013490846044981424, 0.00298884389178889, z=0.002159061575088786),
             Sphere(0.015216187686903714, z=-0.0004806544564623632),
             Torus(0.02161036275382797, 0.0, z=-0.006339061560046816),
             Sphere(0.003560463864941634, z=0.022673065873584343)]  # fmt: skip
    top = PlayTop(0.29976527491430166, 3.3265272210353746e-05, 2.5541150437882398e-05,
                  shape=parts,
                  friction=CoulombContensou(0.9009365943290255, 4.62849601998314e-05),
                  restitution=0.6838274012561539,
                  rolling_resistance=0.00012762322267329077)  # fmt: skip
    st = top.state(theta=math.pi, phi=0.9893410096256464, psi=1.4140707558057273,
                   theta_dot=15.016883018687563, psi_dot=64.14502405030738,
                   vx=0.5592829119585465)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()], rtol=1e-6)
    assert tr.status == "completed"
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert (total - total[0]).max() <= 1e-6 * total[0]
    assert np.diff(tr.dissipated).min() >= -1e-6 * total[0]
    assert part_gaps(parts, tr).min() >= -1e-9


def test_a_drilling_patch_whose_rate_turns_through_zero_in_a_step_sticks():
    """Floor campaign, seed 5, case 8090: a 3.9 g top of a torus and two spheres rolling on
    its torus under Coulomb-Contensou friction with drilling and rolling resistance, its
    patch drilling at about 1.6e-5 rad/s. The drilling's end was located where
    rbar |w_n| falls to the stick speed, which dips below zero only within 2e-7 rad/s of
    w_n = 0: a step of 1.6e-6 s carried the rate from -1.6e-5 to 1.6e-4 rad/s unseen, the
    patch's torque turned round within it, and the part went from drilling to sliding and
    back hundreds of times (15 547 steps), E + dissipated rising by 1.5e-8 of the energy.
    The drilling's end is located on the rate signed as at the phase's start: the patch
    sticks. Checked: E + dissipated, every part above the floor, the run's steps."""
    parts = [Torus(0.006722999823336121, 0.0027589965088848467, z=-0.002065450499955629),
             Sphere(0.00122616812525154, z=0.01339642777377992),
             Sphere(0.0, z=0.002878752207958522)]  # fmt: skip
    top = PlayTop(0.0039444665271388514, 1.4468993063131302e-07, 1.760079131202634e-07,
                  shape=parts,
                  friction=CoulombContensou(0.6825486441882768, 0.00019677194239432503),
                  restitution=0.5679808580242269, rolling_resistance=1.0303978563556022e-05,
                  drilling_resistance=0.0005230747387996042)  # fmt: skip
    st = top.state(theta=math.pi / 2, phi=2.879380046866597, psi=0.724242451992935,
                   psi_dot=7.221104779177102)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed" and tr.stats["steps"] < 3_000
    _ledger_kept(tr, 1e-10)
    assert part_gaps(parts, tr).min() >= -1e-9


def test_a_part_starting_a_phase_at_zero_force_lifts_off_when_it_would_be_pulled():
    """Floor campaign, seed 22 at t_end 5 s, case 72: a 0.33 kg top of three rings and a
    sphere rolling on its sphere and its wide sharp rim under Coulomb-Contensou friction.
    At 1.6025 s the rim was set sliding with its normal force at -0 N; its lift-off (the
    force falling through zero) was watched from there, never crossed from above, and the
    floor pulled the rim by up to 0.114 N for 31 ms. A part that starts a phase at zero
    force or a pull within rounding has its lift-off located a hair below where it starts.
    Checked: no touching part pulled beyond 1e-9 of the weight (as the campaign checks),
    every part above the floor, E + dissipated never rising."""
    parts = [Torus(0.007662869470744073, 0.0, z=-0.005870039266783922),
             Torus(0.006964834233943418, 0.0011808659244683126, z=-0.005010534819197318),
             Torus(0.02439309444565472, 0.0, z=0.007214342846104602),
             Sphere(0.020234585292585365, z=0.009049860356529483)]  # fmt: skip
    top = PlayTop(0.33008678229463184, 8.674931019657507e-05, 0.0001395606781579578,
                  shape=parts,
                  friction=CoulombContensou(0.9568527799103461, 9.815621986719921e-05),
                  rolling_resistance=0.0006184664613445388)  # fmt: skip
    st = top.state(theta=math.pi / 2, theta_dot=-0.1917104085558792,
                   psi_dot=34.21335007895856)  # fmt: skip
    tr = kreisel.simulate(top, st, 1.7, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    force = np.asarray(tr.part_normal_force)
    touching = np.asarray(tr.part_in_contact).reshape(force.shape).astype(bool)
    assert force[touching].min() >= -1e-9 * top.m * G
    assert part_gaps(parts, tr).min() >= -1e-9
    _ledger_kept(tr, 1e-10)


@pytest.mark.parametrize("rtol", [None, 1e-8])
def test_two_parts_sticking_turn_only_about_the_line_through_their_contacts(rtol):
    """Floor campaign, seed 23 at t_end 5 s, case 677: a 1.4 g top of a fat ring and a
    small sphere under point Coulomb friction with a drilling resistance rolls on both from
    0.22 s. Two material points at rest leave a rigid body one freedom, a turn about the line
    through them, and that line lies on the floor: the spin about the vertical is zero.
    The second contact's slip was held at zero only through its acceleration; it drifted,
    the spin about the vertical grew to 4e-5 rad/s by 5 s, and E + dissipated rose 7.5e-9 of
    E at the default rtol (the campaign allows 6e-9) and 9e-6 at rtol 1e-8. The projection
    puts the velocities on that one freedom in the kinetic energy's metric. Checked: the
    spin about the vertical stays at rounding after 1 s while the top still rolls (|w| up
    to 41 rad/s), E + dissipated within 50 rtol."""
    parts = [Torus(0.005453621869490549, 0.0019765078428489145, z=0.0034383692870328356),
             Sphere(0.0018536599787098268, z=2.4441294013963395e-05)]  # fmt: skip
    top = PlayTop(0.0014141731723231418, 1.099064813523988e-08, 2.198129627047976e-08,
                  shape=parts, friction=Coulomb(0.9689698962596084),
                  drilling_resistance=0.0001748448490179819)  # fmt: skip
    st = PlayState(quaternion=[0.705212427682594, 0.7066361755867653, 0.025793707606894964,
                               -0.051724576769870634],
                   omega=[0.13064632850209948, -0.6408512270770091, 0.0],
                   com=[0.0, 0.0, 0.007430129712339462],
                   com_velocity=[-0.20477778368707616, 0.0, 0.0])  # fmt: skip
    kw = {} if rtol is None else {"rtol": rtol}
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()], **kw)
    assert tr.status == "completed"
    w, x, y, z = np.asarray(tr.quaternion).T
    gamma = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1)
    spin = (gamma * np.asarray(tr.omega)).sum(1)
    late = np.asarray(tr.t) > 1.0
    both = (np.asarray(tr.part_mode)[late] == "rolling").all(axis=1)
    assert both.sum() > 100
    assert np.abs(spin[late][both]).max() < 1e-10
    assert np.abs(np.asarray(tr.omega)[late]).max() > 10.0
    _ledger_kept(tr, 1e-10 if rtol is None else rtol)


def test_two_sticking_parts_split_their_forces_by_least_norm_not_by_rounding():
    """Floor campaign, seed 23 at t_end 5 s, case 2129: a 16 g top on a tip and a sphere
    rolls steadily on both from 1.69 s, its friction a tenth of its cone at the tip and a
    thirtieth at the sphere. Two material points at rest always leave one of their six rows
    redundant (the forces along the line between them are indeterminate), but the
    elimination's rounding can leave that row's pivot in the rank test's band of doubt,
    where a full-rank solution within a hundred times the least-norm one was taken: once
    the two parts' velocities were projected onto their one freedom, such a split at 3.188 s
    put the tip outside its cone, it crept, and E + dissipated rose 6.9e-9 of E by 5 s (the
    campaign allows 6e-9). Two sticking parts now always take the redundant solution.
    Checked: no event after 2 s, both parts rolling, the friction use within a fifth of each
    cone, E + dissipated within 50 rtol."""
    parts = [Sphere(0.0, z=-0.010770118632754962),
             Sphere(0.027036842723854735, z=0.022558533787939643),
             Sphere(0.014040608154016934, z=0.006326914197261255)]  # fmt: skip
    mu = 0.49328488733194165
    top = PlayTop(0.016151368512348014, 6.106265013648157e-06, 4.423683378528845e-06,
                  shape=parts, friction=Coulomb(mu))  # fmt: skip
    st = PlayState(quaternion=[-0.6758469094858629, 0.2571322592512668, -0.6613693850515162,
                               -0.19925986225862563],
                   omega=[0.0, 0.0, -3.432519209601927],
                   com=[-0.05632050029887006, 0.0, 0.02719594635863822],
                   com_velocity=[0.0, 0.0, -0.0013283499557153534])  # fmt: skip
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert [e.name for e in tr.events if e.t > 2.0] == []
    late = np.asarray(tr.t) > 2.0
    modes = np.asarray(tr.part_mode)[late]
    assert (modes[:, [0, 2]] == "rolling").all() and (modes[:, 1] == "flight").all()
    force = np.linalg.norm(np.asarray(tr.part_friction_force)[late][:, [0, 2]], axis=2)
    use = force / (mu * np.asarray(tr.part_normal_force)[late][:, [0, 2]])
    assert use.max() < 0.2
    _ledger_kept(tr, 1e-10)


def test_a_rolling_top_held_by_its_drilling_resistances_stiff_band_goes_on_implicitly():
    """Floor campaign, seed 26 at t_end 5 s and rtol 1e-6, case 1735: a 1.4 g ball top
    rolling back and forth on its ball, its spin about the vertical inside the drilling
    resistance's linear band, which relaxes it within microseconds. DOP853's steps were held
    by that stiffness (136 260 steps, 645 299 rejected), the accumulated error fed E +
    dissipated 7.4e-5 of E, and the top ended upside down (u = -0.85 by 4.4 s). A rolling
    phase with a resistance now goes on by Radau IIA where DOP853's steps are held by
    stability, as a slide does. Checked: far fewer steps, E + dissipated within 50 rtol, and
    u at eleven times within 1e-3 of a run at rtol 1e-10 (the story converged)."""
    top = PlayTop(0.001443099259152495, 4.939793113932709e-08, 6.309841402579902e-08,
                  s=0.007704086135715986, rho=0.014596244927567567,
                  friction=Coulomb(0.6039758796515672), restitution=0.95,
                  drilling_resistance=0.00016587417769070838)  # fmt: skip
    st = top.state(theta=0.3923495133880562, psi=3.905407993123862, psi_dot=-28.018840802958437,
                   vx=-0.3150791334600261, vy=-0.44518798356504563,
                   height=6.073693967393231e-05)  # fmt: skip
    times = np.linspace(0.0, 5.0, 11)
    tr = kreisel.simulate(top, st, 5.0, rtol=1e-6)
    assert tr.status == "completed"
    assert tr.stats["steps"] < 20000
    _ledger_kept(tr, 1e-6)
    loose = kreisel.simulate(top, st, 5.0, rtol=1e-6, t_eval=times)
    tight = kreisel.simulate(top, st, 5.0, rtol=1e-10, t_eval=times)
    assert np.abs(np.asarray(loose.u) - np.asarray(tight.u)).max() < 1e-3
    assert np.asarray(tight.u).min() > 0.2


def test_a_rim_rolling_nearly_flat_for_thousands_of_steps_keeps_its_ledger():
    """Floor campaign, seed 27 at t_end 5 s, case 839: a 14.6 g sharp rim of 12 mm under
    Coulomb-Contensou friction, started upside down and nearly flat, spinning at 15 rad/s.
    It rolls on its rim for tens of thousands of steps between 905 slides, and DOP853's
    local error moved E + dissipated both ways by about rtol of the energy a step: it rose
    by 5.6e-8 of E by 5 s (the campaign allows 1e-9 + 50 rtol). Where nothing dissipates
    (flight, or every touching part sticking, no resistance), E + dissipated is a first
    integral of the phase's equations, and each accepted step is now put back on it.
    Checked: E + dissipated within 50 rtol, the dissipated energy never falls, and the run
    tells the same story (the slides and rolls, nearly all its energy dissipated)."""
    top = PlayTop(0.01455116339919623, 9.035541753326787e-07, 1.8071083506653573e-06,
                  shape=[Torus(0.012013670404018371, 0.0, z=0.0)],
                  friction=CoulombContensou(0.7831818872575849, 0.00011731277913321711),
                  restitution=0.95)  # fmt: skip
    st = top.state(theta=3.133634075601824, phi=1.5618967743815402, psi=5.135259158944763,
                   theta_dot=-0.06054462790243988, psi_dot=-15.451782471344176,
                   height=0.0)  # fmt: skip
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    _ledger_kept(tr, 1e-10)
    names = [e.name for e in tr.events]
    assert names.count("slip_to_roll") > 100 and names.count("roll_to_slip") > 100
    total = tr["energy"][0] + tr["dissipated"][0]
    assert tr["dissipated"][-1] > 0.9 * total


def test_a_restart_at_a_resistance_kink_goes_on_implicitly_where_the_phase_did():
    """Floor campaign, seed 26 at t_end 5 s and rtol 1e-6, case 51: a 1.4 g frictionless ball
    top falls over and tumbles, its rate about the vertical in the drilling resistance's
    linear band, which relaxes it at about 1e9 /s. The phase restarts where that rate
    crosses the band's edge (the law's kink), and each restart began again by DOP853,
    whose explicit steps are unstable there: they overshot across the kink, which was
    located again at once. The rate was held at the kink's, 200 000 restarts and 2.6 million
    rejected steps by 2.6 s, and the run was refused as chattering. A restart at the kink
    after a phase that ended by Radau IIA now goes on by Radau IIA. Checked: the run
    completes in far fewer steps, E + dissipated within 50 rtol."""
    top = PlayTop(0.0014015438003801126, 8.080208628894475e-09, 8.277805131313659e-09,
                  s=0.002136099809134523, rho=0.005196946132038474,
                  friction=kreisel.Frictionless(), restitution=0.95,
                  drilling_resistance=1.0266040126167234e-05)  # fmt: skip
    st = top.state(theta=0.001435245837366802, psi_dot=-9.59421923698466)
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()], rtol=1e-6)
    assert tr.status == "completed"
    assert tr.stats["steps"] < 50_000
    _ledger_kept(tr, 1e-6)
    assert np.asarray(tr.u).min() < -0.9  # it fell over


def test_a_ring_sliding_alone_at_the_edge_of_its_ellipse_creeps_where_both_methods_crawl():
    """Floor campaign, seed 27 at t_end 5 s, case 188: a 2.1 g fat torus under
    Coulomb-Contensou friction with rolling and drilling resistance rolls upside down and
    comes down nearly flat, its friction at 0.97 of the ellipse and its patch hardly
    drilling. After a creep ended it slid on under its law at 27 stick speeds, the law's
    direction turning at about 1e10 /s: Radau IIA and then DOP853 crawled in steps of
    6e-10 s, and the run was refused as stalled at 3.275 s. Where both methods crawl, a
    part sliding alone within the creep's range is tried sticking and creeps where it
    cannot. Checked: the ring lands flat on its face and rests before 5 s, no part below
    the floor, E + dissipated within 50 rtol."""
    ring = Torus(0.013088930351092183, 0.005123479152578963, z=0.00092378477263681)
    top = PlayTop(0.002146223354737884, 1.241914150146695e-07, 2.3413848302671635e-07,
                  shape=[ring],
                  friction=kreisel.CoulombContensou(0.8661710274694965, 0.000128472400198242),
                  restitution=0.5809461803253365, rolling_resistance=4.1824439220019714e-05,
                  drilling_resistance=0.0005553339542851052)  # fmt: skip
    st = top.state(theta=np.pi / 2, phi=3.6394068795430004, psi=5.589918995194856,
                   phi_dot=1.7021939683316138, psi_dot=-1.3534386037231156,
                   vx=-0.09961422866063377)  # fmt: skip
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()])
    assert tr.status == "event"
    assert [e.name for e in tr.events][-2:] == ["flat", "rest"]
    assert tr["u"][-1] < -0.9999  # upside down, on its face
    assert part_gaps([ring], tr).min() >= -1e-9
    _ledger_kept(tr, 1e-10)


def test_a_step_across_a_resistance_kink_sees_no_kink_inside_it():
    """Floor campaign, seed 29 at t_end 5 s, case 1032: a 20 g frictionless ball top lying
    on its side spins at 201 rad/s, its rate about the vertical crossing the drilling
    resistance's kink again and again. The phase restarts at each crossing, but the law
    switched where the rate crossed, inside the step that crossed: that step's error
    estimate missed the kink, and one step of 1e-3 s (the first after a restart, a hundred
    times the steps before it) raised E + dissipated by 1.3e-8 of E at rtol 1e-10. A phase
    now keeps each law to the side of its kink it starts on, continued smoothly past it.
    Checked: E + dissipated within 50 rtol over the 5 s."""
    top = PlayTop(0.020097043927212576, 1.9445715600539807e-06, 3.8891431201079614e-06,
                  s=0.016701391503173398, rho=0.024750009043129316,
                  friction=kreisel.Frictionless(),
                  drilling_resistance=4.4331966489997876e-05)  # fmt: skip
    st = top.state(theta=np.pi / 2, phi=0.31173432649562755, psi_dot=201.12001721148056)
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert part_gaps([Sphere(0.024750009043129316, z=-0.016701391503173398)], tr).min() >= -1e-9
    _ledger_kept(tr, 1e-10)


def test_a_part_left_pulled_by_a_joint_stick_lifts_off_and_the_others_stick():
    """Floor campaign, seed 34 at t_end 5 s, case 2414: a 6 g four-part top under
    Coulomb-Contensou friction rocks between a sphere and a sharp rim until, its rotation
    stopped, it slides to rest on both. At the stop the sphere could stick and the rim not:
    the stick left the rim pulled by 1e-3 of the weight, and was refused; both slid on at
    the stick speed, every stick refused, until the steps fell to 1e-14 s and the run was
    refused. A part a stick leaves pulled now lifts off and the others stick. Checked: the
    run reaches its rest, the rim lifted off and the sphere sticking, no part below the
    floor, E + dissipated within 50 rtol."""
    parts = [Sphere(0.0, z=-0.013349728058078778),
             Sphere(0.0038291898508379858, z=-0.0001120716890532147),
             Sphere(0.0, z=-0.013298792945181027),
             Torus(0.009037343730350502, 0.0, z=-0.004486994198509857)]  # fmt: skip
    law = kreisel.CoulombContensou(0.9534094473030107, 9.042126316787616e-05)
    top = PlayTop(0.006266113044158946, 3.2429913566782544e-07, 4.167567340841583e-07,
                  shape=parts, friction=law)  # fmt: skip
    st = top.state(theta=0.42290193674407256, psi=4.344351368455504,
                   height=0.022273125615206606)  # fmt: skip
    tr = kreisel.simulate(top, st, 5.0, events=[kreisel.events.rest()])
    assert tr.status == "event" and tr.events[-1].name == "rest"
    last = [(e.name, e.part) for e in tr.events if e.t > 4.8062]
    assert ("lift_off", "part3") in last and ("slip_to_roll", "part1") in last
    assert list(tr.part_mode[-1]) == ["flight", "rolling", "flight", "flight"]
    assert part_gaps(parts, tr).min() >= -1e-9
    _ledger_kept(tr, 1e-10)


def test_a_strike_beside_a_kept_part_that_no_impulse_keeps_stands_as_it_was():
    """Floor campaign, seed 35 at t_end 5 s, case 34: an 82 g four-part top under
    Coulomb(0.75) with a drilling resistance rolls on a sharp rim when its tip strikes the
    floor. The plastic impact would lift the rim off so slowly that it keeps the rim (a
    rocking's end), but no impulse keeps it (it would have to pull), and the impact was left
    out altogether: the tip went on into the floor at 0.7 mm/s, its touchdown located again
    every 6e-11 s until 200 000 switches refused the run, at every rtol. The impact now
    stands as it was. Checked: the run completes, no part below the floor, E + dissipated
    within 50 rtol."""
    parts = [Sphere(0.007508969551166004, z=-0.03688005528178992),
             Torus(0.014153122882676205, 0.003971457494813681, z=-0.015838074059098053),
             Sphere(0.01046929742869391, z=-0.0026728307089577148),
             Torus(0.01691757890447829, 0.0, z=-0.02046911285658276)]  # fmt: skip
    top = PlayTop(0.08187296015936757, 4.825685821601059e-06, 9.651371643202118e-06,
                  shape=parts, friction=kreisel.Coulomb(0.7457115827154814),
                  drilling_resistance=0.0008792017381470855)  # fmt: skip
    st = top.state(theta=0.6713241379904793, phi=0.12683924277351044,
                   psi=0.7114870246943567, phi_dot=67.22807414470007,
                   psi_dot=-11.38747718500789)  # fmt: skip
    for rtol in (1e-8, 1e-10):
        tr = kreisel.simulate(top, st, 1.0, events=[kreisel.events.rest()], rtol=rtol)
        assert tr.status == "completed"
        assert tr.stats["steps"] < 20_000
        assert part_gaps(parts, tr).min() >= -1e-9
        _ledger_kept(tr, rtol)
