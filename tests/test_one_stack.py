"""One simulation stack for every model: the rules and names of the core, the status of a
run, event indices, and the defects of the fuzz campaign (tiny fixed steps, play-top events
on a pivot top, empty output times) that the stack's single check removes."""

from __future__ import annotations

import dataclasses
import re
import time

import numpy as np
import pytest

import kreisel
from kreisel._simulate import names


@pytest.fixture(scope="module")
def lagrange():
    top = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)
    return top, top.state(0.5, psi_dot=300.0)


@pytest.fixture(scope="module")
def tippe():
    top = kreisel.PlayTop(0.02, 2.56e-6, 3.2e-6, 0.006, 0.02, friction=kreisel.Viscous(1.0))
    return top, top.state(3.0, psi_dot=150.0)


@pytest.mark.parametrize("event", [kreisel.events.rest(), kreisel.events.inversion(0.9)])
def test_a_play_top_event_on_a_pivot_top_is_refused_by_name(lagrange, event):
    top, st = lagrange
    with pytest.raises(kreisel.ParameterError, match=r"events\[0\].*heavy top has the events"):
        kreisel.simulate(top, st, 0.01, events=[event])


def test_a_pivot_top_event_on_a_play_top_is_refused_by_name(tippe):
    top, st = tippe
    with pytest.raises(kreisel.ParameterError, match=r"events\[0\].*play top has the events"):
        kreisel.simulate(top, st, 0.01, events=[kreisel.events.turning_points()])


@pytest.mark.parametrize("method", ["rk4", "splitting", "verlet", "midpoint", "gauss4"])
def test_a_fixed_step_run_of_more_steps_than_allowed_is_refused_at_once(lagrange, method):
    top, st = lagrange
    start = time.perf_counter()
    with pytest.raises(kreisel.ParameterError, match=r"dt = 1e-300 is not allowed: t_end / dt"):
        kreisel.simulate(top, st, 0.01, method=method, dt=1e-300)
    assert time.perf_counter() - start < 1.0
    # the cap is the core's, the same for every entry point
    with pytest.raises(kreisel.ParameterError, match="dt"):
        kreisel.simulate_many(top, [st], 0.01, method=method, dt=1e-300)


def test_empty_output_times_give_empty_columns(lagrange, tippe):
    top, st = lagrange
    traj = kreisel.simulate(top, st, 0.01, t_eval=[])
    for name in traj.columns:
        assert len(traj[name]) == 0, name
    assert "M3" in traj.columns and traj.status == "completed"
    top, st = tippe
    traj = kreisel.simulate(top, st, 0.01, t_eval=[])
    for name in traj.columns:
        assert len(traj[name]) == 0, name


def test_status_says_how_a_run_ended(lagrange, tippe):
    top, st = lagrange
    assert kreisel.simulate(top, st, 0.05).status == "completed"
    ev = kreisel.events.turning_points(terminal=True)
    traj = kreisel.simulate(top, st, 1.0, events=[ev])
    assert traj.status == "event" and traj.t[-1] == traj.events[0].t < 1.0
    top, st = tippe
    traj = kreisel.simulate(top, st, 8.0, events=[kreisel.events.inversion(0.9, terminal=True)])
    assert traj.status == "event" and traj.events[-1].name == "inversion"
    assert traj.t[-1] == traj.events[-1].t


def test_event_index_is_the_position_in_the_users_list(tippe):
    """The play top's own contact switches have index -1; the user's events their
    position in the list, whatever kind of top."""
    top = kreisel.PlayTop(
        0.02, 2.56e-6, 3.2e-6, 0.006, 0.02, friction=kreisel.Coulomb(0.3), restitution=0.5
    )
    st = top.state(2.0, theta_dot=5.0, psi_dot=80.0, height=0.01)
    evs = [kreisel.events.rest(terminal=False), kreisel.events.inversion(-0.5)]
    traj = kreisel.simulate(top, st, 1.0, events=evs)
    own = {"lift_off", "touchdown", "slip_to_roll", "roll_to_slip"}
    assert any(e.name in own for e in traj.events)
    for e in traj.events:
        if e.name in own:
            assert e.index == -1, e
        else:
            assert evs[e.index].name == e.name, e


