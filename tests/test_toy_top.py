"""The life of a toy top: spun below its sleeping threshold it precesses, falls onto
its shoulder, rolls on its tip and shoulder and comes to rest.

Independent references, derived here:

- The tilt at which the tip (a sphere of radius r_t at z_t on the axis) and the shoulder (a
  ring of major radius R, tube r_s at z_s) both touch the floor: the lowest points' heights
  (theory: bodies of revolution) are equal, z_t u - r_t = z_s u - R sqrt(1 - u^2) - r_s, solved by
  brentq.
- Rolling on both parts, the line through the two contact points is the instantaneous axis
  (both points are at rest): omega lies along it, horizontal. G's height is fixed, so the
  normal forces sum to m g, gravity and the contact forces do no work, and the kinetic energy is
  (1/2) I_n |omega|^2 with I_n = A u^2 + C (1 - u^2) + m h^2 the moment about that line (h is
  G's height, the line's distance from G). Rolling resistance (a torque -c N omega/|omega|)
  takes c m g |omega|, so |omega| falls linearly at c m g / I_n and the top stops in finite
  time.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import quat_to_matrix
from scipy.optimize import brentq

import kreisel
from kreisel import bodies, events

RR = 1e-4  # rolling resistance (m)


def lying_tilt(top):
    """u at which the tip and the shoulder both touch the floor (the geometry alone)."""
    tip, shoulder, _ = top.shape

    def gap(u):
        return (tip.z * u - tip.radius) - (
            shoulder.z * u - shoulder.major * np.sqrt(1 - u * u) - shoulder.minor
        )

    return brentq(gap, 0.0, 0.999, xtol=1e-15)


@pytest.fixture(scope="module")
def life():
    top = bodies.toy_top(rolling_resistance=RR)
    # 0.3 rad off the vertical at 60 rad/s: below the sleeping threshold (about 127 rad/s)
    st = top.state(theta=0.3, psi_dot=60.0)
    run = kreisel.simulate(top, st, 30.0, rtol=1e-10, events=[events.rest()])
    return top, run


def test_the_sleeping_threshold_is_above_the_spin(life):
    """The spins of this life and of the preset are below the sleeping threshold,
    C^2 w^2 < 4 A_tip m g l (a Lagrange top about the tip's centre)."""
    top, _ = life
    tip = top.shape[0]
    arm = -tip.z
    a_tip = top.A + top.m * arm * arm
    threshold = 2 * np.sqrt(a_tip * top.m * 9.81 * arm) / top.C
    assert 60.0 < 120.0 < threshold  # this life and the preset toy-top's


def test_it_falls_on_its_shoulder_rolls_and_stops(life):
    top, run = life
    names = [(e.name, e.part) for e in run.events]
    assert names[0] == ("touchdown", "shoulder")
    assert ("slip_to_roll", "tip") in names and ("slip_to_roll", "shoulder") in names
    assert names[-1] == ("rest", None)
    assert run.status == "event"
    # it ends on its tip and shoulder, the handle off the floor, at the tilt they fix
    assert run.part_in_contact[-1].tolist() == [True, True, False]
    assert run.u[-1] == pytest.approx(lying_tilt(top), abs=1e-9)
    # nothing drawn below the floor: G's height from the tip sphere, at every step
    tip = top.shape[0]
    assert (run.com[:, 2] + tip.z * run.u - tip.radius).min() > -1e-9


def test_energy_never_rises_and_is_accounted(life):
    _, run = life
    e = run.energy
    assert np.diff(e).max() <= 1e-12 * e[0]
    np.testing.assert_allclose(e + run.dissipated, e[0], rtol=1e-8)


def test_rolling_on_both_parts_is_a_rotation_about_the_contact_line(life):
    top, run = life
    t_roll = max(e.t for e in run.events if e.name == "slip_to_roll")
    t_rest = run.events[-1].t
    on = (run.t > t_roll) & (run.t < t_rest - 0.05)
    assert on.sum() > 50
    # both parts roll: no slip
    assert np.abs(run.part_slip_velocity[on][:, :2]).max() < 1e-8
    # omega is horizontal (the axis through both contact points lies on the floor)
    r = quat_to_matrix(run.quaternion[on].T)
    w_space = np.einsum("nij,nj->ni", r, run.omega[on])
    speed = np.linalg.norm(w_space, axis=1)
    assert np.abs(w_space[:, 2]).max() < 1e-7 * speed.max()
    # the normal forces carry the weight
    np.testing.assert_allclose(run.part_normal_force[on][:, :2].sum(axis=1), top.m * 9.81,
                               rtol=1e-7)  # fmt: skip
    # |omega| falls linearly at c m g / I_n
    u = lying_tilt(top)
    tip = top.shape[0]
    h = tip.radius - tip.z * u
    i_n = top.A * u * u + top.C * (1 - u * u) + top.m * h * h
    slope = np.polyfit(run.t[on], speed, 1)[0]
    assert slope == pytest.approx(-RR * top.m * 9.81 / i_n, rel=1e-6)
    # so it stops at the time that rate gives; the event "rest" comes when the kinetic energy
    # has fallen to 1e-12 of its start, omega_rest = sqrt(2e-12 KE0 / I_n) before that
    rate = RR * top.m * 9.81 / i_n
    k = np.argmax(on)
    ke0 = run.energy_translation[0] + run.energy_rotation[0]
    t_stop = run.t[k] + (speed[0] - np.sqrt(2e-12 * ke0 / i_n)) / rate
    assert t_rest == pytest.approx(t_stop, rel=1e-7)


def test_the_story_does_not_depend_on_the_tolerance(life):
    """The same switches at the same times at rtol 1e-8 (two parts that stop slipping at one
    instant may be recorded in either order)."""
    top, run = life
    st = top.state(theta=0.3, psi_dot=60.0)
    loose = kreisel.simulate(top, st, 30.0, rtol=1e-8, events=[events.rest()])
    for a, b in ((loose, run), (run, loose)):
        assert {(e.name, e.part) for e in a.events} == {(e.name, e.part) for e in b.events}
    for name in ("touchdown", "slip_to_roll", "rest"):
        ta = max(e.t for e in loose.events if e.name == name)
        tb = max(e.t for e in run.events if e.name == name)
        assert ta == pytest.approx(tb, abs=1e-6), name


def test_nothing_drawn_enters_the_floor(life):
    """The animation draws the toy top as the union of its parts with a cone from the tip to
    the shoulder (inside the parts' convex hull): every vertex at every computed state of its
    life, lying on its side included, is above the floor."""
    from kreisel import animate

    top, run = life
    shape = animate.shape_of(top)
    verts, _ = animate._mesh(shape, 36)
    frames = animate._at(run, top, run.t[::3])
    world = np.einsum("fij,abj->fabi", frames.rotation, verts + shape.centre)
    assert (world + frames.origin[:, None, None, :])[..., 2].min() > -1e-9
    # and it is drawn as a cone: the radius grows from the tip to the shoulder
    tip, shoulder = top.shape[0].z + top.s, top.shape[1].z + top.s
    cone = (shape.z > tip + 0.1 * (shoulder - tip)) & (shape.z < shoulder - 0.1 * (shoulder - tip))
    assert np.all(np.diff(shape.r[cone]) > 0)


def test_an_egg_with_rolling_resistance_comes_to_rest_on_its_side():
    """The default egg (Coulomb-Contensou friction) spun on its side at 80 rad/s with rolling
    resistance c = 0.1 mm: the drilling friction drains its spin, it sinks back and ends at
    rest (the event "rest", status "event") lying on its side. A rest off the lying
    equilibrium is held by the rolling resistance alone: the gravity torque about the contact,
    m g (b^2 - a^2) |u| / a for small u (the contact's offset from below G, theory: bodies of
    revolution), is at
    most c m g, so |u| <= c a / (b^2 - a^2). Sticking over a patch ends the drilling too (a
    drilling rate left below the tolerance would spin on for ever)."""
    egg = bodies.egg(rolling_resistance=1e-4)
    a, b = egg.shape[0].equatorial, egg.shape[0].axial
    run = kreisel.simulate(egg, egg.state(theta=np.pi / 2 - 0.1, phi_dot=80.0), 60.0,
                           rtol=1e-8, events=[events.rest()])  # fmt: skip
    assert run.status == "event" and run.events[-1].name == "rest"
    assert abs(run.u[-1]) <= 1e-4 * a / (b * b - a * a)
    assert np.linalg.norm(run.omega[-1]) < 1e-5
    assert np.diff(run.energy).max() <= 1e-12 * run.energy[0]
    np.testing.assert_allclose(run.energy + run.dissipated, run.energy[0], rtol=1e-7)


def test_simulate_many_reports_when_each_run_rests_or_lies_flat():
    """The batch's summaries rest_time and flat_time are the events of kreisel.simulate run
    alone (the batch ends a play top's run at rest, as simulate with events.rest() does)."""
    import math

    top = bodies.toy_top(rolling_resistance=RR)
    states = [top.state(theta=0.3, psi_dot=w) for w in (60.0, 120.0)]
    b = kreisel.simulate_many(top, states, 10.0, rtol=1e-8)
    for st, t_rest in zip(states, b.rest_time):
        run = kreisel.simulate(top, st, 10.0, rtol=1e-8, events=[events.rest()])
        assert t_rest == run.events[-1].t
    assert np.isnan(b.flat_time).all() and b.final_parts_in_contact.tolist() == [3, 3]
    disk = bodies.disk(0.0375, 0.0125, 0.434, rolling_resistance=2e-3)
    om = math.sqrt(disk.m * 9.81 * 0.0375 / disk.A / math.sin(0.3))
    st = disk.state(theta=0.3, phi_dot=om, psi_dot=-om * math.cos(0.3))
    b = kreisel.simulate_many(disk, st, 5.0, rtol=1e-8)
    run = kreisel.simulate(disk, st, 5.0, rtol=1e-8, events=[events.rest()])
    flat = [e.t for e in run.events if e.name == "flat"]
    # the disk lies flat, then spins down on its face and rests
    assert len(flat) == 1 and b.flat_time[0] == flat[0]
    assert run.events[-1].name == "rest" and b.rest_time[0] == run.events[-1].t > flat[0]
