"""simulate_many for heavy tops, and the thread count of both batches.

Reference: each summary is recomputed here from the full trajectory of a single
``kreisel.simulate`` run (numpy reductions over its columns), an independent path through
the bindings; the batch must agree bit for bit for the angles and to round-off for drifts.
"""

import numpy as np
import pytest

import kreisel

LAG = dict(I1=6.8e-4, I3=1.5e-4, m=0.3, l=0.04)


def test_heavy_batch_matches_single_simulations():
    top = kreisel.LagrangeTop(**LAG)
    states = [top.state(0.2 + 0.15 * i, phi_dot=1.0, psi_dot=90.0 + 5 * i) for i in range(5)]
    res = kreisel.simulate_many(top, states, 3.0, threads=2)
    assert isinstance(res, kreisel.HeavyBatchSummary) and len(res) == 5
    for i, s in enumerate(states):
        tr = kreisel.simulate(top, s, 3.0)
        assert res.final_theta[i] == tr.theta[-1]
        assert res.theta_min[i] == tr.theta.min() and res.theta_max[i] == tr.theta.max()
        dmz = np.abs(tr.Mz - tr.Mz[0]).max()
        assert res.Mz_drift[i] == pytest.approx(
            dmz / np.linalg.norm(np.array([LAG["I1"], LAG["I1"], LAG["I3"]]) * tr.omega[0]),
            rel=1e-12,
            abs=1e-300,
        )
        # energy drift relative to the energy scale T0 + m g l (kinetic energy + the
        # potential's amplitude), from the trajectory's own energy column
        inertia = np.array([LAG["I1"], LAG["I1"], LAG["I3"]])
        scale = 0.5 * inertia @ tr.omega[0] ** 2 + LAG["m"] * 9.81 * LAG["l"]
        assert res.energy_drift[i] == pytest.approx(
            np.abs(tr.energy - tr.energy[0]).max() / scale, rel=1e-12
        )
        assert res.steps[i] == len(tr.t) - 1
        assert np.isnan(res.kovalevskaya_drift[i])
    assert res.errors == (None,) * 5


def test_heavy_batch_fixed_step_and_kovalevskaya():
    kov = kreisel.HeavyTop(2.0, 2.0, 1.0, 1.0, [0.5, 0.0, 0.0], g=1.0)
    st = kov.state(1.0, psi_dot=1.0, phi_dot=0.3)
    res = kreisel.simulate_many([kov, kov], st, 10.0, method="splitting4", dt=1e-3)
    # order-4 splitting at dt = 1e-3: energy and K errors of order dt^4, Mz to round-off
    assert np.all(res.Mz_drift < 1e-12)
    assert np.all(res.energy_drift < 1e-8) and np.all(res.kovalevskaya_drift < 1e-7)
    # and they are the largest relative changes of the trajectory's own columns
    tr = kreisel.simulate(kov, st, 10.0, method="splitting4", dt=1e-3)
    k = tr.kovalevskaya
    assert res.kovalevskaya_drift[0] == pytest.approx(np.abs(k - k[0]).max() / abs(k[0]), rel=1e-12)
    assert res.kovalevskaya_drift[0] > 0 and res.energy_drift[0] > 0
    assert np.all(np.isnan(res.M3_drift))
    assert list(res.steps) == [10000, 10000]


def test_thread_count_does_not_change_any_bit():
    pt = kreisel.PlayTop(0.02, 0.8 * 0.4 * 0.02 * 0.02**2, 0.4 * 0.02 * 0.02**2, 0.006, 0.02)
    states = [pt.state(np.pi - 0.1 - 0.05 * i, psi_dot=150.0) for i in range(6)]
    one = kreisel.simulate_many(pt, states, 1.0, threads=1)
    two = kreisel.simulate_many(pt, states, 1.0, threads=2)
    for name in ("final_u", "inversion_time", "jellett_drift", "energy_drift", "steps"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name))


@pytest.mark.parametrize("threads", [0, -1, 1.5, True, "2"])
def test_bad_thread_count_is_named(threads):
    top = kreisel.LagrangeTop(**LAG)
    with pytest.raises(kreisel.ParameterError, match="threads"):
        kreisel.simulate_many(top, top.state(0.3, psi_dot=90.0), 1.0, threads=threads)


def test_heavy_batch_needs_dt_for_fixed_step_methods():
    top = kreisel.LagrangeTop(**LAG)
    with pytest.raises(kreisel.ParameterError, match="dt"):
        kreisel.simulate_many(top, top.state(0.3, psi_dot=90.0), 1.0, method="rk4")


def test_progress_bar_changes_no_result(capsys):
    pt = kreisel.PlayTop(0.02, 0.8 * 0.4 * 0.02 * 0.02**2, 0.4 * 0.02 * 0.02**2, 0.006, 0.02)
    states = [pt.state(np.pi - 0.1, psi_dot=60.0 + i) for i in range(200)]
    quiet = kreisel.simulate_many(pt, states, 0.3)
    shown = kreisel.simulate_many(pt, states, 0.3, progress=True)
    assert "200/200" in capsys.readouterr().err
    for name in ("final_u", "inversion_time", "jellett_drift", "steps", "final_mode"):
        np.testing.assert_array_equal(getattr(quiet, name), getattr(shown, name))
    assert quiet.errors == shown.errors
    top = kreisel.LagrangeTop(**LAG)
    hs = [top.state(0.3 + 0.001 * i, psi_dot=90.0) for i in range(130)]
    a = kreisel.simulate_many(top, hs, 0.5)
    b = kreisel.simulate_many(top, hs, 0.5, progress=True)
    np.testing.assert_array_equal(a.theta_max, b.theta_max)


def test_a_batch_refuses_at_once_a_run_its_pace_cannot_finish():
    """A Lagrange top spun about the vertical at 1e8 rad/s needs ~1.7e8 steps a second (its
    first 1e-4 s take 17288): more than the step limit, so a batch refuses it by its pace, as
    simulate does, instead of running to the limit (half a minute) and failing there."""
    top = kreisel.LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    s = top.state(theta=0.5, phi_dot=1e8)
    probe = kreisel.simulate(top, s, 1e-4, t_eval=[0.0, 1e-4])
    assert probe.stats["steps"] / 1e-4 > kreisel._simulate.names()["max_steps"]
    res = kreisel.simulate_many([top, top], s, 1.0)
    for e in res.errors:
        assert e.startswith("t_end = 1.0 is not allowed: at the pace of its first"), e