def test_the_core_names_every_mode_and_summary_the_python_layer_shows(tippe):
    top, st = tippe
    traj = kreisel.simulate(top, st, 3.0)
    assert set(np.unique(traj.mode)) <= set(names()["modes"])
    fields = {f["name"] for f in names()["summaries"] if f["default"]}
    play = kreisel.simulate_many(top, [st], 0.5)
    # the core's per-part fields first_touchdown_time_<i> are one (runs, parts) array here
    assert {f.name for f in dataclasses.fields(play)} - {"errors"} == {
        re.sub(r"_\d$", "", f["name"]) for f in names()["summaries"] if f["model"] == "play"
    }
    lt = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)
    heavy = kreisel.simulate_many(lt, [lt.state(0.5, psi_dot=300.0)], 0.01)
    assert {f.name for f in dataclasses.fields(heavy)} - {"errors"} <= fields


def test_settings_are_checked_by_the_core_with_the_same_words_for_every_model(lagrange, tippe):
    for top, st in (lagrange, tippe):
        for kw, match in [
            (dict(rtol=2.0), r"rtol = 2.0 is not allowed: it must lie in \[1e-15, 1\)"),
            (dict(atol=0.0), r"atol = 0.0 is not allowed"),
            (dict(t_eval=[0.0, 0.02]), r"t_eval = 0.02 is not allowed.*\[0, t_end = 0.01\]"),
            (dict(t_eval=[0.005, 0.001]), r"t_eval\[1\] = 0.001 is not allowed: .*ascending"),
        ]:
            with pytest.raises(kreisel.ParameterError, match=match):
                kreisel.simulate(top, st, 0.01, **kw)
        with pytest.raises(kreisel.ParameterError, match=r"t_end = -1.0 is not allowed"):
            kreisel.simulate(top, st, -1.0)
        with pytest.raises(kreisel.ParameterError, match=r"t_end = -1.0 is not allowed"):
            kreisel.simulate_many(top, [st], -1.0)


def test_a_long_run_stops_on_ctrl_c():
    """A run released from the interpreter still asks it for signals (every 256 steps of an
    adaptive method, every 256 * 1024 of a fixed-step one): SIGINT raises KeyboardInterrupt
    within a fraction of a second instead of after the run's ~10 s."""
    import signal
    import subprocess
    import sys

    code = (
        "import kreisel, sys\n"
        "top = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)\n"
        "st = top.state(0.5, psi_dot=300)\n"
        "print('started', flush=True)\n"
        "try:\n"
        "    kreisel.simulate(top, st, 9999.0, method='splitting', dt=1e-4, t_eval=[9999.0])\n"
        "    print('finished')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted')\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert p.stdout.readline().strip() == "started"
    time.sleep(0.5)
    start = time.perf_counter()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=30)
    assert out.strip() == "interrupted"
    assert time.perf_counter() - start < 2.0


def test_the_core_gives_the_columns_figures_need_as_a_second_formula_does():
    """Exact Lagrange trajectories carry E, Mz, M3 and the potential; heavy trajectories the
    potential; rotation matrices and quaternions of Euler angles come from the core. Each is
    compared with the textbook formula written out here in numpy (Goldstein's z-x-z forms)."""
    from kreisel import _core

    top = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)
    st = top.state(0.6, theta_dot=1.0, phi_dot=2.0, psi_dot=300.0)
    ex = top.exact(st, np.linspace(0.0, 0.3, 50))
    th, thd, phd, psd = ex.theta, ex.theta_dot, ex.phi_dot, ex.psi_dot
    w3 = psd + phd * np.cos(th)
    m3 = top.I3 * w3
    mz = top.I1 * phd * np.sin(th) ** 2 + m3 * np.cos(th)
    v = top.m * top.g * top.l * np.cos(th)
    e = 0.5 * top.I1 * (thd**2 + (phd * np.sin(th)) ** 2) + 0.5 * top.I3 * w3**2 + v
    for name, ref in (("energy", e), ("Mz", mz), ("M3", m3), ("potential", v)):
        np.testing.assert_allclose(ex[name], ref, rtol=1e-13, atol=1e-15, err_msg=name)
    # the exact motion keeps them: their spread is round-off
    assert np.ptp(ex.energy) < 1e-12 * abs(ex.energy[0]) + 1e-15

    traj = kreisel.simulate(top, st, 0.05)
    q = traj.quaternion
    w, x, y, z = q.T
    gamma3 = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1)
    np.testing.assert_allclose(traj.potential, top.m * top.g * top.l * gamma3[:, 2], atol=1e-15)
    rot = _core.rotation_matrices(q)
    np.testing.assert_allclose(rot[:, 2, :], gamma3, atol=1e-15)
    np.testing.assert_allclose(rot @ np.swapaxes(rot, 1, 2), np.broadcast_to(np.eye(3), rot.shape),
                               atol=1e-14)  # fmt: skip
    # q(phi, theta, psi) = qz(phi) qx(theta) qz(psi), halves of the angles
    a, b = 0.5 * (traj.phi + traj.psi), 0.5 * (traj.phi - traj.psi)
    c, s = np.cos(0.5 * traj.theta), np.sin(0.5 * traj.theta)
    ref = np.stack([c * np.cos(a), s * np.cos(b), s * np.sin(b), c * np.sin(a)], -1)
    got = _core.quaternions_from_euler(traj.phi, traj.theta, traj.psi)
    np.testing.assert_allclose(np.abs(np.sum(got * ref, axis=1)), 1.0, atol=1e-14)
    np.testing.assert_allclose(np.abs(np.sum(got * q, axis=1)), 1.0, atol=1e-12)


def test_friction_laws_are_typed_values_checked_by_the_core():
    import pickle

    for law in (kreisel.Coulomb(0.4), kreisel.Viscous(2.0), kreisel.Frictionless()):
        again = pickle.loads(pickle.dumps(law))
        assert again == law and repr(again) == repr(law)
        assert law._native.law == {"Coulomb": "coulomb", "Viscous": "viscous"}.get(
            type(law).__name__, "none"
        )
        assert law._native.mu == getattr(law, "mu", 0.0)
    for make in (kreisel.Coulomb, kreisel.Viscous):
        with pytest.raises(kreisel.ParameterError, match="mu = -1.0 is not allowed"):
            make(-1.0)
        with pytest.raises(kreisel.ParameterError, match="mu = nan is not allowed"):
            make(float("nan"))


def test_every_column_of_every_model_has_a_unit():
    """The columns the core adds (potential; an exact trajectory's invariants) are written
    with units like the others."""
    top = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)
    st = top.state(0.5, psi_dot=300.0)
    pt = kreisel.PlayTop(0.02, 2.56e-6, 3.2e-6, 0.006, 0.02)
    for traj in (
        kreisel.simulate(top, st, 0.01),
        top.exact(st, np.linspace(0.0, 0.01, 5)),
        kreisel.simulate(pt, pt.state(3.0, psi_dot=100.0), 0.01),
    ):
        ds = traj.to_xarray()
        for name in ds.data_vars:
            assert ds[name].attrs.get("long_name") != name or name == "mode", name
            assert "units" in ds[name].attrs, name


def test_a_contact_starting_with_a_slip_below_the_tolerance_rolls_instead_of_chattering():
    """The rule of the touchdown fix (a Coulomb drop with restitution 0 hung at touchdown) is
    the contact's, for every way into a slip phase: a start state whose slip lies between the
    start threshold (1e-12 of the speed scale) and the slip tolerance (1e-9 of it at rtol
    1e-10) would start a slip phase whose slip_to_roll event never fires. It rolls, and the
    energy balance holds."""
    pt = kreisel.PlayTop(0.02, 2.56e-6, 3.2e-6, 0.006, 0.02, friction=kreisel.Coulomb(0.5))
    slip = kreisel.simulate(pt, pt.state(0.3, psi_dot=100.0), 0.0).slip_velocity[0]
    st = pt.state(0.3, psi_dot=100.0, vx=-slip[0] + 1e-10, vy=-slip[1])
    start = time.perf_counter()
    traj = kreisel.simulate(pt, st, 0.2)
    assert time.perf_counter() - start < 5.0
    assert traj.mode[0] == "roll" and traj.stats["steps"] < 1000
    balance = traj.energy + traj.dissipated
    assert abs(balance[-1] - balance[0]) < 1e-9 * balance[0]
